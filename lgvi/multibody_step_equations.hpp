// The implicit equations of one step of the multibody LGVIs (multibody_lgvi.hpp), each one
// definition for the flow's Newton iteration and its linearization. Included by the flows' own
// source (multibody_lgvi.cpp) and the tests of the linearizations, not by the flows' header:
// every file that names a multibody flow would otherwise compile these fixed-size Eigen bodies.
#pragma once

#include <array>

#include "lgvi/group_newton.hpp"
#include "lgvi/multibody_lgvi.hpp"
#include "lgvi/so3.hpp"

namespace lgvi {

/// The implicit equation of one cart-pendulum step: eq. 32 with the cart displacement of eqs.
/// 30-31 substituted (derivation in multibody_lgvi.cpp), in A = F - I (group_newton.hpp):
///   G(F; s_k, u_k) = vee(F J_d - J_d F^T) - kappa d x P (F - I) d - b = 0,
///   P = I - n n^T, n = R_k^T e3, kappa = m^2/(M+m), b = h Pi_k + h^2/2 M_k - m h/(M+m) d x R_k^T E p^-,
/// p^- = p_k + c0 u_k. One definition for the flow's Newton iteration (residual, J_G_xi) and its
/// linearization (J_G_xi, J_G_in: the implicit-function theorem). Holds the system by reference
/// (a temporary of one step). Fixed size, no heap.
class CartPendulumStepEquation {
 public:
  /// Tangent of the step's input: [eta (3); dq (2); dPi (3); dp (2); du_k (2)], R -> R exp(hat eta).
  using InputJacobian = Eigen::Matrix<double, 3, 12>;

  CartPendulumStepEquation(const CartPendulum& system, const CartPendulumState& in, double h, double c0,
                           const Vec2& u_k)
      : S_(system), h_(h), c0_(c0), m_(system.mass), total_(system.cart_mass + system.mass),
        kappa_(m_ * m_ / total_), D_(so3::hat(system.d)), p_minus_(in.p + c0 * u_k),
        RtE_(in.R.transpose().leftCols<2>()), n_(in.R.row(2).transpose()),
        P_(Mat3::Identity() - n_ * n_.transpose()),
        coupling_((m_ * h / total_) * system.d.cross(RtE_ * p_minus_)),
        b_(h * in.Pi + (0.5 * h * h) * in.M - coupling_),
        b_scale_((h * in.Pi).norm() + (0.5 * h * h * in.M).norm() + coupling_.norm()), kappa_DP_(kappa_ * D_ * P_) {}

  /// G at F = I + A into G; returns the sum of its terms' magnitudes (the Newton scale).
  double residual(const Mat3& A, Vec3& G) const {
    const Vec3 t1 = vee_of_skew_product(A, S_.inertia.Jd);
    const Vec3 t2 = kappa_ * S_.d.cross(P_ * (A * S_.d));
    G = t1 - t2 - b_;
    return t1.norm() + t2.norm() + b_scale_;
  }
  /// dG/dxi for F -> F exp(hat xi): the Newton matrix (lgvi::J_G_xi for the rotational term).
  Mat3 J_G_xi(const Mat3& F) const { return lgvi::J_G_xi(F, S_.inertia.Jd) + kappa_DP_ * F * D_; }
  /// dG/d[w_k; u_k] at fixed F (the tangent of the input, see InputJacobian).
  InputJacobian J_G_in(const Mat3& F) const;
  /// Newton's start A = F - I: the equation linearized at F = I, (J + kappa hat(d) P hat(d)) f = b.
  Mat3 initial_guess() const {
    const Mat3 J0 = S_.inertia.J + kappa_ * D_ * P_ * D_;
    return so3::exp_minus_identity(J0.partialPivLu().solve(b_));
  }
  /// The cart's displacement q_{k+1} - q_k = (h p^- - m E^T R_k (F - I) d) / (M + m) (eqs. 30-31).
  Vec2 cart_displacement(const Mat3& A) const {
    return (h_ * p_minus_ - m_ * RtE_.transpose() * (A * S_.d)) / total_;
  }
  const Vec2& p_minus() const { return p_minus_; }

 private:
  const CartPendulum& S_;
  double h_, c0_, m_, total_, kappa_;
  Mat3 D_;
  Vec2 p_minus_;
  Eigen::Matrix<double, 3, 2> RtE_;  // R_k^T E
  Vec3 n_;                           // R_k^T e3
  Mat3 P_;
  Vec3 coupling_, b_;
  double b_scale_;
  Mat3 kappa_DP_;
};

/// The implicit equations of one connected-bodies step, eqs. 40-41 in A_i = F_i - I
/// (group_newton.hpp), with Pi1^- = Pi1_k + c0 R1_k^T u_k, Pi2^- = Pi2_k - c0 R2_k^T u_k:
///   G_1 = vee(F1 K1 - K1 F1^T) - mu d1 x R1_k^T a2 - h Pi1^- = 0,
///   G_2 = vee(F2 K2 - K2 F2^T) - mu d2 x R2_k^T a1 - h Pi2^- = 0,   a_i = R_i,k (F_i - I) d_i.
/// One definition for the flow's Newton iteration (residual, J_G_xi) and its linearization
/// (J_G_xi, J_G_in: the implicit-function theorem). Holds the system and the input state by
/// reference (a temporary of one step). Fixed size, no heap.
class ConnectedBodiesStepEquation {
 public:
  /// Tangent of the step's input: [eta1; eta2; dPi1; dPi2; du_k] (15), R_i -> R_i exp(hat eta_i).
  using InputJacobian = Eigen::Matrix<double, 6, 15>;

  ConnectedBodiesStepEquation(const ConnectedBodies& system, const ConnectedBodiesState& in, double h,
                              double c0, const Vec3& u_k)
      : S_(system), in_(in), u_k_(u_k), h_(h), c0_(c0), D1_(so3::hat(system.d1)), D2_(so3::hat(system.d2)),
        R12_(in.R1.transpose() * in.R2), hPi1_(h * in.Pi1), hPi2_(h * in.Pi2) {
    if (c0 != 0.0) {
      hPi1_ += (h * c0) * (in.R1.transpose() * u_k);
      hPi2_ -= (h * c0) * (in.R2.transpose() * u_k);
    }
    rhs_scale_ = hPi1_.norm() + hPi2_.norm();
    mu_D1_R12_ = S_.mu * D1_ * R12_;
    mu_D2_R21_ = S_.mu * D2_ * R12_.transpose();
  }

  /// G at F_i = I + A_i into G; returns the sum of its terms' magnitudes (the Newton scale).
  double residual(const std::array<Mat3, 2>& A, Vec6& G) const {
    const Vec3 t1 = vee_of_skew_product(A[0], S_.reduced1.Jd);
    const Vec3 t2 = vee_of_skew_product(A[1], S_.reduced2.Jd);
    const Vec3 x1 = S_.mu * S_.d1.cross(R12_ * (A[1] * S_.d2));              // mu d1 x R1^T a2
    const Vec3 x2 = S_.mu * S_.d2.cross(R12_.transpose() * (A[0] * S_.d1));  // mu d2 x R2^T a1
    G << t1 - x1 - hPi1_, t2 - x2 - hPi2_;
    return t1.norm() + t2.norm() + x1.norm() + x2.norm() + rhs_scale_;
  }
  /// dG/d[xi1; xi2] for F_i -> F_i exp(hat xi_i): the Newton matrix.
  Mat6x6 J_G_xi(const Mat3& F1, const Mat3& F2) const {
    Mat6x6 J;
    J.topLeftCorner<3, 3>() = lgvi::J_G_xi(F1, S_.reduced1.Jd);
    J.topRightCorner<3, 3>() = mu_D1_R12_ * F2 * D2_;
    J.bottomLeftCorner<3, 3>() = mu_D2_R21_ * F1 * D1_;
    J.bottomRightCorner<3, 3>() = lgvi::J_G_xi(F2, S_.reduced2.Jd);
    return J;
  }
  /// dG/d[w_k; u_k] at fixed (F1, F2) (the tangent of the input, see InputJacobian).
  InputJacobian J_G_in(const Mat3& F1, const Mat3& F2) const;
  /// Newton's start: at F = I the equations linearize to eq. 47's mass matrix times xi = h Omega.
  std::array<Mat3, 2> initial_guess() const {
    Vec3 xi1, xi2;
    S_.velocities(in_.R1, in_.R2, hPi1_, hPi2_, xi1, xi2);
    return {so3::exp_minus_identity(xi1), so3::exp_minus_identity(xi2)};
  }

 private:
  const ConnectedBodies& S_;
  const ConnectedBodiesState& in_;
  Vec3 u_k_;
  double h_, c0_;
  Mat3 D1_, D2_, R12_;
  Vec3 hPi1_, hPi2_;
  double rhs_scale_;
  Mat3 mu_D1_R12_, mu_D2_R21_;
};

}  // namespace lgvi
