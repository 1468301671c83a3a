#include "experiments/suites/common.hpp"

#include <cmath>
#include <algorithm>
#include <cstdio>
#include <map>

#include "baselines/model.hpp"
#include "baselines/solver.hpp"
#include "experiments/output/atomic_file.hpp"
#include "experiments/output/fields.hpp"
#include "experiments/output/plot.hpp"
#include "experiments/systems/systems.hpp"

namespace lgvi::experiments::suites {

namespace fs = std::filesystem;

std::string MethodSpec::label() const {
  if (info->on_group()) return info->legend;
  return info->legend + " (" + model.value_or("?") + ")";
}

std::string MethodSpec::id() const { return model ? method + "-" + *model : method; }

std::vector<MethodSpec> lgvi_methods(bool quick) {
  std::vector<MethodSpec> m;
  if (quick) m = {{"lgvi"}, {"lgvi-yoshida4"}, {"lgvi-kahan-li6"}};
  for (const MethodInfo* info : methods_where([](const MethodInfo& i) { return i.on_group(); })) {
    if (!quick || !info->variational) m.push_back({info->name});
  }
  return m;
}

std::vector<MethodSpec> adaptive_sweep_methods(bool quick) {
  if (quick) {
    return {{"cvode-adams", "quaternion", std::nullopt}, {"cvode-bdf", "quaternion", std::nullopt},
            {"odeint-dopri5", "quaternion", std::nullopt}, {"odeint-dopri5", "matrix", std::nullopt},
            {"gsl-rk8pd", "quaternion", std::nullopt}};
  }
  std::vector<MethodSpec> m;
  for (const MethodInfo* info : methods_where([](const MethodInfo& i) { return i.adaptive(); })) {
    for (const char* model : {"quaternion", "matrix"}) m.push_back({info->name, std::string(model), std::nullopt});
  }
  return m;
}

std::vector<MethodSpec> long_run_methods(bool quick) {
  std::vector<MethodSpec> m = lgvi_methods(quick);
  if (quick) {
    for (const auto& [method, model] : std::vector<std::pair<const char*, const char*>>{
             {"cvode-adams", "quaternion"},
             {"cvode-bdf", "quaternion"},
             {"cvode-bdf-projected", "quaternion"},
             {"odeint-rk4", "quaternion"},
             {"odeint-rk4", "quaternion-renormalized"},
             {"odeint-rk4", "matrix"},
             {"odeint-dopri5", "quaternion"},
             {"odeint-dopri5", "matrix"},
             {"gsl-rk8pd", "quaternion"},
             {"gsl-rk4imp", "quaternion"}}) {
      m.push_back({method, std::string(model), std::nullopt});
    }
    return m;
  }
  for (const MethodInfo* info : methods_where([](const MethodInfo& i) { return !i.on_group(); })) {
    for (const baselines::CoordinateModel model : info->models) {
      m.push_back({info->name, std::string(baselines::to_string(model)), std::nullopt});
    }
  }
  return m;
}

const std::vector<std::string>& simulation_columns() {
  static const std::vector<std::string> columns = {
      "scene",           "system",           "label",           "method",           "model",
      "form",            "variant",          "h",               "rtol",             "h_omega",
      "t_final",         "solver_steps",     "evaluations",     "rhs_evaluations",  "newton_iterations",
      "integrator_seconds", "max_energy_error_relative", "max_energy_error_absolute", "energy_drift_rate",
      "energy_drift_rate_stderr", "energy_oscillation_rms", "energy_trend", "max_orthogonality_error",
      "max_quaternion_norm_error", "max_momentum_drift_absolute", "final_error", "phase_shift", "phase_drift_rate",
      "shape_error", "reference", "csv_path"};
  return columns;
}

const std::vector<std::string>& timing_columns() {
  static const std::vector<std::string> columns = {"integrator_seconds_min", "integrator_seconds_median",
                                                   "integrator_cpu_seconds", "timing_repetitions"};
  return columns;
}

SuiteCase simulate_case(const std::string& id, const std::string& group, SimulateSpec spec, const MethodSpec& m,
                        Expectation expect, std::shared_ptr<const ReferenceRun> reference) {
  spec.method = m.method;
  spec.options = m.options();
  Fields labels = {{"scene", spec.scene}, {"label", m.label()}, {"method", m.method}};
  if (m.model) labels.push_back({"model", *m.model});
  if (spec.edit) labels.push_back({"variant", spec.edit->description});
  if (m.rtol) {
    labels.push_back({"rtol", *m.rtol});
  } else if (spec.overrides.h) {
    labels.push_back({"h", *spec.overrides.h});
  }
  SuiteCase c;
  c.id = id;
  c.group = group;
  c.labels = std::move(labels);
  c.expect = expect;
  c.job = std::make_shared<SimulateJob>(std::move(spec), std::move(reference));
  return c;
}

namespace {

/// Characters per title line of the 6.5 in wide figures (9 pt text).
constexpr std::size_t kTitleWidth = 72;

}  // namespace

PlotStyle row_style(const SummaryRow& row) {
  const std::string& method = row.text("method");
  if (method.empty()) return plot_style(row.text("label"));
  if (method == "lgvi" && row.text("form") == "printed") return plot_style("lgvi-printed");
  return plot_style(method, row.text("model"));
}

std::string curve_list_text(const std::vector<Curve>& curves) {
  std::string text = "n = " + std::to_string(curves.size()) +
                     "\narray file[n]\narray label[n]\narray colour[n]\narray point[n]\narray dash[n]\n";
  std::vector<PlotStyle> styles;
  for (std::size_t i = 0; i < curves.size(); ++i) {
    const std::string k = std::to_string(i + 1);
    PlotStyle style = curves[i].style ? *curves[i].style : plot_style(curves[i].label);
    // Two curves of one method (two steps, two tolerances) would look alike: a curve whose
    // style an earlier curve of the figure has takes its label's.
    if (std::find(styles.begin(), styles.end(), style) != styles.end()) style = plot_style(curves[i].label);
    styles.push_back(style);
    text += "file[" + k + "] = " + gnuplot_path_literal(curves[i].csv) + "\n";
    text += "label[" + k + "] = " + gnuplot_literal(curves[i].label) + "\n";
    text += "colour[" + k + "] = " + gnuplot_literal(style.colour) + "; point[" + k + "] = " +
            std::to_string(style.point) + "; dash[" + k + "] = " + std::to_string(style.dash) + "\n";
  }
  return text;
}

namespace {

/// The curve list (curve_list_text) written into `list`, a temporary next to the figure (removed
/// with it), which gnuplot reads through list.fd_path() (run_gnuplot_script).
void write_curve_list(TempPath& list, const std::vector<Curve>& curves) { list.write(curve_list_text(curves)); }

}  // namespace

fs::path plot_time_series(const RenderContext& ctx, const std::string& name, const std::string& title,
                          const std::string& ylabel, const std::string& column, bool log_x,
                          const std::vector<const SummaryRow*>& rows, CurvesBy by) {
  std::vector<Curve> curves;
  std::string system;
  for (const SummaryRow* r : rows) {
    const fs::path csv = ctx.data_dir / r->text("csv_path");
    std::error_code ec;
    if (r->text("csv_path").empty() || !fs::is_regular_file(csv, ec)) continue;  // no run (rejected input, error)
    std::string label = by == CurvesBy::System ? r->text("scene") : r->text("label");
    if (r->text("status") != "completed") label += " [" + r->text("status") + "]";
    curves.push_back({csv, label, by == CurvesBy::System ? plot_style(r->text("system")) : row_style(*r)});
    system = r->text("system");
  }
  if (curves.empty()) return {};
  const fs::path figure = ctx.figure(name);
  TempPath list(figure.string() + ".curves");
  write_curve_list(list, curves);
  run_gnuplot_script(ctx.gnuplot, ctx.plots_dir / "time_series.gp", figure,
                     {wrap_text(title, kTitleWidth), system_labels(system).time, ylabel, gnuplot_path(list.fd_path()),
                      column + (log_x ? ":logx" : "")},
                     {&list});
  return figure;
}

fs::path plot_iterations(const RenderContext& ctx, const std::string& name, const std::string& title,
                         const std::string& ylabel, const std::string& column, const std::vector<const SummaryRow*>& rows) {
  std::vector<Curve> curves;
  for (const SummaryRow* r : rows) {
    const fs::path csv = ctx.data_dir / r->text("csv_path");
    std::error_code ec;
    if (r->text("csv_path").empty() || !fs::is_regular_file(csv, ec)) continue;
    std::string label = r->text("label");
    // The case's own label: a solver configuration, styled by its name.
    const PlotStyle style = plot_style(label);
    if (r->text("status") != "completed") label += " [" + r->text("status") + "]";
    curves.push_back({csv, label, style});
  }
  if (curves.empty()) return {};
  const fs::path figure = ctx.figure(name);
  TempPath list(figure.string() + ".curves");
  write_curve_list(list, curves);
  run_gnuplot_script(ctx.gnuplot, ctx.plots_dir / "iteration_history.gp", figure,
                     {wrap_text(title, kTitleWidth), "outer (Newton) iteration", ylabel, gnuplot_path(list.fd_path()), column}, {&list});
  return figure;
}

fs::path plot_xy(const RenderContext& ctx, const std::string& name, const std::string& title,
                 const std::string& xlabel, const std::string& ylabel, const std::vector<XyCurve>& curves) {
  const fs::path figure = ctx.figure(name);
  // The points go through a temporary data file (one gnuplot data block per curve), removed
  // afterwards: the figure is the output, the numbers are in summary.csv.
  std::string text;
  std::size_t blocks = 0;
  std::size_t overflowing = 0;
  std::vector<std::pair<std::string, PlotStyle>> labels;
  for (const XyCurve& c : curves) {
    std::string block;
    for (const auto& [x, y] : c.points) {
      if (!(x > 0.0) || !(y > 0.0) || !std::isfinite(x) || !std::isfinite(y)) continue;  // log axes
      if (x > kOverflowingValue || y > kOverflowingValue) {
        ++overflowing;
        continue;
      }
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.17g %.17g\n", x, y);
      block += buf;
      if (c.scatter) block += '\n';  // a blank line: gnuplot does not join the points
    }
    if (block.empty()) continue;
    text += block + "\n\n";
    labels.emplace_back(c.label, c.style ? *c.style : plot_style(c.label));
    ++blocks;
  }
  if (blocks == 0) return {};
  TempPath data(figure.string() + ".dat");
  data.write(text);
  std::vector<Curve> args;
  for (const auto& [label, style] : labels) args.push_back({data.fd_path(), label, style});
  TempPath list(figure.string() + ".curves");
  write_curve_list(list, args);
  std::vector<std::string> script_args = {wrap_text(title, kTitleWidth), xlabel, ylabel, gnuplot_path(list.fd_path())};
  if (overflowing > 0) {
    script_args.push_back(std::to_string(overflowing) + (overflowing == 1 ? " point" : " points") +
                          " above 1e30 not drawn");
  }
  run_gnuplot_script(ctx.gnuplot, ctx.plots_dir / "xy_loglog.gp", figure, script_args, {&data, &list});
  return figure;
}

std::vector<XyCurve> curves_by_label(const std::vector<const SummaryRow*>& rows, const std::string& x,
                                     const std::string& y) {
  std::vector<XyCurve> curves;
  std::map<std::string, std::size_t> where;
  for (const SummaryRow* r : rows) {
    if (r->text("status") != "completed") continue;
    const auto [it, inserted] = where.emplace(r->text("label"), curves.size());
    if (inserted) curves.push_back({r->text("label"), {}, row_style(*r)});
    const auto xv = r->number(x);
    const auto yv = r->number(y);
    if (xv && yv) curves[it->second].points.emplace_back(*xv, *yv);
  }
  return curves;
}

namespace {

/// "rtol = 1e-06" or "h = 0.01": the swept setting of a row.
std::string setting(const SummaryRow& r) {
  const auto rtol = r.number("rtol");
  return rtol ? "rtol = " + fmt(*rtol) : "h = " + fmt(r.number("h").value_or(0.0));
}

}  // namespace

std::string cheapest_table(const std::vector<std::pair<std::string, std::vector<const SummaryRow*>>>& groups,
                           const std::string& error_column, const std::string& error_heading,
                           const std::vector<double>& levels) {
  std::string t = "| scene | " + error_heading +
                  " <= | cheapest by integrator time | time per run [s] | error | cheapest by evaluations | "
                  "evaluations | error |\n|---|---|---|---|---|---|---|---|\n";
  for (const auto& [scene, rows] : groups) {
    for (const double level : levels) {
      const SummaryRow* by_time = nullptr;
      const SummaryRow* by_evals = nullptr;
      for (const SummaryRow* r : rows) {
        const auto e = r->number(error_column);
        if (r->text("status") != "completed" || !e || *e > level) continue;
        const auto time = r->number("integrator_seconds_min");
        if (time && (by_time == nullptr || *time < *by_time->number("integrator_seconds_min"))) by_time = r;
        const auto evals = r->number("evaluations");
        if (evals && (by_evals == nullptr || *evals < *by_evals->number("evaluations"))) by_evals = r;
      }
      t += "| " + scene + " | " + fmt(level) + " | ";
      if (by_time == nullptr) {
        t += "none reached | | | ";
      } else {
        t += by_time->text("label") + ", " + setting(*by_time) + " | " +
             fmt(*by_time->number("integrator_seconds_min")) + " | " + fmt(*by_time->number(error_column)) + " | ";
      }
      if (by_evals == nullptr) {
        t += "none reached | | |\n";
      } else {
        t += by_evals->text("label") + ", " + setting(*by_evals) + " | " + by_evals->text("evaluations") + " | " +
             fmt(*by_evals->number(error_column)) + " |\n";
      }
    }
  }
  return t;
}

fs::path write_text_file(const RenderContext& ctx, const std::string& name, const std::string& text) {
  AtomicFile f(ctx.out_dir / name);
  f.write(text);
  f.commit();
  return ctx.out_dir / name;
}

std::vector<std::pair<std::string, std::vector<const SummaryRow*>>> by_group(const std::vector<SummaryRow>& rows) {
  std::vector<std::pair<std::string, std::vector<const SummaryRow*>>> groups;
  std::map<std::string, std::size_t> where;
  for (const SummaryRow& r : rows) {
    const std::string& g = r.text("group");
    const auto [it, inserted] = where.emplace(g, groups.size());
    if (inserted) groups.push_back({g, {}});
    groups[it->second].second.push_back(&r);
  }
  return groups;
}

std::string fmt(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2g", x);
  return buf;
}

std::string title_number(const SummaryRow& row, const std::string& column) {
  const auto x = row.number(column);
  return x ? shortest(*x) : row.text(column);
}

}  // namespace lgvi::experiments::suites
