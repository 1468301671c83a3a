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
#include "lgvi/multibody_step_equations.hpp"

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

/// X = -J_G_xi^{-1} J_G_in, the implicit-function solve of a step linearization, as `solve` says.
template <int N, int C>
Eigen::Matrix<double, 3 * N, C> implicit_function_solve(const Eigen::Matrix<double, 3 * N, 3 * N>& J_G_xi,
                                                        const Eigen::Matrix<double, 3 * N, C>& J_G_in,
                                                        LinearizationSolve solve) {
  if (solve == LinearizationSolve::ClosedForm) {
    return -group_newton_detail::solve_newton_matrix_columns<N, C>(J_G_xi, J_G_in);
  }
  return -J_G_xi.partialPivLu().solve(J_G_in);
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
  const double m = S.mass;
  const Mat3& Jd = S.inertia.Jd;
  const Vec3& d = S.d;
  const CartPendulumStepEquation equation(S, in, h, c0, u_k);
  auto residual = [&](const std::array<Mat3, 1>& A, Vec3& G) { return equation.residual(A[0], G); };
  auto jacobian = [&](const std::array<Mat3, 1>& A, Mat3& DG) { DG = equation.J_G_xi(Mat3::Identity() + A[0]); };
  std::array<Mat3, 1> A{equation.initial_guess()};
  const RotationUpdateSummary summary = solve_on_rotations<1>(A, residual, jacobian, options_);
  if (!summary.converged()) return summary;

  const Vec2 dq = equation.cart_displacement(A[0]);
  // R_{k+1} = R_k + R_k (F - I) with compensated (Kahan) summation: the increment R_k A is
  // O(h) and formed to eps of its own size, and the compensation keeps the rounding of the sum
  // from accumulating. Plain R_k F lets R drift off SO(3) by ~eps per step, and the vertical
  // momentum map of this system (unlike the single bodies') is sensitive to that drift: its
  // pendulum and cart parts cancel only through R (a x b) = R a x R b.
  const Mat3 increment = in.R * A[0] - in.R_compensation;
  const Mat3 R1 = in.R + increment;
  if (compensated_attitude_) {
    out.R_compensation = (R1 - in.R) - increment;
  } else {
    out.R_compensation.setZero();
  }
  const Vec3 M1 = S.moment(R1);
  out.Pi = so3::vee(Jd * A[0] - A[0].transpose() * Jd) / h +
           (m / h) * d.cross(R1.transpose().leftCols<2>() * dq) + (0.5 * h) * M1;
  out.p = equation.p_minus() + c1 * u_k1;
  out.q = in.q + dq;
  out.R = R1;
  out.M = M1;
  return summary;
}

CartPendulumStepEquation::InputJacobian CartPendulumStepEquation::J_G_in(const Mat3& F) const {
  // Variations of b and of P (n -> n + hat(n) eta) at fixed F; a = (F - I) d.
  const Vec3 a = (F - Mat3::Identity()) * S_.d;
  const Vec3 Rp = RtE_ * p_minus_;
  InputJacobian J = InputJacobian::Zero();
  // -h^2/2 dM_k/deta, dM/deta = m g hat(d) hat(n) (n moves by hat(n) eta).
  J.block<3, 3>(0, 0) = kappa_ * D_ * (n_.dot(a) * Mat3::Identity() + n_ * a.transpose()) * so3::hat(n_) -
                        (0.5 * h_ * h_ * (m_ * S_.gravity)) * D_ * so3::hat(n_) + (m_ * h_ / total_) * D_ * so3::hat(Rp);
  J.block<3, 3>(0, 5) = -h_ * Mat3::Identity();
  const Eigen::Matrix<double, 3, 2> J_G_p = (m_ * h_ / total_) * D_ * RtE_;
  J.block<3, 2>(0, 8) = J_G_p;
  J.block<3, 2>(0, 10) = c0_ * J_G_p;
  return J;
}

void CartPendulumLgvi::linearize(const State& in, const State& out, double h, const Control& u_k,
                                 const Control& /*u_k1*/, StateJacobian& J_out_in, ControlJacobian& J_out_uk,
                                 ControlJacobian& J_out_uk1, LinearizationSolve solve) const {
  const CartPendulum& S = system_;
  const auto [c0, c1] = impulse_weights(form_, h);
  const double m = S.mass, total = S.cart_mass + S.mass;
  const Mat3& Jd = S.inertia.Jd;
  const Mat3 D = so3::hat(S.d);
  const Mat3 F = in.R.transpose() * out.R;
  const Vec3 a = (F - Mat3::Identity()) * S.d;
  const Eigen::Matrix<double, 3, 2> RtE = in.R.transpose().leftCols<2>();

  // G(F; w_k, u_k) = 0 with F -> F exp(hat xi): dxi/d[w_k; u_k] = -J_G_xi^{-1} J_G_in.
  const CartPendulumStepEquation equation(S, in, h, c0, u_k);
  const Eigen::Matrix<double, 3, 12> X = implicit_function_solve<1, 12>(equation.J_G_xi(F), equation.J_G_in(F), solve);

  // eta' = F^T eta + xi.
  Eigen::Matrix<double, 3, 12> Eta = X;
  Eta.block<3, 3>(0, 0) += F.transpose();
  // delta = (h p^- - m E^T R (F - I) d) / (M + m), the cart's displacement.
  Eigen::Matrix<double, 2, 12> Delta = (m / total) * RtE.transpose() * F * D * X;
  Delta.block<2, 3>(0, 0) += (m / total) * RtE.transpose() * so3::hat(a);
  Delta.block<2, 2>(0, 8) += (h / total) * Eigen::Matrix2d::Identity();
  Delta.block<2, 2>(0, 10) += (c0 * h / total) * Eigen::Matrix2d::Identity();
  // Pi' = vee(Jd A - A^T Jd)/h + m/h d x R'^T E delta + h/2 M(R').
  const Vec2 delta = out.q - in.q;
  const Eigen::Matrix<double, 3, 2> E1 = out.R.transpose().leftCols<2>();
  const Vec3 n1 = out.R.row(2).transpose();
  const Mat3 FtJ = F.transpose() * Jd;
  const Mat3 L2 = FtJ.trace() * Mat3::Identity() - FtJ;
  const Eigen::Matrix<double, 3, 12> Pi = (L2 / h) * X + (m / h) * D * so3::hat(E1 * delta) * Eta +
                                          (m / h) * D * E1 * Delta + (0.5 * h * (m * S.gravity)) * D * so3::hat(n1) * Eta;

  J_out_in.setZero();
  J_out_uk.setZero();
  J_out_uk1.setZero();
  J_out_in.block<3, 10>(0, 0) = Eta.leftCols<10>();
  J_out_uk.block<3, 2>(0, 0) = Eta.rightCols<2>();
  J_out_in.block<2, 10>(3, 0) = Delta.leftCols<10>();
  J_out_in.block<2, 2>(3, 3) += Eigen::Matrix2d::Identity();
  J_out_uk.block<2, 2>(3, 0) = Delta.rightCols<2>();
  J_out_in.block<3, 10>(5, 0) = Pi.leftCols<10>();
  J_out_uk.block<3, 2>(5, 0) = Pi.rightCols<2>();
  J_out_in.block<2, 2>(8, 8) = Eigen::Matrix2d::Identity();
  J_out_uk.block<2, 2>(8, 0) = c0 * Eigen::Matrix2d::Identity();
  J_out_uk1.block<2, 2>(8, 0) = c1 * Eigen::Matrix2d::Identity();
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
  const ConnectedBodiesStepEquation equation(S, in, h, c0, u_k);
  auto residual = [&](const std::array<Mat3, 2>& A, Vec6& G) { return equation.residual(A, G); };
  auto jacobian = [&](const std::array<Mat3, 2>& A, Mat6x6& DG) {
    DG = equation.J_G_xi(Mat3::Identity() + A[0], Mat3::Identity() + A[1]);
  };
  std::array<Mat3, 2> A = equation.initial_guess();
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

ConnectedBodiesStepEquation::InputJacobian ConnectedBodiesStepEquation::J_G_in(const Mat3& F1, const Mat3& F2) const {
  // a_i in body frames; R12 = R1_k^T R2_k varies as R12 -> R12 - hat(eta1) R12 + R12 hat(eta2).
  const double mu = S_.mu;
  const Vec3 a1 = (F1 - Mat3::Identity()) * S_.d1, a2 = (F2 - Mat3::Identity()) * S_.d2;
  const double hc0 = h_ * c0_;
  InputJacobian J = InputJacobian::Zero();
  J.block<3, 3>(0, 0) = -mu * D1_ * so3::hat(R12_ * a2) - hc0 * so3::hat(in_.R1.transpose() * u_k_);
  J.block<3, 3>(0, 3) = mu * D1_ * R12_ * so3::hat(a2);
  J.block<3, 3>(0, 6) = -h_ * Mat3::Identity();
  J.block<3, 3>(0, 12) = -hc0 * in_.R1.transpose();
  J.block<3, 3>(3, 0) = mu * D2_ * R12_.transpose() * so3::hat(a1);
  J.block<3, 3>(3, 3) = -mu * D2_ * so3::hat(R12_.transpose() * a1) + hc0 * so3::hat(in_.R2.transpose() * u_k_);
  J.block<3, 3>(3, 9) = -h_ * Mat3::Identity();
  J.block<3, 3>(3, 12) = hc0 * in_.R2.transpose();
  return J;
}

void ConnectedBodiesLgvi::linearize(const State& in, const State& out, double h, const Control& u_k,
                                    const Control& u_k1, StateJacobian& J_out_in, ControlJacobian& J_out_uk,
                                    ControlJacobian& J_out_uk1, LinearizationSolve solve) const {
  const ConnectedBodies& S = system_;
  const auto [c0, c1] = impulse_weights(form_, h);
  const double mu = S.mu;
  const Mat3 &K1 = S.reduced1.Jd, &K2 = S.reduced2.Jd;
  const Mat3 D1 = so3::hat(S.d1), D2 = so3::hat(S.d2);
  const Mat3 F1 = in.R1.transpose() * out.R1, F2 = in.R2.transpose() * out.R2;
  const Vec3 a1 = (F1 - Mat3::Identity()) * S.d1, a2 = (F2 - Mat3::Identity()) * S.d2;  // body frames
  const Mat3 R12 = in.R1.transpose() * in.R2;

  // G(F1, F2; w_k, u_k) = 0 with F_i -> F_i exp(hat xi_i): dxi/d[w_k; u_k] = -J_G_xi^{-1} J_G_in.
  const ConnectedBodiesStepEquation equation(S, in, h, c0, u_k);
  const Eigen::Matrix<double, 6, 15> X =
      implicit_function_solve<2, 15>(equation.J_G_xi(F1, F2), equation.J_G_in(F1, F2), solve);
  const auto X1 = X.topRows<3>();
  const auto X2 = X.bottomRows<3>();

  Eigen::Matrix<double, 3, 15> Eta1 = X1, Eta2 = X2;
  Eta1.block<3, 3>(0, 0) += F1.transpose();
  Eta2.block<3, 3>(0, 3) += F2.transpose();
  // x = R1'^T a2 (inertial a2) = F1^T R12 a2; y = F2^T R12^T a1.
  const Vec3 x = F1.transpose() * R12 * a2, y = F2.transpose() * R12.transpose() * a1;
  Eigen::Matrix<double, 3, 15> dx = so3::hat(x) * X1 - F1.transpose() * R12 * F2 * D2 * X2;
  dx.block<3, 3>(0, 0) += F1.transpose() * so3::hat(R12 * a2);
  dx.block<3, 3>(0, 3) -= F1.transpose() * R12 * so3::hat(a2);
  Eigen::Matrix<double, 3, 15> dy = so3::hat(y) * X2 - F2.transpose() * R12.transpose() * F1 * D1 * X1;
  dy.block<3, 3>(0, 3) += F2.transpose() * so3::hat(R12.transpose() * a1);
  dy.block<3, 3>(0, 0) -= F2.transpose() * R12.transpose() * so3::hat(a1);
  const Mat3 FK1 = F1.transpose() * K1, FK2 = F2.transpose() * K2;
  const Mat3 L1 = FK1.trace() * Mat3::Identity() - FK1, L2 = FK2.trace() * Mat3::Identity() - FK2;
  Eigen::Matrix<double, 3, 15> P1 = (L1 / h) * X1 - (mu / h) * D1 * dx;
  Eigen::Matrix<double, 3, 15> P2 = (L2 / h) * X2 - (mu / h) * D2 * dy;
  // The end kicks +-c1 R_i'^T u_{k+1}.
  if (c1 != 0.0) {
    P1 += c1 * so3::hat(out.R1.transpose() * u_k1) * Eta1;
    P2 -= c1 * so3::hat(out.R2.transpose() * u_k1) * Eta2;
  }
  J_out_in.setZero();
  J_out_in.block<3, 12>(0, 0) = Eta1.leftCols<12>();
  J_out_in.block<3, 12>(3, 0) = Eta2.leftCols<12>();
  J_out_in.block<3, 12>(6, 0) = P1.leftCols<12>();
  J_out_in.block<3, 12>(9, 0) = P2.leftCols<12>();
  J_out_uk.block<3, 3>(0, 0) = Eta1.rightCols<3>();
  J_out_uk.block<3, 3>(3, 0) = Eta2.rightCols<3>();
  J_out_uk.block<3, 3>(6, 0) = P1.rightCols<3>();
  J_out_uk.block<3, 3>(9, 0) = P2.rightCols<3>();
  J_out_uk1.setZero();
  J_out_uk1.block<3, 3>(6, 0) = c1 * out.R1.transpose();
  J_out_uk1.block<3, 3>(9, 0) = -c1 * out.R2.transpose();
}

}  // namespace lgvi
