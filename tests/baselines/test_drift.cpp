// The quaternion and rotation-matrix models conserve nothing exactly: their unit-norm and
// orthogonality errors grow with time under every method that does not conserve quadratic
// invariants. This test pins that down, so that nobody turns a baseline into a projection method
// without noticing; renormalization is the explicit option, and it keeps the error at round-off.
//
// Free rigid body (no control) over T = 200 s (about 70 revolutions), sampled every 1 s.
//  - Drift: the error at the end exceeds a floor, the worst-case round-off of N steps
//    (roundoff(1, N) = 16 N eps, test_support.hpp: 16 eps per step, accumulated linearly; a
//    random walk would give ~sqrt(N) eps), and the worst error over the whole run exceeds
//    kGrowth times the worst over its first tenth (growth, not noise).
//  - Renormalized: every step end is a unit quaternion to round-off, so the worst error stays
//    below roundoff(1, 4) (a normalization: a few operations).
//  - gsl-rk4imp (Gauss-Legendre) conserves every quadratic invariant (|q|^2, R R^T) up to its
//    Newton tolerance: its error stays below newton_tolerance per step, summed.
#include <gtest/gtest.h>

#include "baseline_cases.hpp"

namespace lgvi::test {
namespace {

constexpr double kDriftT = 200.0;
constexpr std::size_t kSamples = 200;
constexpr double kStep = 0.01;     // fixed-step methods
constexpr double kDriftRtol = 1e-6;     // adaptive methods (the default tolerance)
constexpr double kGrowth = 3.0;    // a random walk grows by sqrt(10) ~ 3.2 over ten times the time

SolverSettings settings_for(const std::string& method) {
  return is_fixed_step(method) ? fixed(kStep) : adaptive(kDriftRtol);
}

/// The structural error of a sample: | |q| - 1 | of the raw quaternion, or ||R^T R - I||_F.
std::vector<double> structural_error(const Trajectory& tr, CoordinateModel model) {
  std::vector<double> e;
  for (std::size_t k = 0; k < tr.t.size(); ++k) {
    e.push_back(model == CoordinateModel::Matrix ? so3::orthogonality_error(tr.R[k]) : tr.quaternion_norm_error[k]);
  }
  return e;
}

Trajectory long_run(const std::string& method, CoordinateModel model) {
  static const FreeRigidBody body = free_body();
  return run_attitude(method, model, body, {}, free_body_R0(), free_body_Omega0(), uniform_times(kDriftT, kSamples),
                      settings_for(method));
}

class Drift : public ::testing::TestWithParam<Combination> {};

TEST_P(Drift, GrowsAboveRoundOff) {
  const Combination& c = GetParam();
  const Trajectory tr = long_run(c.method, c.model);
  ASSERT_TRUE(tr.stats.ok()) << tr.stats.brief();
  const std::vector<double> e = structural_error(tr, c.model);
  const double early = *std::max_element(e.begin(), e.begin() + kSamples / 10 + 1);
  const double all = *std::max_element(e.begin(), e.end());
  const double floor = roundoff(1.0, static_cast<double>(tr.stats.steps));
  std::cout << "[ drift    ] " << c.method << "/" << baselines::to_string(c.model) << ": max error to t = 20: "
            << early << ", to t = 200: " << all << ", at t = 200: " << e.back() << " (growth " << all / early
            << ", floor " << floor << ", " << tr.stats.steps << " steps)\n";
  EXPECT_GT(e.back(), floor);
  EXPECT_GT(all, kGrowth * early);
}

std::vector<Combination> drifting() {
  std::vector<Combination> c;
  for (const baselines::SolverInfo& s : baselines::solver_list()) {
    const std::string& m = s.name;
    if (m == "gsl-rk4imp") continue;  // conserves quadratic invariants: see below
    // The projection method (cvode-bdf-projected) keeps |q| = 1 and R^T R = I by design:
    // test_projection.cpp holds it to round-off.
    if (s.projects_onto_invariants) continue;
    for (const CoordinateModel model : {CoordinateModel::Quaternion, CoordinateModel::Matrix}) c.push_back({m, model});
  }
  return c;
}
INSTANTIATE_TEST_SUITE_P(All, Drift, ::testing::ValuesIn(drifting()),
                         [](const auto& info) { return combination_name(info.param); });

class Renormalized : public ::testing::TestWithParam<std::string> {};

TEST_P(Renormalized, StaysAtRoundOff) {
  const Trajectory tr = long_run(GetParam(), CoordinateModel::QuaternionRenormalized);
  ASSERT_TRUE(tr.stats.ok()) << tr.stats.brief();
  double raw = 0.0, orthogonality = 0.0;
  for (std::size_t k = 0; k < tr.t.size(); ++k) {
    raw = std::max(raw, tr.quaternion_norm_error[k]);
    orthogonality = std::max(orthogonality, so3::orthogonality_error(tr.R[k]));
  }
  std::cout << "[ renorm   ] " << GetParam() << ": max | |q| - 1 | of the samples " << raw
            << ", max orthogonality error of R " << orthogonality << "\n";
  // R comes from the normalized quaternion: orthogonal to round-off whatever the sampling.
  EXPECT_LT(orthogonality, roundoff(1.0, 4));
  if (!is_fixed_step(GetParam())) {
    // Adaptive methods interpolate the output times (their dense output, or the Hermite
    // interpolant): the raw samples lie between two normalized steps, off the unit sphere by the
    // local error, which does not accumulate (the model normalizes them for R).
    EXPECT_LT(raw, 10 * kDriftRtol);
  } else {
    EXPECT_LT(raw, roundoff(1.0, 4));  // the samples are step ends
  }
}

std::vector<std::string> renormalizing() {
  std::vector<std::string> m;
  for (const baselines::SolverInfo& s : baselines::solver_list()) {
    if (s.post_step_hook) m.push_back(s.name);
  }
  return m;
}
INSTANTIATE_TEST_SUITE_P(All, Renormalized, ::testing::ValuesIn(renormalizing()), [](const auto& info) {
  std::string n = info.param;
  for (char& ch : n) {
    if (ch == '-') ch = '_';
  }
  return n;
});

TEST(GaussLegendre, ConservesQuadraticInvariantsToItsNewtonTolerance) {
  for (const CoordinateModel model : {CoordinateModel::Quaternion, CoordinateModel::Matrix}) {
    const Trajectory tr = long_run("gsl-rk4imp", model);
    ASSERT_TRUE(tr.stats.ok()) << tr.stats.brief();
    const std::vector<double> e = structural_error(tr, model);
    const double all = *std::max_element(e.begin(), e.end());
    const double bound = SolverSettings{}.newton_tolerance * static_cast<double>(tr.stats.steps);
    std::cout << "[ gauss    ] gsl-rk4imp/" << baselines::to_string(model) << ": max structural error " << all
              << " over " << tr.stats.steps << " steps (bound " << bound << ")\n";
    EXPECT_LT(all, bound);
  }
}

}  // namespace
}  // namespace lgvi::test
