// Hermite-Simpson collocation of the continuous optimal control problems, solved by IPOPT
// (collocation.hpp): one transcription (CollocationNlp) over a system's model (its state layout,
// rate and Jacobian, boundary values, terminal residual), the systems its instances.
#include "lgvi/ocp/collocation.hpp"

#include <IpIpoptApplication.hpp>
#include <IpTNLP.hpp>

#include "lgvi/ocp/direct_ipopt.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "lgvi/cpu_time.hpp"
#include "lgvi/so3.hpp"

namespace lgvi::ocp {

namespace {

using Vec4 = Eigen::Matrix<double, 4, 1>;

/// R(q) = (w^2 - |v|^2) I + 2 v v^T + 2 w hat(v), degree 2 in q (baselines/coordinates.hpp).
Mat3 rotation(const Vec4& q) {
  const double w = q(0);
  const Vec3 v = q.tail<3>();
  return (w * w - v.squaredNorm()) * Mat3::Identity() + 2.0 * v * v.transpose() + 2.0 * w * so3::hat(v);
}

/// d R(q) / d q_i, i = 0..3.
std::array<Mat3, 4> rotation_derivatives(const Vec4& q) {
  const double w = q(0);
  const Vec3 v = q.tail<3>();
  std::array<Mat3, 4> D;
  D[0] = 2.0 * w * Mat3::Identity() + 2.0 * so3::hat(v);
  for (int i = 0; i < 3; ++i) {
    const Vec3 e = Vec3::Unit(i);
    D[1 + i] = -2.0 * v(i) * Mat3::Identity() + 2.0 * (e * v.transpose() + v * e.transpose()) + 2.0 * w * so3::hat(e);
  }
  return D;
}

/// The rotation of q / |q|, R(q) / |q|^2 (a rotation for every q != 0), and its derivatives
/// d/dq_i = dR/dq_i / |q|^2 - 2 q_i R(q) / |q|^4: the multibody systems' physics is evaluated
/// there, so that their mass matrices stay positive definite off the unit sphere (the midpoints,
/// IPOPT's iterates); on the sphere it is R(q), the baselines' quaternion model.
Mat3 unit_rotation(const Vec4& q) { return rotation(q) / q.squaredNorm(); }
std::array<Mat3, 4> unit_rotation_derivatives(const Vec4& q) {
  const double n2 = q.squaredNorm();
  const Mat3 R = rotation(q);
  std::array<Mat3, 4> D = rotation_derivatives(q);
  for (int i = 0; i < 4; ++i) {
    D[static_cast<std::size_t>(i)] = D[static_cast<std::size_t>(i)] / n2 - (2.0 * q(i) / (n2 * n2)) * R;
  }
  return D;
}

/// The unit quaternion of R, scalar first, w >= 0.
Vec4 quaternion(const Mat3& R) {
  Eigen::Quaterniond e(R);
  e.normalize();
  Vec4 q(e.w(), e.x(), e.y(), e.z());
  return q(0) < 0.0 ? Vec4(-q) : q;
}

/// a (x) b, scalar first.
Vec4 multiply(const Vec4& a, const Vec4& b) {
  Vec4 r;
  r(0) = a(0) * b(0) - a.tail<3>().dot(b.tail<3>());
  r.tail<3>() = a(0) * b.tail<3>() + b(0) * a.tail<3>() + a.tail<3>().cross(b.tail<3>());
  return r;
}

/// 1/2 q (x) (0, Omega): bilinear in (q, Omega), so its derivative along (dq, dOmega) is
/// kinematics(dq, Omega) + kinematics(q, dOmega).
Vec4 kinematics(const Vec4& q, const Vec3& Omega) {
  const Vec3 v = q.tail<3>();
  Vec4 r;
  r(0) = -0.5 * v.dot(Omega);
  r.tail<3>() = 0.5 * (q(0) * Omega + v.cross(Omega));
  return r;
}

Eigen::MatrixXd validated_weight(const Eigen::MatrixXd& W, int nu) {
  if (W.size() == 0) return Eigen::MatrixXd::Identity(nu, nu);
  if (W.rows() != nu || W.cols() != nu) {
    throw InvalidInput("W", "must be " + std::to_string(nu) + "x" + std::to_string(nu));
  }
  require_finite(W, "W");
  if ((W - W.transpose()).cwiseAbs().maxCoeff() > 1e-12 * W.cwiseAbs().maxCoeff()) {
    throw InvalidInput("W", "is not symmetric (must be symmetric positive definite)");
  }
  const Eigen::MatrixXd Ws = 0.5 * (W + W.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Ws, Eigen::EigenvaluesOnly);
  if (!(eig.eigenvalues()(0) > 1e-14 * eig.eigenvalues()(nu - 1))) throw InvalidInput("W", "is not positive definite");
  return Ws;
}

void require_rotation(const Mat3& R, const char* field) {
  require_finite(R, field);
  if (!so3::is_rotation(R, 1e-10)) throw InvalidInput(field, "is not a rotation matrix (R^T R != I or det R != 1)");
}

void require_horizon(double t_final) {
  if (!(std::isfinite(t_final) && t_final > 0.0)) throw InvalidInput("t_final", "must be positive and finite");
}

// --- the systems' models -----------------------------------------------------------------------
//
// A model provides: nq (quaternions), nx (further coordinates), ny, nu; VecY, VecU, VecQ, JacY
// (n_y x (n_y + n_u + n_q): d f / d(y, u, mu)); rhs(y, u, mu, f, J*); the boundary states
// initial, target (y); terminal_entries (the entries of y past the quaternions whose terminal
// values are imposed); state(q, Omega, x, x') (y from the attitudes, the body rates and the
// further coordinates: the guess); guess_tilt (radians) and opposite_half_turns (the guess);
// residual(y_K), the full terminal residual of the method's violation norm.

template <int NQ, int NX, int NW, int NU>
struct Dimensions {
  static constexpr int nq = NQ, nx = NX, nw = NW, nu = NU, ny = 4 * NQ + NX + NW;
  using VecY = Eigen::Matrix<double, ny, 1>;
  using VecU = Eigen::Matrix<double, nu, 1>;
  using VecQ = Eigen::Matrix<double, nq, 1>;
  using VecX = Eigen::Matrix<double, nx, 1>;
  using JacY = Eigen::Matrix<double, ny, ny + nu + nq>;
  using Quaternions = std::array<Vec4, nq>;
  using Rates = std::array<Vec3, nq>;
};

// The applied moment M(R) + tau(R, u) of an attitude system (its own functions) and its
// derivatives: with respect to R along dR (the directional derivative, linear in dR) and to u.
struct PendulumMoments {
  const Pendulum3D& s;
  Vec3 value(const Mat3& R, const Vec3& u) const { return s.moment(R) + s.control_moment(R, u); }
  /// M + tau = (m g rho - u) x a with a = R^T e3 = R.row(2) (pendulum.hpp).
  Vec3 along(const Mat3& /*R*/, const Mat3& dR, const Vec3& u) const {
    return (s.mass * s.gravity * s.rho - u).cross(dR.row(2).transpose());
  }
  Mat3 per_control(const Mat3& R) const { return so3::hat(R.row(2).transpose()); }
};
struct FreeBodyMoments {
  const FreeRigidBody& s;
  Vec3 value(const Mat3& R, const Vec3& u) const { return s.moment(R) + s.control_moment(R, u); }
  Vec3 along(const Mat3&, const Mat3&, const Vec3&) const { return Vec3::Zero(); }
  Mat3 per_control(const Mat3&) const { return Mat3::Identity(); }
};

/// The attitude transfers (pendulum, free body): y = (q, Omega), u the moment.
template <class S, class Moments>
struct AttitudeModel : Dimensions<1, 0, 3, 3> {
  const S& system;
  Moments moments;
  VecY initial, target;
  TransferProblem p;
  static constexpr std::array<int, 3> terminal_entries = {4, 5, 6};
  static constexpr double guess_tilt = 0.5;
  static constexpr bool opposite_half_turns = false;

  AttitudeModel(const S& s, const TransferProblem& problem) : system(s), moments{s}, p(problem) {
    require_rotation(p.R0, "R0");
    require_rotation(p.Rf, "Rf");
    require_finite(p.Omega0, "Omega0");
    require_finite(p.Omegaf, "Omegaf");
    require_horizon(p.t_final);
    initial << quaternion(p.R0), p.Omega0;
    target << quaternion(p.Rf), p.Omegaf;
  }
  double t_final() const { return p.t_final; }

  void rhs(const VecY& y, const VecU& u, const VecQ& muq, VecY& f, JacY* J) const {
    const double mu = muq(0);
    const Vec4 q = y.head<4>();
    const Vec3 Omega = y.tail<3>();
    const Vec3 v = q.tail<3>();
    const Mat3 R = rotation(q);
    const Mat3& Jb = system.inertia.J;
    const Mat3& Ji = system.inertia.J_inverse;
    f(0) = -0.5 * v.dot(Omega) + mu * q(0);
    f.segment<3>(1) = 0.5 * (q(0) * Omega + v.cross(Omega)) + mu * v;
    f.tail<3>() = Ji * ((Jb * Omega).cross(Omega) + moments.value(R, u));
    if (J == nullptr) return;
    J->setZero();
    // kinematics: d/dq = 1/2 [[0, -Omega^T], [Omega, -hat(Omega)]] + mu I, d/dOmega, d/dmu = q
    J->block<1, 3>(0, 1) = -0.5 * Omega.transpose();
    J->block<3, 1>(1, 0) = 0.5 * Omega;
    J->block<3, 3>(1, 1) = -0.5 * so3::hat(Omega);
    J->block<4, 4>(0, 0) += mu * Eigen::Matrix4d::Identity();
    J->block<1, 3>(0, 4) = -0.5 * v.transpose();
    J->block<3, 3>(1, 4) = 0.5 * (q(0) * Mat3::Identity() + so3::hat(v));
    J->block<4, 1>(0, ny + nu) = q;
    // Euler's equation: d/dq through R(q), d/dOmega J^{-1} (hat(J Omega) - hat(Omega) J), d/du
    const std::array<Mat3, 4> dR = rotation_derivatives(q);
    for (int i = 0; i < 4; ++i) J->block<3, 1>(4, i) = Ji * moments.along(R, dR[static_cast<std::size_t>(i)], u);
    J->block<3, 3>(4, 4) = Ji * (so3::hat(Jb * Omega) - so3::hat(Omega) * Jb);
    J->block<3, 3>(4, ny) = Ji * moments.per_control(R);
  }
  VecY state(const Quaternions& q, const Rates& Omega, const VecX&, const VecX&) const {
    VecY y;
    y << q[0], Omega[0];
    return y;
  }
  void guess_positions(double, double, double, VecX&, VecX&) const {}
  Eigen::VectorXd residual(const VecY& yK) const {
    Eigen::VectorXd r(6);
    r << so3::log(p.Rf.transpose() * rotation(yK.head<4>().normalized())), yK.tail<3>() - p.Omegaf;
    return r;
  }
};

/// The dumbbell (section 3.1): y = (q, x, Omega, v), u = (u^m, u^f) as lgvi/ocp/models.hpp.
struct DumbbellCollocationModel : Dimensions<1, 3, 6, 6> {
  const DumbbellSpacecraft& system;
  VecY initial, target;
  TransferProblem p;
  static constexpr std::array<int, 9> terminal_entries = {4, 5, 6, 7, 8, 9, 10, 11, 12};
  static constexpr double guess_tilt = 0.0;
  static constexpr bool opposite_half_turns = false;

  DumbbellCollocationModel(const DumbbellSpacecraft& s, const TransferProblem& problem) : system(s), p(problem) {
    require_rotation(p.R0, "R0");
    require_rotation(p.Rf, "Rf");
    for (const auto& [v, name] : {std::pair{&p.x0, "x0"}, {&p.xf, "xf"}, {&p.Omega0, "Omega0"},
                                  {&p.Omegaf, "Omegaf"}, {&p.v0, "v0"}, {&p.vf, "vf"}}) {
      require_finite(*v, name);
    }
    require_horizon(p.t_final);
    s.check_configuration(p.R0, p.x0);
    if (p.xf.norm() <= s.rho.norm()) {
      throw InvalidInput("xf", "places a sphere at or inside the central body's centre (|x| <= |rho|)");
    }
    initial << quaternion(p.R0), p.x0, p.Omega0, p.v0;
    target << quaternion(p.Rf), p.xf, p.Omegaf, p.vf;
  }
  double t_final() const { return p.t_final; }

  /// Force on a sphere at p, -k p / |p|^3 (DumbbellSpacecraft::forces), and its Jacobian
  /// K = -k (I / r^3 - 3 p p^T / r^5) (as lgvi/ocp/models.hpp's DumbbellModel).
  static Mat3 force_jacobian(double k, const Vec3& at) {
    const double r = at.norm(), r3 = r * r * r, r5 = r3 * r * r;
    return -k * (Mat3::Identity() / r3 - 3.0 * at * at.transpose() / r5);
  }

  void rhs(const VecY& y, const VecU& u, const VecQ& mu, VecY& f, JacY* J) const {
    const Vec4 q = y.head<4>();
    const Vec3 x = y.segment<3>(4), Omega = y.segment<3>(7), v = y.segment<3>(10);
    const Mat3 R = rotation(q);
    const Mat3& Jb = system.inertia.J;
    const Mat3& Ji = system.inertia.J_inverse;
    const DumbbellSpacecraft::Forces F = system.forces(R, x);
    f.head<4>() = kinematics(q, Omega) + mu(0) * q;
    f.segment<3>(4) = v;
    f.segment<3>(7) = Ji * ((Jb * Omega).cross(Omega) + F.moment + u.head<3>());
    f.tail<3>() = (F.force + u.tail<3>()) / system.mass;
    if (J == nullptr) return;
    J->setZero();
    // Spheres at p_1,2 = x +- R rho with forces f_1,2: force f_1 + f_2, moment rho x R^T (f_1 - f_2)
    // (dumbbell.cpp); along (dR, dx): dp_1,2 = dx +- dR rho, df = K dp.
    const double k = 0.5 * system.mu * system.mass;
    const Vec3 r = R * system.rho;
    const Vec3 p1 = x + r, p2 = x - r;
    const double n1 = p1.norm(), n2 = p2.norm();
    const Vec3 f1 = (-k / (n1 * n1 * n1)) * p1, f2 = (-k / (n2 * n2 * n2)) * p2;
    const Mat3 K1 = force_jacobian(k, p1), K2 = force_jacobian(k, p2);
    const Mat3 rho_hat = so3::hat(system.rho);
    const std::array<Mat3, 4> dR = rotation_derivatives(q);
    for (int i = 0; i < 4; ++i) {
      const Mat3& D = dR[static_cast<std::size_t>(i)];
      const Vec3 dr = D * system.rho;
      const Vec3 df1 = K1 * dr, df2 = -(K2 * dr);
      J->block<4, 1>(0, i) = kinematics(Vec4::Unit(i), Omega) + mu(0) * Vec4::Unit(i);
      J->block<3, 1>(7, i) = Ji * (rho_hat * (D.transpose() * (f1 - f2) + R.transpose() * (df1 - df2)));
      J->block<3, 1>(10, i) = (df1 + df2) / system.mass;
    }
    // d/dx
    J->block<3, 3>(7, 4) = Ji * rho_hat * R.transpose() * (K1 - K2);
    J->block<3, 3>(10, 4) = (K1 + K2) / system.mass;
    // d/dOmega
    for (int j = 0; j < 3; ++j) J->block<4, 1>(0, 7 + j) = kinematics(q, Vec3::Unit(j));
    J->block<3, 3>(7, 7) = Ji * (so3::hat(Jb * Omega) - so3::hat(Omega) * Jb);
    // d/dv, d/du, d/dmu
    J->block<3, 3>(4, 10) = Mat3::Identity();
    J->block<3, 3>(7, ny) = Ji;
    J->block<3, 3>(10, ny + 3) = Mat3::Identity() / system.mass;
    J->block<4, 1>(0, ny + nu) = q;
  }
  VecY state(const Quaternions& q, const Rates& Omega, const VecX& x, const VecX& x_dot) const {
    VecY y;
    y << q[0], x, Omega[0], x_dot;
    return y;
  }
  /// Along the circular arc from x_0 to x_f (radius interpolated linearly), at the fraction s of
  /// the way with ds/dt = s_dot.
  void guess_positions(double s, double s_dot, double, VecX& x, VecX& x_dot) const {
    const double r0 = p.x0.norm(), rf = p.xf.norm();
    const Vec3 a = p.x0 / r0;
    Vec3 n = p.x0.cross(p.xf);
    const double angle = std::atan2(n.norm(), p.x0.dot(p.xf));
    if (n.norm() <= 1e-12 * r0 * rf) n = a.cross(std::abs(a.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY());
    const Vec3 b = n.normalized().cross(a);
    const double radius = r0 + s * (rf - r0), phi = s * angle;
    const Vec3 dir = std::cos(phi) * a + std::sin(phi) * b;
    x = radius * dir;
    x_dot = s_dot * ((rf - r0) * dir + radius * angle * (-std::sin(phi) * a + std::cos(phi) * b));
  }
  Eigen::VectorXd residual(const VecY& yK) const {
    Eigen::VectorXd r(12);
    r << so3::log(p.Rf.transpose() * rotation(yK.head<4>().normalized())), yK.segment<3>(4) - p.xf,
        yK.segment<3>(7) - p.Omegaf, yK.tail<3>() - p.vf;
    return r;
  }
};

/// The cart-pendulum (section 4.1) in momentum form: y = (q, x_c, Pi, p), u the cart force.
struct CartPendulumCollocationModel : Dimensions<1, 2, 5, 2> {
  const CartPendulum& system;
  VecY initial, target;
  CartPendulumTransfer p;
  static constexpr std::array<int, 7> terminal_entries = {4, 5, 6, 7, 8, 9, 10};
  static constexpr double guess_tilt = 0.5;  // the turn about the vertical: as the pendulum's
  static constexpr bool opposite_half_turns = false;

  CartPendulumCollocationModel(const CartPendulum& s, const CartPendulumTransfer& problem) : system(s), p(problem) {
    require_rotation(p.R0, "R0");
    require_rotation(p.Rf, "Rf");
    require_finite(p.q0, "q0");
    require_finite(p.qf, "qf");
    require_finite(p.Omega0, "Omega0");
    require_finite(p.Omegaf, "Omegaf");
    require_finite(p.q_dot0, "q_dot0");
    require_finite(p.q_dotf, "q_dotf");
    require_horizon(p.t_final);
    initial = state({quaternion(p.R0)}, {p.Omega0}, p.q0, p.q_dot0);
    target = state({quaternion(p.Rf)}, {p.Omegaf}, p.qf, p.q_dotf);
  }
  double t_final() const { return p.t_final; }

  void rhs(const VecY& y, const VecU& u, const VecQ& mu, VecY& f, JacY* J) const {
    const Vec4 q = y.head<4>();
    const Vec5 w = y.tail<5>();
    const Mat3 R = unit_rotation(q);
    const Eigen::PartialPivLU<Mat5> llt(system.mass_matrix(R));  // LU: see the connected bodies
    const Vec5 v = llt.solve(w);  // [Omega; x_c'] (eq. 37)
    const Vec3 Omega = v.head<3>(), Pi = w.head<3>();
    const Vec2 x_dot = v.tail<2>();
    f.head<4>() = kinematics(q, Omega) + mu(0) * q;
    f.segment<2>(4) = x_dot;
    Vec3 Pi_dot;
    Vec2 p_dot;
    system.momentum_rate(R, Omega, x_dot, Pi, u, Pi_dot, p_dot);
    f.segment<3>(6) = Pi_dot;  // Pi x Omega + M(R) + X_c(R, Omega, x_c'): its derivative below term by term
    f.tail<2>() = p_dot;       // u
    if (J == nullptr) return;
    J->setZero();
    // dv = A^{-1} (dw - dA v); A(R) is affine in R: dA along dR = A(dR) - A(0).
    const Mat5 A0 = system.mass_matrix(Mat3::Zero());
    const std::array<Mat3, 4> dR = unit_rotation_derivatives(q);
    for (int c = 0; c < ny; ++c) {
      Vec5 dv = Vec5::Zero();
      Vec3 dPi = Vec3::Zero();
      const Mat3* D = c < 4 ? &dR[static_cast<std::size_t>(c)] : nullptr;
      if (D != nullptr) dv = -llt.solve((system.mass_matrix(*D) - A0) * v);
      if (c >= 6) dv = llt.solve(Vec5::Unit(c - 6));
      if (c >= 6 && c < 9) dPi = Vec3::Unit(c - 6);
      if (c == 4 || c == 5) continue;  // nothing depends on x_c
      const Vec3 dOmega = dv.head<3>();
      const Vec2 dx_dot = dv.tail<2>();
      Vec4 dq_rate = kinematics(q, dOmega);
      Vec3 dPi_rate = dPi.cross(Omega) + Pi.cross(dOmega) + system.coupling_moment(R, dOmega, x_dot) +
                      system.coupling_moment(R, Omega, dx_dot);
      if (D != nullptr) {
        dq_rate += kinematics(Vec4::Unit(c), Omega) + mu(0) * Vec4::Unit(c);
        dPi_rate += system.moment(*D) + system.coupling_moment(*D, Omega, x_dot);
      }
      J->block<4, 1>(0, c) = dq_rate;
      J->block<2, 1>(4, c) = dx_dot;
      J->block<3, 1>(6, c) = dPi_rate;
    }
    J->block<2, 2>(9, ny) = Eigen::Matrix2d::Identity();
    J->block<4, 1>(0, ny + nu) = q;
  }
  VecY state(const Quaternions& q, const Rates& Omega, const VecX& x, const VecX& x_dot) const {
    Vec3 Pi;
    Vec2 pm;
    system.momenta(unit_rotation(q[0]), Omega[0], x_dot, Pi, pm);
    VecY y;
    y << q[0], x, Pi, pm;
    return y;
  }
  void guess_positions(double s, double s_dot, double, VecX& x, VecX& x_dot) const {
    x = p.q0 + s * (p.qf - p.q0);
    x_dot = s_dot * (p.qf - p.q0);
  }
  Eigen::VectorXd residual(const VecY& yK) const {
    const Mat3 R = rotation(yK.head<4>().normalized());
    Vec3 Omega;
    Vec2 x_dot;
    system.velocities(R, yK.segment<3>(6), yK.tail<2>(), Omega, x_dot);
    Eigen::VectorXd r(10);
    r << so3::log(R.transpose() * p.Rf), yK.segment<2>(4) - p.qf, Omega - p.Omegaf, x_dot - p.q_dotf;
    return r;
  }
};

/// The connected bodies (section 4.2) in momentum form: y = (q1, q2, Pi1, Pi2), u the joint moment.
struct ConnectedBodiesCollocationModel : Dimensions<2, 0, 6, 3> {
  const ConnectedBodies& system;
  VecY initial, target;
  ConnectedBodiesTransfer p;
  static constexpr std::array<int, 3> terminal_entries = {8, 9, 10};  // Pi1 (Pi2 follows: the header)
  static constexpr double guess_tilt = 0.0;
  static constexpr bool opposite_half_turns = true;

  ConnectedBodiesCollocationModel(const ConnectedBodies& s, const ConnectedBodiesTransfer& problem)
      : system(s), p(problem) {
    require_rotation(p.R1_0, "R1_0");
    require_rotation(p.R2_0, "R2_0");
    require_rotation(p.R1_f, "R1_f");
    require_rotation(p.R2_f, "R2_f");
    require_finite(p.Omega1_0, "Omega1_0");
    require_finite(p.Omega2_0, "Omega2_0");
    require_finite(p.Omega1_f, "Omega1_f");
    require_finite(p.Omega2_f, "Omega2_f");
    require_horizon(p.t_final);
    initial = state({quaternion(p.R1_0), quaternion(p.R2_0)}, {p.Omega1_0, p.Omega2_0}, {}, {});
    target = state({quaternion(p.R1_f), quaternion(p.R2_f)}, {p.Omega1_f, p.Omega2_f}, {}, {});
    // The internal moment conserves the total angular momentum R1 Pi1 + R2 Pi2: a target with
    // another one is unreachable (and with Pi2 not imposed, would be silently missed).
    const Vec3 L0 = ConnectedBodies::total_angular_momentum(p.R1_0, p.R2_0, initial.segment<3>(8), initial.tail<3>());
    const Vec3 Lf = ConnectedBodies::total_angular_momentum(p.R1_f, p.R2_f, target.segment<3>(8), target.tail<3>());
    if ((L0 - Lf).norm() > 1e-9 * (1.0 + L0.norm())) {
      throw InvalidInput("Omega2_f", "gives a total angular momentum R1 Pi1 + R2 Pi2 other than the initial one, "
                                     "which the internal moment conserves: the target is unreachable");
    }
  }
  double t_final() const { return p.t_final; }

  void rhs(const VecY& y, const VecU& u, const VecQ& mu, VecY& f, JacY* J) const {
    const Vec4 q1 = y.head<4>(), q2 = y.segment<4>(4);
    const Vec6 w = y.tail<6>();
    const Mat3 R1 = unit_rotation(q1), R2 = unit_rotation(q2);
    // LU rather than the systems' Cholesky: the same solve for a positive definite A, and no silent
    // garbage should it ever not be (LLT does not report it).
    const Eigen::PartialPivLU<Mat6x6> llt(system.mass_matrix(R1, R2));
    const Vec6 v = llt.solve(w);  // [Omega1; Omega2] (eq. 47)
    const Vec3 Om1 = v.head<3>(), Om2 = v.tail<3>(), Pi1 = w.head<3>(), Pi2 = w.tail<3>();
    f.head<4>() = kinematics(q1, Om1) + mu(0) * q1;
    f.segment<4>(4) = kinematics(q2, Om2) + mu(1) * q2;
    Vec3 Pi1_dot, Pi2_dot;  // Pi_i x Omega_i + X_i +- R_i^T u: its derivative below term by term
    system.momentum_rate(R1, R2, Om1, Om2, Pi1, Pi2, u, Pi1_dot, Pi2_dot);
    f.segment<3>(8) = Pi1_dot;
    f.tail<3>() = Pi2_dot;
    if (J == nullptr) return;
    J->setZero();
    // dv = A^{-1} (dw - dA v); A(R1, R2) is affine in each attitude: dA along dR1 = A(dR1, R2) - A(0, 0).
    const Mat6x6 A0 = system.mass_matrix(Mat3::Zero(), Mat3::Zero());
    const std::array<Mat3, 4> dR1 = unit_rotation_derivatives(q1), dR2 = unit_rotation_derivatives(q2);
    const Mat3 Z = Mat3::Zero();
    for (int c = 0; c < ny; ++c) {
      Mat3 D1 = Z, D2 = Z;
      Vec6 dw = Vec6::Zero();
      if (c < 4) D1 = dR1[static_cast<std::size_t>(c)];
      else if (c < 8) D2 = dR2[static_cast<std::size_t>(c - 4)];
      else dw(c - 8) = 1.0;
      const Vec6 dv = c < 8 ? Vec6(-llt.solve((system.mass_matrix(c < 4 ? D1 : R1, c < 4 ? R2 : D2) - A0) * v))
                            : Vec6(llt.solve(dw));
      const Vec3 dOm1 = dv.head<3>(), dOm2 = dv.tail<3>();
      Vec3 dX1 = Vec3::Zero(), dX2 = Vec3::Zero(), a, b;
      // X is linear in each of R1, R2, Omega1, Omega2
      system.coupling_moments(R1, R2, dOm1, Om2, a, b);
      dX1 += a;
      dX2 += b;
      system.coupling_moments(R1, R2, Om1, dOm2, a, b);
      dX1 += a;
      dX2 += b;
      Vec4 dq1 = kinematics(q1, dOm1), dq2 = kinematics(q2, dOm2);
      if (c < 4) {
        system.coupling_moments(D1, R2, Om1, Om2, a, b);
        dX1 += a + D1.transpose() * u;
        dX2 += b;
        dq1 += kinematics(Vec4::Unit(c), Om1) + mu(0) * Vec4::Unit(c);
      } else if (c < 8) {
        system.coupling_moments(R1, D2, Om1, Om2, a, b);
        dX1 += a;
        dX2 += b - D2.transpose() * u;
        dq2 += kinematics(Vec4::Unit(c - 4), Om2) + mu(1) * Vec4::Unit(c - 4);
      }
      J->block<4, 1>(0, c) = dq1;
      J->block<4, 1>(4, c) = dq2;
      J->block<3, 1>(8, c) = dw.head<3>().cross(Om1) + Pi1.cross(dOm1) + dX1;
      J->block<3, 1>(11, c) = dw.tail<3>().cross(Om2) + Pi2.cross(dOm2) + dX2;
    }
    J->block<3, 3>(8, ny) = R1.transpose();
    J->block<3, 3>(11, ny) = -R2.transpose();
    J->block<4, 1>(0, ny + nu) = q1;
    J->block<4, 1>(4, ny + nu + 1) = q2;
  }
  VecY state(const Quaternions& q, const Rates& Omega, const VecX&, const VecX&) const {
    Vec3 Pi1, Pi2;
    system.momenta(unit_rotation(q[0]), unit_rotation(q[1]), Omega[0], Omega[1], Pi1, Pi2);
    VecY y;
    y << q[0], q[1], Pi1, Pi2;
    return y;
  }
  void guess_positions(double, double, double, VecX&, VecX&) const {}
  Eigen::VectorXd residual(const VecY& yK) const {
    const Mat3 R1 = rotation(yK.head<4>().normalized()), R2 = rotation(yK.segment<4>(4).normalized());
    Vec3 Om1, Om2;
    system.velocities(R1, R2, yK.segment<3>(8), yK.tail<3>(), Om1, Om2);
    Eigen::VectorXd r(12);
    r << so3::log(R1.transpose() * p.R1_f), so3::log(R2.transpose() * p.R2_f), Om1 - p.Omega1_f, Om2 - p.Omega2_f;
    return r;
  }
};

// --- the transcription -------------------------------------------------------------------------

/// The transcription as IPOPT's TNLP (collocation.hpp: variables, rows, Jacobian).
template <class Model>
class CollocationNlp : public Ipopt::TNLP {
 public:
  static constexpr int NY = Model::ny, NU = Model::nu, NQ = Model::nq;
  static constexpr int NE = static_cast<int>(Model::terminal_entries.size());
  static constexpr int kBlock = 2 * NY + 2 * NU + NQ;  // y_k, u_k, y_m, u_m, mu_k
  static constexpr int kWindow = kBlock + NY + NU;    // an interval's variables: its block and y_{k+1}, u_{k+1}
  static constexpr int kRowsPerInterval = 2 * NY + NQ;  // two defects and the norms at k + 1
  static constexpr int kTerminalRows = 3 * NQ + NE;
  using VecY = typename Model::VecY;
  using VecU = typename Model::VecU;
  using VecQ = typename Model::VecQ;
  using JacY = typename Model::JacY;

  CollocationNlp(const Model& model, int K, const Eigen::MatrixXd& W, CollocationResult* out,
                 IpoptHessian hessian)
      : model_(model), K_(K), h_(model.t_final() / K), W_(W), out_(out), hessian_(hessian) {
    n_ = kBlock * K + NY + NU;
    m_ = kRowsPerInterval * K + kTerminalRows;
    if (hessian_ != IpoptHessian::LimitedMemory) build_hessian_structure();
    // Each attitude's target quaternion with the sign the guess's path ends at (vec(conj(q_f) q)
    // = 0 holds for either sign).
    for (int i = 0; i < NQ; ++i) {
      const Vec4 q0 = model.initial.template segment<4>(4 * i);
      Vec4 qf = model.target.template segment<4>(4 * i);
      if (q0.dot(qf) < 0.0) qf = -qf;
      Vec4 conj0 = q0;
      conj0.tail<3>() *= -1.0;
      const Vec4 rel = multiply(conj0, qf);
      const double s_half = rel.tail<3>().norm();
      Turn& t = turns_[static_cast<std::size_t>(i)];
      t.theta = 2.0 * std::atan2(s_half, rel(0));
      t.axis = s_half > 0.0 ? Vec3(rel.tail<3>() / s_half) : Vec3::UnitX();
      if (Model::opposite_half_turns && i % 2 == 1 && std::abs(t.theta - std::numbers::pi) < 1e-9) {
        t.axis = -t.axis;  // the same half turn the other way round: its path ends at -q_f
        qf = -qf;
      }
      t.q0 = q0;
      t.qf = qf;
    }
  }

  int n() const { return n_; }
  int m() const { return m_; }
  int y(int k) const { return kBlock * k; }             ///< offset of y_k (k = 0..K)
  int u(int k) const { return kBlock * k + NY; }        ///< offset of u_k
  int ym(int k) const { return kBlock * k + NY + NU; }  ///< offset of the midpoint's y
  int um(int k) const { return kBlock * k + 2 * NY + NU; }
  int mu(int k) const { return kBlock * k + 2 * NY + 2 * NU; }

  /// The constraint vector at x.
  Eigen::VectorXd constraints(const double* x) const {
    Eigen::VectorXd g(m_);
    evaluate(x, g.data(), nullptr);
    return g;
  }

  bool get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac_g, Ipopt::Index& nnz_h_lag,
                    IndexStyleEnum& style) override {
    n = n_;
    m = m_;
    nnz_jac_g = nnz();
    nnz_h_lag = static_cast<Ipopt::Index>(h_rows_.size());
    style = C_STYLE;
    return true;
  }
  int nnz() const { return K_ * (2 * NY * kWindow + 4 * NQ) + 12 * NQ + NE; }

  bool get_bounds_info(Ipopt::Index n, Ipopt::Number* x_l, Ipopt::Number* x_u, Ipopt::Index m, Ipopt::Number* g_l,
                       Ipopt::Number* g_u) override {
    for (Ipopt::Index i = 0; i < n; ++i) {
      x_l[i] = -1e19;
      x_u[i] = 1e19;
    }
    for (int i = 0; i < NY; ++i) x_l[i] = x_u[i] = model_.initial(i);
    for (Ipopt::Index i = 0; i < m; ++i) g_l[i] = g_u[i] = 0.0;
    return true;
  }

  /// Every attitude's slew about its fixed body axis (collocation.hpp), the other coordinates
  /// along the same profile.
  void starting_point(double* x) const {
    const double T = model_.t_final();
    const auto profile = [&](double t) { return t / T - std::sin(2.0 * std::numbers::pi * t / T) / (2.0 * std::numbers::pi); };
    // A tilt about a body axis perpendicular to the turn's, out and back (guess_tilt radians at the
    // middle): a rotation of the pendulum about the vertical alone cannot be steered by its
    // control (its moment R^T e3 x u has no vertical part), and from such a guess IPOPT finds the
    // linearized problem infeasible.
    const auto attitude = [&](int i, double t) {
      const Turn& tr = turns_[static_cast<std::size_t>(i)];
      const double s = profile(t);
      const Vec3 perp = tr.axis.cross(std::abs(tr.axis.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).normalized();
      const double tilt = Model::guess_tilt * std::sin(std::numbers::pi * s);
      Vec4 turn, lean;
      turn << std::cos(0.5 * s * tr.theta), std::sin(0.5 * s * tr.theta) * tr.axis;
      lean << std::cos(0.5 * tilt), std::sin(0.5 * tilt) * perp;
      return Vec4(multiply(multiply(tr.q0, turn), lean));
    };
    const auto state = [&](double t, double* at) {
      typename Model::Quaternions q;
      typename Model::Rates Omega;
      for (int i = 0; i < NQ; ++i) {
        const Vec4 qi = attitude(i, t);
        const double dt = 1e-6 * T;
        const Vec4 q_dot = (attitude(i, t + dt) - attitude(i, t - dt)) / (2.0 * dt);
        Vec4 conj = qi;
        conj.tail<3>() *= -1.0;
        q[static_cast<std::size_t>(i)] = qi;
        Omega[static_cast<std::size_t>(i)] = 2.0 * multiply(conj, q_dot).tail<3>();  // q' = 1/2 q (0, Omega)
      }
      const double s_dot = (1.0 - std::cos(2.0 * std::numbers::pi * t / T)) / T;
      typename Model::VecX xs, x_dot;
      model_.guess_positions(profile(t), s_dot, t, xs, x_dot);
      Eigen::Map<VecY> y_at(at);
      y_at = model_.state(q, Omega, xs, x_dot);
    };
    std::fill(x, x + n_, 0.0);
    for (int k = 0; k <= K_; ++k) {
      state(k * h_, x + y(k));
      if (k < K_) state((k + 0.5) * h_, x + ym(k));
    }
    Eigen::Map<VecY>(x + y(0)) = model_.initial;
    VecY last = model_.target;
    for (int i = 0; i < NQ; ++i) last.template segment<4>(4 * i) = turns_[static_cast<std::size_t>(i)].qf;
    Eigen::Map<VecY>(x + y(K_)) = last;
  }
  bool get_starting_point(Ipopt::Index, bool, Ipopt::Number* x, bool, Ipopt::Number*, Ipopt::Number*, Ipopt::Index,
                          bool, Ipopt::Number*) override {
    starting_point(x);
    return true;
  }

  bool eval_f(Ipopt::Index, const Ipopt::Number* x, bool, Ipopt::Number& f) override {
    f = cost(x);
    return std::isfinite(f);
  }
  double cost(const double* x) const {
    double J = 0.0;
    const auto L = [&](int at) {
      const Eigen::Map<const VecU> w(x + at);
      return 0.5 * w.dot(W_ * w);
    };
    for (int k = 0; k < K_; ++k) J += h_ / 6.0 * (L(u(k)) + 4.0 * L(um(k)) + L(u(k + 1)));
    return J;
  }
  bool eval_grad_f(Ipopt::Index n, const Ipopt::Number* x, bool, Ipopt::Number* g) override {
    cost_gradient(x, g, n);
    return true;
  }
  void cost_gradient(const double* x, double* g, int n) const {
    std::fill(g, g + n, 0.0);
    for (int k = 0; k < K_; ++k) {
      Eigen::Map<VecU>(g + u(k)) += h_ / 6.0 * (W_ * Eigen::Map<const VecU>(x + u(k)));
      Eigen::Map<VecU>(g + um(k)) += 4.0 * h_ / 6.0 * (W_ * Eigen::Map<const VecU>(x + um(k)));
      Eigen::Map<VecU>(g + u(k + 1)) += h_ / 6.0 * (W_ * Eigen::Map<const VecU>(x + u(k + 1)));
    }
  }
  bool eval_g(Ipopt::Index, const Ipopt::Number* x, bool, Ipopt::Index, Ipopt::Number* g) override {
    evaluate(x, g, nullptr);
    for (int i = 0; i < m_; ++i) {
      if (!std::isfinite(g[i])) return false;
    }
    return true;
  }
  /// The Jacobian's sparsity (row, column per nonzero), in the order evaluate() writes the values.
  void structure(int* iRow, int* jCol) const {
    int e = 0;
    for (int k = 0; k < K_; ++k) {
      const int row = kRowsPerInterval * k;
      for (int r = 0; r < 2 * NY; ++r) {
        for (int c = 0; c < kWindow; ++c) {
          iRow[e] = row + r;
          jCol[e++] = y(k) + c;
        }
      }
      for (int i = 0; i < NQ; ++i) {
        for (int c = 0; c < 4; ++c) {
          iRow[e] = row + 2 * NY + i;
          jCol[e++] = y(k + 1) + 4 * i + c;
        }
      }
    }
    const int row = kRowsPerInterval * K_;
    for (int i = 0; i < NQ; ++i) {
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 4; ++c) {
          iRow[e] = row + 3 * i + r;
          jCol[e++] = y(K_) + 4 * i + c;
        }
      }
    }
    for (int j = 0; j < NE; ++j) {
      iRow[e] = row + 3 * NQ + j;
      jCol[e++] = y(K_) + Model::terminal_entries[static_cast<std::size_t>(j)];
    }
  }
  bool eval_jac_g(Ipopt::Index, const Ipopt::Number* x, bool, Ipopt::Index, Ipopt::Index nele, Ipopt::Index* iRow,
                  Ipopt::Index* jCol, Ipopt::Number* values) override {
    if (values == nullptr) {
      structure(iRow, jCol);
      return nnz() == nele;
    }
    std::vector<double> g(static_cast<std::size_t>(m_));
    evaluate(x, g.data(), values);
    for (Ipopt::Index i = 0; i < nele; ++i) {
      if (!std::isfinite(values[i])) return false;
    }
    return true;
  }
  bool eval_h(Ipopt::Index, const Ipopt::Number* x, bool, Ipopt::Number sigma, Ipopt::Index m,
              const Ipopt::Number* lambda, bool, Ipopt::Index nele, Ipopt::Index* iRow, Ipopt::Index* jCol,
              Ipopt::Number* values) override {
    if (hessian_ == IpoptHessian::LimitedMemory) return false;
    if (values == nullptr) {
      std::copy(h_rows_.begin(), h_rows_.end(), iRow);
      std::copy(h_cols_.begin(), h_cols_.end(), jCol);
      return nele == static_cast<Ipopt::Index>(h_rows_.size());
    }
    lagrangian_hessian(x, sigma, Eigen::Map<const Eigen::VectorXd>(lambda, m), values);
    for (Ipopt::Index i = 0; i < nele; ++i) {
      if (!std::isfinite(values[i])) return false;
    }
    return true;
  }

  /// The Hessian of the Lagrangian sigma J + lambda^T g at x, lower triangle in the order of
  /// h_rows_, h_cols_ (build_hessian_structure; IpoptHessian::CostOnly: sigma J's alone).
  ///
  /// The curvature is the rate's: the defect rows of interval k are linear in the variables but
  /// for f at its three points z = (y, u, mu_k) (node k, midpoint, node k + 1), so with the rows'
  /// multipliers lambda_A (Hermite) and lambda_B (Simpson) the interval contributes
  ///   sum over its points of  Hess_z (w_z^T f(z)),
  ///   w_0 = -h/8 lambda_A - h/6 lambda_B,  w_m = -4h/6 lambda_B,  w_1 = h/8 lambda_A - h/6 lambda_B,
  /// and the norm rows |q|^2 - 1 their multiplier times 2 I; the terminal rows are linear. Each
  /// point's block (n_y + n_u + NQ square) is the central difference of the exact gradient
  /// J_f(z)^T w_z along each of its coordinates, symmetrized: step eps^(1/3) max(1, |z_j|), which
  /// balances the truncation (delta^2 |d3 f| / 6) against the gradient's round-off
  /// (eps |J_f^T w| / delta), a relative error ~eps^(2/3) ~ 4e-11 (tests/ocp/test_collocation.cpp
  /// compares the assembled Hessian with differences of the whole Lagrangian's gradient). Cost:
  /// 2 n_y evaluations of f and J_f per point (rate_curvature: f is affine in u and mu), 3 points
  /// per interval.
  void lagrangian_hessian(const double* x, double sigma, const Eigen::Ref<const Eigen::VectorXd>& lambda,
                          double* values) const {
    std::fill(values, values + h_rows_.size(), 0.0);
    Local H;
    for (int k = 0; k < K_; ++k) {
      const int row = kRowsPerInterval * k;
      const VecY lamA = lambda.template segment<NY>(row), lamB = lambda.template segment<NY>(row + NY);
      const VecY w[3] = {VecY(-h_ / 8.0 * lamA - h_ / 6.0 * lamB), VecY(-4.0 * h_ / 6.0 * lamB),
                         VecY(h_ / 8.0 * lamA - h_ / 6.0 * lamB)};
      const double cost_weight[3] = {h_ / 6.0, 4.0 * h_ / 6.0, h_ / 6.0};
      for (int p = 0; p < 3; ++p) {
        const int first = point_first(k, p);
        H.setZero();
        if (hessian_ == IpoptHessian::Exact) rate_curvature(x, first, mu(k), w[p], H);
        H.template block<NU, NU>(NY, NY) += sigma * cost_weight[p] * W_;
        if (p == 2 && hessian_ == IpoptHessian::Exact) {
          for (int i = 0; i < 4 * NQ; ++i) H(i, i) += 2.0 * lambda(row + 2 * NY + i / 4);
        }
        const int* entry = point_entries_.data() + static_cast<std::size_t>(3 * k + p) * kPointEntries;
        for (int a = 0, e = 0; a < kPoint; ++a) {
          for (int b = 0; b <= a; ++b) values[entry[e++]] += H(a, b);
        }
      }
    }
  }
  int hessian_nonzeros() const { return static_cast<int>(h_rows_.size()); }
  /// The dense symmetric Hessian of the Lagrangian at x (tests).
  Eigen::MatrixXd dense_hessian(const double* x, double sigma, const Eigen::VectorXd& lambda) const {
    std::vector<double> values(h_rows_.size());
    lagrangian_hessian(x, sigma, lambda, values.data());
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n_, n_);
    for (std::size_t i = 0; i < values.size(); ++i) {
      H(h_rows_[i], h_cols_[i]) = values[i];
      H(h_cols_[i], h_rows_[i]) = values[i];
    }
    return H;
  }
  bool intermediate_callback(Ipopt::AlgorithmMode, Ipopt::Index, Ipopt::Number obj, Ipopt::Number inf_pr,
                             Ipopt::Number, Ipopt::Number, Ipopt::Number, Ipopt::Number, Ipopt::Number, Ipopt::Number,
                             Ipopt::Index, const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    out_->history_cost.push_back(obj);
    out_->history_infeasibility.push_back(inf_pr);
    return true;
  }
  void finalize_solution(Ipopt::SolverReturn, Ipopt::Index n, const Ipopt::Number* x, const Ipopt::Number*,
                         const Ipopt::Number*, Ipopt::Index, const Ipopt::Number*, const Ipopt::Number*, Ipopt::Number,
                         const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    x_.assign(x, x + n);
  }
  const std::vector<double>& solution() const { return x_; }

  /// g (and, with jac non-null, the Jacobian's values in the order of structure()).
  void evaluate(const double* x, double* g, double* jac) const {
    VecY f0, f1, fm;
    JacY J0, J1, Jm;
    int e = 0;
    const Eigen::Matrix<double, NY, NY> I = Eigen::Matrix<double, NY, NY>::Identity();
    for (int k = 0; k < K_; ++k) {
      const Eigen::Map<const VecY> yk(x + y(k)), yk1(x + y(k + 1)), ymk(x + ym(k));
      const Eigen::Map<const VecU> uk(x + u(k)), uk1(x + u(k + 1)), umk(x + um(k));
      const Eigen::Map<const VecQ> muk(x + mu(k));
      model_.rhs(yk, uk, muk, f0, jac ? &J0 : nullptr);
      model_.rhs(yk1, uk1, muk, f1, jac ? &J1 : nullptr);
      model_.rhs(ymk, umk, muk, fm, jac ? &Jm : nullptr);
      const int row = kRowsPerInterval * k;
      Eigen::Map<VecY>(g + row) = ymk - 0.5 * (yk + yk1) - h_ / 8.0 * (f0 - f1);
      Eigen::Map<VecY>(g + row + NY) = yk1 - yk - h_ / 6.0 * (f0 + 4.0 * fm + f1);
      for (int i = 0; i < NQ; ++i) g[row + 2 * NY + i] = yk1.template segment<4>(4 * i).squaredNorm() - 1.0;
      if (jac == nullptr) continue;
      // The window's columns: y_k, u_k, y_m, u_m, mu (NQ), y_{k+1}, u_{k+1}.
      Eigen::Matrix<double, NY, kWindow> A = Eigen::Matrix<double, NY, kWindow>::Zero(), B = A;
      A.template block<NY, NY>(0, 0) = -0.5 * I - h_ / 8.0 * J0.template leftCols<NY>();
      A.template block<NY, NU>(0, NY) = -h_ / 8.0 * J0.template middleCols<NU>(NY);
      A.template block<NY, NY>(0, NY + NU) = I;
      A.template middleCols<NQ>(2 * NY + 2 * NU) =
          -h_ / 8.0 * (J0.template middleCols<NQ>(NY + NU) - J1.template middleCols<NQ>(NY + NU));
      A.template block<NY, NY>(0, kBlock) = -0.5 * I + h_ / 8.0 * J1.template leftCols<NY>();
      A.template block<NY, NU>(0, kBlock + NY) = h_ / 8.0 * J1.template middleCols<NU>(NY);
      B.template block<NY, NY>(0, 0) = -I - h_ / 6.0 * J0.template leftCols<NY>();
      B.template block<NY, NU>(0, NY) = -h_ / 6.0 * J0.template middleCols<NU>(NY);
      B.template block<NY, NY>(0, NY + NU) = -4.0 * h_ / 6.0 * Jm.template leftCols<NY>();
      B.template block<NY, NU>(0, 2 * NY + NU) = -4.0 * h_ / 6.0 * Jm.template middleCols<NU>(NY);
      B.template middleCols<NQ>(2 * NY + 2 * NU) =
          -h_ / 6.0 * (J0.template middleCols<NQ>(NY + NU) + 4.0 * Jm.template middleCols<NQ>(NY + NU) +
                       J1.template middleCols<NQ>(NY + NU));
      B.template block<NY, NY>(0, kBlock) = I - h_ / 6.0 * J1.template leftCols<NY>();
      B.template block<NY, NU>(0, kBlock + NY) = -h_ / 6.0 * J1.template middleCols<NU>(NY);
      for (int r = 0; r < NY; ++r)
        for (int c = 0; c < kWindow; ++c) jac[e++] = A(r, c);
      for (int r = 0; r < NY; ++r)
        for (int c = 0; c < kWindow; ++c) jac[e++] = B(r, c);
      for (int i = 0; i < NQ; ++i)
        for (int c = 0; c < 4; ++c) jac[e++] = 2.0 * yk1(4 * i + c);
    }
    // Per attitude vec(conj(q_f) (x) q) = w_f v - w vf - vf x v (linear in q); then the imposed
    // entries of the velocity state (and positions) minus the target's.
    const int row = kRowsPerInterval * K_;
    const Eigen::Map<const VecY> yK(x + y(K_));
    for (int i = 0; i < NQ; ++i) {
      const Vec4 qf = turns_[static_cast<std::size_t>(i)].qf;
      const Vec4 qK = yK.template segment<4>(4 * i);
      const Vec3 vf = qf.tail<3>();
      Eigen::Map<Vec3>(g + row + 3 * i) = qf(0) * qK.tail<3>() - qK(0) * vf - vf.cross(qK.tail<3>());
    }
    for (int j = 0; j < NE; ++j) {
      const int at = Model::terminal_entries[static_cast<std::size_t>(j)];
      g[row + 3 * NQ + j] = yK(at) - model_.target(at);
    }
    if (jac == nullptr) return;
    for (int i = 0; i < NQ; ++i) {
      const Vec4 qf = turns_[static_cast<std::size_t>(i)].qf;
      const Vec3 vf = qf.tail<3>();
      Eigen::Matrix<double, 3, 4> D;
      D.col(0) = -vf;
      D.rightCols<3>() = qf(0) * Mat3::Identity() - so3::hat(vf);
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) jac[e++] = D(r, c);
    }
    for (int j = 0; j < NE; ++j) jac[e++] = 1.0;
  }

  /// The dense Jacobian at x (tests).
  Eigen::MatrixXd dense_jacobian(const double* x) const {
    std::vector<int> rows(static_cast<std::size_t>(nnz())), cols(rows.size());
    std::vector<double> values(rows.size()), g(static_cast<std::size_t>(m_));
    structure(rows.data(), cols.data());
    evaluate(x, g.data(), values.data());
    Eigen::MatrixXd D = Eigen::MatrixXd::Zero(m_, n_);
    for (std::size_t i = 0; i < rows.size(); ++i) D(rows[i], cols[i]) += values[i];
    return D;
  }

 private:
  struct Turn {
    Vec4 q0, qf;
    Vec3 axis;
    double theta = 0.0;
  };
  // A point's variables: its y and u (contiguous) and its interval's mu.
  static constexpr int kPoint = NY + NU + NQ;
  static constexpr int kPointEntries = kPoint * (kPoint + 1) / 2;
  using Local = Eigen::Matrix<double, kPoint, kPoint>;
  /// The first variable of point p (0 node k, 1 midpoint, 2 node k + 1) of interval k.
  int point_first(int k, int p) const { return p == 0 ? y(k) : p == 1 ? ym(k) : y(k + 1); }
  int point_variable(int k, int p, int a) const { return a < NY + NU ? point_first(k, p) + a : mu(k) + a - NY - NU; }

  /// Hess_z (w^T f(z)) at the point whose (y, u) start at `first`, with mu at `mu_at`, by central
  /// differences of J_f(z)^T w (see lagrangian_hessian) along the state's coordinates only: every
  /// model's rate is affine in (u, mu) (the controls enter as added moments and forces, mu as the
  /// kinematics' term mu q), so the (u, mu) block of the Hessian is zero and its (u, mu) x y block
  /// is read from the y columns (the tests' comparison with the whole Lagrangian's differences
  /// covers every column). n_y columns instead of n_y + n_u + NQ: 26 rate evaluations per point
  /// instead of 40 for the dumbbell. The y block symmetrized.
  void rate_curvature(const double* x, int first, int mu_at, const VecY& w, Local& H) const {
    Eigen::Matrix<double, kPoint, 1> z;
    for (int a = 0; a < NY + NU; ++a) z(a) = x[first + a];
    for (int i = 0; i < NQ; ++i) z(NY + NU + i) = x[mu_at + i];
    const double cbrt_eps = std::cbrt(std::numeric_limits<double>::epsilon());
    VecY f;
    JacY J;
    Eigen::Matrix<double, kPoint, NY> D;
    for (int j = 0; j < NY; ++j) {
      const double delta = cbrt_eps * std::max(1.0, std::abs(z(j)));
      Eigen::Matrix<double, kPoint, 1> gradient[2];
      for (int side = 0; side < 2; ++side) {
        Eigen::Matrix<double, kPoint, 1> zs = z;
        zs(j) += side == 0 ? delta : -delta;
        model_.rhs(zs.template head<NY>(), zs.template segment<NU>(NY), zs.template tail<NQ>(), f, &J);
        gradient[side] = J.transpose() * w;
      }
      D.col(j) = (gradient[0] - gradient[1]) / (2.0 * delta);
    }
    constexpr int NC = NU + NQ;  // the (u, mu) coordinates
    H.template topLeftCorner<NY, NY>() += 0.5 * (D.template topRows<NY>() + D.template topRows<NY>().transpose());
    H.template bottomLeftCorner<NC, NY>() += D.template bottomRows<NC>();
    H.template topRightCorner<NY, NC>() += D.template bottomRows<NC>().transpose();
  }

  /// The Hessian's lower-triangle structure: the union of every point's dense block (the rate's
  /// curvature, the cost's W blocks and the norm rows' diagonal all lie inside them), sorted by
  /// row then column, and each point's entries in it.
  void build_hessian_structure() {
    std::vector<std::pair<int, int>> pairs;
    const auto each_entry = [&](auto&& visit) {
      for (int k = 0; k < K_; ++k) {
        for (int p = 0; p < 3; ++p) {
          for (int a = 0; a < kPoint; ++a) {
            for (int b = 0; b <= a; ++b) {
              const int r = point_variable(k, p, a), c = point_variable(k, p, b);
              visit(std::max(r, c), std::min(r, c));
            }
          }
        }
      }
    };
    each_entry([&](int r, int c) { pairs.emplace_back(r, c); });
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    h_rows_.reserve(pairs.size());
    h_cols_.reserve(pairs.size());
    for (const auto& [r, c] : pairs) {
      h_rows_.push_back(r);
      h_cols_.push_back(c);
    }
    point_entries_.reserve(static_cast<std::size_t>(3 * K_) * kPointEntries);
    each_entry([&](int r, int c) {
      const auto at = std::lower_bound(pairs.begin(), pairs.end(), std::pair{r, c});
      point_entries_.push_back(static_cast<int>(at - pairs.begin()));
    });
  }

  const Model& model_;
  int K_;
  double h_;
  Eigen::MatrixXd W_;
  CollocationResult* out_;
  IpoptHessian hessian_;
  std::array<Turn, NQ> turns_;
  int n_ = 0, m_ = 0;
  std::vector<double> x_;
  std::vector<int> h_rows_, h_cols_, point_entries_;  ///< the Hessian's structure (IpoptHessian other than LimitedMemory)
};

/// Builds the model (which validates the problem) and runs IPOPT; bad input is InvalidInput.
template <class Model, class System, class Problem>
CollocationResult solve(const System& system, const Problem& p, const CollocationOptions& options) {
  using Nlp = CollocationNlp<Model>;
  constexpr int NY = Model::ny, NU = Model::nu, NQ = Model::nq;
  const auto wall0 = std::chrono::steady_clock::now();
  const double cpu0 = thread_cpu_seconds();
  CollocationResult out;
  CollocationSummary& S_ = out.summary;
  Eigen::MatrixXd W;
  std::optional<Model> model;
  try {
    options.validate();
    W = validated_weight(options.W, NU);
    model.emplace(system, p);
  } catch (const InvalidInput& e) {
    S_.status = CollocationStatus::InvalidInput;
    S_.message = e.what();
    return out;
  }
  const int K = options.intervals;
  Ipopt::SmartPtr<Nlp> nlp = new Nlp(*model, K, W, &out, options.hessian);
  S_.intervals = K;
  S_.variables = nlp->n();
  S_.constraints = nlp->m();
  S_.jacobian_nonzeros = nlp->nnz();
  S_.hessian_nonzeros = nlp->hessian_nonzeros();
  out.h = model->t_final() / K;
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  Ipopt::OptionsList& o = *app->Options();
  o.SetIntegerValue("print_level", 0);
  o.SetStringValue("sb", "yes");
  o.SetStringValue("hessian_approximation", options.hessian == IpoptHessian::LimitedMemory ? "limited-memory" : "exact");
  o.SetIntegerValue("max_iter", options.max_iterations);
  o.SetNumericValue("tol", 1e-9);
  o.SetNumericValue("constr_viol_tol", options.tolerance);
  o.SetNumericValue("acceptable_tol", 1e-6);
  o.SetNumericValue("acceptable_constr_viol_tol", options.tolerance);
  if (app->Initialize(std::string()) != Ipopt::Solve_Succeeded) {
    S_.status = CollocationStatus::Failed;
    S_.ipopt_status = "Initialize_Failed";
    return out;
  }
  const Ipopt::ApplicationReturnStatus status = app->OptimizeTNLP(nlp);
  S_.ipopt_status = detail::ipopt_name(status);
  S_.iterations = static_cast<int>(out.history_cost.size()) - 1;
  const std::vector<double>& x = nlp->solution();
  if (static_cast<int>(x.size()) == nlp->n() && Eigen::Map<const Eigen::VectorXd>(x.data(), nlp->n()).allFinite()) {
    const Eigen::VectorXd g = nlp->constraints(x.data());
    double defect = 0.0;
    for (int k = 0; k < K; ++k) {
      defect = std::max(defect, g.segment(Nlp::kRowsPerInterval * k, Nlp::kRowsPerInterval).cwiseAbs().maxCoeff());
    }
    S_.max_defect = defect;
    S_.cost = nlp->cost(x.data());
    out.states.resize(NY, K + 1);
    out.controls.resize(NU, 2 * K + 1);
    double drift = 0.0, normal = 0.0;
    for (int k = 0; k <= K; ++k) {
      out.states.col(k) = Eigen::Map<const typename Model::VecY>(x.data() + nlp->y(k));
      out.controls.col(2 * k) = Eigen::Map<const typename Model::VecU>(x.data() + nlp->u(k));
      for (int i = 0; i < NQ; ++i) {
        drift = std::max(drift, std::abs(out.states.col(k).template segment<4>(4 * i).norm() - 1.0));
      }
      if (k < K) {
        out.controls.col(2 * k + 1) = Eigen::Map<const typename Model::VecU>(x.data() + nlp->um(k));
        for (int i = 0; i < NQ; ++i) {
          drift = std::max(drift, std::abs(Eigen::Map<const Vec4>(x.data() + nlp->ym(k) + 4 * i).norm() - 1.0));
          normal = std::max(normal, std::abs(x[static_cast<std::size_t>(nlp->mu(k) + i)]));
        }
      }
    }
    S_.quaternion_drift = drift;
    S_.max_normal_rate = normal;
    S_.residual = model->residual(out.states.col(K));
    S_.violation = S_.residual.norm();
    const double terminal = g.tail<Nlp::kTerminalRows>().cwiseAbs().maxCoeff();
    const bool within = S_.max_defect <= options.tolerance && terminal <= options.tolerance;
    const bool success = status == Ipopt::Solve_Succeeded || status == Ipopt::Solved_To_Acceptable_Level;
    S_.status = success && within && std::isfinite(S_.cost) && std::isfinite(S_.violation)
                    ? CollocationStatus::Converged
                : status == Ipopt::Maximum_Iterations_Exceeded ? CollocationStatus::IterationLimit
                                                               : CollocationStatus::Failed;
  } else {
    S_.status = status == Ipopt::Maximum_Iterations_Exceeded ? CollocationStatus::IterationLimit
                                                             : CollocationStatus::Failed;
  }
  S_.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  S_.cpu_seconds = thread_cpu_seconds() - cpu0;
  return out;
}

using PendulumCollocationModel = AttitudeModel<Pendulum3D, PendulumMoments>;
using FreeBodyCollocationModel = AttitudeModel<FreeRigidBody, FreeBodyMoments>;

/// collocation_detail::rhs with sizes checked.
template <class Model, class System, class Problem>
void checked_rhs(const System& system, const Problem& problem, const Eigen::VectorXd& y, const Eigen::VectorXd& u,
                 const Eigen::VectorXd& mu, Eigen::VectorXd& f, Eigen::MatrixXd* jacobian) {
  if (y.size() != Model::ny || u.size() != Model::nu || mu.size() != Model::nq) {
    throw InvalidInput("y", "sizes must be " + std::to_string(Model::ny) + ", " + std::to_string(Model::nu) + ", " +
                                std::to_string(Model::nq));
  }
  const Model model(system, problem);
  typename Model::VecY out;
  typename Model::JacY J;
  model.rhs(y, u, mu, out, jacobian ? &J : nullptr);
  f = out;
  if (jacobian) *jacobian = J;
}

template <class Model, class System, class Problem>
collocation_detail::TranscriptionProbe make_probe(const System& system, const Problem& problem, int K,
                                                  const Eigen::VectorXd& x, const collocation_detail::HessianProbe& hp) {
  const Model model(system, problem);
  CollocationResult unused;
  const CollocationNlp<Model> nlp(model, K, Eigen::MatrixXd::Identity(Model::nu, Model::nu), &unused,
                                  hp.lambda.size() > 0 ? hp.hessian : IpoptHessian::LimitedMemory);
  collocation_detail::TranscriptionProbe p;
  p.x = x;
  if (p.x.size() == 0) {
    p.x.resize(nlp.n());
    nlp.starting_point(p.x.data());
  }
  if (p.x.size() != nlp.n()) throw InvalidInput("x", "must have " + std::to_string(nlp.n()) + " entries");
  p.g = nlp.constraints(p.x.data());
  p.jacobian = nlp.dense_jacobian(p.x.data());
  p.cost = nlp.cost(p.x.data());
  p.cost_gradient.resize(nlp.n());
  nlp.cost_gradient(p.x.data(), p.cost_gradient.data(), nlp.n());
  if (hp.lambda.size() > 0) {
    if (hp.lambda.size() != nlp.m()) throw InvalidInput("lambda", "must have " + std::to_string(nlp.m()) + " entries");
    p.hessian = nlp.dense_hessian(p.x.data(), hp.sigma, hp.lambda);
  }
  return p;
}

}  // namespace

void CollocationOptions::validate() const {
  kIntervals.require(intervals, "intervals");
  kTolerance.require(tolerance, "tolerance");
  kMaxIterations.require(max_iterations, "max_iterations");
  if (hessian != IpoptHessian::LimitedMemory && hessian != IpoptHessian::CostOnly && hessian != IpoptHessian::Exact) {
    throw InvalidInput("hessian", "must be limited-memory, cost or exact");
  }
}

const char* to_string(CollocationStatus s) {
  switch (s) {
    case CollocationStatus::Converged: return "converged";
    case CollocationStatus::IterationLimit: return "iteration limit";
    case CollocationStatus::Failed: return "failed";
    case CollocationStatus::InvalidInput: return "invalid input";
  }
  return "?";
}

std::string CollocationSummary::brief() const {
  if (status == CollocationStatus::InvalidInput) return std::string("invalid input: ") + message;
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "%s (%s) in %d iterations, %d intervals: cost %.10g, violation %.3g, max defect %.3g, |q| drift %.3g, "
                "%.3g s CPU",
                to_string(status), ipopt_status.c_str(), iterations, intervals, cost, violation, max_defect,
                quaternion_drift, cpu_seconds);
  return buf;
}

CollocationResult solve_collocation(const Pendulum3D& system, const TransferProblem& problem,
                                    const CollocationOptions& options) {
  return solve<PendulumCollocationModel>(system, problem, options);
}
CollocationResult solve_collocation(const FreeRigidBody& system, const TransferProblem& problem,
                                    const CollocationOptions& options) {
  return solve<FreeBodyCollocationModel>(system, problem, options);
}
CollocationResult solve_collocation(const DumbbellSpacecraft& system, const TransferProblem& problem,
                                    const CollocationOptions& options) {
  return solve<DumbbellCollocationModel>(system, problem, options);
}
CollocationResult solve_collocation(const CartPendulum& system, const CartPendulumTransfer& problem,
                                    const CollocationOptions& options) {
  return solve<CartPendulumCollocationModel>(system, problem, options);
}
CollocationResult solve_collocation(const ConnectedBodies& system, const ConnectedBodiesTransfer& problem,
                                    const CollocationOptions& options) {
  return solve<ConnectedBodiesCollocationModel>(system, problem, options);
}

namespace collocation_detail {
void attitude_rhs(const Pendulum3D& system, const Eigen::Matrix<double, 7, 1>& y, const Vec3& u, double mu,
                  Eigen::Matrix<double, 7, 1>& f, Eigen::Matrix<double, 7, 11>* jacobian) {
  const PendulumCollocationModel model(system, TransferProblem::pendulum_paper());
  model.rhs(y, u, Eigen::Matrix<double, 1, 1>::Constant(mu), f, jacobian);
}
void attitude_rhs(const FreeRigidBody& system, const Eigen::Matrix<double, 7, 1>& y, const Vec3& u, double mu,
                  Eigen::Matrix<double, 7, 1>& f, Eigen::Matrix<double, 7, 11>* jacobian) {
  const FreeBodyCollocationModel model(system, TransferProblem::pendulum_paper());
  model.rhs(y, u, Eigen::Matrix<double, 1, 1>::Constant(mu), f, jacobian);
}
void rhs(const DumbbellSpacecraft& system, const Eigen::VectorXd& y, const Eigen::VectorXd& u,
         const Eigen::VectorXd& mu, Eigen::VectorXd& f, Eigen::MatrixXd* jacobian) {
  checked_rhs<DumbbellCollocationModel>(system, TransferProblem::dumbbell_paper(), y, u, mu, f, jacobian);
}
void rhs(const CartPendulum& system, const Eigen::VectorXd& y, const Eigen::VectorXd& u, const Eigen::VectorXd& mu,
         Eigen::VectorXd& f, Eigen::MatrixXd* jacobian) {
  checked_rhs<CartPendulumCollocationModel>(system, CartPendulumTransfer::paper(), y, u, mu, f, jacobian);
}
void rhs(const ConnectedBodies& system, const Eigen::VectorXd& y, const Eigen::VectorXd& u,
         const Eigen::VectorXd& mu, Eigen::VectorXd& f, Eigen::MatrixXd* jacobian) {
  checked_rhs<ConnectedBodiesCollocationModel>(system, ConnectedBodiesTransfer::paper(), y, u, mu, f, jacobian);
}
TranscriptionProbe probe(const CartPendulum& system, const CartPendulumTransfer& problem, int K,
                         const Eigen::VectorXd& x, const HessianProbe& hessian) {
  return make_probe<CartPendulumCollocationModel>(system, problem, K, x, hessian);
}
TranscriptionProbe probe(const ConnectedBodies& system, const ConnectedBodiesTransfer& problem, int K,
                         const Eigen::VectorXd& x, const HessianProbe& hessian) {
  return make_probe<ConnectedBodiesCollocationModel>(system, problem, K, x, hessian);
}
TranscriptionProbe probe(const DumbbellSpacecraft& system, const TransferProblem& problem, int K,
                         const Eigen::VectorXd& x, const HessianProbe& hessian) {
  return make_probe<DumbbellCollocationModel>(system, problem, K, x, hessian);
}
TranscriptionProbe probe(const Pendulum3D& system, const TransferProblem& problem, int K, const Eigen::VectorXd& x, const HessianProbe& hessian) {
  return make_probe<PendulumCollocationModel>(system, problem, K, x, hessian);
}
}  // namespace collocation_detail

}  // namespace lgvi::ocp
