// 3D pendulum: a rigid body on a fixed frictionless pivot in uniform gravity (section 3.2).
//
// R maps body to inertial frame, gravity acts along +e3 (inertial), rho is the pivot-to-mass-
// centre vector in the body frame, J the inertia about the pivot. Potential
//     U(R) = -m g e3^T R rho,
// moment (eq. 13) M = m g rho x R^T e3, symmetric control moment R^T e3 x u (eq. 23), which
// has no component about the vertical, so the vertical angular momentum e3^T R J Omega is
// conserved with or without control.
#pragma once

#include "lgvi/inertia.hpp"
#include "lgvi/so3.hpp"
#include "lgvi/systems/system.hpp"
#include "lgvi/types.hpp"

namespace lgvi {

struct Pendulum3D {
  using Control = Vec3;  ///< u; the applied moment is R^T e3 x u (body frame)
  static constexpr bool has_potential = true;

  double mass;
  Inertia inertia;
  Vec3 rho;
  double gravity;

  /// Validates m > 0, g >= 0 finite, rho finite, J (see Inertia; in `domain`).
  Pendulum3D(double m, const Mat3& J, const Vec3& rho_, double g, InertiaDomain domain = InertiaDomain::Physical);

  /// The paper's pendulum (section 3.2): m = 1 kg, J = diag(0.13, 0.28, 0.17) kg m^2,
  /// rho = (0, 0, 0.3) m. The paper does not print g; we use standard gravity 9.81 m/s^2.
  static Pendulum3D paper();

  double potential(const Mat3& R) const { return -mass * gravity * R.row(2).dot(rho); }
  /// M = m g rho x (R^T e3) (eq. 13 applied to U above).
  Vec3 moment(const Mat3& R) const {
    return (mass * gravity) * rho.cross(R.row(2).transpose());
  }
  /// R^T e3 x u (eq. 23).
  Vec3 control_moment(const Mat3& R, const Control& u) const {
    return R.row(2).transpose().cross(u);
  }
  /// J_moment_eta = d(M + R^T e3 x u)/deta, the applied moment's derivative for
  /// R -> R exp(hat eta): with a = R^T e3 (moving by hat(a) eta), M + a x u = (m g rho - u) x a, so
  /// hat(m g rho - u) hat(a).
  Mat3 J_moment_eta(const Mat3& R, const Control& u) const {
    return so3::hat(mass * gravity * rho - u) * so3::hat(R.row(2).transpose());
  }
  double energy(const Mat3& R, const Vec3& Omega) const {
    return 0.5 * Omega.dot(inertia.J * Omega) + potential(R);
  }
  /// e3^T R J Omega (section 3.2), the momentum map of rotations about the vertical.
  double vertical_momentum(const Mat3& R, const Vec3& Omega) const {
    return R.row(2).dot(inertia.J * Omega);
  }
  /// Gradient of the vertical momentum e3^T R Pi (Pi = J Omega) in the tangent [eta; dPi]:
  /// [Pi x a; a], a = R^T e3.
  static Eigen::Matrix<double, 6, 1> vertical_momentum_gradient(const Mat3& R, const Vec3& Pi) {
    const Vec3 a = R.row(2).transpose();
    Eigen::Matrix<double, 6, 1> g;
    g << Pi.cross(a), a;
    return g;
  }
};

static_assert(System<Pendulum3D>);

}  // namespace lgvi
