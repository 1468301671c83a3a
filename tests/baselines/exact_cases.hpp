// The two cases with closed-form solutions the one-step methods' order tests use
// (test_lie_group.cpp, test_splitting.cpp; the cases of test_exact.cpp): the free body around its
// largest axis and the Lagrange top spun from hanging.
#pragma once

#include <array>

#include "baselines/exact/free_rigid_body_exact.hpp"
#include "baselines/exact/lagrange_top.hpp"
#include "baselines/mechanics.hpp"
#include "lgvi/so3.hpp"
#include "lgvi/systems/free_rigid_body.hpp"
#include "lgvi/systems/pendulum.hpp"
#include "lgvi/types.hpp"

namespace lgvi::test::exact_cases {

inline const Mat3& free_J() {
  static const Mat3 J = Vec3(0.13, 0.28, 0.17).asDiagonal();
  return J;
}
inline const Mat3& free_R0() {
  static const Mat3 R0 = so3::exp(Vec3(0.3, -0.2, 0.5));
  return R0;
}
inline const Vec3 kFreeOmega0(0.5, 3.0, 0.4);
inline const Pendulum3D& top() {
  static const Pendulum3D p(1.0, Vec3(0.14, 0.14, 0.08).asDiagonal(), Vec3(0.0, 0.0, 0.3), 9.81);
  return p;
}
inline const Vec3 kTopOmega0(1.0, 2.0, 5.0);

/// A method's errors against both closed forms at T = 1 s after N, 2N, 4N, 8N steps.
struct ExactErrors {
  std::array<double, 4> h{}, free_body{}, top{};
};

/// error_at(mech, R0, Omega0, exact_state_at_T, T, steps) runs the method from (R0, Omega0) over
/// `mech` (an AttitudeMechanics of the case) and returns its distance to the exact state.
template <class ErrorAt>
ExactErrors exact_errors(ErrorAt&& error_at, int coarse_steps) {
  const double T = 1.0;
  const FreeRigidBody body(free_J());
  const baselines::AttitudeMechanics<FreeRigidBody> free_mech(body);
  const baselines::FreeRigidBodyExact free_exact(free_J(), free_R0(), kFreeOmega0);
  const baselines::AttitudeMechanics<Pendulum3D> top_mech(top());
  const baselines::LagrangeTopExact top_exact(top(), Mat3::Identity(), kTopOmega0);
  ExactErrors e;
  for (int i = 0; i < 4; ++i) {
    const int n = coarse_steps << i;
    e.h[i] = T / n;
    e.free_body[i] = error_at(free_mech, free_R0(), kFreeOmega0, free_exact.state(T), T, n);
    e.top[i] = error_at(top_mech, Mat3::Identity(), kTopOmega0, top_exact.state(T), T, n);
  }
  return e;
}

}  // namespace lgvi::test::exact_cases
