// Derivations (variations delta R = R hat(eta); tr(hat(eta) A) = -eta . vee(A - A^T)).
//
// Cart-pendulum, eq. 29 with c = E (q_{k+1} - q_k):
//   -dL_d/d eta_k     = vee(F J_d - J_d F^T)/h + m/h d x R_k^T c - h/2 M_k       =: Pi_k^-
//    dL_d/d eta_{k+1} = vee(J_d F - F^T J_d)/h + m/h d x R_{k+1}^T c + h/2 M_{k+1} =: Pi_{k+1}^+
//   -dL_d/dq_k = dL_d/dq_{k+1} = (M+m)/h dq + m/h E^T (R_{k+1} - R_k) d          =: p_k^- = p_{k+1}^+
// The discrete Euler-Lagrange equations with control impulses are Pi_k^- = Pi_k^+ (the cart
// forces do not act on the attitude) and p_k^- = p_k^+ + c0 u_k, p_{k+1}^+ = p_k^- + c1 u_{k+1}.
// These are eqs. 30-36 with the transposes the extracted text lost (e_1^T (R_{k+1} - R_k) d).
// With P = R_k^T E E^T R_k = I - n n^T (n = R_k^T e3) and kappa = m^2/(M+m), eliminating dq:
//   G(F) = vee(F J_d - J_d F^T) - kappa d x P (F - I) d - b = 0,
//   b = h Pi_k + h^2/2 M_k - m h/(M+m) d x R_k^T E p^-.
//
// Connected bodies, reduced eq. 39: -dL_d/d eta_{i,k} and dL_d/d eta_{i,k+1} as in the header;
// the cross term -mu/h a1 . a2 varies as delta a1 = R1_k hat(d1) eta_{1,k} (start) and
// -R1_{k+1} hat(d1) eta_{1,k+1} (end).
#include "lgvi/multibody_lgvi.hpp"

#include <Eigen/Cholesky>

#include "lgvi/composition.hpp"

namespace lgvi {

static_assert(FlowMap<ComposedLgvi<CartPendulumLgvi>>);
static_assert(FlowMap<ComposedLgvi<ConnectedBodiesLgvi>>);

namespace {
void require_rotation(const Mat3& R, const std::string& field) {
  require_finite(R, field);
  if (!so3::is_rotation(R, 1e-10)) {
    throw InvalidInput(field, "is not a rotation matrix (R^T R != I or det R != 1)");
  }
}
}  // namespace

CartPendulumLgvi::State CartPendulumLgvi::make_state(const Mat3& R, const Vec2& q,
                                                     const Vec3& Omega, const Vec2& q_dot) const {
  require_rotation(R, "R0");
  require_finite(q, "q0");
  require_finite(Omega, "Omega0");
  require_finite(q_dot, "q_dot0");
  State s;
  s.R = R;
  s.q = q;
  system_.momenta(R, Omega, q_dot, s.Pi, s.p);
  s.M = system_.moment(R);
  return s;
}

LGVI_FLATTEN RotationUpdateSummary CartPendulumLgvi::step(const State& in, double h, const Control& u_k,
                                             const Control& u_k1, State& out) const {
  const auto [c0, c1] = impulse_weights(form_, h);
  const CartPendulum& S = system_;
  const double m = S.mass, total = S.cart_mass + S.mass, kappa = m * m / total;
  const Mat3& Jd = S.inertia.Jd;
  const Vec3& d = S.d;
  const Mat3 D = so3::hat(d);
  const Vec2 p_minus = in.p + c0 * u_k;
  const Eigen::Matrix<double, 3, 2> RtE = in.R.transpose().leftCols<2>();  // R_k^T E
  const Vec3 n = in.R.row(2).transpose();                                  // R_k^T e3
  const Mat3 P = Mat3::Identity() - n * n.transpose();
  const Vec3 coupling = (m * h / total) * d.cross(RtE * p_minus);
  const Vec3 b = h * in.Pi + (0.5 * h * h) * in.M - coupling;
  const double b_scale = (h * in.Pi).norm() + (0.5 * h * h * in.M).norm() + coupling.norm();

  // In terms of A = F - I (see group_newton.hpp): F J_d - J_d F^T = A J_d - J_d A^T.
  auto residual = [&](const std::array<Mat3, 1>& A, Vec3& G) {
    const Vec3 t1 = vee_of_skew_product(A[0], Jd);
    const Vec3 t2 = kappa * d.cross(P * (A[0] * d));
    G = t1 - t2 - b;
    return t1.norm() + t2.norm() + b_scale;
  };
  const Mat3 kappa_DP = kappa * D * P;
  auto jacobian = [&](const std::array<Mat3, 1>& A, Mat3& DG) {
    const Mat3 F = Mat3::Identity() + A[0];
    DG = J_G_xi(F, Jd) + kappa_DP * F * D;
  };
  // Warm start from the linearization (J + kappa hat(d) P hat(d)) f = b at F = I.
  const Mat3 J0 = S.inertia.J + kappa * D * P * D;
  std::array<Mat3, 1> A{so3::exp_minus_identity(J0.partialPivLu().solve(b))};
  const RotationUpdateSummary summary = solve_on_rotations<1>(A, residual, jacobian, options_);
  if (!summary.converged()) return summary;

  const Vec2 dq = (h * p_minus - m * RtE.transpose() * (A[0] * d)) / total;
  // R_{k+1} = R_k + R_k (F - I) with compensated (Kahan) summation: the increment R_k A is
  // O(h) and formed to eps of its own size, and the compensation keeps the rounding of the sum
  // from accumulating. Plain R_k F lets R drift off SO(3) by ~eps per step, and the vertical
  // momentum map of this system (unlike the single bodies') is sensitive to that drift: its
  // pendulum and cart parts cancel only through R (a x b) = R a x R b.
  const Mat3 increment = in.R * A[0] - in.R_compensation;
  const Mat3 R1 = in.R + increment;
  out.R_compensation = (R1 - in.R) - increment;
  const Vec3 M1 = S.moment(R1);
  out.Pi = so3::vee(Jd * A[0] - A[0].transpose() * Jd) / h +
           (m / h) * d.cross(R1.transpose().leftCols<2>() * dq) + (0.5 * h) * M1;
  out.p = p_minus + c1 * u_k1;
  out.q = in.q + dq;
  out.R = R1;
  out.M = M1;
  return summary;
}

ConnectedBodiesLgvi::State ConnectedBodiesLgvi::make_state(const Mat3& R1, const Mat3& R2,
                                                           const Vec3& Omega1,
                                                           const Vec3& Omega2) const {
  require_rotation(R1, "R1_0");
  require_rotation(R2, "R2_0");
  require_finite(Omega1, "Omega1_0");
  require_finite(Omega2, "Omega2_0");
  State s;
  s.R1 = R1;
  s.R2 = R2;
  system_.momenta(R1, R2, Omega1, Omega2, s.Pi1, s.Pi2);
  return s;
}

LGVI_FLATTEN RotationUpdateSummary ConnectedBodiesLgvi::step(const State& in, double h, const Control& u_k,
                                                const Control& u_k1, State& out) const {
  const auto [c0, c1] = impulse_weights(form_, h);
  const ConnectedBodies& S = system_;
  const double mu = S.mu;
  const Mat3& K1 = S.reduced1.Jd;
  const Mat3& K2 = S.reduced2.Jd;
  const Vec3 &d1 = S.d1, &d2 = S.d2;
  const Mat3 D1 = so3::hat(d1), D2 = so3::hat(d2);
  const Mat3 R12 = in.R1.transpose() * in.R2;
  Vec3 hPi1 = h * in.Pi1, hPi2 = h * in.Pi2;
  if (c0 != 0.0) {
    hPi1 += (h * c0) * (in.R1.transpose() * u_k);
    hPi2 -= (h * c0) * (in.R2.transpose() * u_k);
  }
  const double rhs_scale = hPi1.norm() + hPi2.norm();

  // In terms of A_i = F_i - I (see group_newton.hpp): a_i = R_i A_i d_i.
  auto residual = [&](const std::array<Mat3, 2>& A, Vec6& G) {
    const Vec3 t1 = vee_of_skew_product(A[0], K1);
    const Vec3 t2 = vee_of_skew_product(A[1], K2);
    const Vec3 x1 = mu * d1.cross(R12 * (A[1] * d2));              // mu d1 x R1^T a2
    const Vec3 x2 = mu * d2.cross(R12.transpose() * (A[0] * d1));  // mu d2 x R2^T a1
    G << t1 - x1 - hPi1, t2 - x2 - hPi2;
    return t1.norm() + t2.norm() + x1.norm() + x2.norm() + rhs_scale;
  };
  const Mat3 mu_D1_R12 = mu * D1 * R12, mu_D2_R21 = mu * D2 * R12.transpose();
  auto jacobian = [&](const std::array<Mat3, 2>& A, Mat6x6& DG) {
    const Mat3 F1 = Mat3::Identity() + A[0], F2 = Mat3::Identity() + A[1];
    DG.topLeftCorner<3, 3>() = J_G_xi(F1, K1);
    DG.topRightCorner<3, 3>() = mu_D1_R12 * F2 * D2;
    DG.bottomLeftCorner<3, 3>() = mu_D2_R21 * F1 * D1;
    DG.bottomRightCorner<3, 3>() = J_G_xi(F2, K2);
  };
  // Warm start: at F = I the equations linearize to the mass matrix of eq. 47 times xi = h Omega.
  Vec3 xi1, xi2;
  S.velocities(in.R1, in.R2, hPi1, hPi2, xi1, xi2);
  std::array<Mat3, 2> A{so3::exp_minus_identity(xi1), so3::exp_minus_identity(xi2)};
  const RotationUpdateSummary summary = solve_on_rotations<2>(A, residual, jacobian, options_);
  if (!summary.converged()) return summary;

  const Mat3 R1 = in.R1 * (Mat3::Identity() + A[0]), R2 = in.R2 * (Mat3::Identity() + A[1]);
  const Vec3 a1 = in.R1 * (A[0] * d1), a2 = in.R2 * (A[1] * d2);
  out.Pi1 = so3::vee(K1 * A[0] - A[0].transpose() * K1) / h - (mu / h) * d1.cross(R1.transpose() * a2) +
            c1 * (R1.transpose() * u_k1);
  out.Pi2 = so3::vee(K2 * A[1] - A[1].transpose() * K2) / h - (mu / h) * d2.cross(R2.transpose() * a1) -
            c1 * (R2.transpose() * u_k1);
  out.R1 = R1;
  out.R2 = R2;
  return summary;
}

}  // namespace lgvi
