// "long-horizon": the LGVI's case for work and precision. Over a long horizon (10^4 s; quick
// 10^3 s) each method runs the free body, the pendulum and the dumbbell at a sweep of steps h
// from beyond the largest it tolerates downwards (fixed-step: LGVI orders 2, 4, 6, RK4 on
// quaternions, renormalized quaternions and rotation matrices) or of tolerances rtol
// (adaptive baselines), and reports the maximum energy error, momentum-map error and
// orthogonality error over the horizon against its cost (integrator time, timed serially and
// repeated: Job::timed; evaluations). Figures per scene: energy error vs time and vs
// evaluations, momentum and orthogonality error vs time. Tables: the cheapest method per
// energy-error and per momentum-error level, and each fixed-step method's largest completed step.
#include <cmath>
#include <cstdio>
#include <map>

#include "baselines/solver.hpp"
#include "experiments/suites/common.hpp"

namespace lgvi::experiments::suites {

namespace fs = std::filesystem;

namespace {

/// A scene and the largest step of its sweep: past the largest step some methods tolerate (the
/// rotation update's domain, or Newton's convergence from the linearized guess), measured over
/// 10^3 s: pendulum (|Omega0| = 7.2 rad/s) LGVI order 2 and 6 complete at h = 0.1, order 4
/// fails at the first step; free body (|Omega0| = 3 rad/s) order 6 completes at 0.4, order 2
/// and 4 fail, at 0.2 order 4 fails; dumbbell (orbit period 2 pi, rod-axis inertia 0.001, so a
/// small rotation-update domain) order 6 fails at step 2322 of h = 0.4, order 4 at 0.2.
struct LongHorizonScene {
  std::string scene;
  double h_top;
};

const std::vector<LongHorizonScene> kScenes = {{"free-body", 0.4}, {"pendulum", 0.1}, {"dumbbell", 0.4}};

/// The sweep's two largest steps are probes (Expectation::Either); smaller ones must complete.
constexpr std::size_t kProbeLevels = 2;

/// Samples per run: every K-th step with K = steps / kSamples (fixed-step), the output grid
/// (adaptive). The maximum errors are taken over the samples (the baselines are sampled on the
/// output grid only): measured over every step of the LGVI runs at 10^3 s, 1000 samples catch
/// the maximum energy error to within 12% (dumbbell, order 6, h = 0.1: 0.886 of it; order 2:
/// 0.93; pendulum 0.985-0.999), 500 samples to within 14%. The adaptive solvers without dense
/// output stop at every output time, which caps their step at 1 s (quick), 10 s (full): above
/// the steps they take on these scenes at the tolerances swept.
constexpr std::size_t kSamples = 1000;

std::vector<MethodSpec> fixed_methods(bool quick) {
  std::vector<MethodSpec> m = lgvi_methods(quick);
  for (const char* model : {"quaternion", "quaternion-renormalized", "matrix"}) {
    m.push_back({"odeint-rk4", std::string(model), std::nullopt});
  }
  if (!quick) m.push_back({"gsl-rk4imp", "quaternion", std::nullopt});
  return m;
}

std::string tag(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

/// Levels of the cheapest-method tables.
const std::vector<double> kLevels = {1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12};

/// Per scene and fixed-step method, the largest swept h whose run completed, with its errors and
/// cost: the energy error at the largest step each method tolerates.
std::string largest_step_table(const std::vector<std::pair<std::string, std::vector<const SummaryRow*>>>& groups) {
  std::string t =
      "| scene | method | largest h completed | max energy error | max momentum error | max orthogonality error | "
      "time per run [s] | evaluations | larger h swept: outcome |\n|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& [scene, rows] : groups) {
    std::vector<std::string> labels;
    std::map<std::string, std::vector<const SummaryRow*>> by_label;
    for (const SummaryRow* r : rows) {
      if (r->number("rtol")) continue;  // adaptive
      if (!by_label.count(r->text("label"))) labels.push_back(r->text("label"));
      by_label[r->text("label")].push_back(r);
    }
    for (const std::string& label : labels) {
      const SummaryRow* best = nullptr;
      for (const SummaryRow* r : by_label[label]) {
        if (r->text("status") != "completed" || !r->number("h")) continue;
        if (best == nullptr || *r->number("h") > *best->number("h")) best = r;
      }
      t += "| " + scene + " | " + label + " | ";
      if (best == nullptr) {
        t += "none | | | | | | |\n";
        continue;
      }
      const auto num = [&](const char* column) {
        const auto x = best->number(column);
        return x ? fmt(*x) : std::string();
      };
      std::string larger;
      for (const SummaryRow* r : by_label[label]) {
        if (r->number("h").value_or(0.0) <= *best->number("h")) continue;
        larger += (larger.empty() ? "" : "; ") + std::string("h = ") + fmt(*r->number("h")) + ": " + r->text("status");
      }
      t += fmt(*best->number("h")) + " | " + num("max_energy_error_relative") + " | " + num("max_momentum_drift_absolute") + " | " +
           num("max_orthogonality_error") + " | " + num("integrator_seconds_min") + " | " + best->text("evaluations") +
           " | " + (larger.empty() ? "(largest swept)" : larger) + " |\n";
    }
  }
  return t;
}

}  // namespace

Suite long_horizon_suite(const SuiteParams& params) {
  Suite s;
  s.name = "long-horizon";
  s.description = "energy, momentum and orthogonality error after 10^4 s (quick 10^3 s) vs cost, sweeping h and rtol";
  s.columns = simulation_columns();
  s.columns.insert(s.columns.end(), timing_columns().begin(), timing_columns().end());
  s.columns.push_back("momentum_map");
  const double t_final = params.quick ? 1e3 : 1e4;
  const std::size_t levels = params.quick ? 4 : 8;  // h_top, h_top / 2, ..., h_top / 2^(levels - 1)
  const std::vector<double> tolerances =
      params.quick ? std::vector<double>{1e-6, 1e-8, 1e-10}
                   : std::vector<double>{1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12};

  for (const LongHorizonScene& sc : kScenes) {
    for (const MethodSpec& m : fixed_methods(params.quick)) {
      for (std::size_t k = 0; k < levels; ++k) {
        const double h = sc.h_top / static_cast<double>(std::size_t{1} << k);
        const auto steps = static_cast<std::size_t>(std::llround(t_final / h));
        SimulateSpec spec;
        spec.scene = sc.scene;
        spec.overrides.t_final = t_final;
        spec.overrides.h = h;
        spec.overrides.output_every = static_cast<std::int64_t>(std::max<std::size_t>(1, steps / kSamples));
        spec.timed = true;
        s.cases.push_back(simulate_case(sc.scene + "-" + m.id() + "-h" + tag(h), sc.scene, spec, m,
                                        k < kProbeLevels ? Expectation::Either : Expectation::Complete));
      }
    }
    for (MethodSpec m : adaptive_sweep_methods(params.quick)) {
      for (const double rtol : tolerances) {
        m.rtol = rtol;
        SimulateSpec spec;
        spec.scene = sc.scene;
        spec.overrides.t_final = t_final;
        spec.overrides.h = t_final / static_cast<double>(kSamples);  // the output grid
        spec.overrides.output_every = 1;
        spec.timed = true;
        char tol[16];
        std::snprintf(tol, sizeof tol, "%.0e", rtol);
        s.cases.push_back(
            simulate_case(sc.scene + "-" + m.id() + "-rtol" + tol, sc.scene, spec, m, Expectation::Complete));
      }
    }
  }

  s.render = [](const RenderContext& ctx, const std::vector<SummaryRow>& rows) {
    std::vector<fs::path> files;
    const auto groups = by_group(rows);
    const std::string time_label = "integrator wall time per run [s] (min of repeated serial runs)";
    const std::string evaluations_label = "evaluations (baselines: RHS calls; LGVI: substeps)";
    for (const auto& [scene, group] : groups) {
      const std::string horizon =
          "T = " + group.front()->text("t_final") + (scene == "dumbbell" ? " (orbit period 2π)" : " s");
      const SystemLabels units = system_labels(group.front()->text("system"));
      const struct {
        const char* x;
        const char* y;
        const char* name;
        std::string xlabel;
        std::string ylabel;
        const char* what;
      } figures[] = {
          {"integrator_seconds_min", "max_energy_error_relative", "energy-time", time_label, "max |E - E_0| / |E_0|",
           "max energy error"},
          {"evaluations", "max_energy_error_relative", "energy-evaluations", evaluations_label, "max |E - E_0| / |E_0|",
           "max energy error"},
          {"integrator_seconds_min", "max_momentum_drift_absolute", "momentum-time", time_label, "max " + units.momentum,
           "max momentum-map error"},
          {"integrator_seconds_min", "max_orthogonality_error", "orthogonality-time", time_label, "max ||R^T R - I||_F",
           "max orthogonality error"},
      };
      for (const auto& f : figures) {
        files.push_back(plot_xy(ctx, scene + "-" + f.name + ".png",
                                scene + ": " + f.what + " over " + horizon + " vs cost (sweeps of h and rtol)",
                                f.xlabel, f.ylabel, curves_by_label(group, f.x, f.y)));
      }
    }
    std::string table =
        "# Long horizon: cheapest method per accuracy level\n\n"
        "Errors are maxima over the run's samples (1000 per run, every K-th step or the output grid): energy "
        "|E - E_0| / |E_0|, momentum map |m - m_0| (absolute, in the system's units). Integrator time: wall time per "
        "run excluding recording, the minimum over runs repeated until 20 ms were measured, timed one case at a time "
        "(integrator_seconds_min; CPU time in summary.csv). Evaluations: RHS calls (baselines), substeps (LGVI: "
        "steps x composition stages).\n\n## Energy error\n\n";
    table += cheapest_table(groups, "max_energy_error_relative", "max energy error", kLevels);
    table += "\n## Momentum-map error\n\n";
    table += cheapest_table(groups, "max_momentum_drift_absolute", "max momentum error", kLevels);
    table += "\n## Largest step each fixed-step method completed\n\n";
    table += largest_step_table(groups);
    files.push_back(write_text_file(ctx, "long-horizon-table.md", table));
    return files;
  };
  return s;
}

}  // namespace lgvi::experiments::suites
