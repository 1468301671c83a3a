// Properties every system of the harness must have, checked through its binding and the
// harness's own methods (typed tests in manif's pattern): a new system inherits them by one line
// in `SystemCases` below (its scene model and a scene file).
//   - observed order of the symmetric (2) and printed (the binding's printed_order) LGVI forms;
//   - its momentum map conserved by the uncontrolled symmetric LGVI to round-off;
//   - time reversibility of the uncontrolled symmetric LGVI (h, then -h);
//   - orthogonality of every attitude to round-off;
//   - agreement of its continuous model (a baseline solver) with the LGVI as h -> 0, at order 2.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "experiments/methods/method.hpp"
#include "experiments/methods/recorder.hpp"
#include "experiments/scene/scene.hpp"
#include "experiments/systems/systems.hpp"
#include "tests/experiments/cli/cli_support.hpp"
#include "tests/test_support.hpp"

namespace lgvi::test {
namespace {

using experiments::Scene;
using experiments::SystemBinding;

/// A scene name as a template argument.
template <std::size_t N>
struct SceneName {
  char text[N];
  constexpr SceneName(const char (&s)[N]) { std::copy_n(s, N, text); }
};

/// A system under test: its scene model M and a scene of it (experiments/scenes/<name>.toml).
template <class M, SceneName Name>
struct SystemCase {
  using Model = M;
  static std::string scene() { return Name.text; }
};

// One line per system (the pendulum twice: the paper's tumbling one and the Lagrange top).
using SystemCases = ::testing::Types<SystemCase<experiments::FreeBodyModel, "free-body">,
                                     SystemCase<experiments::PendulumModel, "pendulum-controlled">,
                                     SystemCase<experiments::PendulumModel, "lagrange-top">,
                                     SystemCase<experiments::DumbbellModel, "dumbbell">,
                                     SystemCase<experiments::CartPendulumModel, "cart-pendulum">,
                                     SystemCase<experiments::ConnectedBodiesModel, "connected-bodies">,
                                     SystemCase<experiments::PotentialBodyModel, "magnetic-dipole">,
                                     SystemCase<experiments::PotentialBodyModel, "attitude-spring">,
                                     SystemCase<experiments::PotentialBodySE3Model, "anchored-spring">,
                                     SystemCase<experiments::PotentialBodySE3Model, "uniform-gravity">>;

struct CaseNames {
  template <class Case>
  static std::string GetName(int) {
    return Case::scene();
  }
};

template <class Case>
class SystemProperties : public ::testing::Test {
 protected:
  using M = typename Case::Model;
  using B = SystemBinding<M>;

  /// The case's scene with h = t_final / steps, every step recorded, in `form`; without its
  /// controls when `uncontrolled`.
  static Scene scene(std::size_t steps, double t_final, LgviForm form, bool uncontrolled = false) {
    experiments::SceneOverrides o;
    o.h = t_final / static_cast<double>(steps);
    o.t_final = t_final;
    o.form = form;
    o.output_every = 1;
    Scene s = experiments::load_scene(default_scene_file(Case::scene()), o);
    if (uncontrolled) B::drop_controls(std::get<M>(s.model));
    return s;
  }
  static const M& model(const Scene& s) { return std::get<M>(s.model); }

  struct Run {
    Stats stats;
    experiments::Diagnostics diagnostics;
    experiments::Sample last;
  };
  static Run run(const Scene& s, const std::string& method, const experiments::MethodOptions& options = {}) {
    const auto m = experiments::make_method(method, options);
    experiments::Recorder recorder(s.model, s.horizon.output_every, nullptr, m->records_quaternion_norm());
    Run r;
    r.stats = m->run(s, recorder);
    r.diagnostics = recorder.diagnostics();
    r.last = recorder.last();
    EXPECT_TRUE(r.stats.ok()) << Case::scene() << ", " << method << ": " << r.stats.brief();
    return r;
  }

  /// Steps over t_final with h |Omega0| = kStepRate (at least `minimum`).
  static std::size_t steps_for(const Scene& s, double t_final, std::size_t minimum = 8) {
    const double rate = B::initial_rate(model(s));
    return std::max(minimum, static_cast<std::size_t>(std::ceil(t_final * rate / kStepRate)));
  }

  // Order and agreement runs start at h0 |Omega0| = 0.05. Observed order from differences or
  // errors d_j = C h_j^p (1 + kappa h_j |Omega|): the least-squares slope over h, h/2, h/4 is off
  // by at most log2((1 + kappa h|Omega|) / (1 + kappa h|Omega| / 4)) / 2 ~ 0.54 kappa h|Omega|.
  // For the symmetric form kappa is of order 1 (the scenes are smooth): over h0..h0/4 the bound is
  // 0.027 kappa. The printed form's first-order term is the end-of-step impulse, whose constant
  // can be small against the second-order one: on the Lagrange top the gravity moment m g rho
  // ~ 3 N m is a tenth of J3 |Omega|^2 ~ 32 N m, and its measured slope approaches 1 slowly
  // (1.35 over h0..h0/4, 1.10 over h0/8..h0/32: kappa h|Omega| ~ 0.2 at h0/8). Hence the slope is
  // taken over h0/32..h0/128 (kLevels = 8 runs), where that ratio is 4x smaller again (slope error
  // ~ 0.54 * 0.05 ~ 0.03); |p - nominal| <= 0.1. The finest differences (>= 1e-7) stay far above
  // round-off (~1e-12 over the finest run's ~5e4 steps).
  static constexpr double kStepRate = 0.05;
  static constexpr double kOrderTolerance = 0.1;
  static constexpr double kHorizon = 1.0;
  static constexpr int kLevels = 8;
  // Conservation runs: the scene's h over kSteps steps.
  static constexpr std::size_t kSteps = 2000;
};

TYPED_TEST_SUITE(SystemProperties, SystemCases, CaseNames);

/// -slope of log2 d_j over j = 0, 1, 2 (least squares: (l2 - l0) / 2).
double observed_order(const double d[3]) { return -(std::log2(d[2]) - std::log2(d[0])) / 2.0; }

TYPED_TEST(SystemProperties, ObservedOrderOfBothForms) {
  using Test = TestFixture;
  constexpr int levels = Test::kLevels;
  for (const LgviForm form : {LgviForm::Symmetric, LgviForm::Printed}) {
    const Scene probe = Test::scene(1, Test::kHorizon, form);
    const std::size_t n0 = Test::steps_for(probe, Test::kHorizon);
    experiments::Sample finals[levels];
    for (int j = 0; j < levels; ++j) finals[j] = Test::run(Test::scene(n0 << j, Test::kHorizon, form), "lgvi").last;
    double d[levels - 1];
    for (int j = 0; j + 1 < levels; ++j) d[j] = experiments::state_distance(probe.model, finals[j], finals[j + 1]);
    const double nominal = form == LgviForm::Symmetric ? 2.0 : Test::B::printed_order(Test::model(probe));
    const double p = observed_order(d + (levels - 4));  // over h0/32, h0/64, h0/128
    std::cout << "[ measured ] " << TypeParam::scene() << " " << to_string(form) << ": N0 = " << n0
              << ", differences " << d[0] << " .. " << d[levels - 2] << ", order over h0..h0/4 " << observed_order(d)
              << ", over h0/32..h0/128 " << p << "\n";
    EXPECT_NEAR(p, nominal, Test::kOrderTolerance) << to_string(form);
  }
}

// The uncontrolled symmetric LGVI conserves the momentum map exactly in exact arithmetic (the
// discrete Lagrangian's symmetry); in floating point each step's update (R F, F^T Pi and the
// momenta's sums: ~10 roundings per component of magnitude |m|) adds round-off, at worst
// linearly over n steps: roundoff(|m0|, 10 n) = 16 * 10 n eps |m0|. The implicit solves converge
// to 16 eps relative (RotationUpdateOptions, group_newton), inside the same count. Each R_{k+1}
// = R_k F_k with F_k orthogonal to round-off: the same bound, relative to |R| = 1.
TYPED_TEST(SystemProperties, ConservesItsMomentumMapAndOrthogonality) {
  using Test = TestFixture;
  const double h = experiments::load_scene(default_scene_file(TypeParam::scene())).horizon.h;
  const Scene s = Test::scene(Test::kSteps, h * static_cast<double>(Test::kSteps), LgviForm::Symmetric, true);
  const auto r = Test::run(s, "lgvi");
  const double n = static_cast<double>(Test::kSteps);
  std::cout << "[ measured ] " << TypeParam::scene() << ": momentum error " << r.diagnostics.max_momentum_error
            << " of |m0| = " << r.diagnostics.momentum0_norm << ", orthogonality " << r.diagnostics.max_orthogonality_error
            << "\n";
  EXPECT_LE(r.diagnostics.max_momentum_error, roundoff(std::max(r.diagnostics.momentum0_norm, kEps), 10.0 * n));
  EXPECT_LE(r.diagnostics.max_orthogonality_error, roundoff(1.0, 10.0 * n));
  EXPECT_LE(r.diagnostics.max_determinant_error, roundoff(1.0, 10.0 * n));
}

// n steps with h then n with -h return to the start: the symmetric form is self-adjoint. Each
// step's round-off (and its solve's 16 eps residual) is ~10 roundings of the state's magnitude
// S (|R - I| + |Omega| + |x| + ...); both directions at worst linearly: roundoff(S, 2 * 10 n).
TYPED_TEST(SystemProperties, SymmetricFormIsTimeReversible) {
  using Test = TestFixture;
  using B = typename Test::B;
  using State = typename B::State;
  constexpr std::size_t n = 200;
  const Scene s = Test::scene(1, 1.0, LgviForm::Symmetric, true);
  const double h = experiments::load_scene(default_scene_file(TypeParam::scene())).horizon.h;
  State start, back;
  bool ok = true;
  B::run_lgvi(Test::model(s), LgviForm::Symmetric, RotationUpdateOptions{},
              [&](const auto& lgvi, auto& state, auto&& control, auto&& to_state) {
                to_state(state, start);
                auto x = state;
                const auto observe = [](std::size_t, double, const auto&, const RotationUpdateSummary&) { return true; };
                const Stats forward = integrate(lgvi, x, 0.0, h, n, control, observe);
                const Stats backward = integrate(lgvi, x, static_cast<double>(n) * h, -h, n, control, observe);
                ok = forward.ok() && backward.ok();
                to_state(x, back);
                return backward;
              });
  ASSERT_TRUE(ok);
  const double scale = 1.0 + B::distance(start, State{});
  const double error = B::distance(start, back);
  std::cout << "[ measured ] " << TypeParam::scene() << ": return error " << error << " (state scale " << scale
            << ")\n";
  EXPECT_LE(error, roundoff(scale, 2.0 * 10.0 * static_cast<double>(n)));
}

// The continuous model (a baseline on quaternions, rtol = atol = 1e-12: its global error ~1e-10,
// far below the LGVI's ~1e-5 here) and the symmetric LGVI at h0, h0/2, h0/4: the LGVI's error
// against it decays at order 2 (the symmetric form's bound of the order test over h0..h0/4), so
// the two models agree as h -> 0
// (same equations, controls and initial state through the binding).
TYPED_TEST(SystemProperties, AgreesWithItsContinuousModel) {
  using Test = TestFixture;
  const Scene probe = Test::scene(1, Test::kHorizon, LgviForm::Symmetric);
  const std::size_t n0 = Test::steps_for(probe, Test::kHorizon);
  experiments::MethodOptions o;
  o.model = "quaternion";
  o.rtol = 1e-12;
  o.atol = 1e-12;
  const auto continuous = Test::run(Test::scene(n0, Test::kHorizon, LgviForm::Symmetric), "gsl-rk8pd", o).last;
  double e[3];
  for (int j = 0; j < 3; ++j) {
    const auto lgvi = Test::run(Test::scene(n0 << j, Test::kHorizon, LgviForm::Symmetric), "lgvi").last;
    e[j] = experiments::state_distance(probe.model, lgvi, continuous);
  }
  const double p = observed_order(e);
  std::cout << "[ measured ] " << TypeParam::scene() << ": LGVI - continuous " << e[0] << " .. " << e[2] << ", order "
            << p << "\n";
  EXPECT_NEAR(p, 2.0, Test::kOrderTolerance);
}

}  // namespace
}  // namespace lgvi::test
