// "work-precision": accuracy against cost. Its cases are those of the study file
// experiments/studies/work-precision.toml (one definition; `lgvi-testbed study` runs the same file):
// per scene, fixed-step methods sweep the number of steps over the horizon and adaptive ones the
// tolerance rtol (atol = rtol); each case's final state is compared with the scene's exact
// solution where it has one (the free body, in closed form after Celledoni et al. 2008; the
// Lagrange top; experiments/systems/exact_reference.hpp), else with one very fine reference run of the
// scene (named in every case's CSV metadata and summary row). This file draws the figures: final-
// state error and maximum energy error against integrator wall time and against evaluations,
// log-log, one curve per method and model; and the table of the cheapest method for each accuracy
// level.
#include "experiments/suites/study.hpp"
#include "experiments/suites/common.hpp"

namespace lgvi::experiments::suites {

namespace fs = std::filesystem;

namespace {

/// Integrator time axis of the figures.
constexpr const char* kTimeLabel = "integrator wall time per run [s] (min of repeated serial runs)";

/// Accuracy levels of the table: final-state errors 1e-2, 1e-4, ..., 1e-10.
const std::vector<double> kLevels = {1e-2, 1e-4, 1e-6, 1e-8, 1e-10};

}  // namespace

Suite work_precision_suite(const SuiteParams& params) {
  Suite s = load_study(default_studies_dir() / "work-precision.toml", params);
  s.render = [](const RenderContext& ctx, const std::vector<SummaryRow>& rows) {
    std::vector<fs::path> files;
    const auto groups = by_group(rows);
    for (const auto& [scene, group] : groups) {
      const std::string reference = group.front()->text("reference");
      const struct {
        const char* x;
        const char* y;
        const char* name;
        std::string xlabel;
        std::string ylabel;
      } figures[] = {
          {"integrator_seconds_min", "final_error", "error-time", kTimeLabel,
           "final-state error (dimensionless)"},
          {"evaluations", "final_error", "error-evaluations",
           "evaluations (baselines: RHS calls; LGVI: substeps)", "final-state error (dimensionless)"},
          {"integrator_seconds_min", "max_energy_error_relative", "energy-time", kTimeLabel,
           "max |E - E_0| / |E_0|"},
          {"evaluations", "max_energy_error_relative", "energy-evaluations",
           "evaluations (baselines: RHS calls; LGVI: substeps)", "max |E - E_0| / |E_0|"},
      };
      for (const auto& f : figures) {
        const std::vector<XyCurve> curves = curves_by_label(group, f.x, f.y);
        const std::string title = scene + ": " + (std::string(f.y) == "final_error" ? "final-state error" : "energy error") +
                                  " vs cost (reference: " + reference + ")";
        files.push_back(plot_xy(ctx, scene + "-" + f.name, title, f.xlabel, f.ylabel, curves));
      }
    }
    std::string table = "# Work-precision: cheapest method per accuracy level\n\n"
                        "Final-state error: the largest of ||R - R_ref||_F and |Omega - Omega_ref| / |Omega_ref| at "
                        "t_final against the reference named in summary.csv (the exact solution where the scene has "
                        "one, else a fine run). Integrator time: wall time per run "
                        "excluding recording, the minimum over runs repeated until 20 ms were measured, timed one case "
                        "at a time (integrator_seconds_min; CPU time and repetitions in summary.csv). Evaluations: RHS "
                        "calls (baselines), substeps (LGVI: steps x composition stages).\n\n";
    table += cheapest_table(groups, "final_error", "final-state error", kLevels);
    files.push_back(write_text_file(ctx, "work-precision-table.md", table));
    return files;
  };
  return s;
}

}  // namespace lgvi::experiments::suites
