// [integration] last_step: a t_final that is not a whole number of steps of h, refused by
// default, or ended by one shorter step ("shorter") in the LGVI and the baselines.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "experiments/systems/exact_reference.hpp"
#include "experiments/methods/method.hpp"
#include "experiments/methods/recorder.hpp"
#include "experiments/scene/scene.hpp"

namespace lgvi::experiments {
namespace {

/// A free body (no control, so the closed form is its exact solution) with the given grid.
std::string free_body(double h, double t_final, const std::string& last_step, int output_every = 1) {
  char text[512];
  std::snprintf(text, sizeof text,
                "system = \"free-body\"\n"
                "[parameters]\ninertia = [0.13, 0.28, 0.17]\n"
                "[initial]\nOmega = [0.3, -0.2, 0.5]\n"
                "[integration]\nh = %.17g\nt_final = %.17g\noutput_every = %d\n%s",
                h, t_final, output_every, last_step.empty() ? "" : ("last_step = \"" + last_step + "\"\n").c_str());
  return text;
}

struct RunResult {
  Stats stats;
  Sample last;
  Diagnostics diagnostics;
};

RunResult run(const Scene& scene, const std::string& method, const MethodOptions& options = {}) {
  Recorder recorder(scene.model, scene.horizon.output_every, nullptr);
  const Stats stats = make_method(method, options)->run(scene, recorder);
  recorder.finish();
  EXPECT_TRUE(stats.ok()) << method << ": " << stats.brief();
  return {stats, recorder.last(), recorder.diagnostics()};
}

/// |R - R_exact| + |Omega - Omega_exact| at the run's last sample.
double error_at_end(const Scene& scene, const Sample& last) {
  const baselines::ExactState x = *exact_state(scene.model, last.t);
  const AttitudeInitial& s = state_of<FreeBodyModel>(last);
  return (s.R - x.R).norm() + (s.Omega - x.Omega).norm();
}

TEST(LastStep, BadValueNamesFileAndField) {
  for (const char* value : {"\"sometimes\"", "1"}) {
    std::string text = free_body(0.01, 1.0, "");
    text += std::string("last_step = ") + value + "\n";
    try {
      (void)parse_scene(text, "test.toml");
      ADD_FAILURE() << "accepted last_step = " << value;
    } catch (const SceneError& e) {
      EXPECT_EQ(e.file(), "test.toml");
      EXPECT_EQ(e.field(), "integration.last_step") << e.what();
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    }
  }
}

TEST(LastStep, DefaultAndErrorRefuseWithTodaysMessage) {
  for (const std::string last : {"", "error"}) {
    try {
      (void)parse_scene(free_body(0.01, 1.005, last), "test.toml");
      ADD_FAILURE() << "accepted t_final = 1.005 with h = 0.01";
    } catch (const SceneError& e) {
      EXPECT_EQ(e.field(), "integration.t_final");
      EXPECT_NE(e.reason().find("is not a whole number of steps of h = 0.01"), std::string::npos) << e.what();
    }
  }
  // A command-line t_final takes the scene's choice too.
  SceneOverrides o;
  o.t_final = 0.355;
  EXPECT_THROW((void)parse_scene(free_body(0.01, 1.0, ""), "test.toml", o), SceneError);
  EXPECT_EQ(parse_scene(free_body(0.01, 1.0, "shorter"), "test.toml", o).horizon.steps, 36u);
}

TEST(LastStep, HorizonOfAShorterLastStep) {
  const Horizon hz = make_horizon(0.1, 0.35, 1, LastStep::Shorter);
  EXPECT_TRUE(hz.shorter_last_step);
  EXPECT_EQ(hz.steps, 4u);
  EXPECT_EQ(hz.whole_steps(), 3u);
  EXPECT_EQ(hz.time(3), 3 * 0.1);
  EXPECT_EQ(hz.time(4), 0.35);
  EXPECT_NEAR(hz.last_step(), 0.05, 1e-15);
  // A whole number of steps (within the 1e-9 tolerance) is the same horizon either way.
  const Horizon whole = make_horizon(0.1, 0.3, 1, LastStep::Shorter);
  EXPECT_FALSE(whole.shorter_last_step);
  EXPECT_EQ(whole.steps, 3u);
  // Less than one step of h stays an error.
  EXPECT_THROW(make_horizon(0.1, 0.05, 1, LastStep::Shorter), InvalidInput);
  EXPECT_THROW(parse_last_step("never"), InvalidInput);
}

TEST(LastStep, ShorterIsRefusedWithAnOcp) {
  std::string text = free_body(0.01, 1.005, "shorter");
  text += "[ocp]\nmethod = \"indirect\"\n";
  try {
    (void)parse_scene(text, "test.toml");
    ADD_FAILURE() << "accepted last_step = \"shorter\" with [ocp]";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field(), "integration.last_step") << e.what();
  }
}

TEST(LastStep, FinalSampleIsAtTFinalForEveryKindOfMethod) {
  // 100 steps of 0.01 and one of 0.005 (t_final / h = 100.5); output_every = 7 leaves the last
  // step off the output grid and off the end of the whole steps.
  const Scene scene = parse_scene(free_body(0.01, 1.005, "shorter", 7), "test.toml");
  ASSERT_EQ(scene.horizon.steps, 101u);
  MethodOptions quaternion;
  quaternion.model = "quaternion";
  const std::pair<const char*, MethodOptions> methods[] = {
      {"lgvi", {}}, {"lgvi-yoshida4", {}}, {"odeint-rk4", quaternion}, {"gsl-rk4imp", quaternion},
      {"cvode-bdf", quaternion}, {"odeint-dopri5", quaternion}};
  for (const auto& [name, options] : methods) {
    const RunResult r = run(scene, name, options);
    EXPECT_EQ(r.last.t, 1.005) << name;
    if (std::string(name).rfind("lgvi", 0) == 0 || std::string(name) == "odeint-rk4" ||
        std::string(name) == "gsl-rk4imp") {
      EXPECT_EQ(r.stats.steps, 101u) << name;  // the fixed-step methods: 100 of h, 1 of h / 2
    }
    // Every method ends near the exact state: the loosest (order 2 at h = 0.01, |Omega| ~ 0.6,
    // J ratios ~ 2) has an error ~ (h |Omega|)^2 ~ 4e-5; 1e-3 would catch a missing or doubled
    // last step (|Omega| h / 2 ~ 3e-3 of rotation).
    EXPECT_LE(error_at_end(scene, r.last), 1e-3) << name;
  }
}

// The LGVI with a shorter last step keeps its order: its error at T against the closed form,
// with h = 3 T / (3 N + 1) (T / h = N + 1/3: N steps of h and one of h / 3) for N = 16, 32, 64,
// falls like h^p, p = 2 (lgvi) and 4 (lgvi-yoshida4), estimated as log(e1 / e2) / log(h1 / h2).
// A global error C h^p (1 + O(h |Omega|)) with h |Omega| <= 0.062 * 0.62 ~ 0.04 here moves the
// estimate by ~0.04 / ln 2 ~ 0.06; |p_observed - p| <= 0.15 leaves room for the constant.
TEST(LastStep, LgviKeepsItsOrderWithAShorterLastStep) {
  const double T = 1.0;
  for (const auto& [method, order] : {std::pair{"lgvi", 2.0}, std::pair{"lgvi-yoshida4", 4.0}}) {
    double previous_error = 0.0, previous_h = 0.0;
    for (const int n : {16, 32, 64}) {
      const double h = 3.0 * T / (3.0 * n + 1.0);
      const Scene scene = parse_scene(free_body(h, T, "shorter", 1000000), "test.toml");
      ASSERT_TRUE(scene.horizon.shorter_last_step);
      ASSERT_EQ(scene.horizon.steps, static_cast<std::size_t>(n + 1));
      const double e = error_at_end(scene, run(scene, method).last);
      if (previous_error > 0.0) {
        EXPECT_NEAR(std::log(previous_error / e) / std::log(previous_h / h), order, 0.15) << method << " N = " << n;
      }
      previous_error = e;
      previous_h = h;
    }
  }
}

// Against a run whose h divides the horizon: both are order-2 approximations of the same
// exact state, so |x_shorter - x_whole| <= e_shorter + e_whole; with h' = T / ceil(T / h) the
// two errors have the same leading constant C h^2 (up to (h / h')^2 ~ 1.03), so the difference
// is at most ~2 e_whole (bound used: 2.5 e_whole).
TEST(LastStep, LgviAgreesWithAWholeStepRun) {
  const double T = 2.0, h = 0.03;
  const Scene shorter = parse_scene(free_body(h, T, "shorter", 1000000), "test.toml");
  ASSERT_TRUE(shorter.horizon.shorter_last_step);  // 66 steps of 0.03 and one of 0.02
  const double h_whole = T / std::ceil(T / h);
  const Scene whole = parse_scene(free_body(h_whole, T, "", 1000000), "test.toml");
  const Sample a = run(shorter, "lgvi").last;
  const Sample b = run(whole, "lgvi").last;
  EXPECT_EQ(a.t, T);
  const AttitudeInitial& x = state_of<FreeBodyModel>(a);
  const AttitudeInitial& y = state_of<FreeBodyModel>(b);
  const double e_whole = error_at_end(whole, b);
  EXPECT_LE((x.R - y.R).norm() + (x.Omega - y.Omega).norm(), 2.5 * e_whole);
}

// Energy stays bounded as for whole steps: the whole steps of the shorter run are those of the
// run to N h (same h, same start), and the shorter last step, itself a variational step, changes
// the energy by its local error O(h_last^3), far below the O(h^2) oscillation of the whole run.
TEST(LastStep, FreeBodyEnergyStaysBounded) {
  const double h = 0.005;
  const Scene whole = parse_scene(free_body(h, 50.0, "", 1), "test.toml");
  const Scene shorter = parse_scene(free_body(h, 50.0 + 0.6 * h, "shorter", 1), "test.toml");
  const RunResult a = run(whole, "lgvi");
  const RunResult b = run(shorter, "lgvi");
  ASSERT_GT(a.diagnostics.max_abs_energy_error, 0.0);
  EXPECT_LE(b.diagnostics.max_abs_energy_error, 1.01 * a.diagnostics.max_abs_energy_error);
  EXPECT_EQ(b.stats.steps, whole.horizon.steps + 1);
}

}  // namespace
}  // namespace lgvi::experiments
