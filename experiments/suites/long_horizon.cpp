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
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include "experiments/suites/study.hpp"
#include "experiments/suites/common.hpp"
#include "experiments/systems/exact_reference.hpp"
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

/// The phase shift tau(t) (signed) of a case's written rows against the exact trajectory
/// (ExactReference::phase_fit at each row's time, started from the previous row's shift so that
/// a shift growing past half a period is followed, not wrapped; the rows' R and Omega read from
/// its CSV), t > 0 only; rows whose fit did not converge are left out. Empty when the CSV cannot
/// be read.
std::vector<std::pair<double, double>> phase_history(const fs::path& csv, const ExactReference& exact) {
  std::vector<std::pair<double, double>> out;
  std::ifstream in(csv);
  std::string line;
  std::vector<int> index;  // columns t, R11..R33, Omega1..3
  double shift = 0.0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) cells.push_back(cell);
    if (index.empty()) {
      for (const char* name : {"t", "R11", "R12", "R13", "R21", "R22", "R23", "R31", "R32", "R33", "Omega1", "Omega2",
                               "Omega3"}) {
        const auto at = std::find(cells.begin(), cells.end(), name);
        if (at == cells.end()) return {};
        index.push_back(static_cast<int>(at - cells.begin()));
      }
      continue;
    }
    double v[13];
    bool ok = true;
    for (int i = 0; i < 13 && ok; ++i) {
      const std::size_t j = static_cast<std::size_t>(index[static_cast<std::size_t>(i)]);
      char* end = nullptr;
      v[i] = j < cells.size() ? std::strtod(cells[j].c_str(), &end) : 0.0;
      ok = j < cells.size() && end != cells[j].c_str();
    }
    if (!ok || !(v[0] > 0.0)) continue;
    Mat3 R;
    R << v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8], v[9];
    const PhaseFit fit =
        exact.phase_fit(exact.sample_of(baselines::ExactState{R, Vec3(v[10], v[11], v[12])}, v[0]), shift);
    if (!fit.converged) continue;
    shift = fit.shift;
    out.emplace_back(v[0], fit.shift);
  }
  return out;
}

/// The exponent p of |tau(t)| ~ t^p: the least-squares slope of log |tau| against log t over the
/// last decade of the run (t >= T / 10), where the start-up transient of the shift is gone. 1 for a method whose frequency error is constant (its energy
/// error bounded: the symplectic and the symmetric methods), 2 when the frequency error grows
/// like t (an energy drift). NaN with fewer than 10 points or a zero shift.
double phase_growth_exponent(const std::vector<std::pair<double, double>>& history) {
  if (history.empty()) return std::numeric_limits<double>::quiet_NaN();
  const double t_end = history.back().first;
  double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
  int n = 0;
  for (const auto& [t, tau] : history) {
    if (t < 0.1 * t_end || !(std::abs(tau) > 0.0)) continue;
    const double x = std::log(t), y = std::log(std::abs(tau));
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    ++n;
  }
  if (n < 10) return std::numeric_limits<double>::quiet_NaN();
  const double denominator = n * sxx - sx * sx;
  return denominator > 0.0 ? (n * sxy - sx * sy) / denominator : std::numeric_limits<double>::quiet_NaN();
}

/// Per scene and method, the energy trend (the least-squares line through E - E0, recorder.hpp's
/// EnergyTrend) and, where the scene has an exact solution, the phase fit, at the largest
/// completed step (fixed-step) or the loosest completed tolerance (adaptive): where methods differ
/// most. The last column counts the method's completed runs over the whole sweep whose energy
/// drifts, so one run does not decide the verdict.
/// The methods (labels, first-appearance order) of a scene's rows, each with its completed run at
/// the largest step (fixed-step) or the loosest tolerance (adaptive), where the energy behaviour
/// of methods differs most, its completed run at the smallest step or tightest tolerance, where the
/// phase shift stays small enough to follow (and is in its asymptotic regime), and the counts of
/// its completed and drifting runs over the sweep.
struct TrendPick {
  std::string label;
  const SummaryRow* row = nullptr;     ///< at the largest step or loosest tolerance
  const SummaryRow* finest = nullptr;  ///< at the smallest step or tightest tolerance: the phase's run
  int completed = 0;
  int drifting = 0;
};
std::vector<TrendPick> trend_picks(const std::vector<const SummaryRow*>& rows) {
  std::vector<TrendPick> picks;
  const auto setting = [](const SummaryRow* r) { return r->number("rtol") ? *r->number("rtol") : r->number("h").value_or(0.0); };
  for (const SummaryRow* r : rows) {
    auto at = std::find_if(picks.begin(), picks.end(), [&](const TrendPick& p) { return p.label == r->text("label"); });
    if (at == picks.end()) at = picks.insert(picks.end(), TrendPick{r->text("label")});
    if (r->text("status") != "completed") continue;
    ++at->completed;
    if (r->text("energy_trend") == "drifts") ++at->drifting;
    if (at->row == nullptr || setting(r) > setting(at->row)) at->row = r;
    if (at->finest == nullptr || setting(r) < setting(at->finest)) at->finest = r;
  }
  std::erase_if(picks, [](const TrendPick& p) { return p.row == nullptr; });
  return picks;
}

std::string energy_trend_table(const std::vector<std::pair<std::string, std::vector<const SummaryRow*>>>& groups,
                               const std::map<std::string, double>& phase_exponents,
                               const std::map<std::string, double>& tracked_rates) {
  std::string t =
      "| scene | method | h or rtol | energy drift rate [1/time] | its std. error | oscillation rms | secular change "
      "|b| T | trend | runs that drift | finest h or rtol | phase drift rate tau/T | phase growth exponent | shape "
      "error | final error |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  const auto setting = [](const SummaryRow* r) {
    return r->number("rtol") ? "rtol " + fmt(*r->number("rtol")) : "h " + fmt(r->number("h").value_or(0.0));
  };
  for (const auto& [scene, rows] : groups) {
    for (const TrendPick& p : trend_picks(rows)) {
      const auto num = [](const SummaryRow* r, const char* column) {
        const auto x = r->number(column);
        return x ? fmt(*x) : std::string();
      };
      const SummaryRow* r = p.row;
      const SummaryRow* f = p.finest;
      const auto exponent = phase_exponents.find(scene + "\n" + p.label);
      const auto tracked = tracked_rates.find(scene + "\n" + p.label);
      const bool graded = !f->text("final_error").empty();
      t += "| " + scene + " | " + p.label + " | " + setting(r) + " | " + num(r, "energy_drift_rate") + " | " +
           num(r, "energy_drift_rate_stderr") + " | " + num(r, "energy_oscillation_rms") + " | " +
           fmt(std::abs(r->number("energy_drift_rate").value_or(0.0)) * r->number("t_final").value_or(0.0)) + " | " +
           r->text("energy_trend") + " | " + std::to_string(p.drifting) + " of " + std::to_string(p.completed) + " | " +
           (graded ? setting(f) : std::string()) + " | " +
           (tracked != tracked_rates.end() ? fmt(tracked->second) : num(f, "phase_drift_rate")) + " | " +
           (exponent != phase_exponents.end() && std::isfinite(exponent->second) ? fmt(exponent->second) : std::string()) +
           " | " + num(f, "shape_error") + " | " + num(f, "final_error") + " |\n";
    }
  }
  return t;
}

}  // namespace

Suite long_horizon_suite(const SuiteParams& params) {
  Suite s = load_study(default_studies_dir() / "long-horizon.toml", params);
  s.render = [scenes_dir = params.scenes_dir](const RenderContext& ctx, const std::vector<SummaryRow>& rows) {
    std::vector<fs::path> files;
    const auto groups = by_group(rows);
    const std::string time_label = "integrator wall time per run [s] (min of repeated serial runs)";
    const std::string evaluations_label = "evaluations (baselines: RHS calls; LGVI: substeps)";
    for (const auto& [scene, group] : groups) {
      const SystemLabels units = system_labels(group.front()->text("system"));
      const std::string horizon = "T = " + title_number(*group.front(), "t_final") + units.horizon_unit;
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
        files.push_back(plot_xy(ctx, scene + "-" + f.name,
                                scene + ": " + f.what + " over " + horizon + " vs cost (sweeps of h and rtol)",
                                f.xlabel, f.ylabel, curves_by_label(group, f.x, f.y)));
      }
    }
    // Scenes graded against an exact solution: the phase shift tau(t) of each method's finest run
    // (trend_picks), drawn on log-log axes (slope 1: linear growth, 2: quadratic), and its
    // growth exponent for the table.
    std::map<std::string, double> phase_exponents;
    std::map<std::string, double> tracked_rates;  // tau(T) / T followed along the rows
    for (const auto& [scene, group] : groups) {
      if (group.front()->text("reference").rfind("exact", 0) != 0) continue;
      std::optional<ExactReference> exact;
      try {
        exact = ExactReference::of(load_scene(resolve_scene(group.front()->text("scene"), scenes_dir)).model);
      } catch (const std::exception&) {
        continue;  // the scene no longer loads: its cases reported it
      }
      if (!exact) continue;
      std::vector<XyCurve> curves;
      for (const TrendPick& p : trend_picks(group)) {
        const std::vector<std::pair<double, double>> history =
            phase_history(ctx.data_dir / p.finest->text("csv_path"), *exact);
        phase_exponents[scene + "\n" + p.label] = phase_growth_exponent(history);
        if (!history.empty()) tracked_rates[scene + "\n" + p.label] = history.back().second / history.back().first;
        XyCurve curve{p.label + (p.finest->number("rtol") ? " rtol " : " h ") +
                          fmt(p.finest->number("rtol").value_or(p.finest->number("h").value_or(0.0))),
                      {},
                      row_style(*p.finest)};
        for (const auto& [t, tau] : history) curve.points.emplace_back(t, std::abs(tau));
        curves.push_back(std::move(curve));
      }
      const SystemLabels units = system_labels(group.front()->text("system"));
      files.push_back(plot_xy(ctx, scene + "-phase-time",
                              scene + ": phase shift |tau(t)| against the exact solution (smallest h, tightest rtol)",
                              units.time, "|tau| (time shift to the exact trajectory)", curves));
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
    table +=
        "\n## Energy trend and phase\n\n"
        "The line E - E_0 = a + b t fitted to the run's samples by least squares (relative to |E_0|): its slope b "
        "(energy drift rate) with its standard error (white residuals: a lower bound), the rms of the oscillation "
        "about it, and the verdict: drifts when |b| T > 5 rms and above the round-off floor 10 eps sqrt(steps), else "
        "bounded (experiments/methods/recorder.hpp, EnergyTrend). The free body is graded against its closed form: "
        "the time shift tau that best aligns the state with the exact trajectory, followed row by row from t = 0 "
        "(phase drift rate tau(T) / T), the error left after the shift at T (shape error; empty where the fit "
        "started from tau = 0 at T alone finds no minimum: a shift of a large part of a period), beside the "
        "final-state error, and the exponent p of "
        "|tau(t)| ~ t^p over the last decade of the run (1: a constant frequency error, bounded energy error; 2: a "
        "frequency error growing like t). The energy trend is at the largest completed step or the loosest "
        "tolerance ('runs that drift' counts the whole sweep), the phase at the smallest step or the tightest "
        "tolerance, where the shift stays small enough to follow.\n\n";
    table += energy_trend_table(groups, phase_exponents, tracked_rates);
    files.push_back(write_text_file(ctx, "long-horizon-table.md", table));
    return files;
  };
  return s;
}

}  // namespace lgvi::experiments::suites
