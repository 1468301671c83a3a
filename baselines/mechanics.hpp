// Continuous equations of motion of the project's systems in the variables every coordinate
// model shares: attitudes R_i, other configuration variables x, and a velocity state w (body
// angular velocities and dx/dt for the single bodies; a multibody system may use momenta,
// recovering the velocities by solving its mass matrix, e.g. eq. 37 or eq. 47).
//
// The physics (inertia, moment M of eq. 13, control moments, forces) comes from lgvi/systems;
// what is written here is only the continuous-time form of the equations those systems'
// headers state:
//   free body, 3D pendulum (any AttitudeSystem):  J Omega' = J Omega x Omega + M(R) + tau(R, u)
//   dumbbell:  J Omega' = J Omega x Omega + M(R, x) + u^m,   m v' = f(R, x) + u^f,   x' = v.
//   cart-pendulum (momentum form, w = (Pi, p) of eq. 37):
//              [Omega; q'] = A(R)^{-1} w,  Pi' = Pi x Omega + M(R) + X_c,  p' = u
//   connected bodies (momentum form, w = (Pi1, Pi2) of eq. 47):
//              [Omega1; Omega2] = A(R1, R2)^{-1} w,  Pi_i' = Pi_i x Omega_i + X_i +- R_i^T u
//
// A mechanics type M (checked by the Mechanics concept) provides
//   bodies, positions, velocities          sizes N, NX, NW
//   rates(config, w, rates)                Omega_i and x' from the velocity state
//   acceleration(t, config, w)             w' (controls evaluated at t)
//   velocity_state(config, Omega, x_dot)   w from the paper's variables (initial state)
//   time_dependent()                       true when a control is set
// and optionally
//   rates_are_velocities = true            w = (Omega_1..Omega_N, x'): analytic rate Jacobian
//   velocity_jacobian(t, config, w)        d acceleration / dw, analytic (NW x NW)
//   acceleration(t, config, w, rates)      w' given rates(config, w) already computed (the
//                                          multibody momentum forms: their rates cost a
//                                          factorization of the mass matrix); see
//                                          acceleration_given_rates
//   max_invariants, invariants(config, w, g), invariant_names()
//                                          first integrals from the system's functions, kept by
//                                          cvode-bdf-projected (baselines/projection.hpp): the
//                                          free body, the pendulum, the dumbbell. The cart-pendulum
//                                          and the connected bodies have none here (the method
//                                          refuses them: model.hpp projection_refusal), nor has
//                                          AttitudeMechanicsWithMoment (its extra moment, PD
//                                          feedback or the orbit's gravity gradient, conserves none
//                                          of them).
//   generalized_force(t, config), separable()   a separable Hamiltonian's forces (below)
// The model layer (baselines/model.hpp) differentiates the rest by central differences.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <concepts>
#include <functional>
#include <utility>

#include "lgvi/lgvi.hpp"
#include "lgvi/so3.hpp"
#include "lgvi/systems/cart_pendulum.hpp"
#include "lgvi/systems/connected_bodies.hpp"
#include "lgvi/systems/dumbbell.hpp"
#include "lgvi/types.hpp"

namespace lgvi::baselines {

template <int Rows>
using Vector = Eigen::Matrix<double, Rows, 1>;

/// Configuration: N attitudes and NX further coordinates (dumbbell position, cart position).
template <int N, int NX>
struct Configuration {
  std::array<Mat3, N> R;
  Vector<NX> x = Vector<NX>::Zero();
};

/// The velocities the kinematics need: body angular velocities and x'.
template <int N, int NX>
struct Rates {
  std::array<Vec3, N> Omega;
  Vector<NX> x_dot = Vector<NX>::Zero();
};

template <class M>
concept Mechanics = requires(const M& m, double t, const typename M::Config& c, const typename M::Velocity& w,
                             typename M::Rate& r, const std::array<Vec3, M::bodies>& Omega,
                             const Vector<M::positions>& x_dot) {
  { M::bodies } -> std::convertible_to<int>;
  { M::positions } -> std::convertible_to<int>;
  { M::velocities } -> std::convertible_to<int>;
  requires std::same_as<typename M::Config, Configuration<M::bodies, M::positions>>;
  requires std::same_as<typename M::Rate, Rates<M::bodies, M::positions>>;
  requires std::same_as<typename M::Velocity, Vector<M::velocities>>;
  m.rates(c, w, r);
  { m.acceleration(t, c, w) } -> std::same_as<typename M::Velocity>;
  { m.velocity_state(c, Omega, x_dot) } -> std::same_as<typename M::Velocity>;
  { m.time_dependent() } -> std::convertible_to<bool>;
};

/// A single body whose Hamiltonian is separable, H = 1/2 Pi . J^{-1} Pi (+ 1/2 m |v|^2) +
/// U(R, x, t): the free rigid body, the 3D pendulum and Lagrange top, the dumbbell (the cart and
/// the connected bodies have a configuration-dependent mass matrix). w = (Omega, v), and
/// generalized_force(t, config) is the moment and force of the potential and the controls in
/// the momenta's equations, (J Omega)' = J Omega x Omega + F_rot, (m v)' = F_trans: the kicks of
/// the splitting methods (baselines/splitting.hpp). separable() is false where an extra moment
/// depends on the rate (the scenes' PD feedback): no kick can carry it.
template <class M>
concept SeparableMechanics =
    Mechanics<M> && M::bodies == 1 && M::rates_are_velocities &&
    requires(const M& m, double t, const typename M::Config& c) {
      { m.generalized_force(t, c) } -> std::same_as<typename M::Velocity>;
      { m.separable() } -> std::convertible_to<bool>;
      { m.system().inertia } -> std::convertible_to<Inertia>;
    } && (M::positions == 0 || requires(const M& m) { { m.system().mass } -> std::convertible_to<double>; });

/// Euler's equation with the potential's moment and the control moment of an attitude system
/// (free rigid body, 3D pendulum): w = Omega,
///     Omega' = J^{-1} (J Omega x Omega + M(R) + tau(R, u(t))),
/// with M = system.moment (eq. 13) and tau = system.control_moment (the pendulum's R^T e3 x u).
/// Holds the system by reference (it must outlive the mechanics).
template <AttitudeSystem S>
class AttitudeMechanics {
 public:
  static constexpr int bodies = 1;
  static constexpr int positions = 0;
  static constexpr int velocities = 3;
  static constexpr bool rates_are_velocities = true;
  using System = S;
  using Control = typename S::Control;
  using Config = Configuration<1, 0>;
  using Rate = Rates<1, 0>;
  using Velocity = Vector<3>;

  /// `control` may be empty (no control).
  explicit AttitudeMechanics(const S& system, std::function<Control(double)> control = {})
      : system_(system), control_(std::move(control)) {}

  void rates(const Config& /*c*/, const Velocity& w, Rate& r) const { r.Omega[0] = w; }

  Velocity acceleration(double t, const Config& c, const Velocity& w) const {
    const Mat3& J = system_.inertia.J;
    Vec3 torque = (J * w).cross(w) + system_.moment(c.R[0]);
    if (control_) torque += system_.control_moment(c.R[0], control_(t));
    return system_.inertia.J_inverse * torque;
  }

  /// J^{-1} (hat(J Omega) - hat(Omega) J): the derivative of J^{-1}(J Omega x Omega).
  Mat3 velocity_jacobian(double /*t*/, const Config& /*c*/, const Velocity& w) const {
    const Mat3& J = system_.inertia.J;
    return system_.inertia.J_inverse * (so3::hat(J * w) - so3::hat(w) * J);
  }

  Velocity velocity_state(const Config& /*c*/, const std::array<Vec3, 1>& Omega, const Vector<0>& /*x_dot*/) const {
    return Omega[0];
  }
  /// M(R) + tau(R, u(t)) (SeparableMechanics).
  Velocity generalized_force(double t, const Config& c) const {
    Vec3 moment = system_.moment(c.R[0]);
    if (control_) moment += system_.control_moment(c.R[0], control_(t));
    return moment;
  }
  bool separable() const { return true; }
  bool time_dependent() const { return static_cast<bool>(control_); }
  /// True when neither rates() nor acceleration() reads the attitude: a system without a
  /// potential (S::has_potential false: its moment is zero, the count the LGVI reports as no
  /// potential evaluation) and no control. The Lie group methods then form no stage attitudes
  /// (baselines/lie_group.hpp, field_reads_attitudes).
  bool attitude_unread() const { return !S::has_potential && !control_; }
  const S& system() const { return system_; }

  /// First integrals the projection of cvode-bdf-projected keeps (baselines/projection.hpp), from
  /// the system's own functions:
  ///   energy E = system.energy(R, Omega), when uncontrolled (a control does work);
  ///   the free body's Casimir |Pi| (Pi = J Omega) as the norm of FreeRigidBody::spatial_momentum
  ///   R J Omega (equal for R in SO(3)), when uncontrolled (a moment turns Pi);
  ///   the pendulum's vertical momentum e3^T R J Omega (Pendulum3D::vertical_momentum), with or
  ///   without control (its control moment R^T e3 x u has no vertical component).
  /// Writes them into g and returns how many (the same for every state of a run).
  static constexpr int max_invariants = 2;
  int invariants(const Config& c, const Velocity& w, double* g) const {
    const Mat3& R = c.R[0];
    int k = 0;
    if (!control_) g[k++] = system_.energy(R, w);
    if constexpr (requires { system_.vertical_momentum(R, w); }) {
      g[k++] = system_.vertical_momentum(R, w);
    } else if constexpr (!S::has_potential && requires { system_.spatial_momentum(R, w); }) {
      if (!control_) g[k++] = system_.spatial_momentum(R, w).norm();
    }
    return k;
  }
  /// The invariants() in words, and what is left out.
  std::string invariant_names() const {
    std::string names = control_ ? "" : "E = E_0";
    if constexpr (requires(const Mat3& R, const Vec3& w) { system_.vertical_momentum(R, w); }) {
      names += std::string(names.empty() ? "" : ", ") + "e3.(R J Omega) = its initial value";
    } else if constexpr (!S::has_potential &&
                         requires(const Mat3& R, const Vec3& w) { system_.spatial_momentum(R, w); }) {
      if (!control_) names += ", |Pi| = |Pi_0|";
    }
    if (control_) names += std::string(names.empty() ? "" : "; ") + "no energy (controlled)";
    return names;
  }

 private:
  const S& system_;
  std::function<Control(double)> control_;
};

/// An attitude system's mechanics with an extra body-frame moment tau_e(t, R, Omega) (one
/// wrapper for "a system plus an extra moment"):
///     Omega' = J^{-1} (J Omega x Omega + M(R) + tau(R, u(t)) + tau_e(t, R, Omega)).
/// The scenes' PD attitude feedback (tau_e = tau(R, law(R, Omega)), lgvi/feedback_lgvi.hpp) and
/// the gravity-gradient moment of a body on a circular orbit (tau_e = 3 n^2 c x J c,
/// c = R^T r(t), lgvi/gravity_gradient_lgvi.hpp) are two such moments. The velocity Jacobian adds
/// tau_e's derivative in Omega by central differences when it depends on the rate (exact up to
/// rounding for a moment affine in Omega, as the PD law is); the attitude part comes from the
/// coordinate model's differences of the acceleration.
template <AttitudeSystem S>
class AttitudeMechanicsWithMoment {
 public:
  using Base = AttitudeMechanics<S>;
  static constexpr int bodies = Base::bodies;
  static constexpr int positions = Base::positions;
  static constexpr int velocities = Base::velocities;
  static constexpr bool rates_are_velocities = Base::rates_are_velocities;
  using System = S;
  using Control = typename S::Control;
  using Config = typename Base::Config;
  using Rate = typename Base::Rate;
  using Velocity = typename Base::Velocity;
  using Moment = std::function<Vec3(double t, const Mat3& R, const Vec3& Omega)>;
  /// What tau_e depends on besides R: time (the run is then time-dependent) and the rate Omega
  /// (its derivative then enters the velocity Jacobian).
  struct Dependence {
    bool time = false;
    bool rate = false;
  };

  /// `control` may be empty (no control). Holds the system by reference.
  AttitudeMechanicsWithMoment(const S& system, std::function<Control(double)> control, Moment moment,
                              Dependence depends)
      : base_(system, std::move(control)), moment_(std::move(moment)), depends_(depends) {}

  void rates(const Config& c, const Velocity& w, Rate& r) const { base_.rates(c, w, r); }
  Velocity acceleration(double t, const Config& c, const Velocity& w) const {
    return base_.acceleration(t, c, w) + moment_acceleration(t, c.R[0], w);
  }
  Mat3 velocity_jacobian(double t, const Config& c, const Velocity& w) const {
    Mat3 A = base_.velocity_jacobian(t, c, w);
    if (!depends_.rate) return A;
    for (int k = 0; k < 3; ++k) {
      const double a = 1e-6 * std::max(1.0, std::abs(w(k)));
      Vec3 plus = w, minus = w;
      plus(k) += a;
      minus(k) -= a;
      A.col(k) += (moment_acceleration(t, c.R[0], plus) - moment_acceleration(t, c.R[0], minus)) / (2.0 * a);
    }
    return A;
  }
  Velocity velocity_state(const Config& c, const std::array<Vec3, 1>& Omega, const Vector<0>& x_dot) const {
    return base_.velocity_state(c, Omega, x_dot);
  }
  /// M(R) + tau(R, u(t)) + tau_e(t, R) (SeparableMechanics); only where tau_e does not depend on
  /// the rate (separable()).
  Velocity generalized_force(double t, const Config& c) const {
    return base_.generalized_force(t, c) + moment_(t, c.R[0], Vec3::Zero());
  }
  bool separable() const { return !depends_.rate; }
  bool time_dependent() const { return depends_.time || base_.time_dependent(); }
  const S& system() const { return base_.system(); }

 private:
  Vec3 moment_acceleration(double t, const Mat3& R, const Vec3& Omega) const {
    return base_.system().inertia.J_inverse * moment_(t, R, Omega);
  }

  Base base_;
  Moment moment_;
  Dependence depends_;
};

/// A rigid body on SE(3) (the dumbbell, the potential body on SE(3)): x, v inertial, w = (Omega, v),
///     Omega' = J^{-1} (J Omega x Omega + M(R, x) + u^m(t)),   v' = (f(R, x) + u^f(t)) / m,
/// with f and M from the system's forces(R, x) (one evaluation gives both).
template <RigidBodySystem S>
class RigidBodyMechanics {
 public:
  static constexpr int bodies = 1;
  static constexpr int positions = 3;
  static constexpr int velocities = 6;
  static constexpr bool rates_are_velocities = true;
  using System = S;
  using Control = Wrench;
  using Config = Configuration<1, 3>;
  using Rate = Rates<1, 3>;
  using Velocity = Vector<6>;

  explicit RigidBodyMechanics(const S& system, std::function<Control(double)> control = {})
      : system_(system), control_(std::move(control)) {}

  void rates(const Config& /*c*/, const Velocity& w, Rate& r) const {
    r.Omega[0] = w.head<3>();
    r.x_dot = w.tail<3>();
  }

  Velocity acceleration(double t, const Config& c, const Velocity& w) const {
    const Wrench f = system_.forces(c.R[0], c.x);
    const Mat3& J = system_.inertia.J;
    const Vec3 Omega = w.head<3>();
    Vec3 torque = (J * Omega).cross(Omega) + f.moment;
    Vec3 force = f.force;
    if (control_) {
      const Control u = control_(t);
      torque += u.moment;
      force += u.force;
    }
    Velocity a;
    a.head<3>() = system_.inertia.J_inverse * torque;
    a.tail<3>() = force / system_.mass;
    return a;
  }

  Eigen::Matrix<double, 6, 6> velocity_jacobian(double /*t*/, const Config& /*c*/, const Velocity& w) const {
    const Mat3& J = system_.inertia.J;
    const Vec3 Omega = w.head<3>();
    Eigen::Matrix<double, 6, 6> D = Eigen::Matrix<double, 6, 6>::Zero();
    D.topLeftCorner<3, 3>() = system_.inertia.J_inverse * (so3::hat(J * Omega) - so3::hat(Omega) * J);
    return D;
  }

  Velocity velocity_state(const Config& /*c*/, const std::array<Vec3, 1>& Omega, const Vector<3>& x_dot) const {
    Velocity w;
    w << Omega[0], x_dot;
    return w;
  }
  /// (M(R, x) + u^m(t), f(R, x) + u^f(t)) (SeparableMechanics).
  Velocity generalized_force(double t, const Config& c) const {
    const Wrench f = system_.forces(c.R[0], c.x);
    Velocity F;
    F << f.moment, f.force;
    if (control_) {
      const Control u = control_(t);
      F.head<3>() += u.moment;
      F.tail<3>() += u.force;
    }
    return F;
  }
  bool separable() const { return true; }
  bool time_dependent() const { return static_cast<bool>(control_); }
  const S& system() const { return system_; }

  /// The first integral the projection of cvode-bdf-projected keeps (baselines/projection.hpp):
  /// the energy S::energy(R, x, Omega, v), when uncontrolled. Only the energy: an angular momentum
  /// (S::angular_momentum) is conserved too, but the projection is
  /// scoped to the energy here (its 3 components would make 5 constraints on the 13 states).
  static constexpr int max_invariants = 1;
  int invariants(const Config& c, const Velocity& w, double* g) const {
    if (control_) return 0;
    g[0] = system_.energy(c.R[0], c.x, w.head<3>(), w.tail<3>());
    return 1;
  }
  std::string invariant_names() const { return control_ ? "no energy (controlled)" : "E = E_0"; }

 private:
  const S& system_;
  std::function<Control(double)> control_;
};

/// The dumbbell spacecraft's mechanics (section 3.1).
using DumbbellMechanics = RigidBodyMechanics<DumbbellSpacecraft>;

/// The 3D pendulum on a cart, SO(3) x R^2, in momentum form w = (Pi, p): the mass matrix of
/// eq. 37 is factored (Cholesky, CartPendulum::velocities) at every evaluation of the rates and
/// of the acceleration, and the rates of the momenta are CartPendulum::momentum_rate:
///     [Omega; q'] = A(R)^{-1} [Pi; p],   Pi' = Pi x Omega + M(R) + m (Omega x d) x R^T E q',   p' = u(t).
/// Why momenta: they are the LGVI's state too, p is constant without control (p' = 0 exactly,
/// so every solver keeps it to round-off), and no derivative of A(R) is needed. Off SO(3) (the
/// quaternion and matrix models) the same formulas are evaluated with R as it is.
class CartPendulumMechanics {
 public:
  static constexpr int bodies = 1;
  static constexpr int positions = 2;
  static constexpr int velocities = 5;
  using System = CartPendulum;
  using Control = CartPendulum::Control;
  using Config = Configuration<1, 2>;
  using Rate = Rates<1, 2>;
  using Velocity = Vector<5>;

  explicit CartPendulumMechanics(const CartPendulum& system, std::function<Control(double)> control = {})
      : system_(system), control_(std::move(control)) {}

  void rates(const Config& c, const Velocity& w, Rate& r) const {
    system_.velocities(c.R[0], w.head<3>(), w.tail<2>(), r.Omega[0], r.x_dot);
  }

  Velocity acceleration(double t, const Config& c, const Velocity& w) const {
    Rate r;
    rates(c, w, r);
    return acceleration(t, c, w, r);
  }
  /// The same given r = rates(c, w) (one factorization of the mass matrix per evaluation).
  Velocity acceleration(double t, const Config& c, const Velocity& w, const Rate& r) const {
    const Control u = control_ ? control_(t) : Control::Zero();
    Vec3 Pi_dot;
    Vec2 p_dot;
    system_.momentum_rate(c.R[0], r.Omega[0], r.x_dot, w.head<3>(), u, Pi_dot, p_dot);
    Velocity a;
    a << Pi_dot, p_dot;
    return a;
  }

  Velocity velocity_state(const Config& c, const std::array<Vec3, 1>& Omega, const Vector<2>& x_dot) const {
    Vec3 Pi;
    Vec2 p;
    system_.momenta(c.R[0], Omega[0], x_dot, Pi, p);
    Velocity w;
    w << Pi, p;
    return w;
  }
  bool time_dependent() const { return static_cast<bool>(control_); }
  const CartPendulum& system() const { return system_; }

 private:
  const CartPendulum& system_;
  std::function<Control(double)> control_;
};

/// Two bodies joined by a ball joint, SO(3) x SO(3), in momentum form w = (Pi1, Pi2): the mass
/// matrix of eq. 47 (blocks J_i + alpha_i m_i hat(d_i)^2, coupling mu hat(d1) R1^T R2 hat(d2))
/// is factored (Cholesky, ConnectedBodies::velocities) at every evaluation, and
///     Pi1' = Pi1 x Omega1 + X1 + R1^T u(t),   Pi2' = Pi2 x Omega2 + X2 - R2^T u(t)
/// (ConnectedBodies::momentum_rate, X_i its coupling moments).
class ConnectedBodiesMechanics {
 public:
  static constexpr int bodies = 2;
  static constexpr int positions = 0;
  static constexpr int velocities = 6;
  using System = ConnectedBodies;
  using Control = ConnectedBodies::Control;
  using Config = Configuration<2, 0>;
  using Rate = Rates<2, 0>;
  using Velocity = Vector<6>;

  explicit ConnectedBodiesMechanics(const ConnectedBodies& system, std::function<Control(double)> control = {})
      : system_(system), control_(std::move(control)) {}

  void rates(const Config& c, const Velocity& w, Rate& r) const {
    system_.velocities(c.R[0], c.R[1], w.head<3>(), w.tail<3>(), r.Omega[0], r.Omega[1]);
  }

  Velocity acceleration(double t, const Config& c, const Velocity& w) const {
    Rate r;
    rates(c, w, r);
    return acceleration(t, c, w, r);
  }
  /// The same given r = rates(c, w) (one factorization of the mass matrix per evaluation).
  Velocity acceleration(double t, const Config& c, const Velocity& w, const Rate& r) const {
    const Control u = control_ ? control_(t) : Control::Zero();
    Vec3 Pi1_dot, Pi2_dot;
    system_.momentum_rate(c.R[0], c.R[1], r.Omega[0], r.Omega[1], w.head<3>(), w.tail<3>(), u, Pi1_dot, Pi2_dot);
    Velocity a;
    a << Pi1_dot, Pi2_dot;
    return a;
  }

  Velocity velocity_state(const Config& c, const std::array<Vec3, 2>& Omega, const Vector<0>& /*x_dot*/) const {
    Vec3 Pi1, Pi2;
    system_.momenta(c.R[0], c.R[1], Omega[0], Omega[1], Pi1, Pi2);
    Velocity w;
    w << Pi1, Pi2;
    return w;
  }
  bool time_dependent() const { return static_cast<bool>(control_); }
  const ConnectedBodies& system() const { return system_; }

 private:
  const ConnectedBodies& system_;
  std::function<Control(double)> control_;
};

static_assert(Mechanics<CartPendulumMechanics>);
static_assert(Mechanics<ConnectedBodiesMechanics>);
static_assert(SeparableMechanics<DumbbellMechanics> && SeparableMechanics<RigidBodyMechanics<PotentialBodySE3>> && !SeparableMechanics<CartPendulumMechanics> &&
              !SeparableMechanics<ConnectedBodiesMechanics>);

/// w' at (t, c, w) given r = m.rates(c, w), the same as m.acceleration(t, c, w) to the bit:
/// through the mechanics' acceleration(t, c, w, r) where it has one, so that an evaluation of the
/// equations (a right-hand side, a Lie group method's stage) factors a multibody system's mass
/// matrix once, not twice.
template <Mechanics M>
typename M::Velocity acceleration_given_rates(const M& m, double t, const typename M::Config& c,
                                              const typename M::Velocity& w, const typename M::Rate& r) {
  if constexpr (requires { { m.acceleration(t, c, w, r) } -> std::same_as<typename M::Velocity>; }) {
    return m.acceleration(t, c, w, r);
  } else {
    return m.acceleration(t, c, w);
  }
}

/// The state of a one-step method over continuous mechanics Mech (the Lie group methods of
/// baselines/lie_group.hpp, the harness's one-step driver): the configuration (attitudes R_i,
/// positions x) and the velocity state w (body angular velocities and x', or the momenta of a
/// multibody system's momentum form).
template <Mechanics Mech>
struct MechanicsState {
  typename Mech::Config config;
  typename Mech::Velocity w;
};

/// A state with a non-finite entry names it (lgvi::integrate() stops there; argument-dependent
/// lookup).
template <Mechanics Mech>
const char* non_finite_part(const MechanicsState<Mech>& s) {
  for (const Mat3& R : s.config.R) {
    if (!R.allFinite()) return "R";
  }
  if (!s.config.x.allFinite()) return "x";
  if (!s.w.allFinite()) return "the velocity state";
  return nullptr;
}

}  // namespace lgvi::baselines
