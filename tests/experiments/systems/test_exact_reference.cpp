// The harness's exact references (experiments/systems/exact_reference.hpp): which scenes have one, what
// they are called, that they start from the scene's state, and that the work-precision suite
// grades against them (the free body and the Lagrange top) or against its fine run (the paper's
// pendulum). The solutions themselves are tested in tests/baselines/test_exact.cpp.
#include "experiments/systems/exact_reference.hpp"

#include <gtest/gtest.h>

#include "experiments/suites/jobs.hpp"
#include "tests/experiments/cli/cli_support.hpp"

namespace lgvi::test {
namespace {

using experiments::ExactReference;

experiments::Scene scene(const std::string& name) { return experiments::load_scene(default_scene_file(name)); }

// Round-off of the solutions at t = 0 (tests/baselines/test_exact.cpp: 16 rounding steps).
constexpr double kStartTolerance = 16.0 * 16.0 * 2.220446049250313e-16;

TEST(ExactReference, ExistsForTheFreeBodyAndTheLagrangeTopAndStartsFromTheirState) {
  for (const auto& [name, description] :
       std::vector<std::pair<std::string, std::string>>{{"free-body", "exact (closed form, Celledoni et al. 2008)"},
                                                        {"lagrange-top", "exact (Lagrange top"}}) {
    const experiments::Scene s = scene(name);
    std::string why_not;
    const std::optional<ExactReference> exact = ExactReference::of(s.model, &why_not);
    ASSERT_TRUE(exact.has_value()) << name << ": " << why_not;
    EXPECT_EQ(exact->description().rfind(description, 0), 0u) << exact->description();
    const auto& initial = std::visit(
        [](const auto& m) -> std::pair<Mat3, Vec3> {
          if constexpr (requires { m.initial.R; m.initial.Omega; }) {
            return {m.initial.R, m.initial.Omega};
          } else {
            return {Mat3::Identity(), Vec3::Zero()};
          }
        },
        s.model);
    const baselines::ExactState s0 = exact->state(0.0);
    EXPECT_LE((s0.R - initial.first).norm(), kStartTolerance) << name;
    EXPECT_LE((s0.Omega - initial.second).norm(), kStartTolerance * initial.second.norm()) << name;
    // exact_state is the same solution.
    const std::optional<baselines::ExactState> at = experiments::exact_state(s.model, 1.7);
    ASSERT_TRUE(at.has_value());
    EXPECT_EQ(at->R, exact->state(1.7).R);
    EXPECT_EQ(at->Omega, exact->state(1.7).Omega);
  }
}

TEST(ExactReference, SaysWhyNoneExists) {
  const auto reason = [](const std::string& name) {
    std::string why_not;
    EXPECT_FALSE(ExactReference::of(scene(name).model, &why_not).has_value()) << name;
    EXPECT_FALSE(experiments::exact_state(scene(name).model, 1.0).has_value()) << name;
    return why_not;
  };
  EXPECT_NE(reason("pendulum").find("not a Lagrange top"), std::string::npos);
  EXPECT_NE(reason("pendulum-controlled").find("controlled"), std::string::npos);
  EXPECT_NE(reason("dumbbell").find("dumbbell"), std::string::npos);
  EXPECT_NE(reason("connected-bodies").find("connected-bodies"), std::string::npos);
  // An initial state the closed form rejects: the free body on its separatrix.
  experiments::Scene s = scene("free-body");
  auto& body = std::get<experiments::FreeBodyModel>(s.model);
  body.initial.Omega = Vec3(0.0, 1.0, 0.0);  // steady about the largest axis: fine
  EXPECT_TRUE(ExactReference::of(s.model).has_value());
  body.initial.Omega = Vec3(1e-7, 0.0, 3.0);  // 1e-7 rad/s off the intermediate axis: 1 - k < 1e-8
  std::string why_not;
  EXPECT_FALSE(ExactReference::of(s.model, &why_not).has_value());
  EXPECT_NE(why_not.find("separatrix"), std::string::npos) << why_not;
}

TEST(ExactReference, WorkPrecisionGradesAgainstItWhereTheSceneHasOne) {
  const std::filesystem::path scenes = experiments::default_scenes_dir();
  for (const auto& [name, exact] :
       std::vector<std::pair<std::string, bool>>{{"free-body", true}, {"lagrange-top", true}, {"pendulum", false}}) {
    experiments::SimulateSpec fine;
    fine.scene = name;
    fine.overrides.t_final = 1.0;
    fine.overrides.h = 1e-3;
    fine.method = "lgvi-kahan-li6";
    const auto reference = experiments::ReferenceRun::exact_or_run(fine, scenes);
    EXPECT_EQ(reference->is_exact(), exact) << name;
    if (!exact) {
      EXPECT_EQ(reference->description().rfind("lgvi-kahan-li6", 0), 0u) << reference->description();
      continue;
    }
    // The reference at a case's final time is the exact state there.
    const experiments::Sample s = reference->sample_at(0.75, scenes);
    const baselines::ExactState e = *experiments::exact_state(scene(name).model, 0.75);
    EXPECT_EQ(s.t, 0.75);
    const auto& state = std::visit([](const auto& x) -> const experiments::AttitudeInitial& {
      if constexpr (std::is_same_v<std::decay_t<decltype(x)>, experiments::AttitudeInitial>) {
        return x;
      } else {
        throw std::logic_error("an exact reference of an attitude system samples its attitude record");
      }
    }, s.state);
    EXPECT_EQ(s.state.index(), scene(name).model.index()) << name;
    EXPECT_EQ(state.R, e.R);
    EXPECT_EQ(state.Omega, e.Omega);
  }
  // A scene that does not load keeps the fine run (its cases report the scene's error).
  experiments::SimulateSpec missing;
  missing.scene = "no-such-scene";
  EXPECT_FALSE(experiments::ReferenceRun::exact_or_run(missing, scenes)->is_exact());
}

// The phase fit (ExactReference::phase_fit) recovers a pure time shift of the exact trajectory to
// the closed form's rounding (the residual vanishes at tau0, so the Gauss-Newton fixed point is
// tau0 whatever the velocity's difference error), leaving a shape error at round-off; an error
// that no shift removes (the momentum's magnitude scaled by 1 + s: another orbit) is left in the
// shape error at its size. On the nonphysical Hairer-Lubich-Wanner body too.
TEST(PhaseFit, RecoversATimeShiftAndLeavesTheShapeError) {
  for (const char* name : {"free-body", "hlw-rigid-body", "lagrange-top"}) {
    const experiments::Scene s = scene(name);
    const std::optional<ExactReference> exact = ExactReference::of(s.model);
    ASSERT_TRUE(exact.has_value()) << name;
    const double t = 0.5 * s.horizon.t_final;
    for (const double tau0 : {1e-3, -2e-2, 1e-6}) {
      const baselines::ExactState shifted = exact->state(t + tau0);
      const experiments::PhaseFit fit = exact->phase_fit(exact->sample_of(shifted, t));
      EXPECT_TRUE(fit.converged) << name;
      // The stopping tolerance 8 eps (1 + |Omega| t) <= 2e-13 here, over the scaled state's speed (> 0.5): < 1e-12.
      EXPECT_NEAR(fit.shift, tau0, 1e-12) << name << " tau0 = " << tau0;
      EXPECT_LT(fit.shape_error, 1e-12) << name;
    }
    const double scale = 1e-6;
    const baselines::ExactState x = exact->state(t + 1e-3);
    const experiments::PhaseFit fit = exact->phase_fit(exact->sample_of({x.R, (1.0 + scale) * x.Omega}, t));
    EXPECT_TRUE(fit.converged) << name;
    EXPECT_NEAR(fit.shift, 1e-3, 1e-5) << name;
    EXPECT_GT(fit.shape_error, 0.5 * scale) << name;
    EXPECT_LT(fit.shape_error, 1.5 * scale) << name;
  }
}

}  // namespace
}  // namespace lgvi::test
