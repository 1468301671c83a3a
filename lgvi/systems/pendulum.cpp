#include "lgvi/systems/pendulum.hpp"

#include <cmath>

#include "lgvi/require_nonnegative.hpp"

namespace lgvi {

Pendulum3D::Pendulum3D(double m, const Mat3& J, const Vec3& rho_, double g, InertiaDomain domain)
    : mass(m), inertia(Inertia::from(J, "inertia", domain)), rho(rho_), gravity(g) {
  require_positive(mass, "mass");
  require_finite(rho, "rho");
  require_nonnegative(gravity, "gravity");
}

Pendulum3D Pendulum3D::paper() {
  return Pendulum3D(1.0, Vec3(0.13, 0.28, 0.17).asDiagonal(), Vec3(0.0, 0.0, 0.3), 9.81);
}

}  // namespace lgvi
