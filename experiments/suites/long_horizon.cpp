// "long-horizon": the LGVI's case for work and precision. Its cases are those of the study file
// experiments/studies/long-horizon.toml (one definition; `lgvi-testbed study` runs the same file):
// over a long horizon (10^4 s; quick 10^3 s) each method runs the free body, the pendulum and the
// dumbbell at a sweep of steps h from beyond the largest it tolerates downwards (fixed-step: LGVI
// orders 2, 4, 6, RK4 on quaternions, renormalized quaternions and rotation matrices; the two
// largest steps are probes that may fail) or of tolerances rtol (adaptive baselines), timed
// serially and repeated (Job::timed). This file draws the figures per scene (energy error vs time
// and vs evaluations, momentum and orthogonality error vs time) and writes the tables: the cheapest
// method per energy-error and per momentum-error level, and each fixed-step method's largest
// completed step.
#include <map>

#include "experiments/suites/study.hpp"
#include "experiments/suites/common.hpp"
#include "experiments/systems/systems.hpp"

namespace lgvi::experiments::suites {

namespace fs = std::filesystem;

namespace {

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
  Suite s = load_study(default_studies_dir() / "long-horizon.toml", params);
  s.render = [](const RenderContext& ctx, const std::vector<SummaryRow>& rows) {
    std::vector<fs::path> files;
    const auto groups = by_group(rows);
    const std::string time_label = "integrator wall time per run [s] (min of repeated serial runs)";
    const std::string evaluations_label = "evaluations (baselines: RHS calls; LGVI: substeps)";
    for (const auto& [scene, group] : groups) {
      const SystemLabels units = system_labels(group.front()->text("system"));
      const std::string horizon = "T = " + group.front()->text("t_final") + units.horizon_unit;
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
