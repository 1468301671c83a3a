// Building blocks of the integrator suites: method rosters, case construction, summary columns
// and the figure helpers (time series of case CSVs, x-y curves of summary rows).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "experiments/output/plot.hpp"
#include "experiments/suites/suite.hpp"
#include "experiments/suites/jobs.hpp"
#include "experiments/systems/binding.hpp"

namespace lgvi::experiments::suites {

/// A method with its coordinate model and tolerance (adaptive baselines) as a suite runs it.
struct MethodSpec {
  /// Throws InvalidInput("method") for a method not in the registry.
  MethodSpec(std::string method_, std::optional<std::string> model_ = std::nullopt,
             std::optional<double> rtol_ = std::nullopt)
      : method(std::move(method_)), model(std::move(model_)), rtol(rtol_), info(&method_info(method)) {}

  std::string method;                 ///< make_method name
  std::optional<std::string> model;   ///< baselines only
  std::optional<double> rtol;         ///< adaptive baselines only (atol = rtol)
  const MethodInfo* info;             ///< the registered method

  bool fixed_step() const { return info->fixed_step(); }
  /// Legend text naming method and model: "LGVI order 4 (yoshida4)", "cvode-bdf, quaternion".
  std::string label() const;
  /// File-name part: "lgvi-yoshida4", "cvode-bdf-quaternion".
  std::string id() const;
  MethodOptions options() const { return {model, rtol, std::nullopt, std::nullopt}; }
};

/// Every method on the group without a coordinate model, each once: the variational ones
/// (the LGVIs of order 2, 4, 6) and the other one-step methods, in registration order. Quick:
/// the deliberate pick lgvi, lgvi-yoshida4, lgvi-kahan-li6 (one per order) and the one-step
/// methods that are not variational.
std::vector<MethodSpec> lgvi_methods(bool quick);
/// Adaptive solvers of the tolerance sweeps (work-precision, long-horizon). Quick: CVODE Adams and
/// BDF, odeint Dormand-Prince and GSL rk8pd on quaternions, Dormand-Prince on matrices. Full:
/// every adaptive method (trait) on the quaternion and matrix models.
std::vector<MethodSpec> adaptive_sweep_methods(bool quick);
/// Methods of the long-horizon suites. Quick: the LGVIs of order 2, 4, 6, CVODE Adams and BDF,
/// odeint RK4 and Dormand-Prince on the quaternion and matrix models, RK4 with renormalized
/// quaternions, GSL rk8pd and rk4imp (and lgvi_methods(true)). Full: every registered method,
/// each on every coordinate model it accepts (Euler angles included).
std::vector<MethodSpec> long_run_methods(bool quick);

/// Summary columns of the integrator suites.
const std::vector<std::string>& simulation_columns();
/// Summary columns of the timed integrator suites (SimulateJob::measure), appended to
/// simulation_columns(): integrator_seconds_min, integrator_seconds_median,
/// integrator_cpu_seconds, timing_repetitions.
const std::vector<std::string>& timing_columns();

/// A case running `spec` (case id "<prefix><scene>-<method id>[suffix]").
SuiteCase simulate_case(const std::string& id, const std::string& group, SimulateSpec spec, const MethodSpec& m,
                        Expectation expect, std::shared_ptr<const ReferenceRun> reference = nullptr);


/// What tells a figure's curves apart: their method (label and palette style of the row's
/// method, model and form), or their system (the soak: one run per system of one method; label
/// the scene, style the system's).
enum class CurvesBy { Method, System };

/// The palette style of a summary row's curve: its method's (registry name, "lgvi-printed" for
/// the printed form) with its coordinate model's dash type.
PlotStyle row_style(const SummaryRow& row);

/// The curve-list file the curve scripts load (gnuplot -c takes at most 9 arguments): n,
/// file[i], label[i], colour[i], point[i], dash[i], the style of each curve its own or its
/// label's (plot_style); a curve whose style an earlier curve already has (one method at two
/// steps) takes its label's.
std::string curve_list_text(const std::vector<Curve>& curves);

/// A figure (file ctx.figure(name)) of one CSV column against time, one curve per case of
/// `rows` (failed runs drawn up to their last good step). log_x: logarithmic time axis (t = 0
/// left out).
std::filesystem::path plot_time_series(const RenderContext& ctx, const std::string& name, const std::string& title,
                                       const std::string& ylabel, const std::string& column, bool log_x,
                                       const std::vector<const SummaryRow*>& rows, CurvesBy by = CurvesBy::Method);

/// A figure (file ctx.figure(name)) of one column of iteration-history CSVs (column "iteration"
/// on x, |column| on a log y axis; gnuplot script iteration_history.gp), one curve per row of
/// `rows` with its csv_path and label (the status appended when it is not "completed").
std::filesystem::path plot_iterations(const RenderContext& ctx, const std::string& name, const std::string& title,
                                      const std::string& ylabel, const std::string& column,
                                      const std::vector<const SummaryRow*>& rows);

/// One curve of an x-y figure: points in drawing order, and its style (none: its label's).
/// scatter: the points are drawn unjoined (independent runs, e.g. the starts of a multistart).
struct XyCurve {
  std::string label;
  std::vector<std::pair<double, double>> points;
  std::optional<PlotStyle> style = std::nullopt;
  bool scatter = false;
};
/// Points above this are left out of the log-log figures, as non-finite ones are: a run that
/// diverged without stopping would stretch the axis over a hundred decades. The figure says how
/// many.
inline constexpr double kOverflowingValue = 1e30;
/// Log-log x-y figure (file ctx.figure(name); gnuplot script xy_loglog.gp); curves without
/// points are left out, and so are points not positive, not finite or above kOverflowingValue.
std::filesystem::path plot_xy(const RenderContext& ctx, const std::string& name, const std::string& title,
                              const std::string& xlabel, const std::string& ylabel, const std::vector<XyCurve>& curves);

/// One curve per label (first-appearance order) of the completed rows' (x, y) columns, rows
/// without both numbers left out, each styled by its first row (row_style): a work-precision
/// diagram's curves.
std::vector<XyCurve> curves_by_label(const std::vector<const SummaryRow*>& rows, const std::string& x,
                                     const std::string& y);

/// Markdown table of the cheapest method per accuracy level: for each group and each level, among
/// the completed rows whose `error_column` is at most the level, the one with the least
/// integrator time per run (integrator_seconds_min, rows without it are not ranked by time) and
/// the one with the fewest evaluations; "none reached" when no row is that accurate.
/// error_heading names the error in the header ("final-state error").
std::string cheapest_table(const std::vector<std::pair<std::string, std::vector<const SummaryRow*>>>& groups,
                           const std::string& error_column, const std::string& error_heading,
                           const std::vector<double>& levels);

/// Writes text to ctx.out_dir / name atomically; returns the path.
std::filesystem::path write_text_file(const RenderContext& ctx, const std::string& name, const std::string& text);

/// The rows of each group, groups in first-appearance order.
std::vector<std::pair<std::string, std::vector<const SummaryRow*>>> by_group(const std::vector<SummaryRow>& rows);

/// "%.2g" of a number.
std::string fmt(double x);
/// A row's number for a title, as short as reads back the same (0.005, not the summary's
/// 0.0050000000000000001); the cell's text when it holds no number.
std::string title_number(const SummaryRow& row, const std::string& column);

// The suites (experiments/suites/*.cpp).
Suite default_suite(const SuiteParams& params);
Suite energy_drift_suite(const SuiteParams& params);
Suite orthogonality_suite(const SuiteParams& params);
Suite momentum_suite(const SuiteParams& params);
Suite work_precision_suite(const SuiteParams& params);
Suite long_horizon_suite(const SuiteParams& params);
Suite extremes_suite(const SuiteParams& params);
/// 10^7 steps (quick 10^5) per system: conservation and resident memory (experiments/suites/soak.cpp).
Suite soak_suite(const SuiteParams& params);
/// Optimal control (experiments/suites/sensitivity.cpp, shooting.cpp).
Suite sensitivity_suite(const SuiteParams& params);
const std::vector<std::string>& sensitivity_columns();
Suite shooting_suite(const SuiteParams& params);
/// Every optimal control method on each of the paper's examples (experiments/suites/ocp_comparison.cpp).
Suite ocp_comparison_suite(const SuiteParams& params);
/// Every suite above, cases prefixed "<suite>/" (one subdirectory per suite), each rendered by
/// its own renderer.
Suite all_suite(const SuiteParams& params);

}  // namespace lgvi::experiments::suites
