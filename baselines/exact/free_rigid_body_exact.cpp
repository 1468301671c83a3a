#include "baselines/exact/free_rigid_body_exact.hpp"

#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

#include "lgvi/inertia.hpp"
#include "lgvi/so3.hpp"

namespace lgvi::baselines {

namespace {


/// The rotation B with B m = |m| e3 of the header: rows (m2, -m1, 0)/rho, b3 x b1, m/|m|.
/// Precondition: rho = |(m1, m2)| > 0.
Mat3 momentum_frame(const Vec3& m) {
  const double rho = std::hypot(m.x(), m.y());
  const double G = m.norm();
  Mat3 B;
  B << m.y() / rho, -m.x() / rho, 0.0,                              //
      m.z() * m.x() / (G * rho), m.z() * m.y() / (G * rho), -rho / G,  //
      m.x() / G, m.y() / G, m.z() / G;
  return B;
}

Mat3 rotation_about_e3(double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  Mat3 Z;
  Z << c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0;
  return Z;
}

double sign(double x) { return x < 0.0 ? -1.0 : 1.0; }

}  // namespace

FreeRigidBodyExact::FreeRigidBodyExact(const Mat3& J, const Mat3& R0, const Vec3& Omega0, InertiaDomain domain)
    : R0_(R0), Omega0_(Omega0) {
  const Inertia inertia = Inertia::from(J, "inertia", domain);
  require_finite(R0, "R0");
  if (!so3::is_rotation(R0, 1e-10)) throw InvalidInput("R0", "is not a rotation matrix (R^T R != I or det R != 1)");
  require_finite(Omega0, "Omega0");

  // A rotation about a principal axis is steady: Pi' = Pi x Omega vanishes (to the rounding of
  // Pi = J Omega, a few eps |Pi| |Omega|).
  const Vec3 Pi0 = inertia.J * Omega0;
  if (Pi0.cross(Omega0).norm() <= 16.0 * kEps * Pi0.norm() * Omega0.norm()) {
    regime_ = Regime::SteadyRotation;
    return;
  }

  // Principal axes, moments ascending: smallest s, intermediate m, largest l.
  const Eigen::SelfAdjointEigenSolver<Mat3> eigen(inertia.J);
  const Vec3 I = eigen.eigenvalues();
  const Mat3 V = eigen.eigenvectors();
  const Vec3 w = V.transpose() * Omega0;
  // G^2 - 2 E I2 = I_l (I_l - I_m) w_l^2 - I_s (I_m - I_s) w_s^2: a sum of a positive and a
  // negative term, so it is decided to the rounding of those terms.
  const double toward_largest = I(2) * (I(2) - I(1)) * w(2) * w(2);
  const double toward_smallest = I(0) * (I(1) - I(0)) * w(0) * w(0);
  const double separatrix_distance = toward_largest - toward_smallest;
  if (std::abs(separatrix_distance) <= 16.0 * kEps * (toward_largest + toward_smallest)) {
    throw InvalidInput("Omega0", "lies on the separatrix G^2 = 2 E I2 (the homoclinic motion through the "
                                 "intermediate axis); no closed form is computed for it");
  }
  const bool around_largest = separatrix_distance > 0.0;
  regime_ = around_largest ? Regime::AroundLargestAxis : Regime::AroundSmallestAxis;
  const int order[3] = {around_largest ? 0 : 2, 1, around_largest ? 2 : 0};
  for (int i = 0; i < 3; ++i) {
    Q_.col(i) = V.col(order[i]);
    moments_(i) = I(order[i]);
  }
  if (Q_.determinant() < 0.0) Q_.col(1) = -Q_.col(1);  // still a principal axis; now a rotation

  const double I1 = moments_(0), I2 = moments_(1), I3 = moments_(2);
  const Vec3 Om = Q_.transpose() * Omega0;
  // The ratios below are positive in both orders (numerator and denominator change sign together).
  const double a2 = Om(0) * Om(0) + Om(1) * Om(1) * I2 * (I3 - I2) / (I1 * (I3 - I1));
  const double b2 = Om(1) * Om(1) + Om(0) * Om(0) * I1 * (I3 - I1) / (I2 * (I3 - I2));
  const double c2 = Om(2) * Om(2) + Om(1) * Om(1) * I2 * (I2 - I1) / (I3 * (I3 - I1));
  const double k2 = (I2 - I1) * I1 * a2 / ((I3 - I2) * I3 * c2);
  const double k = std::sqrt(k2);
  // 1 - k^2 = (G^2 - 2 E I2) / ((I3 - I2) I3 c^2): from the separatrix distance, not 1 - k^2.
  const double k_complement = std::sqrt(separatrix_distance / ((I3 - I2) * I3 * c2));
  if (!(k < 1.0) || k_complement * k_complement / (1.0 + k) < exact_detail::kMinimumDistanceToSeparatrix) {
    throw InvalidInput("Omega0", "is within 1 - k = " + std::to_string(exact_detail::kMinimumDistanceToSeparatrix) +
                                     " of the separatrix G^2 = 2 E I2 (k = " + std::to_string(k) +
                                     "), where the elliptic integrals lose their digits");
  }
  a_ = std::sqrt(a2);
  b_ = std::sqrt(b2);
  c_ = sign(Om(2)) * std::sqrt(c2);
  lambda_ = sign(I3 - I2) * c_ * std::sqrt((I3 - I2) * (I3 - I1) / (I1 * I2));
  jacobi_ = exact_detail::Jacobi(k, k_complement);
  // cn w0 = Omega1 / a, sn w0 = Omega2 / b: the amplitude of w0 (any quadrant; F extends).
  w0_ = jacobi_.argument_of_amplitude(std::atan2(Om(1) / b_, Om(0) / a_));

  momentum_ = (moments_.asDiagonal() * Om).norm();
  const double n = -I3 * (I2 - I1) / (I1 * (I3 - I2));
  phase_ = exact_detail::SnSquaredIntegral(jacobi_, 1.0, -n);
  const double G_over = momentum_ * (I3 - I1) / (I1 * I3);
  precession_rate_ = momentum_ / I3 + G_over * phase_.mean();
  precession_coefficient_ = G_over / lambda_;
  const exact_detail::JacobiPoint p0 = jacobi_.at(w0_);
  periodic0_ = phase_.periodic(p0);
  // B(0) from the same formulas state(0) uses, so that state(0).R reproduces R0 to rounding.
  const Vec3 m0 = moments_.asDiagonal() * Vec3(a_ * p0.cn, b_ * p0.sn, c_ * p0.dn);
  Y_ = R0_ * Q_ * momentum_frame(m0).transpose();
}

double FreeRigidBodyExact::period() const {
  if (regime_ == Regime::SteadyRotation) return std::numeric_limits<double>::infinity();
  return 4.0 * jacobi_.quarter_period() / std::abs(lambda_);
}

ExactState FreeRigidBodyExact::state(double t) const {
  if (!std::isfinite(t)) throw InvalidInput("t", "must be finite");
  if (regime_ == Regime::SteadyRotation) return {R0_ * so3::exp(t * Omega0_), Omega0_};
  const exact_detail::JacobiPoint p = jacobi_.at(lambda_ * t + w0_);
  const Vec3 Om(a_ * p.cn, b_ * p.sn, c_ * p.dn);
  const Vec3 m = moments_.asDiagonal() * Om;
  const double phi = precession_rate_ * t + precession_coefficient_ * (phase_.periodic(p) - periodic0_);
  return {Y_ * rotation_about_e3(phi) * momentum_frame(m) * Q_.transpose(), Q_ * Om};
}

}  // namespace lgvi::baselines
