// LGVIs of the multibody systems: the 3D pendulum on a cart (eqs. 29-37) and two bodies joined
// by a ball joint (eqs. 39-47). Both carry the discrete momenta as state (no mass-matrix solve in
// the recursion; velocities are recovered for output only) and solve their coupled implicit
// updates by Newton on SO(3)^N with the analytic Jacobian (lgvi/group_newton.hpp).
//
// Forms, as for the single bodies (lgvi/lgvi.hpp): the potential of eq. 29 is already split h/2
// at both ends of the step; LgviForm selects where the control impulse goes:
// Symmetric: h/2 u_k at the start and h/2 u_{k+1} at the end (second order with smooth controls);
// Printed: h u_{k+1} at the end, as eqs. 34-35 and 44-45 print it.
#pragma once

#include "lgvi/group_newton.hpp"
#include "lgvi/lgvi.hpp"
#include "lgvi/systems/cart_pendulum.hpp"
#include "lgvi/systems/connected_bodies.hpp"

namespace lgvi {

/// State of the cart-pendulum: attitude, cart position q = (x, y), discrete momenta Pi (body)
/// and p (cart), and the cached gravity moment at R.
struct CartPendulumState {
  Mat3 R = Mat3::Identity();
  Vec2 q = Vec2::Zero();
  Vec3 Pi = Vec3::Zero();
  Vec2 p = Vec2::Zero();
  Vec3 M = Vec3::Zero();
  /// Round-off carried from the attitude update R_{k+1} = R_k + R_k (F - I) (compensated
  /// summation; see CartPendulumLgvi::step).
  Mat3 R_compensation = Mat3::Zero();
};

/// As non_finite_part(const AttitudeState&) (lgvi.hpp).
inline const char* non_finite_part(const CartPendulumState& s) {
  if (!s.R.allFinite() || !s.R_compensation.allFinite()) return "R";
  if (!s.q.allFinite()) return "q (cart position)";
  if (!s.Pi.allFinite()) return "Pi (pendulum momentum)";
  if (!s.p.allFinite()) return "p (cart momentum)";
  if (!s.M.allFinite()) return "M (moment of the potential)";
  return nullptr;
}

/// The cart-pendulum LGVI. Derived from eq. 29 (see the .cpp for the derivation):
///   p^- = p_k + c0 u_k,
///   (M+m) dq = h p^- - m E^T R_k (F - I) d                                    (eqs. 30, 31)
///   vee(F J_d - J_d F^T) = h Pi_k + h^2/2 M_k - m d x R_k^T E dq              (eq. 32)
///   R_{k+1} = R_k F, q_{k+1} = q_k + dq                                        (eq. 33)
///   p_{k+1} = p^- + c1 u_{k+1}                                                 (eqs. 34, 35)
///   Pi_{k+1} = vee(J_d F - F^T J_d)/h + m/h d x R_{k+1}^T E dq + h/2 M_{k+1}   (eq. 36)
/// Substituting dq makes eq. 32 an equation in F alone, solved by Newton on SO(3).
class CartPendulumLgvi {
 public:
  using System = CartPendulum;
  using State = CartPendulumState;
  using Control = Vec2;
  static constexpr int potential_evaluations_per_step = 1;

  /// `compensated_attitude` false forms R_{k+1} = R_k + R_k (F - I) as a plain sum
  /// (RotationUpdateOptions::compensated_attitude: a degradation, for the gate's test only).
  explicit CartPendulumLgvi(const CartPendulum& system, LgviForm form = LgviForm::Symmetric,
                            GroupNewtonOptions options = {}, bool compensated_attitude = true)
      : system_(system), form_(form), options_(options), compensated_attitude_(compensated_attitude) {}

  /// From the paper's variables (eq. 37). Validates R orthonormal and finite values.
  State make_state(const Mat3& R, const Vec2& q, const Vec3& Omega, const Vec2& q_dot) const;
  void velocities(const State& s, Vec3& Omega, Vec2& q_dot) const {
    system_.velocities(s.R, s.Pi, s.p, Omega, q_dot);
  }

  RotationUpdateSummary step(const State& in, double h, const Control& u_k, const Control& u_k1,
                             State& out) const;

  /// Tangent w = [eta (3); dq (2); dPi (3); dp (2)] of a state (R -> R exp(hat eta), the rest added).
  using StateJacobian = Eigen::Matrix<double, 10, 10>;
  using ControlJacobian = Eigen::Matrix<double, 10, 2>;
  /// The step linearized at its converged result out = step(in, h, u_k, u_k1) (eq. 16):
  /// J_out_in = dw_{k+1}/dw_k, J_out_uk = dw_{k+1}/du_k, J_out_uk1 = dw_{k+1}/du_{k+1}, by the
  /// implicit-function theorem on the step's CartPendulumStepEquation (multibody_step_equations.hpp), its 3x3 system solved as
  /// `solve` says (LinearizationSolve: the same Jacobians to round-off). Allocates nothing.
  void linearize(const State& in, const State& out, double h, const Control& u_k, const Control& u_k1,
                 StateJacobian& J_out_in, ControlJacobian& J_out_uk, ControlJacobian& J_out_uk1,
                 LinearizationSolve solve = LinearizationSolve::PivotedLu) const;

  const CartPendulum& system() const { return system_; }
  LgviForm form() const { return form_; }

 private:
  const CartPendulum& system_;
  LgviForm form_;
  GroupNewtonOptions options_;
  bool compensated_attitude_ = true;
};

/// State of the connected bodies: attitudes and discrete body momenta.
struct ConnectedBodiesState {
  Mat3 R1 = Mat3::Identity(), R2 = Mat3::Identity();
  Vec3 Pi1 = Vec3::Zero(), Pi2 = Vec3::Zero();
};

/// As non_finite_part(const AttitudeState&) (lgvi.hpp).
inline const char* non_finite_part(const ConnectedBodiesState& s) {
  if (!s.R1.allFinite()) return "R1";
  if (!s.R2.allFinite()) return "R2";
  if (!s.Pi1.allFinite()) return "Pi1 (body 1 momentum)";
  if (!s.Pi2.allFinite()) return "Pi2 (body 2 momentum)";
  return nullptr;
}

/// The connected-bodies LGVI, from the reduced discrete Lagrangian (eq. 39 with the zero-total-
/// momentum constraint substituted; see the .cpp):
///   L_d = sum_i tr[(I - F_i) K_i]/h - mu/h a1 . a2,  a_i = R_i (F_i - I) d_i,
///   K_i = J_di - alpha_i m_i d_i d_i^T (the non-standard inertia of Jr_i),
/// giving, with Pi1^- = Pi1_k + c0 R1_k^T u_k, Pi2^- = Pi2_k - c0 R2_k^T u_k,
///   h Pi1^- = vee(F1 K1 - K1 F1^T) - mu d1 x R1_k^T a2                        (eq. 40)
///   h Pi2^- = vee(F2 K2 - K2 F2^T) - mu d2 x R2_k^T a1                        (eq. 41)
///   Pi1_{k+1} = vee(K1 F1 - F1^T K1)/h - mu/h d1 x R1_{k+1}^T a2 + c1 R1_{k+1}^T u_{k+1}  (eq. 44)
///   Pi2_{k+1} = vee(K2 F2 - F2^T K2)/h - mu/h d2 x R2_{k+1}^T a1 - c1 R2_{k+1}^T u_{k+1}  (eq. 45)
/// Eqs. 40-41 are solved jointly for (F1, F2) by Newton on the 6-vector.
class ConnectedBodiesLgvi {
 public:
  using System = ConnectedBodies;
  using State = ConnectedBodiesState;
  using Control = Vec3;
  static constexpr int potential_evaluations_per_step = 0;

  explicit ConnectedBodiesLgvi(const ConnectedBodies& system, LgviForm form = LgviForm::Symmetric,
                               GroupNewtonOptions options = {})
      : system_(system), form_(form), options_(options) {}

  State make_state(const Mat3& R1, const Mat3& R2, const Vec3& Omega1, const Vec3& Omega2) const;
  void velocities(const State& s, Vec3& Omega1, Vec3& Omega2) const {
    system_.velocities(s.R1, s.R2, s.Pi1, s.Pi2, Omega1, Omega2);
  }

  RotationUpdateSummary step(const State& in, double h, const Control& u_k, const Control& u_k1,
                             State& out) const;

  /// Tangent w = [eta1; eta2; dPi1; dPi2] of a state (R_i -> R_i exp(hat eta_i), Pi_i added).
  using StateJacobian = Eigen::Matrix<double, 12, 12>;
  using ControlJacobian = Eigen::Matrix<double, 12, 3>;
  /// The step linearized at its converged result out = step(in, h, u_k, u_k1), as
  /// CartPendulumLgvi::linearize, on the step's ConnectedBodiesStepEquation (its 6x6 system as
  /// `solve` says). Allocates nothing.
  void linearize(const State& in, const State& out, double h, const Control& u_k, const Control& u_k1,
                 StateJacobian& J_out_in, ControlJacobian& J_out_uk, ControlJacobian& J_out_uk1,
                 LinearizationSolve solve = LinearizationSolve::PivotedLu) const;

  const ConnectedBodies& system() const { return system_; }
  LgviForm form() const { return form_; }

 private:
  const ConnectedBodies& system_;
  LgviForm form_;
  GroupNewtonOptions options_;
};

static_assert(FlowMap<CartPendulumLgvi>);
static_assert(FlowMap<ConnectedBodiesLgvi>);

}  // namespace lgvi
