// Two rigid bodies joined by a ball joint, reduced to SO(3) x SO(3) (section 4.2).
//
// Body i has mass m_i, inertia J_i about the JOINT (body frame) and mass centre at d_i from the
// joint. The total linear momentum is set to zero (the system's mass centre is fixed), which
// eliminates the joint position. With alpha = m1/(m1+m2), beta = m2/(m1+m2) and the reduced mass
// mu = m1 m2/(m1+m2) = beta m1 = alpha m2, the reduced Lagrangian is
//     L = sum_i 1/2 Omega_i^T Jr_i Omega_i - mu (R1 hat(Omega_1) d1) . (R2 hat(Omega_2) d2),
//     Jr_1 = J1 + alpha m1 hat(d1)^2,   Jr_2 = J2 + beta m2 hat(d2)^2,
// and the momenta (eq. 47) are
//     [Pi1; Pi2] = [Jr_1, mu hat(d1) R1^T R2 hat(d2); mu hat(d2) R2^T R1 hat(d1), Jr_2] [Omega1; Omega2].
// The extracted text of eq. 47 prints "J_1 + alpha m_1 hat(d_1)^T": the exponent 2 of hat(d_1)^2
// read as a transpose. Jr_i = J_i - alpha_i m_i hat(d_i)^T hat(d_i) is what eq. 39 gives (its J_d
// term minus alpha_i m_i d_i d_i^T, as eqs. 40-41 print it, is Jr_i's non-standard inertia); the
// sign is checked by the energy test in tests/lgvi/test_multibody.cpp.
//
// Control: a moment u (inertial frame) on body 1 and -u on body 2 at the joint: internal, so
// the total angular momentum R1 Pi1 + R2 Pi2 is conserved with or without it.
//
// Continuous equations (baselines/, see momentum_rate): Hamilton's principle with
// R_i -> R_i exp(hat(eta_i)), delta Omega_i = eta_i' + Omega_i x eta_i gives
// Pi_i' = Pi_i x Omega_i + X_i + (body-frame control moment), X_i the coupling term's moments.
// Along them dE/dt = u . (R1 Omega1 - R2 Omega2) (the power of the joint moment).
#pragma once

#include "lgvi/inertia.hpp"
#include "lgvi/systems/system.hpp"
#include "lgvi/types.hpp"

namespace lgvi {

using Mat6x6 = Eigen::Matrix<double, 6, 6>;

struct ConnectedBodies {
  using Control = Vec3;  ///< u, inertial frame: +u on body 1, -u on body 2

  double mass1, mass2;
  Inertia inertia1, inertia2;  ///< about the joint
  Vec3 d1, d2;                 ///< joint to mass centres, body frames
  double mu;                   ///< reduced mass m1 m2 / (m1 + m2)
  Inertia reduced1, reduced2;  ///< Jr_1, Jr_2 (validated: positive definite, triangle inequality)

  ConnectedBodies(double m1, const Mat3& J1, const Vec3& d1_, double m2, const Mat3& J2,
                  const Vec3& d2_);

  /// Section 4.2: m1 = 1.5, J1, d1 = (-1.08, 0.2, 0.2); m2 = 1, J2, d2 = (0.9, 0.2, 0.2) as printed.
  static ConnectedBodies paper();

  /// The mass matrix of eq. 47 at (R1, R2).
  Mat6x6 mass_matrix(const Mat3& R1, const Mat3& R2) const;
  /// Omega = mass_matrix^{-1} Pi (Cholesky).
  void velocities(const Mat3& R1, const Mat3& R2, const Vec3& Pi1, const Vec3& Pi2, Vec3& Omega1,
                  Vec3& Omega2) const;
  void momenta(const Mat3& R1, const Mat3& R2, const Vec3& Omega1, const Vec3& Omega2, Vec3& Pi1,
               Vec3& Pi2) const;
  double energy(const Mat3& R1, const Mat3& R2, const Vec3& Omega1, const Vec3& Omega2) const;
  /// No potential: the Lagrangian is the kinetic energy.
  double lagrangian(const Mat3& R1, const Mat3& R2, const Vec3& Omega1, const Vec3& Omega2) const {
    return energy(R1, R2, Omega1, Omega2);
  }

  /// Moments of the coupling term -mu a1 . a2, a_i = R_i (Omega_i x d_i), on each body (body
  /// frames), its left-trivialized R_i-derivatives (R_i -> R_i exp(hat(eta_i)) changes it by
  /// eta_i . X_i):  X1 = -mu (Omega1 x d1) x R1^T a2,  X2 = -mu (Omega2 x d2) x R2^T a1.
  /// R1 X1 + R2 X2 = -mu (a1 x a2 + a2 x a1) = 0: the coupling exchanges angular momentum only.
  void coupling_moments(const Mat3& R1, const Mat3& R2, const Vec3& Omega1, const Vec3& Omega2, Vec3& X1,
                        Vec3& X2) const;
  /// The continuous Lagrange-Poincare equations of L with the joint moment u (the continuous
  /// limit of eqs. 40-45):
  ///     Pi1' = Pi1 x Omega1 + X1 + R1^T u,     Pi2' = Pi2 x Omega2 + X2 - R2^T u,
  /// (Pi1, Pi2) the momenta of eq. 47 at (R1, R2, Omega1, Omega2), supplied consistent.
  void momentum_rate(const Mat3& R1, const Mat3& R2, const Vec3& Omega1, const Vec3& Omega2, const Vec3& Pi1,
                     const Vec3& Pi2, const Control& u, Vec3& Pi1_dot, Vec3& Pi2_dot) const;
  /// Total angular momentum about the fixed mass centre, inertial frame: R1 Pi1 + R2 Pi2.
  static Vec3 total_angular_momentum(const Mat3& R1, const Mat3& R2, const Vec3& Pi1,
                                     const Vec3& Pi2) {
    return R1 * Pi1 + R2 * Pi2;
  }
};

static_assert(System<ConnectedBodies>);

}  // namespace lgvi
