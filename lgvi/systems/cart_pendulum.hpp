// 3D pendulum on a 2D cart, SO(3) x R^2 (section 4.1).
//
// The cart moves in the horizontal plane spanned by e1, e2 (inertial); gravity acts along +e3.
// q = (x, y) is the cart position, R the pendulum attitude, d the pivot-to-mass-centre vector
// (body frame), J the pendulum's inertia about the pivot, m its mass, M the cart's mass. With
// E = [e1 e2] (3x2) the Lagrangian is
//     L = 1/2 (M + m)|q'|^2 + m (E q') . (R hat(Omega) d) + 1/2 Omega^T J Omega + m g e3^T R d,
// and the Legendre map (eq. 37) is
//     [Pi; p] = [J, m hat(d) R^T E; -m E^T R hat(d), (M + m) I_2] [Omega; q'],
// a symmetric positive-definite mass matrix. Controls: forces u = (u_x, u_y) on the cart.
//
// The Lagrangian is invariant under rotations about the vertical acting on R and on q, so
//     e3^T R Pi + (q x p)_3 = e3^T R Pi + x p_y - y p_x
// is conserved without control (the pendulum's and the cart's parts), and so is p (no force acts
// on the cart's plane motion but the control).
//
// Continuous equations (baselines/, see momentum_rate): with R -> R exp(hat(eta)) and
// delta Omega = eta' + Omega x eta, Hamilton's principle gives Pi' = Pi x Omega + X with
// delta_R L = eta . X, X = M(R) + m (Omega x d) x R^T E q' (gravity and the coupling term), and
// p' = dL/dq + u = u. Along them dE/dt = u . q' and d/dt (vertical momentum) = x u_y - y u_x.
#pragma once

#include <Eigen/Cholesky>

#include "lgvi/inertia.hpp"
#include "lgvi/systems/system.hpp"
#include "lgvi/types.hpp"

namespace lgvi {

using Vec5 = Eigen::Matrix<double, 5, 1>;
using Mat5 = Eigen::Matrix<double, 5, 5>;

struct CartPendulum {
  using Control = Vec2;  ///< forces (u_x, u_y) on the cart, inertial frame

  double cart_mass;  ///< M
  double mass;       ///< m, pendulum
  Inertia inertia;   ///< J about the pivot
  Vec3 d;            ///< pivot to mass centre, body frame
  double gravity;

  /// Validates M, m > 0, J (see Inertia), d finite, g >= 0.
  CartPendulum(double M, double m, const Mat3& J, const Vec3& d_, double g);

  /// Section 4.1: M = m = 1 kg, J = diag(1.03, 1.04, 0.03) kg m^2, d = (0, 0, 1) m; g = 9.81
  /// (not printed; the paper's units are SI).
  static CartPendulum paper();

  double potential(const Mat3& R) const { return -mass * gravity * R.row(2).dot(d); }
  /// Moment of gravity about the pivot, body frame: m g d x R^T e3 (eq. 13).
  Vec3 moment(const Mat3& R) const { return (mass * gravity) * d.cross(R.row(2).transpose()); }

  /// The mass matrix of eq. 37 at attitude R.
  Mat5 mass_matrix(const Mat3& R) const;
  /// Momenta (Pi, p) from velocities (Omega, q') by eq. 37.
  void momenta(const Mat3& R, const Vec3& Omega, const Vec2& q_dot, Vec3& Pi, Vec2& p) const;
  /// Velocities from momenta: eq. 37 solved with a Cholesky factorization of the mass matrix.
  void velocities(const Mat3& R, const Vec3& Pi, const Vec2& p, Vec3& Omega, Vec2& q_dot) const;

  double energy(const Mat3& R, const Vec3& Omega, const Vec2& q_dot) const;
  /// The Lagrangian L = 1/2 [Omega; q']^T A(R) [Omega; q'] - U(R), A of eq. 37.
  double lagrangian(const Mat3& R, const Vec3& Omega, const Vec2& q_dot) const {
    return energy(R, Omega, q_dot) - 2.0 * potential(R);
  }

  /// Moment of the coupling term m (E q') . (R hat(Omega) d) on the pendulum, body frame:
  /// X_c = m (Omega x d) x R^T E q', the left-trivialized R-derivative of that term
  /// (R -> R exp(hat(eta)) changes it by eta . X_c).
  Vec3 coupling_moment(const Mat3& R, const Vec3& Omega, const Vec2& q_dot) const {
    return mass * Omega.cross(d).cross(R.transpose().leftCols<2>() * q_dot);
  }
  /// The continuous Lagrange-Poincare equations of L with the cart force u (the continuous
  /// limit of eqs. 30-36):
  ///     Pi' = Pi x Omega + M(R) + X_c(R, Omega, q'),     p' = u,
  /// (Pi, p) the momenta of eq. 37 at (R, Omega, q'); M = moment (eq. 13). L does not depend
  /// on q, so only the control changes p. The caller supplies consistent (Omega, q') and (Pi, p).
  void momentum_rate(const Mat3& R, const Vec3& Omega, const Vec2& q_dot, const Vec3& Pi,
                     const Control& u, Vec3& Pi_dot, Vec2& p_dot) const {
    Pi_dot = Pi.cross(Omega) + moment(R) + coupling_moment(R, Omega, q_dot);
    p_dot = u;
  }
  /// The momentum map of rotations about the vertical: e3^T R Pi + x p_y - y p_x.
  double vertical_momentum(const Mat3& R, const Vec2& q, const Vec3& Pi, const Vec2& p) const {
    return R.row(2).dot(Pi) + q.x() * p.y() - q.y() * p.x();
  }
};

static_assert(System<CartPendulum>);

}  // namespace lgvi
