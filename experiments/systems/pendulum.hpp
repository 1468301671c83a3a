// The 3D pendulum in the harness (scene system "pendulum").
#pragma once

#include "experiments/systems/attitude.hpp"

namespace lgvi::experiments {

template <>
struct SystemBinding<PendulumModel> : AttitudeBinding<PendulumModel> {
  static Conserved conserved(const PendulumModel& m, const Sample& s) {
    return {m.system.energy(s.R, s.Omega), Vec3(m.system.vertical_momentum(s.R, s.Omega), 0.0, 0.0), 1};
  }
  static MomentumMap momentum_map() { return {"vertical angular momentum e3^T R J Omega", {"vertical_momentum"}}; }
  static SystemLabels labels() {
    return {"time [s]", "|E - E_0| [J]", "|e_3^T R J Ω - (e_3^T R J Ω)_0| [kg m^2/s]"};
  }
};

}  // namespace lgvi::experiments
