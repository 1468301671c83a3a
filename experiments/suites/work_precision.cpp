// "work-precision": accuracy against cost. Per scene, fixed-step methods sweep the step h and
// adaptive ones the tolerance rtol (atol = rtol) over the same horizon; each case's final state
// is compared with the scene's exact solution where it has one (the free body, in closed form
// after Celledoni et al. 2008; the Lagrange top; experiments/exact_reference.hpp), else with one
// very fine reference run of the scene (the order-6 composed LGVI kahan-li6 at a step 4 times
// smaller than the finest swept one, whose own round-off floor, ~4e-11 on the free body, would
// otherwise cap the grades); the reference is named in every case's CSV metadata and summary
// row. Figures: final-state error and maximum energy error against integrator wall time and
// against evaluations, log-log, one curve per method and model. Table: the cheapest method for
// each accuracy level.
#include <cmath>

#include "baselines/solver.hpp"
#include "experiments/suites/common.hpp"

namespace lgvi::experiments::suites {

namespace fs = std::filesystem;

namespace {

struct Sweep {
  std::string scene;
  double t_final;
};

/// Output rows of the fixed-step runs (decimation only: their steps are h).
constexpr std::size_t kOutputIntervals = 100;
/// Output grid of the adaptive runs (it does not change their steps: they interpolate it). Coarse,
/// because the solvers without dense output (rk8pd, rkf78, msbdf) pay ~6-18 RHS evaluations per
/// interpolated step, left out of `evaluations` but not out of the integrator time; the maximum
/// energy error of these runs is thus taken over 20 samples.
constexpr std::size_t kAdaptiveOutputIntervals = 20;
/// Integrator time axis of the figures.
constexpr const char* kTimeLabel = "integrator wall time per run [s] (min of repeated serial runs)";
/// Coarsest number of fixed steps over the horizon; each level doubles it.
constexpr std::size_t kCoarsestSteps = 250;

std::vector<MethodSpec> fixed_methods(bool quick) {
  std::vector<MethodSpec> m = lgvi_methods(quick);
  m.push_back({"odeint-rk4", "quaternion", std::nullopt});
  m.push_back({"odeint-rk4", "matrix", std::nullopt});
  m.push_back({"gsl-rk4imp", "quaternion", std::nullopt});
  if (!quick) m.push_back({"gsl-rk4imp", "matrix", std::nullopt});
  return m;
}

/// Accuracy levels of the table: final-state errors 1e-2, 1e-4, ..., 1e-10.
const std::vector<double> kLevels = {1e-2, 1e-4, 1e-6, 1e-8, 1e-10};

}  // namespace

Suite work_precision_suite(const SuiteParams& params) {
  Suite s;
  s.name = "work-precision";
  s.description = "final-state and energy error against wall time and evaluations, sweeping h and rtol";
  s.columns = simulation_columns();
  s.columns.insert(s.columns.end(), timing_columns().begin(), timing_columns().end());
  // The Lagrange top over 2.5 s: 3.3 nutation periods, h |Omega| = 0.2 at the coarsest step.
  std::vector<Sweep> sweeps = {{"pendulum", 5.0}, {"free-body", 20.0}, {"lagrange-top", 2.5}};
  // One orbit only: the dumbbell's circular relative equilibrium is unstable, and over two
  // orbits it amplifies round-off to 1e-4 in the final attitude (measured: the reference and the
  // finest RK4 runs then disagree non-monotonically), which no method can beat.
  if (!params.quick) sweeps.push_back({"dumbbell", 2.0 * M_PI});
  const std::size_t levels = params.quick ? 7 : 9;  // finest: 250 x 2^(levels-1) steps
  const std::size_t finest = kCoarsestSteps << (levels - 1);
  const std::vector<double> tolerances =
      params.quick ? std::vector<double>{1e-3, 1e-5, 1e-7, 1e-9, 1e-11}
                   : std::vector<double>{1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12};

  for (const Sweep& sw : sweeps) {
    SimulateSpec ref_spec;
    ref_spec.scene = sw.scene;
    ref_spec.overrides.t_final = sw.t_final;
    ref_spec.overrides.h = sw.t_final / static_cast<double>(4 * finest);
    ref_spec.overrides.output_every = static_cast<std::int64_t>(4 * finest);
    ref_spec.method = "lgvi-kahan-li6";
    const auto reference = ReferenceRun::exact_or_run(ref_spec, params.scenes_dir);

    for (const MethodSpec& m : fixed_methods(params.quick)) {
      for (std::size_t k = 0; k < levels; ++k) {
        const std::size_t n = kCoarsestSteps << k;
        SimulateSpec spec;
        spec.scene = sw.scene;
        spec.overrides.t_final = sw.t_final;
        spec.overrides.h = sw.t_final / static_cast<double>(n);
        spec.overrides.output_every = static_cast<std::int64_t>(std::max<std::size_t>(1, n / kOutputIntervals));
        spec.timed = true;
        s.cases.push_back(simulate_case(sw.scene + "-" + m.id() + "-n" + std::to_string(n), sw.scene, spec, m,
                                        Expectation::Complete, reference));
      }
    }
    for (MethodSpec m : adaptive_sweep_methods(params.quick)) {
      for (const double rtol : tolerances) {
        m.rtol = rtol;
        SimulateSpec spec;
        spec.scene = sw.scene;
        spec.overrides.t_final = sw.t_final;
        spec.overrides.h = sw.t_final / static_cast<double>(kAdaptiveOutputIntervals);  // the output grid
        spec.overrides.output_every = 1;
        spec.timed = true;
        char tol[16];
        std::snprintf(tol, sizeof tol, "%.0e", rtol);
        s.cases.push_back(simulate_case(sw.scene + "-" + m.id() + "-rtol" + tol, sw.scene, spec, m,
                                        Expectation::Complete, reference));
      }
    }
  }

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
        files.push_back(plot_xy(ctx, scene + "-" + f.name + ".png", title, f.xlabel, f.ylabel, curves));
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
