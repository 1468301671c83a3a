// The one-step driver (experiments/methods/one_step.hpp) with a scheme defined here, not
// registered: the explicit Lie-Euler method over each system's continuous mechanics,
//     R_i,k+1 = R_i,k exp(h hat(Omega_i,k)),  x_k+1 = x_k + h x'_k,  w_k+1 = w_k + h a(t_k, R_k, x_k, w_k),
// the first-order Lie group method of Crouch-Grossman and Munthe-Kaas (a one-stage RKMK method).
// Through MechanicsFlowMethod it runs every shipped system's scene: it must stay on SO(3) to
// round-off (each update multiplies by a rotation) and converge at order 1 (final-state
// differences halve with h), the properties that tell a driver which hands the scheme the
// wrong state, time or control from one that works.
#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "experiments/cli/cli_support.hpp"
#include "experiments/methods/one_step.hpp"
#include "lgvi/so3.hpp"

namespace lgvi::experiments {
namespace {

struct LieEulerScheme {
  template <baselines::Mechanics Mech>
  class Flow {
   public:
    using State = MechanicsState<Mech>;
    using Control = double;  // the time at each end of the step
    static constexpr int potential_evaluations_per_step = 1;

    explicit Flow(const Mech& mech) : mech_(mech) {}

    StepSummary step(const State& in, double h, double t_k, double /*t_k1*/, State& out) const {
      typename Mech::Rate rates;
      mech_.rates(in.config, in.w, rates);
      const typename Mech::Velocity a = mech_.acceleration(t_k, in.config, in.w);
      for (std::size_t i = 0; i < in.config.R.size(); ++i) {
        out.config.R[i] = in.config.R[i] * so3::exp(h * rates.Omega[i]);
      }
      out.config.x = in.config.x + h * rates.x_dot;
      out.w = in.w + h * a;
      return {};
    }

   private:
    const Mech& mech_;
  };
};

struct DriverRun {
  Stats stats;
  Diagnostics diagnostics;
  Sample last;
};

DriverRun run(const std::string& scene_name, double h, double t_final) {
  SceneOverrides o;
  o.h = h;
  o.t_final = t_final;
  const Scene scene = load_scene(test::default_scene_file(scene_name), o);
  const MechanicsFlowMethod<LieEulerScheme> method("lie-euler");
  Recorder recorder(scene.model, 1, nullptr);
  DriverRun r;
  r.stats = method.run(scene, recorder);
  recorder.finish();
  r.diagnostics = recorder.diagnostics();
  r.last = recorder.last();
  return r;
}

class OneStepDriver : public ::testing::TestWithParam<const char*> {};

// Order 1: d_j = |y_{N 2^j} - y_{N 2^(j+1)}| ~ C h^p; the ratio d_0 / d_1 is 2^p = 2 to O(h)
// (N = 200 .. 800 steps over 0.5 s: h |Omega| <= 0.02 on every shipped scene, so the O(h)
// correction to the ratio is a few percent); [1.8, 2.2] accepts p in [0.85, 1.14].
TEST_P(OneStepDriver, LieEulerStaysOnTheGroupAndConvergesAtOrderOne) {
  const std::string scene = GetParam();
  const double T = 0.5;
  Sample finals[3];
  for (int j = 0; j < 3; ++j) {
    const std::size_t n = std::size_t{200} << j;
    const DriverRun r = run(scene, T / static_cast<double>(n), T);
    ASSERT_TRUE(r.stats.ok()) << scene << ": " << r.stats.brief();
    EXPECT_EQ(r.stats.steps, n);
    EXPECT_EQ(r.stats.potential_evaluations, n);  // one acceleration per step
    // Each attitude is a product of n + 1 rotations: its orthogonality error is a random walk of
    // one rounding (~eps per entry, |.|_F over 9 entries) per step; 10 sqrt(n) eps bounds it.
    EXPECT_LT(r.diagnostics.max_orthogonality_error,
              10.0 * std::sqrt(static_cast<double>(n)) * std::numeric_limits<double>::epsilon())
        << scene;
    finals[j] = r.last;
  }
  const Model model = load_scene(test::default_scene_file(scene)).model;
  const double d0 = state_distance(model, finals[0], finals[1]);
  const double d1 = state_distance(model, finals[1], finals[2]);
  ASSERT_GT(d1, 0.0) << scene;
  EXPECT_GT(d0 / d1, 1.8) << scene << ": d0 = " << d0 << ", d1 = " << d1;
  EXPECT_LT(d0 / d1, 2.2) << scene << ": d0 = " << d0 << ", d1 = " << d1;
}

INSTANTIATE_TEST_SUITE_P(EverySystem, OneStepDriver,
                         ::testing::Values("free-body", "pendulum-controlled", "dumbbell", "cart-pendulum",
                                           "connected-bodies"),
                         [](const auto& info) {
                           std::string name = info.param;
                           for (char& c : name) c = c == '-' ? '_' : c;
                           return name;
                         });

}  // namespace
}  // namespace lgvi::experiments
