// The gravity-gradient potential of a rigid body on a circular orbit (the free body's
// "orbit_rate" scene parameter).
//
// The orbit: radius r with mean motion n = sqrt(mu / r^3), in the inertial e1-e2 plane; the
// direction from the attracting centre to the body is
//     r_hat(t) = (cos n t, sin n t, 0).
// Expanding the potential of the mass distribution to second order in its size over r gives,
// up to terms independent of the attitude (Hughes, "Spacecraft Attitude Dynamics", ch. 8),
//     V(R, t) = (3 n^2 / 2) c^T J c,   c = R^T r_hat(t)   (r_hat in the body frame),
// and its moment (the M of eq. 13: d/dt V = -Omega . M along R' = R hat(Omega)) is
//     M(R, t) = 3 n^2 c x J c,
// which vanishes for an isotropic J and for a principal axis along r_hat.
//
// V depends on t, so the energy 1/2 Omega^T J Omega + V is not conserved. In the frame that
// turns with the orbit (Q = exp(-n t hat(e3)) R) the Lagrangian is autonomous, and its energy
// is the Jacobi integral
//     E_J = 1/2 Omega^T J Omega + V(R, t) - n e3^T R J Omega,
// (Omega = Omega_rel + n R^T e3: E_J = Omega^T J Omega_rel - L), conserved by the flow.
#pragma once

#include <cmath>

#include "lgvi/inertia.hpp"
#include "lgvi/types.hpp"

namespace lgvi {

struct GravityGradient {
  double orbit_rate;  ///< n [rad/s]

  /// Throws InvalidInput("orbit_rate", ...) unless n is finite and positive.
  explicit GravityGradient(double n) : orbit_rate(n) { require_positive(n, "orbit_rate"); }

  /// r_hat(t) in the inertial frame.
  Vec3 direction(double t) const { return Vec3(std::cos(orbit_rate * t), std::sin(orbit_rate * t), 0.0); }

  double potential(const Mat3& J, const Mat3& R, double t) const {
    const Vec3 c = R.transpose() * direction(t);
    return 1.5 * orbit_rate * orbit_rate * c.dot(J * c);
  }
  Vec3 moment(const Mat3& J, const Mat3& R, double t) const {
    const Vec3 c = R.transpose() * direction(t);
    return 3.0 * orbit_rate * orbit_rate * c.cross(J * c);
  }
  double jacobi_integral(const Mat3& J, const Mat3& R, const Vec3& Omega, double t) const {
    const Vec3 JOmega = J * Omega;
    return 0.5 * Omega.dot(JOmega) + potential(J, R, t) - orbit_rate * R.row(2).dot(JOmega);
  }
};

}  // namespace lgvi
