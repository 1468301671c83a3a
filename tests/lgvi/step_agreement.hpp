// Agreement of two step maps of the same flow to round-off, along a trajectory: the per-step
// difference, and the trajectories' distance against the bound of its propagation by the flow's
// tangent map. Used by test_reference_agreement.cpp (the fast steps against the pre-optimization
// reference) and test_minimal_lgvi.cpp (the step benchmark's minimal LGVI against the project's
// step).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "lgvi/lgvi.hpp"
#include "lgvi/rotation_update.hpp"
#include "lgvi/so3.hpp"
#include "test_support.hpp"

namespace lgvi::test {

/// A system's fast and reference steps with the helpers the comparison needs.
template <class State>
struct StepCase {
  std::string name;
  std::function<RotationUpdateSummary(const State&, State&)> fast, reference;
  /// Distance in units where eps is meaningful: attitudes by |R_a - R_b|_F, momenta and other
  /// variables relative to their initial size, combined in the Euclidean norm.
  std::function<double(const State&, const State&)> distance;
  /// The state perturbed by eps along tangent direction i (0 <= i < dimension), with any cached
  /// quantity (moment, forces) recomputed.
  std::function<State(const State&, int, double)> perturb;
  int dimension;
};

/// An attitude case's distance and perturbations, the state (R, Pi) made and its cached moment
/// recomputed by `lgvi` (an AttitudeLgvi, kept alive by the case with `owner`, e.g. its system):
/// |R_a - R_b|_F combined with |Pi_a - Pi_b| / pi_scale; directions 0-2 move R by
/// R exp(eps e_i), 3-5 move Pi by eps pi_scale e_i.
template <class Lgvi>
void set_attitude_geometry(StepCase<AttitudeState>& c, std::shared_ptr<const Lgvi> lgvi,
                           double pi_scale, std::shared_ptr<const void> owner = nullptr) {
  c.distance = [pi_scale](const AttitudeState& a, const AttitudeState& b) {
    return std::hypot((a.R - b.R).norm(), (a.Pi - b.Pi).norm() / pi_scale);
  };
  c.perturb = [lgvi, owner, pi_scale](const AttitudeState& s, int i, double eps) {
    if (i < 3) return lgvi->make_state(s.R * so3::exp(eps * Vec3::Unit(i)), lgvi->omega(s));
    AttitudeState t = lgvi->make_state(s.R, lgvi->omega(s));
    t.Pi += eps * pi_scale * Vec3::Unit(i - 3);
    return t;
  };
  c.dimension = 6;
}

struct StepComparison {
  double max_step_difference = 0.0;  ///< max_k delta_k in distance units
  double sum_step_difference = 0.0;  ///< sum_k delta_k
  double final_difference = 0.0;     ///< e_N
  double growth = 0.0;               ///< G_N
  double self_divergence = 0.0;      ///< max_i |x_N - x_N^(i)|, x^(i) from s0 moved 4 eps along i
  int iteration_mismatches = 0;
};

/// Runs both maps N steps from s0. With y_k the fast trajectory and x_k the reference one,
///   e_N = |y_N - x_N| = |sum_k Phi^{N-k-1}(fast(y_k)) - Phi^{N-k-1}(ref(y_k))|
///       <= sum_k ||D Phi^{N-k-1}|| delta_k,   delta_k = distance(fast(y_k), ref(y_k))
/// (Phi the reference map), so delta_k is measured along the fast trajectory. G_N from
/// `dimension` reference trajectories started eps = 1e-7 away along each tangent direction: for
/// the tangent map M, ||M|| <= ||M||_F = sqrt(sum_i |M e_i|^2) (eps = 1e-7 keeps the nonlinear
/// terms, ~eps G^2, and the round-off noise of the perturbed runs, ~N eps_mach G / eps, below
/// 1e-3 relative for G < 1e4).
template <class State>
StepComparison compare(const StepCase<State>& c, const State& s0, int steps) {
  StepComparison r;
  constexpr double kPerturbation = 1e-7;
  std::vector<State> perturbed, nudged;
  std::vector<double> initial_distance;
  for (int i = 0; i < c.dimension; ++i) {
    perturbed.push_back(c.perturb(s0, i, kPerturbation));
    initial_distance.push_back(c.distance(perturbed.back(), s0));
    nudged.push_back(c.perturb(s0, i, 4.0 * kEps));
  }
  State ref = s0, fast = s0;
  for (int k = 0; k < steps; ++k) {
    State next_fast, check;
    const RotationUpdateSummary a = c.fast(fast, next_fast);
    const RotationUpdateSummary b = c.reference(fast, check);
    EXPECT_TRUE(a.converged() && b.converged()) << c.name << " step " << k;
    if (!a.converged() || !b.converged() || !c.reference(ref, ref).converged()) return r;
    r.iteration_mismatches += a.iterations != b.iterations;
    const double delta = c.distance(next_fast, check);
    r.max_step_difference = std::max(r.max_step_difference, delta);
    r.sum_step_difference += delta;
    fast = next_fast;
    double tangent2 = 0.0;
    for (int i = 0; i < c.dimension; ++i) {
      c.reference(perturbed[i], perturbed[i]);
      c.reference(nudged[i], nudged[i]);
      const double g = c.distance(perturbed[i], ref) / initial_distance[i];
      tangent2 += g * g;
    }
    r.growth = std::max(r.growth, std::sqrt(tangent2));
  }
  r.final_difference = c.distance(fast, ref);
  for (const State& x : nudged) r.self_divergence = std::max(r.self_divergence, c.distance(x, ref));
  return r;
}

/// The per-step bound: F differs by the residual bound of the solver test above, at most
/// ~sqrt(2) sensitivity (r_a + r_b) |h p| with r <= 4 eps after polishing (sensitivity <= 1/J_min
/// ~ 1/|h p| units: a few eps relative) plus forming F (8 flops); R F and F^T kick pass it on
/// with one more product (3 flops of 1). Asserted as 16 eps: "a few eps". The same bound holds
/// for the local round-off rho of either map against its exact-arithmetic value (the distance
/// of each from the exact solution is what the argument bounds).
inline constexpr double kStepBound = 16.0 * kEps;

// The trajectory bounds. The first-order propagation above treats the reference map Phi as
// smooth; in floating point it is not: once the trajectories differ at all, each step rounds
// differently on the two, and those local round-offs rho (<= kStepBound each) propagate like
// delta_k. Measured: with the delta_k alone the bound G_N sum delta_k failed for the free body
// (4.8e-11 against 1.1e-11). So
//   (a) e_N <= 2 G_N (sum_k delta_k + 2 N kStepBound),
// worst case (all round-offs aligned); the factor 2 because G_N, the growth from the start over
// all N steps, bounds the growth from y_k over the remaining N - k steps only approximately (it
// is larger for linear and exponential growth alike, but the growth rate varies along the
// trajectory). Round-off is rather a random walk (e ~ G sqrt(N) rho), and the sharp statement
// of "the same to round-off" is
//   (b) e_N <= 4 D_N, D_N = max_i |x_N - x_N^(i)|, the reference against itself started 4 eps
//       away along each tangent direction i:
// the fast path moves the trajectory no more than the reference's own sensitivity to a few eps
// (the factor 4 for the spread of one random-walk sample against a maximum of 2n).
template <class State>
void expect_agreement(const StepCase<State>& c, const State& s0, int steps) {
  const StepComparison r = compare(c, s0, steps);
  const double worst_case = 2.0 * r.growth * (r.sum_step_difference + 2.0 * steps * kStepBound);
  std::cout << "[ measured ] " << c.name << ", " << steps << " steps: per-step difference max "
            << r.max_step_difference / kEps << " eps, sum " << r.sum_step_difference / kEps
            << " eps; tangent growth G_N " << r.growth << "; final difference e_N "
            << r.final_difference << " (worst-case bound " << worst_case
            << ", reference from 4 eps away D_N " << r.self_divergence
            << "); iteration counts differ in " << r.iteration_mismatches << " steps\n";
  EXPECT_LE(r.max_step_difference, kStepBound) << c.name;
  EXPECT_LE(r.final_difference, worst_case) << c.name;
  EXPECT_LE(r.final_difference, 4.0 * r.self_divergence) << c.name;
  EXPECT_LE(r.iteration_mismatches, steps / 100) << c.name;
}

}  // namespace lgvi::test
