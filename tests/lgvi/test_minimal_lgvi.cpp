// The step benchmark's floor reference, the minimal LGVI (experiments/benchmarks/minimal_lgvi.hpp),
// against the project's step (AttitudeLgvi, symmetric form, Cayley chart) from the benchmark's
// states (experiments/benchmarks/step_cases.hpp): both solve eqs. 8, 9, 11 / 21-23 with the same
// convergence test, so they must step alike to round-off, or the benchmark's floor is not a floor
// of the same computation.
//
// 1. One step: the states agree to kStepBound = 16 eps (R by |dR|_F, Pi relative to |Pi|;
//    step_agreement.hpp derives it: F from two Newton solves of the same equation, each within
//    a few eps of the root, then one product). The Newton iterations are equal, the project's
//    polishing step (not in the minimal step) left out of its count.
// 2. 1000 steps (10 s of the free body, 1 s of the tumbling pendulum): the per-step differences
//    delta_k and each map's local round-off (<= kStepBound) propagate through the tangent map of
//    the project's flow, G_N = max_{m <= N} ||D Phi^m|| measured from perturbed trajectories, so
//      e_N <= 2 G_N (sum_k delta_k + 2 N kStepBound)     (worst case, all round-offs aligned)
//    and, as round-off walks at random, e_N <= 4 D_N with D_N the project's trajectory against
//    itself started 4 eps away along each tangent direction (step_agreement.hpp). Iteration
//    counts (polishing left out) may differ where |G| lands within round-off of the tolerance:
//    asserted in at most 1% of the steps.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <memory>
#include <string>

#include "experiments/benchmarks/minimal_lgvi.hpp"
#include "experiments/benchmarks/step_cases.hpp"
#include "lgvi/lgvi.hpp"
#include "lgvi/so3.hpp"
#include "step_agreement.hpp"
#include "test_support.hpp"

namespace lgvi::test {
namespace {

using benchmarks::AttitudeCase;
using benchmarks::MinimalLgvi;

/// The project's step as the reference map, its Newton iterations counted without the polishing
/// step (the minimal step does not polish).
template <class System>
RotationUpdateSummary project_step(const AttitudeLgvi<System>& lgvi, const AttitudeState& in,
                                   double h, AttitudeState& out) {
  const Vec3 u = Vec3::Zero();
  RotationUpdateSummary s = lgvi.step(in, h, u, u, out);
  if (s.polished) --s.iterations;
  return s;
}

/// The minimal step as a map with a summary (converged, its iteration count).
template <class System>
RotationUpdateSummary minimal_step(const MinimalLgvi<System>& minimal, const AttitudeState& in,
                                   double h, AttitudeState& out) {
  out = in;
  RotationUpdateSummary s;
  s.iterations = minimal.step(out, h);
  s.status =
      s.iterations >= 0 ? RotationUpdateStatus::Converged : RotationUpdateStatus::NotConverged;
  return s;
}

/// The comparison of the minimal step (as "fast") with the project's (as "reference") for a case.
template <class System>
StepCase<AttitudeState> minimal_case(const AttitudeCase<System>& bench_case, double pi_scale) {
  auto system = std::make_shared<System>(bench_case.system);
  auto lgvi = std::make_shared<AttitudeLgvi<System>>(*system);
  auto minimal = std::make_shared<MinimalLgvi<System>>(*system);
  const double h = bench_case.h;
  StepCase<AttitudeState> c;
  c.name = bench_case.name + " minimal vs project";
  c.fast = [system, minimal, h](const AttitudeState& in, AttitudeState& out) {
    return minimal_step(*minimal, in, h, out);
  };
  c.reference = [system, lgvi, h](const AttitudeState& in, AttitudeState& out) {
    return project_step(*lgvi, in, h, out);
  };
  set_attitude_geometry<AttitudeLgvi<System>>(c, lgvi, pi_scale, system);
  return c;
}

template <class System>
void expect_one_step_agreement(const AttitudeCase<System>& c) {
  const AttitudeLgvi<System> lgvi(c.system);
  const MinimalLgvi<System> minimal(c.system);
  const AttitudeState s0 = lgvi.make_state(c.R0, c.Omega0);
  ASSERT_EQ(minimal.make_state(c.R0, c.Omega0).Pi, s0.Pi);
  AttitudeState a, b;
  const RotationUpdateSummary ra = minimal_step(minimal, s0, c.h, a);
  const RotationUpdateSummary rb = project_step(lgvi, s0, c.h, b);
  ASSERT_TRUE(ra.converged() && rb.converged()) << c.name;
  const double dR = (a.R - b.R).norm();
  const double dPi = (a.Pi - b.Pi).norm() / b.Pi.norm();
  std::cout << "[ measured ] " << c.name << ", one step: |dR|_F " << dR / kEps << " eps, |dPi|/|Pi| "
            << dPi / kEps << " eps; Newton iterations " << ra.iterations << " (minimal), "
            << rb.iterations << " (project, without polishing)\n";
  EXPECT_LE(dR, kStepBound) << c.name;
  EXPECT_LE(dPi, kStepBound) << c.name;
  if (System::has_potential) {
    EXPECT_LE((a.M - b.M).norm(), kStepBound * b.M.norm()) << c.name;  // M(R): one product of R
  }
  EXPECT_EQ(ra.iterations, rb.iterations) << c.name;
}

TEST(MinimalLgvi, OneStepAgreesWithTheProjectStep) {
  expect_one_step_agreement(benchmarks::free_body_case());
  expect_one_step_agreement(benchmarks::pendulum_case());
}

TEST(MinimalLgvi, AgreesWithTheProjectStepOver1000Steps) {
  const auto free_body = benchmarks::free_body_case();
  const auto pendulum = benchmarks::pendulum_case();
  const AttitudeLgvi free_body_lgvi(free_body.system);
  const AttitudeLgvi pendulum_lgvi(pendulum.system);
  const AttitudeState free_body_s0 = free_body_lgvi.make_state(free_body.R0, free_body.Omega0);
  const AttitudeState pendulum_s0 = pendulum_lgvi.make_state(pendulum.R0, pendulum.Omega0);
  expect_agreement(minimal_case(free_body, free_body_s0.Pi.norm()), free_body_s0, 1000);
  expect_agreement(minimal_case(pendulum, pendulum_s0.Pi.norm()), pendulum_s0, 1000);
}

}  // namespace
}  // namespace lgvi::test
