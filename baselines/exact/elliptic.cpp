#include "baselines/exact/elliptic.hpp"

#include <cmath>

#include <boost/math/special_functions/ellint_1.hpp>
#include <boost/math/special_functions/ellint_2.hpp>
#include <boost/math/special_functions/ellint_3.hpp>
#include <boost/math/special_functions/jacobi_elliptic.hpp>

namespace lgvi::baselines::exact_detail {

Jacobi::Jacobi(double k) : k_(k), K_(boost::math::ellint_1(k)) {}

JacobiPoint Jacobi::at(double w) const {
  JacobiPoint p;
  p.w = w;
  const double half_period = 2.0 * K_;
  p.j = std::nearbyint(w / half_period);
  p.r = std::fma(-half_period, p.j, w);
  p.sn_r = boost::math::jacobi_elliptic(k_, p.r, &p.cn_r, &p.dn_r);
  const bool odd = std::fmod(std::fabs(p.j), 2.0) == 1.0;
  p.sn = odd ? -p.sn_r : p.sn_r;
  p.cn = odd ? -p.cn_r : p.cn_r;
  p.dn = p.dn_r;
  return p;
}

double Jacobi::argument_of_amplitude(double phi) const { return boost::math::ellint_1(k_, phi); }

double Jacobi::second_kind(double phi) const { return boost::math::ellint_2(k_, phi); }

SnSquaredIntegral::SnSquaredIntegral(const Jacobi& jacobi, double p, double q) : jacobi_(jacobi), p_(p), q_(q) {
  // Complete integral over a half-period: 2 Pi(-q/p | k) / p; the mean divides by 2K.
  mean_ = boost::math::ellint_3(jacobi_.k(), -q_ / p_) / (p_ * jacobi_.quarter_period());
}

double SnSquaredIntegral::integral_over_r(const JacobiPoint& at) const {
  const double amplitude = std::atan2(at.sn_r, at.cn_r);  // in [-pi/2, pi/2]: cn_r >= 0
  if (q_ <= kLargeRatio * p_) return boost::math::ellint_3(jacobi_.k(), -q_ / p_, amplitude) / p_;
  // The peak part exactly, the bounded remainder in its p -> 0 limit (see the header).
  const double k2 = jacobi_.k() * jacobi_.k();
  const double peak = std::atan(std::sqrt(q_ / p_) * at.sn_r) / std::sqrt(p_ * q_);
  // (1 - cn dn) / sn = sn (1 + k^2 cn^2) / (1 + cn dn): no cancellation at small sn.
  const double remainder = (at.r - jacobi_.second_kind(amplitude) +
                            at.sn_r * (1.0 + k2 * at.cn_r * at.cn_r) / (1.0 + at.cn_r * at.dn_r)) /
                           q_;
  return peak + remainder;
}

double SnSquaredIntegral::periodic(const JacobiPoint& at) const { return integral_over_r(at) - mean_ * at.r; }

}  // namespace lgvi::baselines::exact_detail
