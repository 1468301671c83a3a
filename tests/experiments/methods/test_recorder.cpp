// The recorder refuses a sample with a non-finite value (a finite state whose energy overflows):
// the run stops with status NonFiniteState naming the step, the time and the quantity, and no
// row with inf or NaN is written.
#include "experiments/methods/recorder.hpp"

#include <cmath>
#include <functional>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "experiments/cli/cli_support.hpp"
#include "experiments/methods/method.hpp"
#include "experiments/methods/simulate.hpp"

namespace lgvi::experiments {
namespace {

using test::TempDir;

TEST(Recorder, AFiniteStateWithAnInfiniteEnergyIsRefusedAndNamed) {
  const Scene scene = load_scene(test::default_scene_file("free-body"));
  Recorder recorder(scene.model, 1, nullptr);
  Sample sample = sample_of(scene.model);
  ASSERT_TRUE(recorder.record(0, sample));
  // Omega1 = 1e160 with J1 = 0.13: Pi1 = 1.3e159 is finite, E = Omega1 Pi1 / 2 = 6.5e318 is not.
  sample.t = 0.5;
  state_of<FreeBodyModel>(sample).Omega = Vec3(1e160, 0.0, 0.0);
  EXPECT_FALSE(recorder.record(1, sample));
  EXPECT_EQ(recorder.samples(), 1u);  // nothing of the refused sample kept
  EXPECT_EQ(recorder.last().t, 0.0);
  EXPECT_EQ(recorder.diagnostics().max_abs_energy_error, 0.0);
  Stats stats;
  stats.steps = 1;
  recorder.stop_on_non_finite(stats);
  EXPECT_EQ(stats.status, IntegrationStatus::NonFiniteState);
  EXPECT_EQ(stats.failed_step, 1u);
  EXPECT_EQ(stats.failed_time, 0.5);
  EXPECT_EQ(stats.brief().rfind("non-finite state at step 1 (t = 0.5): energy is not finite in the sample of this "
                                "step, though the state is",
                                0),
            0u)
      << stats.brief();
  // A non-finite state entry is named as a state column.
  Recorder second(scene.model, 1, nullptr);
  state_of<FreeBodyModel>(sample).Omega = Vec3(0.0, std::numeric_limits<double>::quiet_NaN(), 0.0);
  EXPECT_FALSE(second.record(0, sample));
  Stats other;
  second.stop_on_non_finite(other);
  EXPECT_EQ(other.failure_detail.rfind("Omega2 is not finite in the sample of this step (overflow: the state", 0), 0u)
      << other.failure_detail;
}

TEST(Recorder, AFiniteRunKeepsItsStatus) {
  const Scene scene = load_scene(test::default_scene_file("free-body"));
  Recorder recorder(scene.model, 1, nullptr);
  ASSERT_TRUE(recorder.record(0, sample_of(scene.model)));
  Stats stats;
  recorder.stop_on_non_finite(stats);
  EXPECT_TRUE(stats.ok());
}

// A dumbbell pushed by a constant force of 1e100 for one step of h = 1e55 (every input within
// the scene ranges): v1 = h u / m = 1e155 and x1 = h^2 u / (2 m) = 5e209 are finite, the kinetic
// energy m |v1|^2 / 2 = 5e309 is not. The rod lies along x and the body is at rest: no gravity
// moment, so the rotation update stays at F = I. The LGVI and a fixed-step baseline both stop
// at step 1 with the energy named, and their CSVs hold the first row only.
TEST(Recorder, ARunWhoseEnergyOverflowsStopsWithTheQuantityNamed) {
  const std::string text = R"(system = "dumbbell"
[parameters]
mass = 1.0
mu = 1.0
rho = [0.15, 0.0, 0.0]
sphere_radius = 0.05
[initial]
x = [1.0, 0.0, 0.0]
v = [0.0, 0.0, 0.0]
Omega = [0.0, 0.0, 0.0]
[control.force]
type = "constant"
value = [1e100, 0.0, 0.0]
[integration]
h = 1e55
t_final = 1e55
)";
  const Scene scene = parse_scene(text, "overflow.toml");
  TempDir dir;
  for (const std::string method : {"lgvi", "odeint-rk4"}) {
    MethodOptions options;
    if (method != "lgvi") options.model = "quaternion";
    const RunSummary run = simulate(scene, *make_method(method, options), {dir.work() / (method + ".csv"), "", {}});
    EXPECT_EQ(run.stats.status, IntegrationStatus::NonFiniteState) << method << ": " << run.stats.brief();
    EXPECT_EQ(run.stats.failed_step, 1u) << method;
    EXPECT_NE(run.stats.brief().find("energy is not finite"), std::string::npos) << method << ": " << run.stats.brief();
    EXPECT_EQ(run.output_rows, 1u) << method;
    // The lines that are not metadata: the header and one row, finite.
    std::istringstream csv(test::read_text(dir.work() / (method + ".csv")));
    std::vector<std::string> lines;
    for (std::string line; std::getline(csv, line);) {
      if (!line.starts_with("#")) lines.push_back(line);
    }
    ASSERT_EQ(lines.size(), 2u) << method;
    EXPECT_EQ(lines[1].find("inf"), std::string::npos) << method << ": " << lines[1];
    EXPECT_EQ(lines[1].find("nan"), std::string::npos) << method << ": " << lines[1];
  }
}

// EnergyTrend: the one-pass least-squares line through E - E0 and its verdict.
EnergyTrend trend_of(const std::function<double(double)>& e, double t0, double T, std::size_t n, double energy = 1.0) {
  EnergyTrend f;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = t0 + T * static_cast<double>(i) / static_cast<double>(n - 1);
    f.add(i * 100, t, energy + e(t), e(t));
  }
  return f;
}

TEST(EnergyTrend, ALineIsFittedExactlyEvenFarFromTheOrigin) {
  // Centred updates: at t ~ 1e8 the raw sums of t^2 would cancel every digit of the slope.
  for (const double t0 : {0.0, 1e8}) {
    const EnergyTrend f = trend_of([t0](double t) { return 3e-9 * (t - t0) - 1e-10; }, t0, 1e3, 1001);
    EXPECT_NEAR(f.slope(), 3e-9, 1e-9 * 3e-9 * (1.0 + t0 / 1e3)) << t0;
    // The residual sum of squares is a difference, C_ee - C_te^2 / C_tt: it resolves the rms to
    // ~sqrt(eps) of the spread of e (here 3e-6 / sqrt(12)), 4 sqrt(eps) allowed.
    EXPECT_LT(f.residual_rms(), 4.0 * 1.5e-8 * 3e-6 / std::sqrt(12.0)) << t0;
    EXPECT_TRUE(f.drifts()) << t0;
  }
}

TEST(EnergyTrend, AnOscillationOverWholePeriodsIsBoundedAtEveryPhase) {
  // |b| T <= 4.3 rms for one whole period, 1.5 rms for two (recorder.hpp): below the threshold 5.
  for (const double periods : {1.0, 2.0, 10.0}) {
    for (const double phase : {0.0, 0.5, 1.0, 3.14159}) {
      const double w = 2.0 * M_PI * periods / 100.0;
      const EnergyTrend f = trend_of([&](double t) { return 1e-6 * std::sin(w * t + phase); }, 0.0, 100.0, 2001);
      EXPECT_FALSE(f.drifts()) << periods << " periods, phase " << phase;
      // Between 0.44 A (one period, cos(phi) = 1) and A / sqrt(2).
      EXPECT_GT(f.residual_rms(), 0.43e-6) << periods;
      EXPECT_LT(f.residual_rms(), 0.71e-6) << periods;
    }
  }
}

TEST(EnergyTrend, ADriftUnderAnOscillationIsFoundWithItsSlope) {
  // c T = 1e-5 against an oscillation of amplitude 1e-6 (rms 7e-7): 14 rms, above 5.
  const EnergyTrend f = trend_of([](double t) { return 1e-7 * t + 1e-6 * std::sin(3.0 * t); }, 0.0, 100.0, 4001);
  EXPECT_TRUE(f.drifts());
  // The oscillation's share of the slope: 12 A / (w T^2) ~ 4e-10 at most.
  EXPECT_NEAR(f.slope(), 1e-7, 1e-9);
  EXPECT_GT(f.slope_standard_error(), 0.0);
  EXPECT_LT(f.slope_standard_error(), 1e-9);
}

TEST(EnergyTrend, ARoundOffWalkIsBounded) {
  // A linear change smaller than 10 eps sqrt(k) |E| over k = 4e5 steps: round-off, not a drift.
  const EnergyTrend f = trend_of([](double t) { return 1e-15 * t / 100.0; }, 0.0, 100.0, 4001);
  EXPECT_LT(f.secular_change(), f.round_off_floor());
  EXPECT_FALSE(f.drifts());
}

}  // namespace
}  // namespace lgvi::experiments
