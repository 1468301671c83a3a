// Dumbbell spacecraft in a central gravity field on SE(3) (section 3.1, eq. 20).
//
// Two spheres of mass m/2 each at body positions +rho and -rho from the mass centre, joined
// by a massless rod. Potential (eq. 20)
//     U(R, x) = -(mu m / 2) sum_q 1 / |x + R rho^q|,   rho^1 = rho, rho^2 = -rho, mu = G M.
// Force on the mass centre f = -dU/dx and moment (eq. 13) M = sum_q rho^q x R^T f^q, with f^q the
// force on sphere q. Controls: a force u^f in the inertial frame, a moment u^m in the body frame.
//
// Normalized units (section 3.1): mass by the dumbbell's mass (m = 1), length by the reference
// orbit radius, time such that mu = 1, i.e. the reference circular orbit of a point mass has
// speed 1 and period 2 pi (the paper's initial speed 0.9835 and quarter-orbit horizon fit this).
//
// Parameters the paper omits (justification, docs/lgvi.md "Parameters the paper leaves out"):
//  - rho = (0.15, 0, 0), spheres along body e1, which R_0 points along-track. Then the circular
//    speed of the mass centre at radius 1 is (1 + l^2)^(-3/4) = 0.98345 for l = 0.15, the
//    paper's 0.9835 (the orbit normal e3 gives the same speed; along-track was chosen because
//    the paper's Omega_0 = (0, 0, 0.9835) then keeps the rod along-track: a relative equilibrium,
//    unstable under the gravity gradient, so an uncontrolled run leaves it within about an orbit).
//  - sphere radius 0.05 (solid spheres, own inertia (2/5)(m/2) r^2 each) so that J is positive
//    definite: J = m l^2 (I - e1 e1^T) + (2/5) m r^2 I.
#pragma once

#include "lgvi/inertia.hpp"
#include "lgvi/systems/system.hpp"
#include "lgvi/types.hpp"

namespace lgvi {

struct DumbbellSpacecraft {
  using Control = Wrench;  ///< u^f (inertial frame), u^m (body frame)
  /// Derivatives of the potential at one configuration, -dU/dx and M of eq. 13: one evaluation
  /// gives both.
  using Forces = Wrench;

  double mass;
  double mu;
  Vec3 rho;  ///< sphere 1 at +rho, sphere 2 at -rho (body frame)
  double sphere_radius;
  Inertia inertia;  ///< derived from mass, rho and sphere_radius

  /// Validates m > 0, mu > 0, rho finite and nonzero, sphere_radius >= 0 (0 is allowed only if
  /// the resulting J is positive definite, which it never is for a rod: the check reports it).
  DumbbellSpacecraft(double m, double mu_, const Vec3& rho_, double sphere_radius_);

  /// The default dumbbell: m = 1, mu = 1, rho = (0.15, 0, 0), sphere radius 0.05.
  static DumbbellSpacecraft paper();

  /// Circular-orbit speed of the mass centre at radius r with the rod perpendicular to the
  /// radius: sqrt(mu) r / (r^2 + l^2)^(3/4), which is (1 + l^2)^(-3/4) for r = mu = 1.
  double circular_speed(double radius) const;

  /// Throws InvalidInput("x0", ...) when a sphere is at or inside the central body's centre
  /// (|x| <= |rho|): the LGVI's make_state calls it.
  void check_configuration(const Mat3& R, const Vec3& x) const;

  double potential(const Mat3& R, const Vec3& x) const;
  Forces forces(const Mat3& R, const Vec3& x) const;

  double energy(const Mat3& R, const Vec3& x, const Vec3& Omega, const Vec3& v) const {
    return 0.5 * mass * v.squaredNorm() + 0.5 * Omega.dot(inertia.J * Omega) + potential(R, x);
  }
  /// Total angular momentum about the central body: x x m v + R J Omega (spatial).
  Vec3 angular_momentum(const Mat3& R, const Vec3& x, const Vec3& Omega, const Vec3& v) const {
    return x.cross(mass * v) + R * (inertia.J * Omega);
  }
};

static_assert(System<DumbbellSpacecraft>);

}  // namespace lgvi
