// Free rigid body on SO(3): no potential, optional body-frame control moment.
//
// Continuous equations: R' = R hat(Omega), J Omega' = J Omega x Omega + u.
// Conserved without control: energy 1/2 Omega^T J Omega, spatial angular momentum R J Omega.
#pragma once

#include "lgvi/inertia.hpp"
#include "lgvi/systems/system.hpp"
#include "lgvi/types.hpp"

namespace lgvi {

struct FreeRigidBody {
  using Control = Vec3;  ///< control moment u in the body frame
  static constexpr bool has_potential = false;

  Inertia inertia;

  /// Throws InvalidInput("inertia", ...) for a J outside `domain` (lgvi/inertia.hpp).
  explicit FreeRigidBody(const Mat3& J, InertiaDomain domain = InertiaDomain::Physical)
      : inertia(Inertia::from(J, "inertia", domain)) {}

  double potential(const Mat3& /*R*/) const { return 0.0; }
  Vec3 moment(const Mat3& /*R*/) const { return Vec3::Zero(); }
  Vec3 control_moment(const Mat3& /*R*/, const Control& u) const { return u; }

  double energy(const Mat3& /*R*/, const Vec3& Omega) const {
    return 0.5 * Omega.dot(inertia.J * Omega);
  }
  /// Spatial angular momentum R J Omega (the momentum map of the left SO(3) symmetry).
  Vec3 spatial_momentum(const Mat3& R, const Vec3& Omega) const { return R * (inertia.J * Omega); }
};

static_assert(System<FreeRigidBody>);

}  // namespace lgvi
