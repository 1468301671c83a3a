// Attitude coordinates of the continuous-time baselines: the unit quaternion, Euler angles
// (3-2-1, yaw-pitch-roll) and the rotation matrix itself, each with its kinematic equation
// R' = R hat(Omega) written in its own variables, the analytic Jacobians of that equation, the
// map back to a matrix R (the output, compared like with like with the LGVI's R) and its
// Jacobian.
//
// A chart C provides (c is C::Coords, a fixed-size vector of C::size entries):
//   from_rotation(R)          coordinates of a rotation (the initial state)
//   rotation(c)               R(c); off the chart's constraint set (|q| != 1, R^T R != I) this is
//                             what the formula gives, so the drift shows in R's diagnostics
//   rotation_jacobian(c)      d vec(R) / dc, vec row-major (R11 R12 R13 R21 ... R33): 9 x size
//   rate(c, Omega)            dc/dt for the body angular velocity Omega
//   rate_jacobian(c, Omega)   d rate / dc (size x size);  rate_omega_jacobian(c): d rate / dOmega
// The charts never normalize on their own: a baseline that conserves nothing shows it.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Dense>

#include "lgvi/so3.hpp"
#include "lgvi/types.hpp"

namespace lgvi::baselines {

using Mat9x3 = Eigen::Matrix<double, 9, 3>;

/// vec(A) row-major: (A11, A12, A13, A21, ..., A33), the order of the CSV columns R11..R33.
inline Eigen::Matrix<double, 9, 1> vec_rows(const Mat3& A) {
  Eigen::Matrix<double, 9, 1> v;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) v(3 * i + j) = A(i, j);
  }
  return v;
}

/// Unit quaternion q = (w, x, y, z) = (cos(theta/2), sin(theta/2) n) with body angular velocity.
///
/// Kinematics q' = 1/2 q (x) (0, Omega) (quaternion product): the right-hand side is linear in q
/// with a skew-symmetric matrix, so |q| is a first integral of the exact flow but not of a
/// Runge-Kutta or multistep discretization (except Gauss methods, which conserve every quadratic
/// invariant).
/// Rotation: R(q) = (w^2 - |v|^2) I + 2 v v^T + 2 w hat(v), v = (x, y, z): the matrix of
/// p -> q p q* (the sandwich product). Homogeneous of degree 2, it equals |q|^2 R(q/|q|) for
/// |q| != 1, so R^T R = |q|^4 I: the orthogonality error of the reconstructed R is
/// sqrt(3) | |q|^4 - 1 | ~ 4 sqrt(3) | |q| - 1 |, independent of the attitude. (The other common
/// form I + 2 w hat(v) + 2 hat(v)^2 agrees on unit quaternions; off them its error depends on the
/// rotation angle.)
struct QuaternionChart {
  static constexpr int size = 4;
  static constexpr const char* name = "quaternion";
  using Coords = Eigen::Matrix<double, 4, 1>;

  /// The unit quaternion of R with w >= 0 (Eigen's Shepperd-type conversion, then normalized).
  static Coords from_rotation(const Mat3& R) {
    Eigen::Quaterniond q(R);
    q.normalize();
    Coords c(q.w(), q.x(), q.y(), q.z());
    return c(0) < 0.0 ? Coords(-c) : c;
  }

  static Mat3 rotation(const Coords& q) {
    const double w = q(0);
    const Vec3 v = q.tail<3>();
    return (w * w - v.squaredNorm()) * Mat3::Identity() + 2.0 * v * v.transpose() + 2.0 * w * so3::hat(v);
  }

  static Eigen::Matrix<double, 9, 4> rotation_jacobian(const Coords& q) {
    const double w = q(0);
    const Vec3 v = q.tail<3>();
    Eigen::Matrix<double, 9, 4> D;
    D.col(0) = vec_rows(2.0 * w * Mat3::Identity() + 2.0 * so3::hat(v));
    for (int i = 0; i < 3; ++i) {
      const Vec3 e = Vec3::Unit(i);
      D.col(1 + i) = vec_rows(-2.0 * v(i) * Mat3::Identity() + 2.0 * (e * v.transpose() + v * e.transpose()) +
                             2.0 * w * so3::hat(e));
    }
    return D;
  }

  /// q' = 1/2 (-v . Omega, w Omega + v x Omega).
  static Coords rate(const Coords& q, const Vec3& Omega) {
    const Vec3 v = q.tail<3>();
    Coords r;
    r(0) = -0.5 * v.dot(Omega);
    r.tail<3>() = 0.5 * (q(0) * Omega + v.cross(Omega));
    return r;
  }
  /// 1/2 [[0, -Omega^T], [Omega, -hat(Omega)]] (skew-symmetric).
  static Eigen::Matrix<double, 4, 4> rate_jacobian(const Coords& /*q*/, const Vec3& Omega) {
    Eigen::Matrix<double, 4, 4> D;
    D(0, 0) = 0.0;
    D.block<1, 3>(0, 1) = -0.5 * Omega.transpose();
    D.block<3, 1>(1, 0) = 0.5 * Omega;
    D.block<3, 3>(1, 1) = -0.5 * so3::hat(Omega);
    return D;
  }
  /// 1/2 [[-v^T], [w I + hat(v)]].
  static Eigen::Matrix<double, 4, 3> rate_omega_jacobian(const Coords& q) {
    const Vec3 v = q.tail<3>();
    Eigen::Matrix<double, 4, 3> D;
    D.row(0) = -0.5 * v.transpose();
    D.block<3, 3>(1, 0) = 0.5 * (q(0) * Mat3::Identity() + so3::hat(v));
    return D;
  }

  /// | |q| - 1 |: the unit-norm error.
  static double norm_error(const Coords& q) { return std::abs(q.norm() - 1.0); }
};

/// Euler angles, sequence 3-2-1 (yaw psi about e3, then pitch theta about the new e2, then roll
/// phi about the new e1): R = Rz(psi) Ry(theta) Rx(phi), coordinates c = (phi, theta, psi).
/// The body angular velocity is Omega = B(phi, theta) (phi', theta', psi') with
/// B = [e1, (0, cos phi, -sin phi), (-sin theta, sin phi cos theta, cos phi cos theta)], so
///     phi'   = p + (q sin phi + r cos phi) tan theta,
///     theta' = q cos phi - r sin phi,
///     psi'   = (q sin phi + r cos phi) / cos theta,            Omega = (p, q, r),
/// singular at cos theta = 0 (pitch +-90 deg, gimbal lock: roll and yaw turn about the same axis).
///
/// Singular set threshold |cos theta| < kGimbalThreshold = sqrt(eps) ~ 1.49e-8 (pitch within
/// 8.5e-7 deg of +-90 deg). Why: near pi/2, theta is represented with an absolute error of
/// ~eps pi/2 ~ 3.5e-16, which is the absolute error of cos theta; the rates divide by cos theta,
/// so at |cos theta| = c they carry a relative round-off error of 3.5e-16 / c: sqrt(eps) is where
/// half the digits are gone (the same balance as a finite-difference step), and where the rates
/// reach |Omega| / sqrt(eps) ~ 7e7 |Omega|. Closer than that the right-hand side is noise, so
/// the model stops there with a status rather than producing numbers.
struct EulerChart {
  static constexpr int size = 3;
  static constexpr const char* name = "euler";
  using Coords = Eigen::Matrix<double, 3, 1>;
  static inline const double kGimbalThreshold = std::sqrt(std::numeric_limits<double>::epsilon());

  /// Angles of R: theta = -asin(R31) in [-pi/2, pi/2], phi = atan2(R32, R33),
  /// psi = atan2(R21, R11). At gimbal lock (|R31| = 1) phi and psi are not unique; the model
  /// then stops at t = 0 (see singular()).
  static Coords from_rotation(const Mat3& R) {
    const double theta = -std::asin(std::clamp(R(2, 0), -1.0, 1.0));
    return Coords(std::atan2(R(2, 1), R(2, 2)), theta, std::atan2(R(1, 0), R(0, 0)));
  }

  static Mat3 rotation(const Coords& c) {
    const double sf = std::sin(c(0)), cf = std::cos(c(0));
    const double st = std::sin(c(1)), ct = std::cos(c(1));
    const double sp = std::sin(c(2)), cp = std::cos(c(2));
    Mat3 R;
    R << ct * cp, sf * st * cp - cf * sp, cf * st * cp + sf * sp,  //
        ct * sp, sf * st * sp + cf * cp, cf * st * sp - sf * cp,   //
        -st, sf * ct, cf * ct;
    return R;
  }

  /// B(phi, theta): Omega = B c'. Its columns are also the body-frame directions of
  /// dR/dphi, dR/dtheta, dR/dpsi: dR/dc_j = R hat(B e_j).
  static Mat3 omega_matrix(const Coords& c) {
    const double sf = std::sin(c(0)), cf = std::cos(c(0));
    const double st = std::sin(c(1)), ct = std::cos(c(1));
    Mat3 B;
    B << 1.0, 0.0, -st,  //
        0.0, cf, sf * ct,  //
        0.0, -sf, cf * ct;
    return B;
  }

  static Eigen::Matrix<double, 9, 3> rotation_jacobian(const Coords& c) {
    const Mat3 R = rotation(c);
    const Mat3 B = omega_matrix(c);
    Eigen::Matrix<double, 9, 3> D;
    for (int j = 0; j < 3; ++j) D.col(j) = vec_rows(R * so3::hat(B.col(j)));
    return D;
  }

  /// |theta| at which |cos theta| reaches the threshold: acos(sqrt(eps)) = pi/2 - 1.49e-8.
  static inline const double kGimbalPitch = std::acos(kGimbalThreshold);

  /// True on the singular set |cos theta| < kGimbalThreshold (the rates are not evaluated there).
  static bool singular(const Coords& c) { return !(std::abs(std::cos(c(1))) >= kGimbalThreshold); }
  /// Event function kGimbalPitch - |theta|: > 0 while |cos theta| > threshold, 0 where it reaches
  /// it. theta starts in [-pi/2, pi/2] and can leave (-pi/2, pi/2) only through the singular set,
  /// so measuring the distance in theta keeps the function negative however far a step overshoots
  /// (a function of cos theta is periodic: one long step of a steady spin can jump a whole turn
  /// and come back positive, which happened with odeint's dopri5 on a linear pitch).
  static double singularity_function(const Coords& c) { return kGimbalPitch - std::abs(c(1)); }

  /// Precondition: !singular(c).
  static Coords rate(const Coords& c, const Vec3& Omega) {
    const double sf = std::sin(c(0)), cf = std::cos(c(0));
    const double ct = std::cos(c(1)), tt = std::tan(c(1));
    const double a = Omega(1) * sf + Omega(2) * cf;
    return Coords(Omega(0) + a * tt, Omega(1) * cf - Omega(2) * sf, a / ct);
  }
  /// With a = q sin phi + r cos phi, b = q cos phi - r sin phi (da/dphi = b, db/dphi = -a):
  /// d phi'/d(phi, theta) = (b tan theta, a / cos^2 theta), d theta'/dphi = -a,
  /// d psi'/d(phi, theta) = (b / cos theta, a sin theta / cos^2 theta); nothing depends on psi.
  static Mat3 rate_jacobian(const Coords& c, const Vec3& Omega) {
    const double sf = std::sin(c(0)), cf = std::cos(c(0));
    const double st = std::sin(c(1)), ct = std::cos(c(1));
    const double a = Omega(1) * sf + Omega(2) * cf;
    const double b = Omega(1) * cf - Omega(2) * sf;
    Mat3 D;
    D << b * st / ct, a / (ct * ct), 0.0,  //
        -a, 0.0, 0.0,                     //
        b / ct, a * st / (ct * ct), 0.0;
    return D;
  }
  /// B^{-1} = [[1, sin phi tan theta, cos phi tan theta], [0, cos phi, -sin phi],
  ///          [0, sin phi / cos theta, cos phi / cos theta]].
  static Mat3 rate_omega_jacobian(const Coords& c) {
    const double sf = std::sin(c(0)), cf = std::cos(c(0));
    const double ct = std::cos(c(1)), tt = std::tan(c(1));
    Mat3 D;
    D << 1.0, sf * tt, cf * tt,  //
        0.0, cf, -sf,            //
        0.0, sf / ct, cf / ct;
    return D;
  }
};

/// The rotation matrix as 9 states (row-major), R' = R hat(Omega): linear in R, so any
/// discretization keeps R's rows' Gram matrix R R^T only if it conserves quadratic invariants
/// (Gauss methods); every other method drifts off SO(3).
struct MatrixChart {
  static constexpr int size = 9;
  static constexpr const char* name = "matrix";
  using Coords = Eigen::Matrix<double, 9, 1>;

  static Coords from_rotation(const Mat3& R) { return vec_rows(R); }
  static Mat3 rotation(const Coords& c) {
    Mat3 R;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) R(i, j) = c(3 * i + j);
    }
    return R;
  }
  static Eigen::Matrix<double, 9, 9> rotation_jacobian(const Coords& /*c*/) {
    return Eigen::Matrix<double, 9, 9>::Identity();
  }
  static Coords rate(const Coords& c, const Vec3& Omega) { return vec_rows(rotation(c) * so3::hat(Omega)); }
  /// (R hat(Omega))_ij = sum_k R_ik hat(Omega)_kj: row i of R' depends on row i of R only,
  /// through hat(Omega)^T.
  static Eigen::Matrix<double, 9, 9> rate_jacobian(const Coords& /*c*/, const Vec3& Omega) {
    Eigen::Matrix<double, 9, 9> D = Eigen::Matrix<double, 9, 9>::Zero();
    const Mat3 Wt = so3::hat(Omega).transpose();
    for (int i = 0; i < 3; ++i) D.block<3, 3>(3 * i, 3 * i) = Wt;
    return D;
  }
  /// d(R hat(Omega))/dOmega_m = R hat(e_m).
  static Eigen::Matrix<double, 9, 3> rate_omega_jacobian(const Coords& c) {
    const Mat3 R = rotation(c);
    Eigen::Matrix<double, 9, 3> D;
    for (int m = 0; m < 3; ++m) D.col(m) = vec_rows(R * so3::hat(Vec3::Unit(m)));
    return D;
  }
};

}  // namespace lgvi::baselines
