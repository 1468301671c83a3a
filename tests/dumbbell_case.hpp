// The dumbbell test scenario shared by the LGVI and baseline tests: the paper's circular orbit
// (section 3.1) perturbed off its relative equilibrium, with small smooth controls.
#pragma once

#include <cmath>

#include "lgvi/so3.hpp"
#include "lgvi/systems/dumbbell.hpp"

namespace lgvi::test {

/// Dumbbell near the paper's circular orbit (section 3.1), perturbed off the relative
/// equilibrium so that attitude and orbit both evolve.
inline Mat3 dumbbell_R0() {
  Mat3 R;
  R << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  return R * so3::exp(Vec3(0.1, -0.05, 0.2));
}
inline Vec3 dumbbell_x0() { return Vec3(1.0, 0.0, 0.0); }
inline Vec3 dumbbell_v0() { return Vec3(0.05, 0.95, 0.1); }
inline Vec3 dumbbell_Omega0() { return Vec3(0.1, -0.2, 1.3); }
inline DumbbellSpacecraft::Control dumbbell_control(double t) {
  DumbbellSpacecraft::Control u;
  u.force = Vec3(0.02 * std::sin(t), 0.01 * std::cos(2.0 * t), 0.015 * std::sin(0.5 * t));
  u.moment = Vec3(1e-3 * std::cos(t), 2e-3 * std::sin(1.5 * t), 1e-3 * std::sin(t + 1.0));
  return u;
}

}  // namespace lgvi::test
