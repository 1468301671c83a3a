#include "lgvi/ocp/models.hpp"

namespace lgvi::ocp {

namespace {

/// One sphere of the dumbbell at p = x + R rho_q: its force, the force's Jacobian and the
/// configuration map P_q = [-R hat(rho_q), I].
struct Sphere {
  Vec3 rho;  // rho_q (body)
  Vec3 p;    // inertial position
  double r;
  double k;
  Vec3 f;  // -k p / r^3
  Mat3 K;  // df/dp
  Eigen::Matrix<double, 3, 6> P;

  Sphere(const DumbbellSpacecraft& d, const Mat3& R, const Vec3& x, double sign)
      : rho(sign * d.rho), p(x + R * rho), r(p.norm()), k(0.5 * d.mu * d.mass) {
    const double r3 = r * r * r;
    const double r5 = r3 * r * r;
    f = (-k / r3) * p;
    K = -k * (Mat3::Identity() / r3 - 3.0 * p * p.transpose() / r5);
    P.leftCols<3>() = -R * so3::hat(rho);
    P.rightCols<3>() = Mat3::Identity();
  }
  /// N(y) = d(K y)/dp (third derivative of the potential), symmetric.
  Mat3 N(const Vec3& y) const {
    const double r2 = r * r;
    const double r5 = r2 * r2 * r;
    const double py = p.dot(y);
    return -k * (-3.0 * (y * p.transpose() + p * y.transpose() + py * Mat3::Identity()) / r5 +
                 15.0 * py * p * p.transpose() / (r5 * r2));
  }
};

}  // namespace

DumbbellModel::MatQ DumbbellModel::force_jacobian(const Mat3& R, const Vec3& x, const VecU&) const {
  MatQ G = MatQ::Zero();
  for (const double sign : {1.0, -1.0}) {
    const Sphere s(system, R, x, sign);
    G += s.P.transpose() * s.K * s.P;
    G.topLeftCorner<3, 3>() += so3::hat(s.rho) * so3::hat(R.transpose() * s.f);
  }
  return G;
}

DumbbellModel::MatQ DumbbellModel::force_jacobian_transpose_derivative(const Mat3& R, const Vec3& x,
                                                                        const VecU&,
                                                                        const VecQ& nu) const {
  // G^T nu = sum_q [hat(rho) R^T K y + (R^T f) x c; K y], y = P nu = -R c + nu_x,
  // c = rho_q x nu_R. Differentiated along (eta', dx'):
  //   d p = P (eta', dx'),  d y = R hat(c) eta',  d(K y) = N(y) d p + K d y,
  //   d(hat(rho) R^T K y) = hat(rho) (hat(R^T K y) eta' + R^T d(K y)),
  //   d((R^T f) x c) = -hat(c) (hat(R^T f) eta' + R^T K d p).
  const Vec3 nu_R = nu.head<3>();
  const Vec3 nu_x = nu.tail<3>();
  Eigen::Matrix<double, 3, 6> E = Eigen::Matrix<double, 3, 6>::Zero();
  E.leftCols<3>() = Mat3::Identity();
  MatQ H = MatQ::Zero();
  for (const double sign : {1.0, -1.0}) {
    const Sphere s(system, R, x, sign);
    const Vec3 c = s.rho.cross(nu_R);
    const Vec3 y = -R * c + nu_x;
    const Vec3 Ky = s.K * y;
    const Eigen::Matrix<double, 3, 6> Dy = R * so3::hat(c) * E;
    const Eigen::Matrix<double, 3, 6> DKy = s.N(y) * s.P + s.K * Dy;
    H.topRows<3>() += so3::hat(s.rho) * (so3::hat(R.transpose() * Ky) * E + R.transpose() * DKy) -
                      so3::hat(c) * (so3::hat(R.transpose() * s.f) * E + R.transpose() * s.K * s.P);
    H.bottomRows<3>() += DKy;
  }
  return H;
}

}  // namespace lgvi::ocp
