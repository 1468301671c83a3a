// The free rigid body in the harness (scene system "free-body").
#pragma once

#include <functional>
#include <sstream>
#include <utility>

#include <Eigen/Eigenvalues>

#include "experiments/systems/exact_reference.hpp"
#include "experiments/systems/attitude.hpp"
#include "lgvi/gravity_gradient_lgvi.hpp"
#include "lgvi/systems/gravity_gradient.hpp"
#include "lgvi/systems/pendulum.hpp"

namespace lgvi::experiments {

// The free body's scene model (a scene holds only the state and controls its system uses).
struct FreeBodyModel {
  using State = AttitudeInitial;
  static constexpr const char* name = "free-body";
  FreeRigidBody system;
  State initial;
  // (Defaults written out: the binding fills system and initial only.)
  std::optional<TimeControl> control = std::nullopt;  ///< body-frame moment
  std::optional<AttitudeFeedback> feedback = std::nullopt;  ///< body-frame moment tau(R, Omega) (instead of control)
  /// [parameters] orbit_rate: on a circular orbit, under the gravity-gradient moment
  /// (lgvi/systems/gravity_gradient.hpp).
  std::optional<GravityGradient> gravity_gradient = std::nullopt;
};

template <std::same_as<FreeBodyModel> BoundModel>
struct SystemBinding<BoundModel> : AttitudeBinding<FreeBodyModel> {
  static constexpr std::array<std::string_view, 3> kParameterKeys = {"inertia", "orbit_rate", "nonphysical_inertia"};
  /// No potential: the printed form is the symmetric one unless a control or the gravity
  /// gradient acts.
  static int printed_order(const FreeBodyModel& m) { return controlled(m) || m.gravity_gradient ? 1 : 2; }
  /// [parameters] inertia, and nonphysical_inertia (default false): true accepts principal
  /// moments that violate the triangle inequality (InertiaDomain::PositiveDefinite, e.g. the
  /// test sets' (2, 1, 2/3)); the momentum and the attitude are then those of the Euler equations
  /// R' = R hat(Omega), J Omega' = J Omega x Omega, not of any physical body.
  static FreeRigidBody read_parameters(const SceneReader& r, const SceneTable& parameters) {
    const Mat3 J = r.inertia(parameters, "inertia");
    const bool nonphysical = r.has(parameters, "nonphysical_inertia") && r.boolean(parameters, "nonphysical_inertia");
    FreeRigidBody body = r.physics("parameters.", [&] { return FreeRigidBody(J, InertiaDomain::PositiveDefinite); });
    if (!nonphysical && !body.inertia.physical) {
      const Eigen::SelfAdjointEigenSolver<Mat3> eig(body.inertia.J, Eigen::EigenvaluesOnly);
      const Vec3 moments = eig.eigenvalues();
      std::ostringstream s;
      s.precision(6);
      s << "violates the triangle inequality J1 + J2 >= J3 (principal moments " << moments(0) << ", " << moments(1)
        << ", " << moments(2) << "): no physical body has these moments; to integrate the Euler equations of this "
        << "inertia (a test-set body), set [parameters] nonphysical_inertia = true";
      r.fail("parameters.inertia", s.str());
    }
    return body;
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
    const baselines::AttitudeMechanicsWithMoment<FreeRigidBody> mech(
        m.system, std::move(control),
        [&m](double t, const Mat3& R, const Vec3& /*Omega*/) {
          return m.gravity_gradient->moment(m.system.inertia.J, R, t);
        },
        {.time = true, .rate = false});
    return chart(mech, std::array<Mat3, 1>{m.initial.R}, std::array<Vec3, 1>{m.initial.Omega},
                 baselines::Vector<0>(), baselines::Vector<0>());
  }
  /// The body as a 3D pendulum with rho = 0 and g = 0, whose moment m g rho x a and its
  /// derivatives vanish identically: the pendulum's LGVI and linearization (lgvi/ocp) are then
  /// the free body's (the sensitivity suite). Controls and orbit are left out.
  static Pendulum3D as_pendulum(const FreeBodyModel& m) {
    return Pendulum3D(1.0, m.system.inertia.J, Vec3::Zero(), 0.0, m.system.inertia.domain());
  }
  /// Replaces the inertia (the extremes suite's near-symmetric and near-flat bodies).
  static void set_inertia(FreeBodyModel& m, const Mat3& J) { m.system = FreeRigidBody(J); }
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
        baselines::FreeRigidBodyExact(m.system.inertia.J, m.initial.R, m.initial.Omega, m.system.inertia.domain()),
        kFreeBodyExactDescription);
  }
};

}  // namespace lgvi::experiments
