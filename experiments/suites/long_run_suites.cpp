// The long-horizon suites: energy-drift, orthogonality and momentum. Each runs its scenes at the
// scene's own step h for a fixed number of steps (the horizon follows: t_final = steps h) with
// every method of the roster, and draws, per scene, the error against time on log-log axes:
// the LGVI's bounded oscillation against the baselines' drift.
#include "experiments/scene/scene.hpp"
#include "experiments/suites/common.hpp"

namespace lgvi::experiments::suites {

namespace fs = std::filesystem;

namespace {

struct LongRun {
  std::string scene;
  std::size_t steps;
  std::vector<MethodSpec> methods;
};

/// Rows kept in each CSV: enough for a readable curve on a log time axis, few enough that the
/// quick suites' CSVs stay small.
constexpr std::size_t kRowsPerCsv = 500;

/// Probes, not requirements (any outcome is as expected): Euler angles, which meet gimbal lock on
/// a tumbling body; a fixed-step implicit baseline, whose Newton iteration may stop converging at
/// the scene's h over 10^5 steps (gsl-rk4imp's modified Newton, capped at 7 iterations by GSL, on
/// the connected bodies at t = 119 s of the quick momentum suite); and a first-order method
/// (Lie-Euler), whose energy grows geometrically, by (1 + h^2 |Omega|^2)^(1/2) a step. Every other
/// method must complete.
Expectation long_run_expectation(const MethodSpec& m) {
  const bool probe = m.model == std::optional<std::string>("euler") ||
                     (m.info->uses_jacobian && m.info->fixed_step()) || m.info->order == 1;
  return probe ? Expectation::Either : Expectation::Complete;
}

void add_long_runs(Suite& s, const SuiteParams& params, const std::vector<LongRun>& runs) {
  for (const LongRun& run : runs) {
    const Scene scene = load_scene(resolve_scene(run.scene, params.scenes_dir));
    SimulateSpec spec;
    spec.scene = run.scene;
    spec.overrides.t_final = static_cast<double>(run.steps) * scene.horizon.h;
    spec.overrides.output_every = static_cast<std::int64_t>(std::max<std::size_t>(1, run.steps / kRowsPerCsv));
    for (const MethodSpec& m : run.methods) {
      if (!m.info->applies_to(scene.system())) continue;  // e.g. a splitting on the connected bodies
      s.cases.push_back(simulate_case(run.scene + "-" + m.id(), run.scene, spec, m, long_run_expectation(m)));
    }
  }
}

std::string steps_text(const std::vector<const SummaryRow*>& rows) {
  const SummaryRow& r = *rows.front();
  return r.text("grid_steps") + " steps of h = " + fmt(r.number("h").value_or(0.0)) +
         " (adaptive: rtol = atol = 1e-6)";
}

}  // namespace

Suite energy_drift_suite(const SuiteParams& params) {
  Suite s;
  s.name = "energy-drift";
  s.description = "energy error over 10^5 (quick) or 10^7 steps, every method, free body, pendulum, dumbbell";
  s.columns = simulation_columns();
  s.columns.push_back("grid_steps");
  const std::size_t steps = params.quick ? 100'000 : 10'000'000;
  const std::vector<MethodSpec> methods = long_run_methods(params.quick);
  add_long_runs(s, params, {{"free-body", steps, methods}, {"pendulum", steps, methods}, {"dumbbell", steps, methods}});
  s.render = [](const RenderContext& ctx, const std::vector<SummaryRow>& rows) {
    std::vector<fs::path> files;
    for (const auto& [scene, group] : by_group(rows)) {
      const std::string system = group.front()->text("system");
      files.push_back(plot_time_series(ctx, scene + "-energy-drift",
                                       scene + ": energy error, " + steps_text(group), system_labels(system).energy,
                                       "energy_error", true, group));
    }
    return files;
  };
  return s;
}

Suite orthogonality_suite(const SuiteParams& params) {
  Suite s;
  s.name = "orthogonality";
  s.description = "||R^T R - I|| and quaternion norm error against time, every method, free body and pendulum";
  s.columns = simulation_columns();
  s.columns.push_back("grid_steps");
  const std::size_t steps = params.quick ? 50'000 : 1'000'000;
  const std::vector<MethodSpec> methods = long_run_methods(params.quick);
  add_long_runs(s, params, {{"free-body", steps, methods}, {"pendulum", steps, methods}});
  s.render = [](const RenderContext& ctx, const std::vector<SummaryRow>& rows) {
    std::vector<fs::path> files;
    for (const auto& [scene, group] : by_group(rows)) {
      files.push_back(plot_time_series(ctx, scene + "-orthogonality",
                                       scene + ": orthogonality error, " + steps_text(group), "||R^T R - I||_F",
                                       "orthogonality_error", true, group));
      std::vector<const SummaryRow*> quaternion;
      for (const SummaryRow* r : group) {
        if (r->text("model").starts_with("quaternion")) quaternion.push_back(r);
      }
      if (quaternion.empty()) continue;
      files.push_back(plot_time_series(ctx, scene + "-quaternion-norm",
                                       scene + ": quaternion norm error (quaternion models), " + steps_text(group),
                                       "| |q| - 1 |", "quaternion_norm_error", true, quaternion));
    }
    return files;
  };
  return s;
}

Suite momentum_suite(const SuiteParams& params) {
  Suite s;
  s.name = "momentum";
  s.description =
      "momentum maps against time: pendulum vertical, free body spatial, connected bodies total";
  s.columns = simulation_columns();
  s.columns.push_back("grid_steps");
  s.columns.push_back("momentum_map");
  const std::size_t steps = params.quick ? 50'000 : 1'000'000;
  const std::vector<MethodSpec> methods = long_run_methods(params.quick);
  add_long_runs(s, params,
                {{"pendulum", steps, methods}, {"free-body", steps, methods}, {"connected-bodies", steps, methods}});
  s.render = [](const RenderContext& ctx, const std::vector<SummaryRow>& rows) {
    std::vector<fs::path> files;
    for (const auto& [scene, group] : by_group(rows)) {
      const SummaryRow& first = *group.front();
      files.push_back(plot_time_series(ctx, scene + "-momentum",
                                       scene + ": " + first.text("momentum_map") + " error, " + steps_text(group),
                                       system_labels(first.text("system")).momentum, "momentum_error", true, group));
    }
    return files;
  };
  return s;
}

}  // namespace lgvi::experiments::suites
