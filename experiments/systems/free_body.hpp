// The free rigid body in the harness (scene system "free-body").
#pragma once

#include "experiments/exact_reference.hpp"
#include "experiments/systems/attitude.hpp"

namespace lgvi::experiments {

template <>
struct SystemBinding<FreeBodyModel> : AttitudeBinding<FreeBodyModel> {
  static constexpr std::array<std::string_view, 1> kParameterKeys = {"inertia"};
  /// No potential: the printed form is the symmetric one unless a control acts.
  static int printed_order(const FreeBodyModel& m) { return controlled(m) ? 1 : 2; }
  static FreeRigidBody read_parameters(const SceneReader& r, const SceneTable& parameters) {
    const Mat3 J = r.inertia(parameters, "inertia");
    return r.physics("parameters.", [&] { return FreeRigidBody(J); });
  }
  static Conserved conserved(const FreeBodyModel& m, const State& s) {
    return {m.system.energy(s.R, s.Omega), m.system.spatial_momentum(s.R, s.Omega), 3};
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
    return ExactReference::of_attitude<FreeBodyModel>(
        baselines::FreeRigidBodyExact(m.system.inertia.J, m.initial.R, m.initial.Omega), kFreeBodyExactDescription);
  }
};

}  // namespace lgvi::experiments
