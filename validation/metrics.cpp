// The metrics of `lgvi-testbed validate` (validation/validate.hpp states the kinds' rules).
// Every metric is computed here by running the project's own code: scenes through the methods
// of the harness (the same code path as `simulate`), the cases of the sensitivity and shooting
// suites, and the `ocp` command on the paper's four examples. Nothing is switched on the
// system: scenes are loaded by name and compared through their Sample (the bindings' distance).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <sstream>
#include <system_error>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "experiments/systems/exact_reference.hpp"
#include "experiments/methods/method.hpp"
#include "experiments/ocp/ocp_command.hpp"
#include "experiments/input/literature_references.hpp"
#include "experiments/input/paper_values.hpp"
#include "experiments/output/data_dir.hpp"
#include "experiments/methods/recorder.hpp"
#include "experiments/methods/structure_defect.hpp"
#include "experiments/scene/scene.hpp"
#include "experiments/suites/suite.hpp"
#include "experiments/suites/jobs.hpp"
#include "experiments/suites/common.hpp"
#include "experiments/systems/systems.hpp"
#include "validation/validate.hpp"

namespace lgvi::experiments {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string format(const char* fmt, double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, x);
  return buf;
}

/// A method of the harness (the suites' MethodSpec: name, model, rtol) as the metrics name and
/// run it.
struct MethodUnderTest {
  std::string label;             ///< metric name component: "lgvi", "lgvi-printed", "odeint-rk4-quaternion"
  suites::MethodSpec spec;
  std::optional<LgviForm> form;  ///< LGVI form override
  /// Order metrics: multiple of the base step count. yoshida6's error constant is ~10^3 times
  /// kahan-li6's (its substeps reach 1.7 h against 0.4 h): it needs twice the steps to be
  /// in its asymptotic regime.
  std::size_t step_factor = 1;

  /// Nominal order (fixed-step methods; 0 for the adaptive ones): the registered method's, 1 for
  /// the printed LGVI form (its end-of-step impulse).
  double order() const { return form == LgviForm::Printed ? 1.0 : static_cast<double>(spec.info->order); }
};

/// The LGVIs' rotation-update options with the run's degradations planted.
RotationUpdateOptions rotation_options(const ValidateOptions& options) {
  RotationUpdateOptions r;
  if (options.degrades(Degradation::RotationUpdate)) {
    r.relative_tolerance = 1e-9;
    r.polish = false;
  }
  if (options.degrades(Degradation::UncompensatedAttitude)) r.compensated_attitude = false;
  return r;
}

std::unique_ptr<Method> make(const MethodUnderTest& m, const ValidateOptions& options) {
  MethodOptions o = m.spec.options();
  if (m.spec.info->takes_rotation_update) o.rotation_update = rotation_options(options);
  return make_method(m.spec.method, o);
}

/// The closed form's time argument: t, or with the exact-reference degradation t (1 - 1e-9).
double reference_time(const ValidateOptions& options, double t) {
  return options.degrades(Degradation::ExactReference) ? t * (1.0 - 1e-9) : t;
}

struct Run {
  Stats stats;
  Diagnostics diagnostics;
  Sample last;
  double seconds = 0.0;
};

/// Runs a scene with a method, recording every output_every-th step into the diagnostics only.
Run run_scene(const Scene& scene, const Method& method) {
  Recorder recorder(scene.model, scene.horizon.output_every, nullptr, method.records_quaternion_norm());
  const auto t0 = Clock::now();
  Run r;
  r.stats = method.run(scene, recorder);
  recorder.finish();
  r.seconds = seconds_since(t0);
  r.diagnostics = recorder.diagnostics();
  r.last = recorder.last();
  return r;
}

/// A scene of the gate's own (validation/scenes/NAME.toml: controlled variants, a badly
/// conditioned body) or else a shipped one (the scenes directory).
fs::path scene_file(const ValidateOptions& options, const std::string& name) {
  const fs::path own = data_dir("validation", "validation") / "scenes" / (name + ".toml");
  std::error_code ec;
  return fs::exists(own, ec) ? own : options.scenes_dir / (name + ".toml");
}

Scene load_named(const ValidateOptions& options, const std::string& name) { return load_scene(scene_file(options, name)); }

/// The scene with h, t_final, output_every and form replaced; with the control-timing
/// degradation every control late by one step h.
Scene scene_with(const ValidateOptions& options, const std::string& name, double h, double t_final,
                 std::int64_t every, std::optional<LgviForm> form = std::nullopt) {
  SceneOverrides o;
  o.h = h;
  o.t_final = t_final;
  o.output_every = every;
  o.form = form;
  Scene scene = load_scene(scene_file(options, name), o);
  if (options.degrades(Degradation::ControlTiming)) {
    visit_binding(scene.model, [h](auto binding, auto& m) { decltype(binding)::delay_controls(m, h); });
  }
  return scene;
}

// ---- order --------------------------------------------------------------------------------
// Observed order from the final states at N0, 2 N0, 4 N0, 8 N0 steps over T: the differences
// d_j = |y_{2^j N0} - y_{2^(j+1) N0}| decay as C h^p, and p is the least-squares slope of
// log2 d_j against j. No reference solution is needed (d_j is the error of the coarser run to
// O(2^-p)). N0 is chosen per nominal order so that every d_j lies between the asymptotic regime
// (h |Omega| <~ 0.1 for order 2; the composed methods' substeps reach 1.7 h, so orders 4 and 6
// start at h |Omega| ~ 0.1-0.2, where yoshida6 at twice that step already leaves the rotation
// update's domain on the connected bodies) and the round-off floor (the finest differences of
// order 6 are ~1e-11, 100x above it). The detail column prints the differences.

struct OrderScene {
  const char* scene;
  double t_final;
  std::size_t step_factor;  ///< multiplies base_steps: 2 for a fast scene
  /// The scene has a control: its final-state difference is gated too ("final/SCENE/METHOD").
  bool controlled = false;
};
// The five systems uncontrolled where a shipped scene is, and each with a control (the
// control's impulses are part of the order: the printed form's end-of-step impulse is first
// order, the symmetric form's half impulses second): pendulum-controlled and
// connected-bodies-controlled are shipped, the other three controlled variants are the gate's
// own (validation/scenes/).
// The pendulum tumbles at |Omega| ~ 7 rad/s and the connected bodies' coupling makes their
// error constants large: twice the steps of the other scenes.
constexpr OrderScene kOrderScenes[] = {
    {"free-body", 1.0, 1},
    {"pendulum-controlled", 1.0, 2, true},
    {"dumbbell", 2.0, 1},
    {"cart-pendulum", 1.0, 1},
    {"connected-bodies", 1.0, 2},
    {"connected-bodies-controlled", 1.0, 2, true},
    {"free-body-controlled", 1.0, 1, true},
    {"dumbbell-controlled", 2.0, 1, true},
    {"cart-pendulum-controlled", 1.0, 1, true},
};

std::size_t base_steps(double order) { return order <= 1.0 ? 100 : order <= 2.0 ? 50 : order <= 4.0 ? 32 : 16; }

/// The methods on the group that are not variational (a Lie group method run by the one-step
/// driver): every conservation and exact roster takes them beside its deliberate picks.
std::vector<MethodUnderTest> other_group_methods() {
  std::vector<MethodUnderTest> m;
  for (const MethodInfo* info : methods_where([](const MethodInfo& i) { return i.on_group() && !i.variational; })) {
    m.push_back({info->name, {info->name}, LgviForm::Symmetric});
  }
  return m;
}

/// Every fixed-step method on the group (by trait; the one taking the scene's form in both
/// forms), then fixed-step baselines picked by name.
std::vector<MethodUnderTest> order_methods() {
  std::vector<MethodUnderTest> m;
  for (const MethodInfo* info : methods_where([](const MethodInfo& i) { return i.on_group() && i.fixed_step(); })) {
    // yoshida6's error constant is ~10^3 times kahan-li6's (its substeps reach 1.7 h against
    // 0.4 h): it needs twice the steps to be in its asymptotic regime.
    const std::size_t step_factor = info->name == "lgvi-yoshida6" ? 2 : 1;
    m.push_back({info->name, {info->name}, LgviForm::Symmetric, step_factor});
    if (info->takes_form) m.push_back({info->name + "-printed", {info->name}, LgviForm::Printed});
  }
  for (MethodUnderTest picked : std::vector<MethodUnderTest>{
           {"odeint-rk4-quaternion", {"odeint-rk4", "quaternion"}, {}},
           {"odeint-rk4-matrix", {"odeint-rk4", "matrix"}, {}},
           {"gsl-rk4imp-quaternion", {"gsl-rk4imp", "quaternion"}, {}},
       }) {
    m.push_back(std::move(picked));
  }
  return m;
}

/// The nominal order of the printed LGVI form on a scene (its binding's printed_order).
double printed_order(const char* scene, const ValidateOptions& options) {
  const Scene s = load_named(options, scene);
  return visit_binding(s.model, [](auto binding, const auto& m) { return double(decltype(binding)::printed_order(m)); });
}

void order_metrics(const ValidateOptions& options, std::vector<Metric>& out) {
  for (const OrderScene& os : kOrderScenes) {
    const std::string system = load_named(options, os.scene).system();
    for (const MethodUnderTest& mut : order_methods()) {
      if (!mut.spec.info->applies_to(system)) continue;  // a splitting on a non-separable system
      // The order scene free-body.toml has no control: splitting-exact integrates it exactly.
      if (mut.spec.info->exact_for_free_body && std::string_view(os.scene) == "free-body") continue;
      const auto t0 = Clock::now();
      const std::unique_ptr<Method> method = make(mut, options);
      const std::size_t n0 = base_steps(mut.order()) * os.step_factor * mut.step_factor;
      // Nominal order: the printed form is first order where a potential or a control acts at
      // the step's end; without either (the free body and the cart scene have no control, the
      // free body no potential, the cart's potential is split in eq. 29 already) it is the
      // symmetric form (the system binding's printed_order).
      const double nominal = mut.form == LgviForm::Printed ? printed_order(os.scene, options) : mut.order();
      std::vector<Sample> finals;
      std::optional<Model> model;  // the scene's system, for the distance of its states
      bool ok = true;
      for (int j = 0; j < 4 && ok; ++j) {
        const std::size_t n = n0 << j;
        const Scene scene = scene_with(options, os.scene, os.t_final / static_cast<double>(n), os.t_final,
                                       static_cast<std::int64_t>(n), mut.form);
        const Run r = run_scene(scene, *method);
        ok = r.stats.ok();
        finals.push_back(r.last);
        model = scene.model;
      }
      double p = std::numeric_limits<double>::quiet_NaN();
      std::string detail;
      if (ok) {
        // Least-squares slope of log2 d_j over j = 0, 1, 2: (l2 - l0) / 2.
        double l[3];
        for (int j = 0; j < 3; ++j) l[j] = std::log2(state_distance(*model, finals[j], finals[j + 1]));
        p = -(l[2] - l[0]) / 2.0;
        detail = std::string(os.scene) + ", T = " + format("%g", os.t_final) + ", N = " + std::to_string(n0) +
                 ".." + std::to_string(8 * n0) + " steps; differences " + format("%.2g", std::exp2(l[0])) +
                 " .. " + format("%.2g", std::exp2(l[2]));
      } else {
        detail = std::string(os.scene) + ": a run failed";
      }
      Metric m;
      m.name = "order/" + std::string(os.scene) + "/" + mut.label;
      m.kind = MetricKind::Order;
      m.value = p;
      m.nominal = nominal;
      m.seconds = seconds_since(t0);
      m.detail = detail;
      out.push_back(m);
      if (os.controlled) {
        // The finest difference |y_{4 N0} - y_{8 N0}|: the 4 N0 run's error to O(2^-p), set by
        // the discretization (truncation kind). Any change of where or how a control acts moves
        // its leading digits even where the order stays, and either way: a printed form's
        // impulse moved one step late lands nearer the symmetric placement and lowers it. So it
        // is two-sided (where a control acts is the scheme's definition). Its round-off share:
        // eps per step over the 8 N0 steps.
        Metric f;
        f.name = "final/" + std::string(os.scene) + "/" + mut.label;
        f.kind = MetricKind::Truncation;
        f.two_sided = true;
        f.value = ok ? state_distance(*model, finals[2], finals[3]) : std::numeric_limits<double>::quiet_NaN();
        f.floor = kEps * static_cast<double>(8 * n0);
        f.seconds = 0.0;
        f.detail = std::string(os.scene) + ", T = " + format("%g", os.t_final) + "; final-state difference of the " +
                   std::to_string(4 * n0) + "- and " + std::to_string(8 * n0) + "-step runs";
        out.push_back(f);
      }
    }
  }
}

// ---- conservation: energy, momentum map, orthogonality, quaternion norm, Newton iterations --
// Each scene at its own h over a fixed number of steps (quick 10^4, full 10^5), every step
// recorded into the diagnostics. A quantity a method keeps to round-off (the LGVI's momentum
// maps and orthogonality, a renormalized quaternion's norm) is gated as round-off with the
// floor of how its error grows (round_off_floor); the rest as truncation.
// The badly conditioned body (validation/scenes/ill-conditioned-body.toml) is the case where
// the rotation update's tolerance matters: its Newton counts and energy move with it.
// Controls are dropped (each system's binding), none of these scenes has one: a control's work
// changes the energy (the connected bodies' sinusoid by 10-60x the initial energy over 40 s), so
// an "energy error" would measure the control along a chaotic trajectory, not the integrator.

constexpr const char* kConservationScenes[] = {"free-body", "pendulum", "dumbbell", "cart-pendulum",
                                               "connected-bodies", "ill-conditioned-body", "magnetic-dipole",
                                               "anchored-spring"};

/// How a round-off error grows over N steps, and so its floor.
enum class ErrorGrowth {
  RandomWalk,  ///< one fresh rounding per step, uncorrelated: eps sqrt(N)
  Bounded,     ///< rounding carried (compensated sum) or removed (renormalized) each step: 4 eps
};

/// The floor of a round-off metric. Bounded: the state's own rounding (a 3x3 product or a
/// normalization, <= 2 eps) plus that of forming the metric (R^T R - I: <= 2 eps), whatever N;
/// a lost compensation or renormalization random-walks to ~eps sqrt(N), 100 x the floor at
/// N = 10^4, beyond the factor 10 of the round-off rule.
double round_off_floor(ErrorGrowth growth, std::size_t steps) {
  return growth == ErrorGrowth::Bounded ? 4.0 * kEps : kEps * std::sqrt(static_cast<double>(steps));
}

/// The system's LGVI forms R_{k+1} by a compensated sum (the binding's optional trait
/// lgvi_attitude_compensated; the cart-pendulum's).
bool lgvi_attitude_compensated(const Model& model) {
  return visit_binding(model, [](auto binding, const auto&) {
    using B = decltype(binding);
    if constexpr (requires { B::lgvi_attitude_compensated; }) {
      return bool(B::lgvi_attitude_compensated);
    } else {
      return false;
    }
  });
}

/// The LGVI in both forms and at order 4, the other methods on the group (by trait), and
/// baselines picked by name.
std::vector<MethodUnderTest> conservation_methods() {
  std::vector<MethodUnderTest> m = {
      {"lgvi", {"lgvi"}, LgviForm::Symmetric},
      {"lgvi-printed", {"lgvi"}, LgviForm::Printed},
      {"lgvi-yoshida4", {"lgvi-yoshida4"}, LgviForm::Symmetric},
  };
  for (MethodUnderTest& other : other_group_methods()) m.push_back(std::move(other));
  for (MethodUnderTest picked : std::vector<MethodUnderTest>{
           {"odeint-rk4-quaternion", {"odeint-rk4", "quaternion"}, {}},
           {"odeint-rk4-quaternion-renormalized", {"odeint-rk4", "quaternion-renormalized"}, {}},
           {"odeint-rk4-matrix", {"odeint-rk4", "matrix"}, {}},
           {"cvode-bdf-quaternion-rtol1e-8", {"cvode-bdf", "quaternion", 1e-8}, {}},
           {"gsl-rk8pd-quaternion-rtol1e-8", {"gsl-rk8pd", "quaternion", 1e-8}, {}},
           {"odeint-dopri5-matrix-rtol1e-8", {"odeint-dopri5", "matrix", 1e-8}, {}},
           {"arkode-erk-quaternion-rtol1e-8", {"arkode-erk", "quaternion", 1e-8}, {}},
           {"arkode-dirk-quaternion-rtol1e-8", {"arkode-dirk", "quaternion", 1e-8}, {}},
           {"cvode-bdf-projected-quaternion-rtol1e-8", {"cvode-bdf-projected", "quaternion", 1e-8}, {}},
       }) {
    m.push_back(std::move(picked));
  }
  return m;
}

void conservation_metrics(const ValidateOptions& options, std::vector<Metric>& out) {
  const std::size_t steps = options.quick ? 10'000 : 100'000;
  for (const char* scene_name : kConservationScenes) {
    const Scene base = load_named(options, scene_name);
    const double h = base.horizon.h;
    for (const MethodUnderTest& mut : conservation_methods()) {
      if (!mut.spec.info->applies_to(base.system())) continue;
      const std::unique_ptr<Method> method = make(mut, options);
      Scene scene = scene_with(options, scene_name, h, h * static_cast<double>(steps), 1, mut.form);
      visit_binding(scene.model, [](auto binding, auto& m) { decltype(binding)::drop_controls(m); });
      const Run r = run_scene(scene, *method);
      const Diagnostics& d = r.diagnostics;
      const double nan = std::numeric_limits<double>::quiet_NaN();
      const bool ok = r.stats.ok();
      const double floor = round_off_floor(ErrorGrowth::RandomWalk, steps);
      const std::string subject = std::string(scene_name) + "/" + mut.label;
      const std::string detail = std::string(scene_name) + ", h = " + format("%g", h) + ", " + std::to_string(steps) +
                                 " steps" + (mut.spec.rtol ? ", rtol = " + format("%g", *mut.spec.rtol) : std::string()) +
                                 (ok ? "" : ": " + r.stats.brief());
      const auto add = [&](const std::string& quantity, double value, bool kept, double metric_floor) {
        Metric m;
        m.name = quantity + "/" + subject;
        m.kind = kept ? MetricKind::RoundOff : MetricKind::Truncation;
        m.value = ok ? value : nan;
        m.floor = metric_floor;
        m.seconds = r.seconds;
        m.detail = detail;
        out.push_back(m);
      };
      add("energy", d.max_energy_error(), false, floor);
      const double momentum = d.momentum0_norm > 0.0 ? d.max_momentum_error / d.momentum0_norm : d.max_momentum_error;
      add("momentum", momentum, mut.spec.info->preserves_momentum_map, floor);
      const bool compensated = mut.spec.info->takes_rotation_update && lgvi_attitude_compensated(scene.model);
      add("orthogonality", d.max_orthogonality_error, mut.spec.info->stays_on_group || mut.spec.model != "matrix",
          compensated ? round_off_floor(ErrorGrowth::Bounded, steps) : floor);
      if (d.quaternion_norm_recorded) {
        // The norm of the solver's state before any normalization (CoordinateOde::decode): the
        // renormalized model's is bounded, the plain quaternion's a truncation error.
        const bool renormalized = mut.spec.model == "quaternion-renormalized";
        add("quaternion-norm", d.max_quaternion_norm_error, renormalized,
            renormalized ? round_off_floor(ErrorGrowth::Bounded, steps) : floor);
      }
      if (mut.spec.info->reports_step_iterations && ok) {
        Metric m;
        m.name = "newton/" + subject;
        m.kind = MetricKind::Count;
        m.value = static_cast<double>(r.stats.newton_iterations) / static_cast<double>(r.stats.steps);
        m.seconds = r.seconds;
        m.detail = detail + "; mean rotation-update Newton iterations per step (max " +
                   std::to_string(r.stats.max_newton_iterations) + ")";
        out.push_back(m);
      }
    }
  }
}

// ---- exact: errors against the closed-form solutions ---------------------------------------
// The free body (Celledoni et al. 2008) and the Lagrange top have exact solutions
// (baselines/exact/, experiments/systems/exact_reference.hpp): each method's final-state error against
// them (final_state_error: ||R - R_ex||_F and |Omega - Omega_ex| / |Omega_ex|) at the scene's
// step over a fixed horizon, no finer run needed. Truncation kind, with floor eps N: each of the
// N steps rounds the phase by ~eps, and a reordering of operations moves that share of the error
// (the exact solutions themselves hold 1e-15, test_exact).

struct ExactScene {
  const char* scene;
  double quick_t_final;
  double full_t_final;
};
// Free body: 10 s = 2000 steps of 0.005 (quick), the scene's 50 s (full); top: 2.5 s = 3.3
// nutation periods at h = 1e-3 (quick), the scene's 10 s (full).
constexpr ExactScene kExactScenes[] = {{"free-body", 10.0, 50.0}, {"lagrange-top", 2.5, 10.0}};

/// The LGVI at orders 2, 4, 6, the other methods on the group (by trait), and baselines picked
/// by name.
std::vector<MethodUnderTest> exact_methods() {
  std::vector<MethodUnderTest> m = {
      {"lgvi", {"lgvi"}, LgviForm::Symmetric},
      {"lgvi-yoshida4", {"lgvi-yoshida4"}, LgviForm::Symmetric},
      {"lgvi-kahan-li6", {"lgvi-kahan-li6"}, LgviForm::Symmetric},
  };
  for (MethodUnderTest& other : other_group_methods()) m.push_back(std::move(other));
  for (MethodUnderTest picked : std::vector<MethodUnderTest>{
      {"odeint-rk4-quaternion", {"odeint-rk4", "quaternion"}, {}},
      {"odeint-rk4-matrix", {"odeint-rk4", "matrix"}, {}},
      {"gsl-rk4imp-quaternion", {"gsl-rk4imp", "quaternion"}, {}},
      {"cvode-bdf-quaternion-rtol1e-8", {"cvode-bdf", "quaternion", 1e-8}, {}},
      {"cvode-adams-quaternion-rtol1e-8", {"cvode-adams", "quaternion", 1e-8}, {}},
      {"gsl-rk8pd-quaternion-rtol1e-10", {"gsl-rk8pd", "quaternion", 1e-10}, {}},
      {"odeint-dopri5-matrix-rtol1e-8", {"odeint-dopri5", "matrix", 1e-8}, {}},
      {"arkode-erk-quaternion-rtol1e-8", {"arkode-erk", "quaternion", 1e-8}, {}},
      {"arkode-dirk-quaternion-rtol1e-8", {"arkode-dirk", "quaternion", 1e-8}, {}},
      {"cvode-bdf-projected-quaternion-rtol1e-8", {"cvode-bdf-projected", "quaternion", 1e-8}, {}},
       }) {
    m.push_back(std::move(picked));
  }
  return m;
}

/// The exact roster (exact_methods) on one scene, each method graded by its final-state error
/// against a reference: the exact and literature groups.
struct FinalErrorRoster {
  const char* group;  ///< the metrics' names: GROUP/SCENE/LABEL
  const char* scene;
  double h = 0.0;
  std::int64_t steps = 0;
  double t_final = 0.0;                     ///< the horizon as the detail prints it
  std::function<Sample(double)> reference;  ///< the reference state at a run's final time
  std::string against;                      ///< what the detail says the error is against
  /// The reference's own error bound: an error below 10 times it is said to measure the
  /// reference more than the method.
  double reference_error = 0.0;
  /// A method that refuses the scene's body (InvalidInput from its run) has no metric; else the
  /// refusal ends validate.
  bool skip_refusing = false;
};

/// One truncation metric per method of the roster that applies to the scene's system, with
/// floor eps N: each of the N steps rounds the phase by ~eps, and a reordering of operations
/// moves that share of the error.
void final_error_metrics(const ValidateOptions& options, const FinalErrorRoster& roster, std::vector<Metric>& out) {
  for (const MethodUnderTest& mut : exact_methods()) {
    const Scene scene = scene_with(options, roster.scene, roster.h, roster.h * static_cast<double>(roster.steps),
                                   roster.steps, mut.form);
    if (!mut.spec.info->applies_to(scene.system())) continue;
    const std::unique_ptr<Method> method = make(mut, options);
    Run r;
    try {
      r = run_scene(scene, *method);
    } catch (const InvalidInput&) {
      if (!roster.skip_refusing) throw;
      continue;
    }
    const bool ok = r.stats.ok();
    Metric m;
    m.name = std::string(roster.group) + "/" + roster.scene + "/" + mut.label;
    m.kind = MetricKind::Truncation;
    m.value = ok ? final_state_error(scene.model, r.last, roster.reference(r.last.t))
                 : std::numeric_limits<double>::quiet_NaN();
    m.floor = kEps * static_cast<double>(roster.steps);
    m.two_sided = true;  // it measures the reference as much as the method
    m.seconds = r.seconds;
    m.detail = std::string(roster.scene) + ", h = " + format("%g", roster.h) + ", T = " + format("%g", roster.t_final) +
               (mut.spec.rtol ? ", rtol = " + format("%g", *mut.spec.rtol) : std::string()) +
               "; final-state error against " + roster.against +
               (ok && m.value < 10.0 * roster.reference_error ? ": below 10x the reference's own error bound" : "") +
               (ok ? "" : ": " + r.stats.brief());
    out.push_back(m);
  }
}

void exact_metrics(const ValidateOptions& options, std::vector<Metric>& out) {
  for (const ExactScene& es : kExactScenes) {
    const Scene base = load_named(options, es.scene);
    const double h = base.horizon.h;
    const double t_final = options.quick ? es.quick_t_final : es.full_t_final;
    const auto steps = static_cast<std::int64_t>(std::llround(t_final / h));
    std::string why_not;
    const std::optional<ExactReference> exact = ExactReference::of(base.model, &why_not);
    if (!exact) throw std::logic_error("validate: scene " + std::string(es.scene) + " has no exact solution: " + why_not);
    {
      // The closed form itself against gsl-rk8pd (Prince-Dormand 8(7), quaternion model) at
      // rtol = atol = 1e-13 over the same horizon: an integration that shares no code with it.
      // The distance is the tight run's error (~1e-12), reproduced by the same code to round-off:
      // truncation kind, two-sided, with the closed form's own rounding floor 8 eps (1 +
      // |Omega0| T) (its elliptic functions' arguments, as the literature group's).
      MethodOptions tight;
      tight.model = "quaternion";
      tight.rtol = 1e-13;
      tight.atol = 1e-13;
      const auto t0 = Clock::now();
      const Scene scene = scene_with(options, es.scene, h, h * static_cast<double>(steps), steps);
      const Run r = run_scene(scene, *make_method("gsl-rk8pd", tight));
      Metric m;
      m.name = "exact/" + std::string(es.scene) + "/closed-form";
      m.kind = MetricKind::Truncation;
      m.two_sided = true;
      m.value = r.stats.ok() ? final_state_error(scene.model, r.last, exact->sample(reference_time(options, r.last.t)))
                             : std::numeric_limits<double>::quiet_NaN();
      m.floor = 8.0 * kEps * (1.0 + exact->state(0.0).Omega.norm() * t_final);
      m.seconds = seconds_since(t0);
      m.detail = std::string(es.scene) + ", T = " + format("%g", t_final) + "; " + exact->description() +
                 " against gsl-rk8pd on the quaternion model at rtol = atol = 1e-13" +
                 (r.stats.ok() ? "" : ": " + r.stats.brief());
      out.push_back(m);
    }
    final_error_metrics(options,
                        {.group = "exact",
                         .scene = es.scene,
                         .h = h,
                         .steps = steps,
                         .t_final = t_final,
                         .reference = [&exact, &options](double t) {
                           return exact->sample(reference_time(options, t));
                         },
                         .against = exact->description()},
                        out);
  }
}

// ---- literature: the test problems of the field against their stored references -------------
// The shipped literature scenes (kLiteratureScenes) with their states at t_final stored in
// validation/literature_references.toml, computed by the closed forms and checked against a
// tight gsl-rk8pd run (compute_literature_references). Two metrics per problem:
//  - closed-form: the closed form at t_final against the stored state. Round-off kind: the code
//    that wrote the file reproduces it to the rounding of its elliptic functions' arguments,
//    eps |lambda t| with |lambda| <= |Omega0|, so the floor is 8 eps (1 + |Omega0| T). A change
//    of the closed form that moves the reference (a reference drifting like the methods) shows
//    here first.
//  - each method of the exact roster at the scene's own h and T against the stored state:
//    truncation kind with floor eps N, like the exact group. Where the error is below 10 times
//    the reference's own error bound (agreement), the detail says the metric measures the
//    reference more than the method.

struct LiteratureScene {
  const char* scene;
  const char* source;
};
constexpr LiteratureScene kLiteratureScenes[] = {
    {"hlw-rigid-body",
     "Hairer, Lubich, Wanner, Geometric Numerical Integration, 2nd ed. (2006), Sections I.2.3 and IV.1: I = (2, 1, "
     "2/3), y0 = (cos 1.1, 0, sin 1.1), T = 100, h = 0.1"},
    {"manifold-rigid-body",
     "ManifoldDiffEq.jl documentation's body I = (1.6, 1, 2/3), with the Hairer-Lubich-Wanner y0 (this scene's choice)"},
    {"detest-b5",
     "Hull, Enright, Fellen, Sedgwick, SIAM J. Numer. Anal. 9 (1972) 603-637, DETEST problem B5: y = (sn, cn, dn)(t | "
     "0.51), T = 12"},
    {"symmetric-top", "the free symmetric top (free precession), J = (2, 2, 1)"},
    {"lagrange-top", "the Lagrange top (heavy symmetric top), closed form by Jacobi sn and elliptic integrals"},
};

fs::path literature_references_file() {
  return data_dir("validation", "validation") / "literature_references.toml";
}

void literature_metrics(const ValidateOptions& options, std::vector<Metric>& out) {
  const std::vector<LiteratureReference> references = read_literature_references(literature_references_file());
  for (const LiteratureScene& ls : kLiteratureScenes) {
    const auto found = std::find_if(references.begin(), references.end(),
                                    [&](const LiteratureReference& r) { return r.scene == ls.scene; });
    if (found == references.end()) {
      throw std::logic_error("validate: " + literature_references_file().string() + " has no problem '" + ls.scene +
                             "': write it again with validate --write-literature-references");
    }
    const LiteratureReference& ref = *found;
    const Scene base = load_named(options, ls.scene);
    const double h = base.horizon.h;
    const double T = base.horizon.t_final;
    if (std::abs(T - ref.t) > 1e-12 * T) {
      throw std::logic_error("validate: the stored reference of " + std::string(ls.scene) + " is at t = " +
                             format("%g", ref.t) + ", the scene ends at " + format("%g", T) +
                             ": write it again with validate --write-literature-references");
    }
    std::string why_not;
    const std::optional<ExactReference> exact = ExactReference::of(base.model, &why_not);
    if (!exact) throw std::logic_error("validate: literature scene " + std::string(ls.scene) + " has no closed form: " + why_not);
    const Sample reference = exact->sample_of(baselines::ExactState{ref.R, ref.Omega}, T);
    const std::string digits = std::to_string(ref.digits) + " digits";
    {
      Metric m;
      m.name = "literature/" + std::string(ls.scene) + "/closed-form";
      m.kind = MetricKind::RoundOff;
      m.two_sided = true;
      m.value = final_state_error(base.model, exact->sample(reference_time(options, T)), reference);
      m.floor = 8.0 * kEps * (1.0 + exact->state(0.0).Omega.norm() * T);
      m.detail = std::string(ls.scene) + ", T = " + format("%g", T) + "; " + exact->description() +
                 " against the stored reference (" + digits + ")";
      out.push_back(m);
    }
    // RATTLE needs J_d positive definite: it refuses the flat DETEST B5 body and the nonphysical
    // Hairer-Lubich-Wanner one, and has no metric there.
    final_error_metrics(options,
                        {.group = "literature",
                         .scene = ls.scene,
                         .h = h,
                         .steps = static_cast<std::int64_t>(std::llround(T / h)),
                         .t_final = T,
                         .reference = [&reference](double) { return reference; },
                         .against = "the stored reference (" + digits + ")",
                         .reference_error = ref.agreement,
                         .skip_refusing = true},
                        out);
  }
}

// ---- structure: the Poisson-structure defect of every fixed-step method ----------------------
// structure_defect (experiments/methods/structure_defect.hpp): the defect of one step's map in
// preserving the free body's Lie-Poisson structure (h = 0.1) and the pendulum's canonical one on
// T*SO(3) (h = 0.05), from its Jacobian by differences, on the probe scenes shared with the test
// and the docs' table; the fixed-step baselines on the quaternion model (its attitude projected
// onto the nearest rotation). A symplectic method's defect is the differences' error (round-off kind, its
// floor the one structure_defect derives for an exact Poisson map); another's is O(h^(p+1))
// (truncation kind: the discretization sets it).

void structure_metrics(const ValidateOptions& options, std::vector<Metric>& out) {
  (void)options;
  for (const auto& [system, h] : std::vector<std::pair<const char*, double>>{{"free-body", 0.1}, {"pendulum", 0.05}}) {
    const Scene scene = structure_probe_scene(system, h);
    // Every fixed-step method on the group, and the fixed-step baselines on the quaternion model.
    for (const MethodInfo* info : methods_where([](const MethodInfo& i) { return i.fixed_step(); })) {
      if (!info->applies_to(system)) continue;
      const auto t0 = Clock::now();
      const StructureDefect d = structure_defect(scene, *info);
      Metric m;
      m.name = "structure/" + std::string(system) + "/" + info->name + (info->on_group() ? "" : "-quaternion");
      m.kind = info->symplectic ? MetricKind::RoundOff : MetricKind::Truncation;
      m.value = d.defect;
      m.floor = d.floor;
      m.seconds = seconds_since(t0);
      m.detail = std::string(system) + ", h = " + format("%g", h) + "; " +
                 (std::string(system) == "free-body" ? "Lie-Poisson" : "T*SO(3)") +
                 " structure defect of one step (floor of an exact Poisson map " + format("%.2g", d.floor) + ")";
      out.push_back(m);
    }
  }
}

// ---- suites: the LGVI linearization and the shooting methods -------------------------------
// The cases of the sensitivity and shooting suites (quick form), run in a scratch directory;
// their summary fields are the metrics.

struct ScratchDir {
  fs::path path;
  ScratchDir() {
    path = fs::temp_directory_path() / ("lgvi-validate-" + std::to_string(::getpid()) + "-" +
                                        std::to_string(Clock::now().time_since_epoch().count()));
    fs::create_directories(path);
  }
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

double field_number(const Fields& fields, const std::string& key) {
  for (const Field& f : fields) {
    if (f.key != key) continue;
    if (const double* d = std::get_if<double>(&f.value)) return *d;
    if (const std::int64_t* i = std::get_if<std::int64_t>(&f.value)) return static_cast<double>(*i);
  }
  return std::numeric_limits<double>::quiet_NaN();
}

/// Runs the named cases of a suite (quick form); returns each case's result fields.
std::map<std::string, JobResult> run_suite_cases(const std::string& suite_name, const std::vector<std::string>& ids,
                                                 const ValidateOptions& options, const fs::path& scratch,
                                                 std::map<std::string, double>& seconds) {
  const Suite suite = make_suite(suite_name, SuiteParams{true, options.scenes_dir});
  std::map<std::string, JobResult> results;
  for (const std::string& id : ids) {
    const SuiteCase* found = nullptr;
    for (const SuiteCase& c : suite.cases) {
      if (c.id == id) found = &c;
    }
    if (!found) throw std::logic_error("validate: suite " + suite_name + " has no case " + id);
    found->job->validate(options.scenes_dir);
    const auto t0 = Clock::now();
    results[id] = found->job->run(JobContext{scratch, options.scenes_dir, id, "lgvi-testbed validate"});
    seconds[id] = seconds_since(t0);
  }
  return results;
}

void linearization_metrics(const ValidateOptions& options, std::vector<Metric>& out) {
  ScratchDir scratch;
  const char* const scenes[] = {"pendulum", "free-body"};
  const char* const horizons[] = {"0.5", "2"};
  const double steps[] = {0.01, 0.005, 0.0025};
  const auto case_id = [](const char* scene, const char* T, double h) {
    return std::string(scene) + "-T" + T + "-lgvi-h" + format("%g", h);
  };
  std::vector<std::string> ids;
  for (const char* scene : scenes) {
    for (const char* T : horizons) {
      for (const double h : steps) ids.push_back(case_id(scene, T, h));
    }
  }
  std::map<std::string, double> seconds;
  const auto results = run_suite_cases("sensitivity", ids, options, scratch.path, seconds);
  for (const char* scene : scenes) {
    for (const char* T : horizons) {
      std::vector<double> differences;
      for (const double h : steps) {
        const std::string id = case_id(scene, T, h);
        const Fields& f = results.at(id).fields;
        const std::string subject = std::string(scene) + "/T" + T + "/h" + format("%g", h);
        // The differences' own error (truncation O(a^2) and round-off eps/a of the central
        // differences) is what |Phi - Phi_fd| measures when the linearization is exact: gated
        // as round-off over the differences' estimate of their own error.
        Metric fd;
        fd.name = "linearization/" + subject + "/vs-differences";
        fd.kind = MetricKind::RoundOff;
        fd.value = field_number(f, "fd_error");
        fd.floor = field_number(f, "fd_estimate");
        fd.seconds = seconds[id];
        fd.detail = "LGVI transition matrix vs central differences of the flow, relative (suite sensitivity, " + id + ")";
        out.push_back(fd);
        Metric cont;
        cont.name = "linearization/" + subject + "/vs-continuous";
        cont.kind = MetricKind::Truncation;
        cont.value = field_number(f, "continuous_difference");
        cont.seconds = seconds[id];
        cont.detail = "LGVI transition matrix vs CVODES at rtol 1e-12, relative (" + id + ")";
        out.push_back(cont);
        differences.push_back(cont.value);
      }
      Metric order;
      order.name = "linearization/" + std::string(scene) + "/T" + T + "/order";
      order.kind = MetricKind::Order;
      order.nominal = 2.0;
      order.value = -(std::log2(differences[2]) - std::log2(differences[0])) / 2.0;
      order.detail = "order in h of the LGVI linearization's difference from the continuous one, h = 0.01 .. 0.0025";
      out.push_back(order);
    }
  }
}

void shooting_metrics(const ValidateOptions& options, std::vector<Metric>& out) {
  ScratchDir scratch;
  const PaperValues& paper = paper_values();
  struct Case {
    const char* id;
    const char* label;
    bool condition;        ///< gate the condition numbers of the shooting Jacobian
    bool paper_condition;  ///< ... against the paper's range (sec. 3.2: the decomposed pendulum)
  };
  const Case cases[] = {
      {"pendulum-discrete-symmetric-n1000-decomposed-ones", "pendulum-discrete-decomposed", true, true},
      {"pendulum-continuous-rtol1e-10-decomposed-ones", "pendulum-continuous-decomposed", false, false},
      {"dumbbell-discrete-printed-n100-zero", "dumbbell-discrete-n100", true, false},
      {"cart-pendulum-direct-n200", "cart-pendulum-direct-n200", false, false},
  };
  std::vector<std::string> ids;
  for (const Case& c : cases) ids.push_back(c.id);
  std::map<std::string, double> seconds;
  const auto results = run_suite_cases("shooting", ids, options, scratch.path, seconds);
  for (const Case& c : cases) {
    const Fields& f = results.at(c.id).fields;
    const std::string base = std::string("shooting/") + c.label + "/";
    const std::string detail = std::string("suite shooting, case ") + c.id + ": " + results.at(c.id).detail;
    const auto add = [&](const std::string& what, MetricKind kind, double value, double floor = 0.0,
                         std::optional<double> paper_value = std::nullopt) {
      Metric m;
      m.name = base + what;
      m.kind = kind;
      m.value = value;
      m.floor = floor;
      m.paper = paper_value;
      m.seconds = seconds[c.id];
      m.detail = detail;
      out.push_back(m);
    };
    add("cost", MetricKind::Cost, field_number(f, "cost"));
    // A converged violation is at the shooting's tolerance or below: round-off over 1e-15.
    add("violation", MetricKind::RoundOff, field_number(f, "violation"), 1e-15);
    add("iterations", MetricKind::Count, field_number(f, "iterations"));
    if (c.condition) {
      add("cond-min", MetricKind::Condition, field_number(f, "cond_min"), 0.0,
          c.paper_condition ? std::optional<double>(paper.decomposed_condition_min) : std::nullopt);
      add("cond-max", MetricKind::Condition, field_number(f, "cond_max"), 0.0,
          c.paper_condition ? std::optional<double>(paper.decomposed_condition_max) : std::nullopt);
    }
  }
}

// ---- the paper's four optimal control examples ---------------------------------------------
// `ocp SYSTEM` with its defaults (the table of docs/paper-examples.md), run in-process into a scratch directory
// and read back from its summary JSON. The quick form reruns only the connected bodies'
// converging start of the default 8-start multistart (start 6 of seed 1: the full form runs all
// eight and gates the same optimum).

constexpr int kConnectedBodiesConvergingStart = 6;

void ocp_metrics(const ValidateOptions& options, std::vector<Metric>& out) {
  ScratchDir scratch;
  const PaperValues& paper = paper_values();
  // The dumbbell also by the continuation globalization (issue 17: <= 40 outer iterations on the
  // extremal Newton-Armijo finds), as "ocp/dumbbell-continuation/...".
  // The direct examples also by DDP (`--solver ddp`, lgvi/ocp/ddp.hpp), as "ocp/SYSTEM-ddp/...":
  // its quick form reruns DDP's best start of the multistart (start 1 of seed 1).
  struct Run {
    const char* system;
    const char* globalization;  ///< "" : the command's default
    bool quick_one_start = false;  ///< quick form: only kConnectedBodiesConvergingStart (DDP: start 1)
    bool ddp = false;
  };
  for (const Run run : {Run{"pendulum", ""}, Run{"dumbbell", ""}, Run{"dumbbell", "continuation"},
                        Run{"cart-pendulum", ""}, Run{"connected-bodies", "", true},
                        Run{"cart-pendulum", "", false, true}, Run{"connected-bodies", "", true, true}}) {
    const std::string system = run.system;
    const std::string name = system + (*run.globalization ? std::string("-") + run.globalization : std::string()) +
                             (run.ddp ? "-ddp" : "");
    OcpCommand cmd;
    cmd.system = system;
    if (*run.globalization) cmd.globalization = run.globalization;
    if (run.ddp) cmd.solver = "ddp";
    cmd.out = scratch.path.string();
    if (run.quick_one_start && options.quick) {
      cmd.starts = 1;
      cmd.first_start = run.ddp ? 1 : kConnectedBodiesConvergingStart;
    }
    std::ostringstream log, err;
    const auto t0 = Clock::now();
    const int code = run_ocp_command(cmd, "lgvi-testbed validate", log, err);
    const double seconds = seconds_since(t0);
    const fs::path summary = ocp_output_file(scratch.path, system, "summary.json");
    nlohmann::json j;
    std::ifstream in(summary);
    if (in) j = nlohmann::json::parse(in, nullptr, false);
    // One object (older summaries: an array of one object).
    if (j.is_array() && !j.empty()) {
      nlohmann::json first = j[0];
      j = std::move(first);
    }
    const bool read = j.is_object();
    const auto number = [&](const char* key) {
      if (!read || !j.contains(key) || !j[key].is_number()) return std::numeric_limits<double>::quiet_NaN();
      return j[key].get<double>();
    };
    const PaperExample& example = paper.example(system);
    const bool direct = is_direct_system(system);
    std::string detail = "ocp " + system + (*run.globalization ? std::string(" --globalization ") + run.globalization
                                                                : std::string()) +
                         (run.ddp ? " --solver ddp" : "") +
                         (cmd.first_start > 0 ? " --starts 1 --first-start " +
                                                                      std::to_string(cmd.first_start)
                                                                : std::string()) +
                         ": exit " + std::to_string(code) + "; " +
                         (read ? j.value("status_detail", j.value("status", std::string())) : err.str());
    if (detail.size() > 200) detail = detail.substr(0, 200) + "...";
    const auto add = [&](const std::string& what, MetricKind kind, double value, std::optional<double> p,
                         double floor = 0.0) {
      Metric m;
      m.name = "ocp/" + name + "/" + what;
      m.kind = kind;
      m.value = value;
      m.floor = floor;
      m.paper = p;
      m.seconds = seconds;
      m.detail = detail;
      out.push_back(m);
    };
    if (run.ddp) {
      // DDP: another discretization of the controls (free nodes), so no paper value; its violation
      // is gated against its stopping tolerance (1e-8), not round-off.
      add("cost", MetricKind::Cost, number("cost"), std::nullopt);
      add("violation", MetricKind::RoundOff, number("violation"), std::nullopt, 1e-8);
      add("iterations", MetricKind::Count, number("iterations"), std::nullopt);
      continue;
    }
    add("cost", MetricKind::Cost, number("cost"), example.cost);
    add("violation", MetricKind::RoundOff, number("violation"), example.terminal_violation, 1e-15);
    add("iterations", MetricKind::Count, number(direct ? "iterations" : "outer_iterations"),
        direct ? std::nullopt : example.outer_iterations_approx);
  }
}

// ---- the comparison of the optimal control methods -------------------------------------------
// Start 0 (the documented guess) of every method that applies to each of the paper's examples,
// the cases of suite ocp-comparison (quick form): the replayed yardstick of each answer (its
// controls on the quaternion model, gsl-rk8pd at 1e-13). The replayed violation of a discrete
// answer is its discretization error, reproduced by the same discretization; the answer itself is
// fixed only to within its own violation, so that is its floor (truncation rule: relative 1e-6
// plus 10 x the floor). The replayed cost: the cost rule. The continuous shooting, which has no
// node controls to replay, by its own cost. A start that did not converge gives no metric.

void ocp_comparison_metrics(const ValidateOptions& options, std::vector<Metric>& out) {
  ScratchDir scratch;
  const Suite suite = make_suite("ocp-comparison", SuiteParams{true, options.scenes_dir});
  std::vector<std::string> ids;
  for (const SuiteCase& c : suite.cases) {
    if (c.id.ends_with("-s0")) ids.push_back(c.id);
  }
  std::map<std::string, double> seconds;
  const auto results = run_suite_cases("ocp-comparison", ids, options, scratch.path, seconds);
  for (const std::string& id : ids) {
    const JobResult& r = results.at(id);
    if (!r.completed) continue;
    const std::string subject = "ocp-comparison/" + id.substr(0, id.size() - 3);
    const auto add = [&](const std::string& what, MetricKind kind, double value, double floor) {
      Metric m;
      m.name = subject + "/" + what;
      m.kind = kind;
      m.value = value;
      m.floor = floor;
      m.seconds = seconds[id];
      m.detail = "suite ocp-comparison, case " + id + ": " + r.detail.substr(0, 160);
      out.push_back(m);
    };
    const double replayed_violation = field_number(r.fields, "replayed_violation");
    if (std::isfinite(replayed_violation)) {
      add("replayed-violation", MetricKind::Truncation, replayed_violation, field_number(r.fields, "violation"));
      add("replayed-cost", MetricKind::Cost, field_number(r.fields, "replayed_cost"), 0.0);
    } else {
      add("cost", MetricKind::Cost, field_number(r.fields, "cost"), 0.0);
    }
  }
}

struct Group {
  const char* name;
  const char* description;
  void (*compute)(const ValidateOptions&, std::vector<Metric>&);
};

const Group kGroups[] = {
    {"order", "observed order of every integrator on every system (final-state differences, steps halved 3x)",
     order_metrics},
    {"conservation",
     "energy, momentum-map, orthogonality and quaternion-norm errors after a fixed number of steps; "
     "rotation-update Newton iterations per step",
     conservation_metrics},
    {"exact", "final-state errors against the exact free-body and Lagrange-top solutions", exact_metrics},
    {"literature", "the literature's test problems (Hairer-Lubich-Wanner body, DETEST B5, ...): closed forms and "
                   "methods against the stored references",
     literature_metrics},
    {"structure", "Poisson-structure defect of every fixed-step method's one step (free body: Lie-Poisson; "
                  "pendulum: T*SO(3))",
     structure_metrics},
    {"linearization", "LGVI transition matrices vs finite differences and vs CVODES (suite sensitivity)",
     linearization_metrics},
    {"shooting", "indirect and direct shooting: cost, violation, iterations, condition numbers (suite shooting)",
     shooting_metrics},
    {"ocp", "the paper's four optimal control examples: cost, violation, iterations", ocp_metrics},
    {"ocp-comparison", "every optimal control method from its documented guess on the paper's examples: replayed "
                       "violation and cost (suite ocp-comparison)", ocp_comparison_metrics},
};

}  // namespace

const std::vector<std::pair<std::string, std::string>>& metric_groups() {
  static const std::vector<std::pair<std::string, std::string>> groups = [] {
    std::vector<std::pair<std::string, std::string>> g;
    for (const Group& group : kGroups) g.emplace_back(group.name, group.description);
    return g;
  }();
  return groups;
}

std::string metric_group(const std::string& name) {
  const std::string first = name.substr(0, name.find('/'));
  for (const char* q : {"energy", "momentum", "orthogonality", "quaternion-norm", "newton"}) {
    if (first == q) return "conservation";
  }
  if (first == "final") return "order";
  return first;
}

std::vector<LiteratureReference> compute_literature_references(const fs::path& scenes_dir) {
  // The check run: gsl-rk8pd (Prince-Dormand 8(7)) on the quaternion model at rtol = atol =
  // 1e-13, an integration that shares no code with the closed forms.
  MethodOptions tight;
  tight.model = "quaternion";
  tight.rtol = 1e-13;
  tight.atol = 1e-13;
  const std::unique_ptr<Method> check = make_method("gsl-rk8pd", tight);
  std::vector<LiteratureReference> out;
  for (const LiteratureScene& ls : kLiteratureScenes) {
    const Scene scene = load_scene(scenes_dir / (std::string(ls.scene) + ".toml"));
    const double T = scene.horizon.t_final;
    std::string why_not;
    const std::optional<ExactReference> exact = ExactReference::of(scene.model, &why_not);
    if (!exact) throw std::logic_error("literature scene " + std::string(ls.scene) + " has no closed form: " + why_not);
    const Run r = run_scene(scene, *check);
    if (!r.stats.ok()) throw std::runtime_error(std::string(ls.scene) + ": the check run failed: " + r.stats.brief());
    const baselines::ExactState x = exact->state(T);
    LiteratureReference ref;
    ref.scene = ls.scene;
    ref.source = ls.source;
    ref.t = T;
    ref.R = x.R;
    ref.Omega = x.Omega;
    ref.computed_by = exact->description() + " at t; checked against gsl-rk8pd on the quaternion model at rtol = atol "
                      "= 1e-13 (agreement: the final-state distance of the two)";
    ref.agreement = final_state_error(scene.model, r.last, exact->sample(T));
    ref.digits = ref.agreement > 0.0 ? static_cast<int>(std::floor(-std::log10(ref.agreement))) : 16;
    out.push_back(std::move(ref));
  }
  return out;
}

std::vector<Metric> compute_metrics(const ValidateOptions& options, std::ostream& log) {
  for (const std::string& g : options.only) {
    bool known = false;
    for (const Group& group : kGroups) known = known || g == group.name;
    if (!known) {
      std::string names;
      for (const Group& group : kGroups) names += (names.empty() ? "" : ", ") + std::string(group.name);
      throw InvalidInput("--only", "unknown group '" + g + "' (known: " + names + ")");
    }
  }
  std::vector<Metric> metrics;
  for (const Group& group : kGroups) {
    if (!options.only.empty() &&
        std::find(options.only.begin(), options.only.end(), std::string(group.name)) == options.only.end()) {
      continue;
    }
    const auto t0 = Clock::now();
    const std::size_t before = metrics.size();
    group.compute(options, metrics);
    log << "validate: " << group.name << ": " << metrics.size() - before << " metrics in "
        << format("%.1f", seconds_since(t0)) << " s\n"
        << std::flush;
  }
  return metrics;
}

}  // namespace lgvi::experiments
