// The free rigid body in the harness (scene system "free-body").
#pragma once

#include "experiments/systems/attitude.hpp"

namespace lgvi::experiments {

template <>
struct SystemBinding<FreeBodyModel> : AttitudeBinding<FreeBodyModel> {
  static Conserved conserved(const FreeBodyModel& m, const Sample& s) {
    return {m.system.energy(s.R, s.Omega), m.system.spatial_momentum(s.R, s.Omega), 3};
  }
  static MomentumMap momentum_map() {
    return {"spatial angular momentum R J Omega", {"spatial_momentum1", "spatial_momentum2", "spatial_momentum3"}};
  }
  static SystemLabels labels() { return {"time [s]", "|E - E_0| [J]", "|R J Ω - (R J Ω)_0| [kg m^2/s]"}; }
};

}  // namespace lgvi::experiments
