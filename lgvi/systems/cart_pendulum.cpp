#include "lgvi/systems/cart_pendulum.hpp"

#include <cmath>

#include "lgvi/require_nonnegative.hpp"
#include "lgvi/so3.hpp"

namespace lgvi {

CartPendulum::CartPendulum(double M, double m, const Mat3& J, const Vec3& d_, double g)
    : cart_mass(M), mass(m), inertia(Inertia::from(J)), d(d_), gravity(g) {
  require_positive(cart_mass, "cart_mass");
  require_positive(mass, "mass");
  require_finite(d, "d");
  require_nonnegative(gravity, "gravity");
}

CartPendulum CartPendulum::paper() {
  return CartPendulum(1.0, 1.0, Vec3(1.03, 1.04, 0.03).asDiagonal(), Vec3(0.0, 0.0, 1.0), 9.81);
}

Mat5 CartPendulum::mass_matrix(const Mat3& R) const {
  Eigen::Matrix<double, 3, 2> coupling = mass * so3::hat(d) * R.transpose().leftCols<2>();  // m hat(d) R^T E
  Mat5 A;
  A.topLeftCorner<3, 3>() = inertia.J;
  A.topRightCorner<3, 2>() = coupling;
  A.bottomLeftCorner<2, 3>() = coupling.transpose();  // -m E^T R hat(d)
  A.bottomRightCorner<2, 2>() = (cart_mass + mass) * Eigen::Matrix2d::Identity();
  return A;
}

void CartPendulum::momenta(const Mat3& R, const Vec3& Omega, const Vec2& q_dot, Vec3& Pi,
                           Vec2& p) const {
  Vec5 v;
  v << Omega, q_dot;
  const Vec5 P = mass_matrix(R) * v;
  Pi = P.head<3>();
  p = P.tail<2>();
}

void CartPendulum::velocities(const Mat3& R, const Vec3& Pi, const Vec2& p, Vec3& Omega,
                              Vec2& q_dot) const {
  Vec5 P;
  P << Pi, p;
  const Vec5 v = Eigen::LLT<Mat5>(mass_matrix(R)).solve(P);
  Omega = v.head<3>();
  q_dot = v.tail<2>();
}

double CartPendulum::energy(const Mat3& R, const Vec3& Omega, const Vec2& q_dot) const {
  Vec5 v;
  v << Omega, q_dot;
  return 0.5 * v.dot(mass_matrix(R) * v) + potential(R);
}

}  // namespace lgvi
