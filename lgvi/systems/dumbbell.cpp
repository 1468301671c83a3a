#include "lgvi/systems/dumbbell.hpp"

#include <cmath>

#include "lgvi/require_nonnegative.hpp"

namespace lgvi {

namespace {
Mat3 dumbbell_inertia(double m, const Vec3& rho, double r) {
  // Point masses m/2 at +-rho: sum (m/2)(|rho|^2 I - rho rho^T) = m (|rho|^2 I - rho rho^T);
  // two solid spheres of mass m/2 and radius r: 2 * (2/5)(m/2) r^2 I = (2/5) m r^2 I.
  return m * (rho.squaredNorm() * Mat3::Identity() - rho * rho.transpose()) +
         0.4 * m * r * r * Mat3::Identity();
}
}  // namespace

DumbbellSpacecraft::DumbbellSpacecraft(double m, double mu_, const Vec3& rho_, double r)
    : mass(m), mu(mu_), rho(rho_), sphere_radius(r), inertia() {
  require_positive(mass, "mass");
  require_positive(mu, "mu");
  require_finite(rho, "rho");
  if (rho.norm() == 0.0) throw InvalidInput("rho", "must be nonzero (the spheres coincide)");
  require_nonnegative(r, "sphere_radius");
  inertia = Inertia::from(dumbbell_inertia(mass, rho, r), "inertia (from rho and sphere_radius)");
}

DumbbellSpacecraft DumbbellSpacecraft::paper() {
  return DumbbellSpacecraft(1.0, 1.0, Vec3(0.15, 0.0, 0.0), 0.05);
}

double DumbbellSpacecraft::circular_speed(double radius) const {
  const double l2 = rho.squaredNorm();
  return std::sqrt(mu) * radius / std::pow(radius * radius + l2, 0.75);
}

void DumbbellSpacecraft::check_configuration(const Mat3& /*R*/, const Vec3& x) const {
  if (x.norm() <= rho.norm()) {
    throw InvalidInput("x0", "places a sphere at or inside the central body's centre (|x| <= |rho|)");
  }
}

double DumbbellSpacecraft::potential(const Mat3& R, const Vec3& x) const {
  const Vec3 r = R * rho;
  return -0.5 * mu * mass * (1.0 / (x + r).norm() + 1.0 / (x - r).norm());
}

DumbbellSpacecraft::Forces DumbbellSpacecraft::forces(const Mat3& R, const Vec3& x) const {
  const Vec3 r = R * rho;
  const Vec3 p1 = x + r;
  const Vec3 p2 = x - r;
  const double n1 = p1.norm();
  const double n2 = p2.norm();
  const double k = 0.5 * mu * mass;
  const Vec3 f1 = (-k / (n1 * n1 * n1)) * p1;  // force on sphere 1, inertial
  const Vec3 f2 = (-k / (n2 * n2 * n2)) * p2;
  Forces out;
  out.force = f1 + f2;
  // M = rho x R^T f1 + (-rho) x R^T f2 = rho x R^T (f1 - f2).
  out.moment = rho.cross(R.transpose() * (f1 - f2));
  return out;
}

}  // namespace lgvi
