// The tolerances of the adaptive methods: their default and their one range, checked where a
// method's settings are validated (baselines/solver.hpp resolve_settings, which every baseline run
// and the harness's MethodOptions go through; the harness's rkmk45, make_rkmk45) and by the
// readers that take a tolerance from a user (study files). The CLI and the Python module reach it
// through those. lie_group.hpp's integrate_rkmk45 itself takes any positive tolerance: its tests
// step with rtol = 1 to force one step of a chosen size.
#pragma once

#include <cmath>
#include <string>

#include "lgvi/inertia.hpp"
#include "lgvi/range.hpp"

namespace lgvi::baselines {

/// Default relative tolerance of the adaptive methods; atol defaults to rtol (the states are
/// O(1): quaternion and matrix entries are bounded by 1, angles by pi, rates of order 1-10; with
/// atol = rtol the control is rtol (1 + |y_i|), which does not collapse at zero crossings).
inline constexpr double kDefaultRtol = 1e-6;

/// The range of rtol and atol of every adaptive method (the baselines' resolve_settings, the
/// harness's rkmk45; the CLI's --rtol/--atol, the study files' tolerances and the Python module
/// check against it through check_tolerance): [kMinTolerance, kMaxTolerance] = [1e-14, 0.1].
///
/// Above 0.1 (an error of 10% per step) a run is no solution (rtol = 1e308 ran to a non-finite
/// state). The floor: the local error test of component i is err_i <= atol + rtol |y_i|, and
/// err_i, a difference of two solutions of the step, carries the rounding of the state, eps
/// times the state's scale (eps = 2.2e-16; the models' states are O(1): quaternion and matrix
/// entries at most 1, angles at most pi, rates 1-10). A tolerance near eps is met by rounding
/// luck, not by a shorter step; a component that crosses zero (where atol alone is the bound)
/// takes its rounding from the O(1) components its rotation mixes into it, so atol has the same
/// floor as rtol. Below it the step control chases rounding: with atol = 1e-300 (rtol 1e-6)
/// odeint-rkf78 on the free body spent its budget of 5e7 steps at t = 0 (28.6 s), on the
/// pendulum it ran for more than 30 s; the initial states have components exactly 0. The floor
/// 1e-14 = 45 eps is the tightest tolerance the project itself uses (gsl-rk8pd references at
/// rtol = atol = 1e-14, tests/baselines); there every adaptive method completes every shipped
/// scene, the slowest arkode-dirk on connected-bodies in 3.6 s, the others' runs at most 0.9 s
/// (docs/cli.md).
inline constexpr double kMinTolerance = 1e-14;
inline constexpr double kMaxTolerance = 0.1;
inline constexpr Range kToleranceRange = Range::numbers(kMinTolerance, kMaxTolerance);

/// Throws InvalidInput(field, reason) unless value lies in kToleranceRange: below it "is below
/// round-off: ..." (the reason names the floor and why), above it or not finite "must be a
/// number in [1e-14, 0.1] (got 2)". `field` names the option as the caller's user knows it
/// ("rtol", "--atol", "tolerances[2]").
inline void check_tolerance(double value, const std::string& field) {
  if (kToleranceRange.contains(value)) return;
  if (std::isfinite(value) && value > 0.0 && value < kMinTolerance) {
    throw InvalidInput(field, "is below round-off: no step size meets a tolerance under " +
                                  Range::text(kMinTolerance) + " (45 eps relative to the O(1) states; "
                                  "baselines/tolerance.hpp); " + kToleranceRange.problem(value));
  }
  throw InvalidInput(field, kToleranceRange.problem(value));
}

}  // namespace lgvi::baselines
