#include "baselines/exact/elliptic.hpp"

#include <cmath>

#include <boost/math/special_functions/ellint_1.hpp>
#include <boost/math/special_functions/ellint_2.hpp>
#include <boost/math/special_functions/ellint_3.hpp>
#include <boost/math/special_functions/ellint_rj.hpp>
#include <boost/math/special_functions/jacobi_elliptic.hpp>

namespace lgvi::baselines::exact_detail {

Jacobi::Jacobi(double k) : Jacobi(k, std::sqrt((1.0 - k) * (1.0 + k))) {}

Jacobi::Jacobi(double k, double k_complement) : k_(k), k_complement_(k_complement), K_(boost::math::ellint_1(k)) {}

JacobiPoint Jacobi::shifted(const JacobiPoint& p, int direction) const {
  // The reduced argument moves by +-K; when it leaves [-K, K] it wraps by one half-period.
  JacobiPoint q;
  q.w = p.w + direction * K_;
  const double cd = p.cn_r / p.dn_r, sd = p.sn_r / p.dn_r;
  q.dn_r = k_complement_ / p.dn_r;
  const bool wraps = direction > 0 ? p.r > 0.0 : p.r < 0.0;
  q.j = wraps ? p.j + direction : p.j;
  // Unwrapped: r + K (sn cd, cn -k' sd) or r - K (sn -cd, cn k' sd); a wrap changes r by
  // -+2K, flipping both signs, which keeps cn_r >= 0 on the new reduced argument.
  const double sign = (direction > 0) == !wraps ? 1.0 : -1.0;
  q.r = wraps ? p.r - direction * K_ : p.r + direction * K_;
  q.sn_r = sign * cd;
  q.cn_r = -sign * k_complement_ * sd;
  const bool odd = std::fmod(std::fabs(q.j), 2.0) == 1.0;
  q.sn = odd ? -q.sn_r : q.sn_r;
  q.cn = odd ? -q.cn_r : q.cn_r;
  q.dn = q.dn_r;
  return q;
}

JacobiPoint Jacobi::at(double w) const {
  JacobiPoint p;
  p.w = w;
  const double half_period = 2.0 * K_;
  p.j = std::nearbyint(w / half_period);
  p.r = std::fma(-half_period, p.j, w);
  double dn_boost = 1.0;
  p.sn_r = boost::math::jacobi_elliptic(k_, p.r, &p.cn_r, &dn_boost);
  // Boost 1.74's dn is wrong near odd multiples of K (measured against 50-digit arithmetic: 4e-4
  // at r = K, 1e-8 at K (1 - 1e-12); sn and cn stay within 1.5e-16): dn^2 = k'^2 + k^2 cn^2
  // instead, a sum of positive terms, from the accurate cn.
  p.dn_r = std::sqrt(k_complement_ * k_complement_ + k_ * k_ * p.cn_r * p.cn_r);
  const bool odd = std::fmod(std::fabs(p.j), 2.0) == 1.0;
  p.sn = odd ? -p.sn_r : p.sn_r;
  p.cn = odd ? -p.cn_r : p.cn_r;
  p.dn = p.dn_r;
  return p;
}

double Jacobi::argument_of_amplitude(double phi) const { return boost::math::ellint_1(k_, phi); }

double Jacobi::second_kind(double phi) const { return boost::math::ellint_2(k_, phi); }

SnSquaredIntegral::SnSquaredIntegral(const Jacobi& jacobi, double p, double q)
    : jacobi_(jacobi), p_(p), q_(q), n_(-q / p) {
  // Complete integral over a half-period: 2 Pi(n | k) / p; the mean divides by 2K.
  const double K = jacobi_.quarter_period();
  if (std::abs(n_) <= kSmallCharacteristic) {
    const double kc = jacobi_.k_complement();
    mean_ = (1.0 + n_ / (3.0 * K) * boost::math::ellint_rj(0.0, kc * kc, 1.0, 1.0 - n_)) / p_;
  } else {
    mean_ = boost::math::ellint_3(jacobi_.k(), n_) / (p_ * K);
  }
}

double SnSquaredIntegral::integral_over_r(const JacobiPoint& at) const {
  const double amplitude = std::atan2(at.sn_r, at.cn_r);  // in [-pi/2, pi/2]: cn_r >= 0
  if (q_ <= kLargeRatio * p_) return boost::math::ellint_3(jacobi_.k(), n_, amplitude) / p_;
  // The peak part exactly, the bounded remainder in its p -> 0 limit (see the header).
  const double k2 = jacobi_.k() * jacobi_.k();
  const double peak = std::atan(std::sqrt(q_ / p_) * at.sn_r) / std::sqrt(p_ * q_);
  // (1 - cn dn) / sn = sn (1 + k^2 cn^2) / (1 + cn dn): no cancellation at small sn.
  const double remainder = (at.r - jacobi_.second_kind(amplitude) +
                            at.sn_r * (1.0 + k2 * at.cn_r * at.cn_r) / (1.0 + at.cn_r * at.dn_r)) /
                           q_;
  return peak + remainder;
}

double SnSquaredIntegral::periodic(const JacobiPoint& at) const {
  if (std::abs(n_) <= kSmallCharacteristic) {
    if (n_ == 0.0) return 0.0;
    const double kc = jacobi_.k_complement();
    const double sn2 = at.sn_r * at.sn_r;
    return n_ / (3.0 * p_) *
           (sn2 * at.sn_r * boost::math::ellint_rj(at.cn_r * at.cn_r, at.dn_r * at.dn_r, 1.0, 1.0 - n_ * sn2) -
            at.r / jacobi_.quarter_period() * boost::math::ellint_rj(0.0, kc * kc, 1.0, 1.0 - n_));
  }
  return integral_over_r(at) - mean_ * at.r;
}

}  // namespace lgvi::baselines::exact_detail
