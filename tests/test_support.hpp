// Shared test support: the seeded random generator and the derived tolerances, in one place.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <random>
#include <string>

#include "lgvi/types.hpp"

namespace lgvi::test {

using lgvi::kEps;  // lgvi/types.hpp: the one machine epsilon


/// Seed for every randomized test: LGVI_TEST_SEED overrides the default; the seed is printed
/// so that a failure can be replayed.
inline std::uint64_t test_seed() {
  static const std::uint64_t seed = [] {
    std::uint64_t s = 20261121;
    if (const char* env = std::getenv("LGVI_TEST_SEED")) s = std::strtoull(env, nullptr, 10);
    std::cout << "[ seed     ] LGVI_TEST_SEED=" << s << "\n";
    return s;
  }();
  return seed;
}
inline std::mt19937_64 make_rng(std::uint64_t salt = 0) { return std::mt19937_64(test_seed() + salt); }

// --- Derived tolerances ---------------------------------------------------------------------
// Central finite differences with step a have truncation error O(a^2) and round-off
// O(eps/a); a = eps^(1/3) ~ 6e-6 balances them at ~eps^(2/3) ~ 4e-11 relative. We assert
// with a 1e3 safety factor for the constants (third derivatives of order 1..10).
constexpr double kFdStep = 6.0554544523933395e-06;  // cbrt(eps)
constexpr double kFdTolerance = 1e3 * 3.666852862501036e-11;  // 1e3 * eps^(2/3)

/// Round-off of a quantity computed by O(n) floating-point operations of magnitude `scale`:
/// a few eps per operation, counted generously as 16 n eps scale.
inline double roundoff(double scale, double operations = 1.0) { return 16.0 * operations * kEps * scale; }

// An O(1) 3x3 result (exp, Cayley, Jacobians, R^T R) is built in <= 8 flops per entry on
// quantities of size <= 2 (|a| <= 1, |b hat(w)^2| = 1 - cos <= 2); roundoff() counts 16 eps per
// flop, which also covers the factor 3 of a Frobenius norm over 9 entries: 128 eps ~ 2.8e-14.
inline const double kMatTol = roundoff(1.0, 8);

// Long LGVI runs (10^5-10^6 steps): round-off alone predicts far less. Each step perturbs R by
// ~eps and the momentum by ~eps |Pi|; a random walk over n = 1e6 steps gives ~sqrt(n) eps
// ~ 1e-13, a systematic bias at worst n eps ~ 2e-10 (which the momentum bound would catch).
inline constexpr double kOrthogonalityBound = 1e-12;
inline constexpr double kMomentumRelativeBound = 1e-10;

// The acceptance band of a fitted convergence slope against the nominal order (the order tests).
inline constexpr double kOrderTolerance = 0.1;

/// Slope of the least-squares line through (log x_i, log y_i).
template <class Vec>
double loglog_slope(const Vec& x, const Vec& y) {
  const std::size_t n = x.size();
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double lx = std::log(x[i]), ly = std::log(y[i]);
    sx += lx; sy += ly; sxx += lx * lx; sxy += lx * ly;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

// --- Optimal control (tests/ocp) -------------------------------------------------------------
// Linearizations A_k, B_k and sensitivities Psi against central differences: the issue fixes
// the step (1e-6, scaled by the size of the perturbed variable) and the bound (1e-6 relative).
// Expected: truncation a^2 |f'''| / 6 ~ 1e-12 and round-off eps |f| / a ~ 2e-10 relative, so
// the bound has a margin of ~1e3.
constexpr double kOcpFdStep = 1e-6;
constexpr double kOcpFdTolerance = 1e-6;
// Gradients of a cost by central differences with the balanced step kFdStep: compared with
// the adjoint gradient to kFdTolerance relative to the gradient's norm (see above).
// Terminal violation the shooting must reach (the acceptance bound).
constexpr double kOcpViolation = 1e-12;

// --- Continuous sensitivities and shooting (tests/baselines) ----------------------------------
// Integration tolerance of the CVODES sensitivities under test.
constexpr double kSensRtol = 1e-10;
// Global error of an adaptive run over the O(1) horizons used, as a multiple of rtol (states and
// sensitivities of order 1..10; the baselines' README measures global errors of 1..100 rtol).
constexpr double kSensGlobalErrorPerRtol = 1e3;
// Finite differences of the baseline flow: step a, flow tolerance rtol_fd. Error
// a^2 |y'''| / 6 + kSensGlobalErrorPerRtol rtol_fd / a ~ 2e-9 + 1e-6 worst case, plus the
// sensitivities' own 1e3 rtol; asserted relative to |S| with that sum.
constexpr double kSensFdStep = 1e-4;
constexpr double kSensFdRtol = 1e-13;
constexpr double kSensFdTolerance =
    kSensFdStep * kSensFdStep + kSensGlobalErrorPerRtol * kSensFdRtol / kSensFdStep + kSensGlobalErrorPerRtol * kSensRtol;
// Observed order of convergence: 2 +- 0.2.
constexpr double kSensOrderTolerance = 0.2;

}  // namespace lgvi::test
