// The attitude cases of the step-cost benchmark (step_benchmark.cpp), shared with the test that
// checks its minimal LGVI against the project's step from the same states
// (tests/lgvi/test_minimal_lgvi.cpp).
#pragma once

#include <string>

#include "lgvi/systems/free_rigid_body.hpp"
#include "lgvi/systems/pendulum.hpp"
#include "lgvi/types.hpp"

namespace lgvi::benchmarks {

/// An attitude system's benchmark case: the system, its initial state and step.
template <class System>
struct AttitudeCase {
  std::string name;
  System system;
  Mat3 R0;
  Vec3 Omega0;
  double h;
};

/// Free body, J = diag(0.13, 0.28, 0.17), a generic tumble, h = 1e-2.
inline AttitudeCase<FreeRigidBody> free_body_case() {
  return {"free-body", FreeRigidBody(Vec3(0.13, 0.28, 0.17).asDiagonal()), Mat3::Identity(),
          Vec3(1.0, 2.0, -0.5), 1e-2};
}

/// The paper's 3D pendulum in its tumbling state (Omega0 = 4.14 (1, 1, 1)), h = 1e-3.
inline AttitudeCase<Pendulum3D> pendulum_case() {
  return {"pendulum", Pendulum3D::paper(), Mat3::Identity(), Vec3(4.14, 4.14, 4.14), 1e-3};
}

}  // namespace lgvi::benchmarks
