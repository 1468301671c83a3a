// Test scenarios shared by the LGVI order and structure tests: each system with an initial
// state away from equilibrium and, where used, a smooth control.
#pragma once

#include <cmath>

#include "lgvi/integrate.hpp"
#include "lgvi/lgvi.hpp"
#include "lgvi/so3.hpp"
#include "lgvi/systems/dumbbell.hpp"
#include "lgvi/systems/free_rigid_body.hpp"
#include "lgvi/systems/pendulum.hpp"
#include "dumbbell_case.hpp"

namespace lgvi::test {

/// Free body, J = diag(0.13, 0.28, 0.17) (the paper's pendulum inertia), a generic tumble.
inline FreeRigidBody free_body() { return FreeRigidBody(Vec3(0.13, 0.28, 0.17).asDiagonal()); }
inline Mat3 free_body_R0() { return so3::exp(Vec3(0.3, -0.2, 0.5)); }
inline Vec3 free_body_Omega0() { return Vec3(1.0, 2.0, -0.5); }
/// Smooth body-frame control moment for the free body.
inline Vec3 free_body_control(double t) {
  return Vec3(0.3 * std::sin(2.0 * t), 0.2 * std::cos(3.0 * t), 0.1 * std::sin(t + 0.4));
}

/// The paper's pendulum in the tumbling state of the authors' 3D pendulum LGVI study:
/// R0 = I, Omega0 = 4.14 (1, 1, 1) rad/s.
inline Vec3 pendulum_Omega0() { return Vec3(4.14, 4.14, 4.14); }
/// Smooth control parameter u(t) for the pendulum (moment R^T e3 x u).
inline Vec3 pendulum_control(double t) {
  return Vec3(0.5 * std::sin(2.0 * M_PI * 0.5 * t), 0.3 * std::sin(2.0 * M_PI * 0.9 * t + 1.0),
              0.4 * std::sin(2.0 * M_PI * 1.3 * t + 2.0));
}

/// Distance between two attitude states: |log(R_a^T R_b)| + |Omega_a - Omega_b|.
template <class Lgvi>
double attitude_distance(const Lgvi& lgvi, const AttitudeState& a, const AttitudeState& b) {
  return so3::log(a.R.transpose() * b.R).norm() + (lgvi.omega(a) - lgvi.omega(b)).norm();
}
/// Distance between two SE(3) states: rotation + position + angular and linear velocity.
inline double rigid_distance(const DumbbellLgvi& lgvi, const RigidBodyState& a,
                             const RigidBodyState& b) {
  return so3::log(a.R.transpose() * b.R).norm() + (a.x - b.x).norm() +
         (lgvi.omega(a) - lgvi.omega(b)).norm() + (a.v - b.v).norm();
}

}  // namespace lgvi::test
