// The 3D pendulum in the harness (scene system "pendulum").
#pragma once

#include "experiments/exact_reference.hpp"
#include "experiments/systems/attitude.hpp"

namespace lgvi::experiments {

template <>
struct SystemBinding<PendulumModel> : AttitudeBinding<PendulumModel> {
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
