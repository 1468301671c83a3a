// Jacobi elliptic functions with the argument reduced to one half-period, and the phase
// integrals of the exact solutions (free rigid body, Lagrange top) built on them.
//
// Why reduce: the exact solutions evaluate sn, cn, dn at w = nu t + w0, which grows without
// bound with t. Here w = 2 K j + r with |r| <= K, and sn(w) = (-1)^j sn(r), cn(w) = (-1)^j cn(r),
// dn(w) = dn(r) (DLMF 22.4.2), so every special function sees an argument of at most K; what
// remains of a long horizon is the rounding of w itself (eps |w|), which no evaluation of the
// solution at a floating-point t can avoid.
//
// Boost.Math (header-only) provides the functions; this header does not expose it. Its dn is
// replaced by sqrt(k'^2 + k^2 cn^2): Boost 1.74 returns dn wrong by up to 4e-4 at r = K.
#pragma once

namespace lgvi::baselines::exact_detail {

/// sn, cn, dn at w, with w = 2 K j + r, |r| <= K (amplitude am(r) in [-pi/2, pi/2]).
struct JacobiPoint {
  double w = 0.0;
  double j = 0.0;  ///< half-periods, an integer-valued double
  double r = 0.0;
  double sn_r = 0.0, cn_r = 1.0, dn_r = 1.0;  ///< at r (cn_r >= 0)
  double sn = 0.0, cn = 1.0, dn = 1.0;        ///< at w
};

/// Closest approach to the separatrix k = 1 the exact solutions accept: 1 - k >= this. Boost's
/// incomplete Pi loses digits as k -> 1 (measured against 50-digit arithmetic, absolute error at
/// am -> pi/2: 1.4e-15 at 1 - k = 1e-3, 1.1e-14 at 1e-5, 7e-14 at 1e-7, 1.1e-11 at 1e-9; the
/// Jacobi functions themselves stay at 5e-17), which the solutions multiply by O(1) rates; below
/// 1e-8 the attitude would carry more than ~1e-12.
inline constexpr double kMinimumDistanceToSeparatrix = 1e-8;

/// Jacobi elliptic functions of modulus k in [0, 1) (not the parameter m = k^2).
class Jacobi {
 public:
  /// Precondition: 0 <= k < 1 (the callers reject the separatrix k = 1). k_complement =
  /// sqrt(1 - k^2), passed when the caller knows it more accurately than 1 - k^2 gives it.
  explicit Jacobi(double k);
  Jacobi(double k, double k_complement);
  double k() const { return k_; }
  double k_complement() const { return k_complement_; }
  /// The complete elliptic integral of the first kind K(k), the quarter-period of sn.
  double quarter_period() const { return K_; }
  JacobiPoint at(double w) const;
  /// The incomplete integral of the first kind F(phi | k): the w with am(w) = phi.
  double argument_of_amplitude(double phi) const;
  /// The incomplete integral of the second kind E(phi | k).
  double second_kind(double phi) const;
  /// The point at w + K (direction +1) or w - K (-1) from the point at w, by the quarter-period
  /// shifts sn(z + K) = cd z, cn(z + K) = -k' sd z, dn(z + K) = k' nd z (and z - K: -cd, k' sd,
  /// k' nd; DLMF 22.4.3), without evaluating the functions again. Why: the point keeps the
  /// relative accuracy of small sn at the far end (near w = K of the original), where evaluating
  /// at w + K directly would carry the absolute rounding eps K of the argument.
  JacobiPoint shifted(const JacobiPoint& p, int direction) const;

 private:
  double k_;
  double k_complement_;
  double K_;
};

/// The integral of 1 / (p + q sn^2(v | k)) over v, for p > 0 and p + q > 0 (the integrand is
/// positive and bounded), split into its mean and a periodic remainder:
///     int_0^w dv / (p + q sn^2 v) = mean() w + periodic(w),
/// periodic(w) odd with period 2K. In closed form int_0^r = Pi(-q/p; am r | k) / p with the
/// incomplete integral of the third kind Pi(n; phi | k) = int_0^phi dt / ((1 - n sin^2 t)
/// sqrt(1 - k^2 sin^2 t)) (DLMF 19.2.7, Boost.Math's convention), and over a half-period
/// 2 Pi(-q/p | k) / p.
///
/// Small |q/p| <= kSmallCharacteristic (a nearly axisymmetric body, a nearly steady precession): the periodic part
/// is O(q/p) while the integral and the mean times w are O(w), and the callers divide it by
/// rates that are then small too (measured: the free body's precession lost 1e-7 to that
/// cancellation). So it is formed without it, from Pi = F + (n/3) sin^3 R_J(cos^2, dn^2, 1,
/// 1 - n sin^2) (Carlson, DLMF 19.25.14) and F(am r) = r:
///     periodic(r) = n / (3p) [sn^3 R_J(cn^2, dn^2, 1, 1 - n sn^2) - (r / K) R_J(0, k'^2, 1, 1 - n)].
/// (Not for large |n|: there the two terms of Pi = F + ... cancel instead.)
///
/// Large q/p (a sharp peak of the integrand at sn = 0: the Euler-angle chart passing close to a
/// pole): Boost's incomplete Pi loses all accuracy for -n beyond ~1e17 (measured against 50-digit
/// arithmetic: 1e-16 relative at n = -1e16, 1e6 at n = -1e20; the complete integral stays
/// accurate). Beyond kLargeRatio the integral is split as
///     1/(p + q s^2) = cn dn / (p + q s^2) + (1 - cn dn) / (p + q s^2),
/// the first part integrating to atan(sqrt(q/p) sn) / sqrt(p q) exactly, the second (bounded,
/// no peak on |r| <= K where cn >= 0) replaced by its p -> 0 limit
///     int (1 - cn dn) / (q sn^2) = (r - E(am r) + sn (1 + k^2 cn^2) / (1 + cn dn)) / q,
/// whose error is O(sqrt(p/q) / q) relative to 1/q, below 1e-8 / q there; the callers
/// multiply this integral by a coefficient that is O(sqrt(p)), so the state error is
/// O(p / q) <= 1e-16.
class SnSquaredIntegral {
 public:
  static constexpr double kLargeRatio = 1e16;
  /// |n| up to which the periodic part is formed by Carlson's R_J (measured against 50-digit
  /// arithmetic, error / (|n| / p) <= 3e-16 there; toward n -> 1 Boost's Pi is the better one).
  static constexpr double kSmallCharacteristic = 0.5;

  /// Preconditions: p > 0, p + q > 0, finite.
  SnSquaredIntegral(const Jacobi& jacobi, double p, double q);
  /// The mean of the integrand over a period: 2 Pi(-q/p | k) / (2 K p).
  double mean() const { return mean_; }
  /// int_0^w minus mean() w, from the reduced point of w.
  double periodic(const JacobiPoint& at) const;

 private:
  double integral_over_r(const JacobiPoint& at) const;  ///< int_0^r, |r| <= K

  Jacobi jacobi_;  // three doubles: held by value, so the owners stay copyable
  double p_, q_;
  double n_;  ///< -q/p, the characteristic of Pi
  double mean_;
};

}  // namespace lgvi::baselines::exact_detail
