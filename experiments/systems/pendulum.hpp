// The 3D pendulum in the harness (scene system "pendulum").
#pragma once

#include "experiments/systems/exact_reference.hpp"
#include "experiments/systems/attitude.hpp"

namespace lgvi::experiments {

struct PendulumModel {
  using State = AttitudeInitial;
  static constexpr const char* name = "pendulum";
  Pendulum3D system;
  State initial;
  std::optional<TimeControl> control = std::nullopt;  ///< u of eq. 23; the applied moment is R^T e3 x u
  /// Instead of control: u = tau x R^T e3 with tau the feedback's moment, so that the applied
  /// moment R^T e3 x u is tau's part normal to the vertical (eq. 23's u cannot turn the pendulum
  /// about the vertical).
  std::optional<AttitudeFeedback> feedback = std::nullopt;
};

template <std::same_as<PendulumModel> BoundModel>
struct SystemBinding<BoundModel> : AttitudeBinding<PendulumModel> {
  static constexpr std::array<std::string_view, 4> kParameterKeys = {"mass", "inertia", "rho", "gravity"};
  /// The gravity moment acts at the printed step's end (eq. 22's impulse): first order.
  static int printed_order(const PendulumModel&) { return 1; }
  static Pendulum3D read_parameters(const SceneReader& r, const SceneTable& parameters) {
    const double mass = r.number(parameters, "mass");
    const Mat3 J = r.inertia(parameters, "inertia");
    const Vec3 rho = r.vec3(parameters, "rho");
    const double g = r.number(parameters, "gravity");
    return r.physics("parameters.", [&] { return Pendulum3D(mass, J, rho, g); });
  }
  static Conserved conserved(const PendulumModel& m, const State& s, double /*t*/) {
    return {m.system.energy(s.R, s.Omega), Vec3(m.system.vertical_momentum(s.R, s.Omega), 0.0, 0.0), 1};
  }
  /// The control u for the feedback moment tau(t, R, Omega): tau x R^T e3, whose moment R^T e3 x u
  /// is tau's part normal to the vertical (eq. 23's u cannot turn the pendulum about it).
  static Vec3 feedback_control(const PendulumModel& m, double t, const Mat3& R, const Vec3& Omega) {
    return m.feedback->moment(t, R, Omega).cross(R.row(2).transpose());
  }
  /// The pendulum itself (the free body's binding has its own: the sensitivity suite runs both).
  static const Pendulum3D& as_pendulum(const PendulumModel& m) { return m.system; }
  static MomentumMap momentum_map() { return {"vertical angular momentum e3^T R J Omega", {"vertical_momentum"}}; }
  static SystemLabels labels() {
    return {"time [s]", "|E - E_0| [J]", "|e_3^T R J Ω - (e_3^T R J Ω)_0| [kg m^2/s]", " s"};
  }
  /// The Lagrange top's closed form when uncontrolled and J is axisymmetric about rho (the free
  /// body's when there is no gravity torque); else nullopt and the reason. Throws InvalidInput
  /// for an initial state the closed form rejects.
  static std::optional<ExactReference> exact_solution(const PendulumModel& m, std::string& why_not) {
    if (controlled(m)) {
      why_not = "the pendulum is controlled";
      return std::nullopt;
    }
    if (!baselines::is_lagrange_top(m.system)) {
      why_not = "the pendulum is not a Lagrange top (J not axisymmetric about rho)";
      return std::nullopt;
    }
    baselines::LagrangeTopExact top(m.system, m.initial.R, m.initial.Omega);
    const char* description = top.is_free_body() ? kFreeBodyExactDescription : kLagrangeTopExactDescription;
    return ExactReference::of_attitude<PendulumModel>(std::move(top), description);
  }
};

}  // namespace lgvi::experiments
