// The one-step driver (experiments/methods/one_step.hpp) and the registered one-step methods
// (the Lie group methods of baselines/lie_group.hpp, the splittings and RATTLE of
// baselines/splitting.hpp) on every shipped system's scene they apply to, through make_method
// as the CLI runs them (and refused on the others): each fixed-step method must stay on
// SO(3) to round-off (each update multiplies by rotations), cost `stages` accelerations per
// step, and converge at its order (final-state differences of N, 2N, 4N steps fall by 2^p), the
// properties that tell a driver which hands the scheme the wrong state, time or control from
// one that works; rkmk45 must meet its tolerance on each system.
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "experiments/cli/cli_support.hpp"
#include "experiments/methods/one_step.hpp"

namespace lgvi::experiments {
namespace {

struct DriverRun {
  Stats stats;
  Diagnostics diagnostics;
  Sample last;
};

DriverRun run(const std::string& method_name, const std::string& scene_name, double h, double t_final,
              const MethodOptions& options = {}) {
  SceneOverrides o;
  o.h = h;
  o.t_final = t_final;
  const Scene scene = load_scene(test::default_scene_file(scene_name), o);
  const std::unique_ptr<Method> method = make_method(method_name, options);
  Recorder recorder(scene.model, 1, nullptr);
  DriverRun r;
  r.stats = method->run(scene, recorder);
  recorder.finish();
  r.diagnostics = recorder.diagnostics();
  r.last = recorder.last();
  return r;
}

const std::vector<std::string>& system_scenes() {
  static const std::vector<std::string> scenes = {"free-body", "pendulum-controlled", "dumbbell", "cart-pendulum",
                                                  "connected-bodies"};
  return scenes;
}

struct Case {
  std::string method;
  std::string scene;
};

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  std::string name = info.param.method + "_on_" + info.param.scene;
  for (char& c : name) c = (c == '-') ? '_' : c;
  return name;
}

class FixedStepLieGroupMethod : public ::testing::TestWithParam<Case> {};

// Order p: d_j = |y_{N 2^j} - y_{N 2^(j+1)}| ~ C h^p, so d_0 / d_1 = 2^p to O(h). N = 200, 50, 20
// steps over 0.5 s for p = 1, 2, >= 3 keeps h |Omega| <= 0.2 on every shipped scene and the
// finest difference far above round-off; the band 2^(p +- 0.25) holds the O(h) correction of
// the ratio at these steps (a few percent for p = 1, up to ~15% at the coarsest fourth-order
// steps, printed).
TEST_P(FixedStepLieGroupMethod, StaysOnTheGroupAndConvergesAtItsOrder) {
  const Case& c = GetParam();
  const MethodInfo& info = method_info(c.method);
  const int p = info.order;
  const std::size_t coarse = p == 1 ? 200 : p == 2 ? 50 : 20;
  const double T = 0.5;
  Sample finals[3];
  for (int j = 0; j < 3; ++j) {
    const std::size_t n = coarse << j;
    const DriverRun r = run(c.method, c.scene, T / static_cast<double>(n), T);
    ASSERT_TRUE(r.stats.ok()) << r.stats.brief();
    EXPECT_EQ(r.stats.steps, n);
    EXPECT_EQ(r.stats.potential_evaluations, n * info.stages);
    // Each attitude is a product of at most n stages + 1 rotations: its orthogonality error is a
    // random walk of one rounding (~eps per entry, |.|_F over 9 entries) per factor; 10 sqrt(.)
    // eps bounds it.
    EXPECT_LT(r.diagnostics.max_orthogonality_error,
              10.0 * std::sqrt(static_cast<double>(n * info.stages)) * std::numeric_limits<double>::epsilon());
    finals[j] = r.last;
  }
  const Model model = load_scene(test::default_scene_file(c.scene)).model;
  const double d0 = state_distance(model, finals[0], finals[1]);
  const double d1 = state_distance(model, finals[1], finals[2]);
  if (info.exact_for_free_body && c.scene == "free-body") {
    // Exact on the uncontrolled free body: the runs differ by rounding only, at most 16 eps per
    // step of the finest run on the scene's state (|Omega| = 3, R's entries <= 1: scale 10).
    EXPECT_LE(std::max(d0, d1), 16.0 * std::numeric_limits<double>::epsilon() * static_cast<double>(coarse << 2) * 10.0)
        << "d0 = " << d0 << ", d1 = " << d1;
    return;
  }
  ASSERT_GT(d1, 0.0);
  const double observed = std::log2(d0 / d1);
  std::cout << "[ order    ] " << c.method << " on " << c.scene << ": " << observed << " (d0 = " << d0
            << ", d1 = " << d1 << ")\n";
  EXPECT_NEAR(observed, p, 0.25) << "d0 = " << d0 << ", d1 = " << d1;
}

std::string system_of(const std::string& scene) { return load_scene(test::default_scene_file(scene)).system(); }

/// The fixed-step one-step methods on the scenes of the systems they apply to (applies: true), or
/// of the others (false).
std::vector<Case> fixed_step_cases(bool applies) {
  std::vector<Case> cases;
  for (const MethodInfo* m : methods_where([](const MethodInfo& i) {
         return i.family == MethodFamily::OneStep && i.fixed_step();
       })) {
    for (const std::string& scene : system_scenes()) {
      if (m->applies_to(system_of(scene)) == applies) cases.push_back({m->name, scene});
    }
  }
  return cases;
}

INSTANTIATE_TEST_SUITE_P(EverySystem, FixedStepLieGroupMethod, ::testing::ValuesIn(fixed_step_cases(true)), case_name);

class OneStepMethodOffItsSystems : public ::testing::TestWithParam<Case> {};

// A method on a system its traits exclude (a splitting on the cart or the connected bodies, whose
// mass matrices depend on the configuration) is refused with one line naming the method and why.
TEST_P(OneStepMethodOffItsSystems, IsRefusedNamingWhy) {
  const Case& c = GetParam();
  try {
    (void)run(c.method, c.scene, 0.01, 0.1);
    FAIL() << c.method << " ran on " << c.scene;
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.field(), "method");
    const std::string what = e.what();
    EXPECT_NE(what.find(c.method), std::string::npos) << what;
    EXPECT_NE(what.find("separable"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

INSTANTIATE_TEST_SUITE_P(ExcludedSystems, OneStepMethodOffItsSystems, ::testing::ValuesIn(fixed_step_cases(false)),
                         case_name);

class AdaptiveLieGroupMethod : public ::testing::TestWithParam<std::string> {};

// rkmk45 at rtol 1e-6 against itself at 1e-10: the difference is the 1e-6 run's global error, at
// most kSensGlobalErrorPerRtol (1e3) rtol on these O(1)..O(10) states, and not zero; its rows
// stay on SO(3) (interpolated ones too: y_n exp(xi(sigma))).
TEST_P(AdaptiveLieGroupMethod, MeetsItsToleranceOnTheGroup) {
  const std::string& scene = GetParam();
  MethodOptions loose, tight;
  loose.rtol = 1e-6;
  tight.rtol = 1e-10;
  const DriverRun a = run("rkmk45", scene, 0.01, 2.0, loose);
  const DriverRun b = run("rkmk45", scene, 0.01, 2.0, tight);
  ASSERT_TRUE(a.stats.ok() && b.stats.ok()) << a.stats.brief() << " / " << b.stats.brief();
  const Model model = load_scene(test::default_scene_file(scene)).model;
  const double d = state_distance(model, a.last, b.last);
  std::cout << "[ rkmk45   ] " << scene << ": |y(1e-6) - y(1e-10)| = " << d << ", " << a.stats.steps << " / "
            << b.stats.steps << " steps\n";
  EXPECT_GT(d, 0.0);
  EXPECT_LE(d, 1e3 * 1e-6);
  EXPECT_LT(a.diagnostics.max_orthogonality_error, 1e-13);
  EXPECT_GT(a.stats.rhs_evaluations, 0u);
}

INSTANTIATE_TEST_SUITE_P(EverySystem, AdaptiveLieGroupMethod, ::testing::ValuesIn(system_scenes()),
                         [](const auto& info) {
                           std::string name = info.param;
                           for (char& c : name) c = c == '-' ? '_' : c;
                           return name;
                         });

TEST(LieGroupMethodOptions, FixedStepOnesTakeNoneAndRkmk45TakesTolerances) {
  MethodOptions model;
  model.model = "quaternion";
  EXPECT_THROW(make_method("rkmk4", model), InvalidInput);
  MethodOptions rtol;
  rtol.rtol = 1e-8;
  EXPECT_THROW(make_method("cg4", rtol), InvalidInput);
  EXPECT_NO_THROW(make_method("rkmk45", rtol));
  EXPECT_THROW(make_method("rkmk45", model), InvalidInput);
  MethodOptions bad;
  bad.rtol = -1.0;
  EXPECT_THROW(make_method("rkmk45", bad), InvalidInput);
}

}  // namespace
}  // namespace lgvi::experiments
