#include "lgvi/systems/connected_bodies.hpp"

#include <Eigen/Cholesky>

#include "lgvi/so3.hpp"

namespace lgvi {

ConnectedBodies::ConnectedBodies(double m1, const Mat3& J1, const Vec3& d1_, double m2,
                                 const Mat3& J2, const Vec3& d2_)
    : mass1(m1), mass2(m2), inertia1(Inertia::from(J1, "inertia1")),
      inertia2(Inertia::from(J2, "inertia2")), d1(d1_), d2(d2_), mu(0.0) {
  require_positive(mass1, "mass1");
  require_positive(mass2, "mass2");
  require_finite(d1, "d1");
  require_finite(d2, "d2");
  const double total = mass1 + mass2;
  mu = mass1 * mass2 / total;
  const Mat3 D1 = so3::hat(d1), D2 = so3::hat(d2);
  reduced1 = Inertia::from(inertia1.J + (mass1 * mass1 / total) * D1 * D1,
                           "inertia1 (reduced: J1 + alpha m1 hat(d1)^2)");
  reduced2 = Inertia::from(inertia2.J + (mass2 * mass2 / total) * D2 * D2,
                           "inertia2 (reduced: J2 + beta m2 hat(d2)^2)");
}

ConnectedBodies ConnectedBodies::paper() {
  Mat3 J1, J2;
  J1 << 0.18, 0.32, 0.32, 0.32, 1.88, -0.06, 0.32, -0.06, 1.86;
  J2 << 0.11, -0.18, -0.18, -0.18, 0.89, -0.04, -0.18, -0.04, 0.88;
  return ConnectedBodies(1.5, J1, Vec3(-1.08, 0.2, 0.2), 1.0, J2, Vec3(0.9, 0.2, 0.2));
}

Mat6x6 ConnectedBodies::mass_matrix(const Mat3& R1, const Mat3& R2) const {
  const Mat3 C = mu * so3::hat(d1) * R1.transpose() * R2 * so3::hat(d2);
  Mat6x6 A;
  A.topLeftCorner<3, 3>() = reduced1.J;
  A.topRightCorner<3, 3>() = C;
  A.bottomLeftCorner<3, 3>() = C.transpose();  // mu hat(d2) R2^T R1 hat(d1)
  A.bottomRightCorner<3, 3>() = reduced2.J;
  return A;
}

void ConnectedBodies::velocities(const Mat3& R1, const Mat3& R2, const Vec3& Pi1, const Vec3& Pi2,
                                 Vec3& Omega1, Vec3& Omega2) const {
  Vec6 P;
  P << Pi1, Pi2;
  const Vec6 v = Eigen::LLT<Mat6x6>(mass_matrix(R1, R2)).solve(P);
  Omega1 = v.head<3>();
  Omega2 = v.tail<3>();
}

void ConnectedBodies::momenta(const Mat3& R1, const Mat3& R2, const Vec3& Omega1,
                              const Vec3& Omega2, Vec3& Pi1, Vec3& Pi2) const {
  Vec6 v;
  v << Omega1, Omega2;
  const Vec6 P = mass_matrix(R1, R2) * v;
  Pi1 = P.head<3>();
  Pi2 = P.tail<3>();
}

double ConnectedBodies::energy(const Mat3& R1, const Mat3& R2, const Vec3& Omega1,
                               const Vec3& Omega2) const {
  Vec6 v;
  v << Omega1, Omega2;
  return 0.5 * v.dot(mass_matrix(R1, R2) * v);
}

void ConnectedBodies::coupling_moments(const Mat3& R1, const Mat3& R2, const Vec3& Omega1, const Vec3& Omega2,
                                       Vec3& X1, Vec3& X2) const {
  const Vec3 w1 = Omega1.cross(d1), w2 = Omega2.cross(d2);  // body-frame velocities of the mass centres
  const Vec3 a1 = R1 * w1, a2 = R2 * w2;
  X1 = -mu * w1.cross(R1.transpose() * a2);
  X2 = -mu * w2.cross(R2.transpose() * a1);
}

void ConnectedBodies::momentum_rate(const Mat3& R1, const Mat3& R2, const Vec3& Omega1, const Vec3& Omega2,
                                    const Vec3& Pi1, const Vec3& Pi2, const Control& u, Vec3& Pi1_dot,
                                    Vec3& Pi2_dot) const {
  Vec3 X1, X2;
  coupling_moments(R1, R2, Omega1, Omega2, X1, X2);
  Pi1_dot = Pi1.cross(Omega1) + X1 + R1.transpose() * u;
  Pi2_dot = Pi2.cross(Omega2) + X2 - R2.transpose() * u;
}

}  // namespace lgvi
