// The free rigid body in the harness (scene system "free-body").
#pragma once

#include <functional>
#include <utility>

#include "experiments/exact_reference.hpp"
#include "experiments/systems/attitude.hpp"

namespace lgvi::experiments {

/// The control of a flow whose potential depends on time: the control moment u(t) and t itself,
/// so that a step knows the times of its ends (integrate() and the compositions sample controls
/// at the ends of each step and substep).
struct TimedMoment {
  Vec3 u = Vec3::Zero();
  double t = 0.0;
};

/// The free body's LGVI on a circular orbit. The gravity-gradient potential V(R, t)
/// (lgvi/systems/gravity_gradient.hpp) enters as a potential does in eqs. 13-14, through its
/// moment with the form's impulse weights: c0 M(R_k, t_k) and c1 M(R_{k+1}, t_{k+1}) (symmetric:
/// h/2, h/2, the discrete Lagrangian's trapezoidal V(R_k, t_k) + V(R_{k+1}, t_{k+1}); printed:
/// 0, h). The state keeps M(R_k, t_k) in AttitudeState::M, from which the base step takes its start
/// impulse; the end impulse depends on R_{k+1} alone (not on Pi_{k+1}), so it is added after the
/// rotation update, explicitly: one gravity-gradient evaluation per step. In the frame turning
/// with the orbit the discrete Lagrangian does not depend on k (R_k^T R_{k+1} = Q_k^T exp(n h
/// hat(e3)) Q_{k+1}), so the map is a variational integrator of an autonomous system there: its
/// Jacobi integral stays bounded (tests/experiments/gravity_gradient_test.cpp).
class GravityGradientLgvi {
 public:
  using State = AttitudeState;
  using Control = TimedMoment;
  static constexpr int potential_evaluations_per_step = 1;

  GravityGradientLgvi(const AttitudeLgvi<FreeRigidBody>& lgvi, const GravityGradient& gravity)
      : lgvi_(lgvi), gravity_(gravity) {}

  /// The state at (R, Omega) at time t, with the gravity-gradient moment there.
  State make_state(const Mat3& R, const Vec3& Omega, double t) const {
    State s = lgvi_.make_state(R, Omega);
    s.M = gravity_.moment(lgvi_.system().inertia.J, R, t);
    return s;
  }

  /// One step from t_k = u_k.t to t_{k+1} = u_k1.t; `in.M` must be the moment at (in.R, t_k).
  RotationUpdateSummary step(const State& in, double h, const Control& u_k, const Control& u_k1, State& out) const {
    const RotationUpdateSummary summary = lgvi_.step(in, h, u_k.u, u_k1.u, out);
    if (!summary.converged()) return summary;
    out.M = gravity_.moment(lgvi_.system().inertia.J, out.R, u_k1.t);
    out.Pi += impulse_weights(lgvi_.form(), h).end * out.M;
    return summary;
  }

  LgviForm form() const { return lgvi_.form(); }
  const FreeRigidBody& system() const { return lgvi_.system(); }
  Vec3 omega(const State& s) const { return lgvi_.omega(s); }

 private:
  const AttitudeLgvi<FreeRigidBody>& lgvi_;
  GravityGradient gravity_;
};

/// The baselines' side: Euler's equation with the gravity-gradient moment added,
/// Omega' = J^{-1} (J Omega x Omega + u(t) + 3 n^2 c x J c), c = R^T r_hat(t). The velocity
/// Jacobian is the free body's (the moment does not depend on Omega); the attitude part comes
/// from CoordinateOde's differences of the acceleration.
class GravityGradientMechanics : public baselines::AttitudeMechanics<FreeRigidBody> {
 public:
  GravityGradientMechanics(const FreeRigidBody& body, std::function<Vec3(double)> control,
                           const GravityGradient& gravity)
      : AttitudeMechanics(body, std::move(control)), gravity_(gravity) {}

  Velocity acceleration(double t, const Config& c, const Velocity& w) const {
    const Inertia& inertia = system().inertia;
    return AttitudeMechanics::acceleration(t, c, w) + inertia.J_inverse * gravity_.moment(inertia.J, c.R[0], t);
  }
  bool time_dependent() const { return true; }

 private:
  GravityGradient gravity_;
};

template <>
struct SystemBinding<FreeBodyModel> : AttitudeBinding<FreeBodyModel> {
  static constexpr std::array<std::string_view, 2> kParameterKeys = {"inertia", "orbit_rate"};
  /// No potential: the printed form is the symmetric one unless a control or the gravity
  /// gradient acts.
  static int printed_order(const FreeBodyModel& m) { return controlled(m) || m.gravity_gradient ? 1 : 2; }
  static FreeRigidBody read_parameters(const SceneReader& r, const SceneTable& parameters) {
    const Mat3 J = r.inertia(parameters, "inertia");
    return r.physics("parameters.", [&] { return FreeRigidBody(J); });
  }
  /// AttitudeBinding's model, and the orbit when [parameters] has orbit_rate.
  static FreeBodyModel read(const SceneReader& r, const SceneTable& parameters, const SceneTable& initial,
                            const std::optional<SceneTable>& control) {
    FreeBodyModel m = AttitudeBinding<FreeBodyModel>::read(r, parameters, initial, control);
    if (r.has(parameters, "orbit_rate")) {
      const double n = r.number(parameters, "orbit_rate");
      m.gravity_gradient = r.physics("parameters.", [&] { return GravityGradient(n); });
      if (m.feedback) {
        r.fail("control.type", "type \"pd\" is not available with parameters.orbit_rate (the feedback LGVI has no "
                               "time-dependent potential)");
      }
    }
    return m;
  }
  /// The energy, or on an orbit the Jacobi integral (the conserved one; the energy is not).
  static Conserved conserved(const FreeBodyModel& m, const State& s, double t) {
    const double energy = m.gravity_gradient
                              ? m.gravity_gradient->jacobi_integral(m.system.inertia.J, s.R, s.Omega, t)
                              : m.system.energy(s.R, s.Omega);
    return {energy, m.system.spatial_momentum(s.R, s.Omega), 3};
  }

  template <class Drive>
  static Stats run_lgvi(const FreeBodyModel& m, LgviForm form, const RotationUpdateOptions& options, Drive&& drive) {
    if (!m.gravity_gradient) return AttitudeBinding::run_lgvi(m, form, options, std::forward<Drive>(drive));
    const AttitudeLgvi<FreeRigidBody> lgvi(m.system, form, options);
    const GravityGradientLgvi orbit(lgvi, *m.gravity_gradient);
    AttitudeState state = orbit.make_state(m.initial.R, m.initial.Omega, 0.0);
    const auto control = [&m](double t) { return TimedMoment{m.control ? (*m.control)(t) : Vec3::Zero(), t}; };
    const auto to_state = [&](const AttitudeState& s, State& out) {
      out.R = s.R;
      out.Omega = lgvi.omega(s);
    };
    return drive(orbit, state, control, to_state);
  }
  template <class Chart>
  static Stats run_baseline(const FreeBodyModel& m, Chart&& chart) {
    if (!m.gravity_gradient) return AttitudeBinding::run_baseline(m, std::forward<Chart>(chart));
    std::function<Vec3(double)> control;
    if (m.control) control = [&m](double t) -> Vec3 { return (*m.control)(t); };
    const GravityGradientMechanics mech(m.system, std::move(control), *m.gravity_gradient);
    return chart(mech, std::array<Mat3, 1>{m.initial.R}, std::array<Vec3, 1>{m.initial.Omega},
                 baselines::Vector<0>(), baselines::Vector<0>());
  }
  static MomentumMap momentum_map() {
    return {"spatial angular momentum R J Omega", {"spatial_momentum1", "spatial_momentum2", "spatial_momentum3"}};
  }
  static SystemLabels labels() { return {"time [s]", "|E - E_0| [J]", "|R J Ω - (R J Ω)_0| [kg m^2/s]", " s"}; }
  /// The closed form (Celledoni et al. 2008) when uncontrolled; else nullopt and the reason.
  /// Throws InvalidInput for an initial state the closed form rejects (a separatrix).
  static std::optional<ExactReference> exact_solution(const FreeBodyModel& m, std::string& why_not) {
    if (controlled(m)) {
      why_not = "the free body is controlled";
      return std::nullopt;
    }
    if (m.gravity_gradient) {
      why_not = "the free body is under the gravity-gradient moment";
      return std::nullopt;
    }
    return ExactReference::of_attitude<FreeBodyModel>(
        baselines::FreeRigidBodyExact(m.system.inertia.J, m.initial.R, m.initial.Omega), kFreeBodyExactDescription);
  }
};

}  // namespace lgvi::experiments
