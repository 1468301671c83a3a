#include "experiments/suites/ensemble_statistics.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>

#include "experiments/output/atomic_file.hpp"
#include "experiments/output/fields.hpp"
#include "experiments/output/plot.hpp"
#include "experiments/suites/common.hpp"
#include "experiments/suites/study.hpp"

namespace lgvi::experiments {

namespace fs = std::filesystem;

double quantile(const std::vector<double>& sorted, double p) {
  const double h = static_cast<double>(sorted.size() - 1) * p;
  const auto lo = static_cast<std::size_t>(std::floor(h));
  if (lo + 1 >= sorted.size()) return sorted.back();
  return sorted[lo] + (h - static_cast<double>(lo)) * (sorted[lo + 1] - sorted[lo]);
}

const std::vector<std::string>& ensemble_metric_columns() {
  static const std::vector<std::string> columns = {
      "final_error",       "phase_shift",    "phase_drift_rate", "shape_error",
      "max_energy_error_relative", "max_momentum_drift_absolute", "max_orthogonality_error",
      "max_quaternion_norm_error", "evaluations", "integrator_seconds", "integrator_seconds_min"};
  return columns;
}

const std::vector<std::string>& ensemble_statistics_columns() {
  static const std::vector<std::string> columns = {
      "group", "label", "method", "model", "h", "rtol", "metric", "samples", "completed", "count",
      "median", "q05", "q25", "q75", "q95", "max", "failures", "failing_samples"};
  return columns;
}

std::vector<EnsembleStatistic> ensemble_statistics(const std::vector<SummaryRow>& rows) {
  // The metrics some row reports.
  std::vector<std::string> metrics;
  for (const std::string& m : ensemble_metric_columns()) {
    if (std::any_of(rows.begin(), rows.end(), [&](const SummaryRow& r) { return r.number(m).has_value(); })) {
      metrics.push_back(m);
    }
  }
  // The rows of each (group, label, setting), in first-appearance order.
  std::vector<std::vector<const SummaryRow*>> blocks;
  std::map<std::string, std::size_t> where;
  for (const SummaryRow& r : rows) {
    const std::string key = r.text("group") + '\n' + r.text("label") + '\n' + r.text("h") + '\n' + r.text("rtol");
    const auto [it, inserted] = where.emplace(key, blocks.size());
    if (inserted) blocks.emplace_back();
    blocks[it->second].push_back(&r);
  }
  std::vector<EnsembleStatistic> out;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const std::vector<const SummaryRow*>& block : blocks) {
    EnsembleStatistic base;
    const SummaryRow& first = *block.front();
    base.group = first.text("group");
    base.label = first.text("label");
    base.method = first.text("method");
    base.model = first.text("model");
    base.h = first.text("h");
    base.rtol = first.text("rtol");
    base.samples = block.size();
    std::map<std::string, std::size_t> failures;
    for (const SummaryRow* r : block) {
      if (r->text("status") == "completed") {
        ++base.completed;
        continue;
      }
      ++failures[r->text("status").empty() ? std::string("unknown") : r->text("status")];
      base.failing_samples += (base.failing_samples.empty() ? "" : " ") + r->text("sample");
    }
    for (const auto& [status, n] : failures) {
      base.failures += (base.failures.empty() ? "" : "; ") + status + ": " + std::to_string(n);
    }
    for (const std::string& m : metrics) {
      EnsembleStatistic s = base;
      s.metric = m;
      std::vector<double> v;
      for (const SummaryRow* r : block) {
        if (r->text("status") != "completed") continue;
        if (const auto x = r->number(m)) v.push_back(*x);
      }
      s.count = v.size();
      std::sort(v.begin(), v.end());
      if (v.empty()) {
        s.median = s.q05 = s.q25 = s.q75 = s.q95 = s.max = nan;
      } else {
        s.median = quantile(v, 0.5);
        s.q05 = quantile(v, 0.05);
        s.q25 = quantile(v, 0.25);
        s.q75 = quantile(v, 0.75);
        s.q95 = quantile(v, 0.95);
        s.max = v.back();
      }
      out.push_back(std::move(s));
    }
  }
  return out;
}

namespace {

std::string number_text(double x) {
  if (!std::isfinite(x)) return "";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

/// "h = 0.05" or "rtol = 1e-06": the setting as short as reads back the same (the summary writes
/// 0.050000000000000003).
std::string setting_text(const EnsembleStatistic& s) {
  const auto short_text = [](const std::string& t) {
    double x = 0.0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), x);
    return ec == std::errc() && end == t.data() + t.size() ? shortest(x) : t;
  };
  return s.rtol.empty() ? "h = " + short_text(s.h) : "rtol = " + short_text(s.rtol);
}

/// The statistic of `metric` in the block of `s` (same group, label and setting), or null.
const EnsembleStatistic* find_metric(const std::vector<EnsembleStatistic>& stats, const EnsembleStatistic& s,
                              const std::string& metric) {
  for (const EnsembleStatistic& x : stats) {
    if (x.metric == metric && x.group == s.group && x.label == s.label && x.h == s.h && x.rtol == s.rtol) return &x;
  }
  return nullptr;
}

/// A banded curve: per setting (x, median, q05, q25, q75, q95).
struct BandCurve {
  std::string label;
  PlotStyle style;
  std::vector<std::array<double, 6>> points;
};

/// Log-log figure of banded curves (gnuplot script xy_bands_loglog.gp): points not positive or
/// not finite are left out; curves without points too.
fs::path plot_bands(const RenderContext& ctx, const std::string& name, const std::string& title,
                    const std::string& xlabel, const std::string& ylabel, const std::vector<BandCurve>& curves) {
  const fs::path figure = ctx.figure(name);
  std::string text;
  std::vector<Curve> args;
  TempPath data(figure.string() + ".dat");
  for (const BandCurve& c : curves) {
    std::string block;
    for (const auto& p : c.points) {
      if (!std::all_of(p.begin(), p.end(), [](double x) { return x > 0.0 && x <= suites::kOverflowingValue; })) continue;
      char buf[160];
      std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g %.17g %.17g %.17g\n", p[0], p[1], p[2], p[3], p[4], p[5]);
      block += buf;
    }
    if (block.empty()) continue;
    text += block + "\n\n";
    args.push_back({data.fd_path(), c.label, c.style});
  }
  if (args.empty()) return {};
  data.write(text);
  TempPath list(figure.string() + ".curves");
  list.write(suites::curve_list_text(args));
  run_gnuplot_script(ctx.gnuplot, ctx.plots_dir / "xy_bands_loglog.gp", figure,
                     {wrap_text(title, 64) /* 72, the study figures' width, cut the last character off these titles */, xlabel, ylabel, gnuplot_path(list.fd_path())}, {&data, &list});
  return figure;
}

/// The cheapest method per level of `column` for one group: among the blocks every sample of
/// which completed and whose `which` (median or q95) of the error is at most the level, the one
/// with the least median of `cost`.
std::string cheapest_rows(const std::vector<EnsembleStatistic>& stats, const std::string& group,
                          const std::string& column, const std::string& cost, bool by_q95) {
  std::string t;
  for (const double level : kStudyLevels) {
    const EnsembleStatistic* best = nullptr;
    const EnsembleStatistic* best_cost = nullptr;
    for (const EnsembleStatistic& s : stats) {
      if (s.group != group || s.metric != column || s.count == 0 || s.completed != s.samples) continue;
      if (!((by_q95 ? s.q95 : s.median) <= level)) continue;
      const EnsembleStatistic* c = find_metric(stats, s, cost);
      if (c == nullptr || c->count == 0) continue;
      if (best == nullptr || c->median < best_cost->median) {
        best = &s;
        best_cost = c;
      }
    }
    t += "| " + group + " | " + suites::fmt(level) + " | ";
    if (best == nullptr) {
      t += "none reached | | |\n";
    } else {
      t += best->label + ", " + setting_text(*best) + " | " + suites::fmt(best_cost->median) + " | " +
           suites::fmt(by_q95 ? best->q95 : best->median) + " |\n";
    }
  }
  return t;
}

}  // namespace

std::string ensemble_statistics_csv(const std::vector<EnsembleStatistic>& stats) {
  std::string t =
      "# statistics: per group, method (label) and setting (h or rtol), over the samples: of the completed runs "
      "with a finite value (count), the median, the 5/25/75/95% quantiles (definition 7 of Hyndman and Fan 1996: "
      "linear interpolation between order statistics at (n - 1) p, numpy's default) and the maximum; failures: "
      "runs per status other than completed; failing_samples: their sample numbers\n";
  for (std::size_t i = 0; i < ensemble_statistics_columns().size(); ++i) {
    t += (i == 0 ? "" : ",") + ensemble_statistics_columns()[i];
  }
  t += "\n";
  for (const EnsembleStatistic& s : stats) {
    t += summary_cell(s.group) + "," + summary_cell(s.label) + "," + summary_cell(s.method) + "," + summary_cell(s.model) + "," + s.h + "," + s.rtol +
         "," + s.metric + "," + std::to_string(s.samples) + "," + std::to_string(s.completed) + "," +
         std::to_string(s.count) + "," + number_text(s.median) + "," + number_text(s.q05) + "," +
         number_text(s.q25) + "," + number_text(s.q75) + "," + number_text(s.q95) + "," + number_text(s.max) + "," +
         summary_cell(s.failures) + "," + summary_cell(s.failing_samples) + "\n";
  }
  return t;
}

SuiteRenderer ensemble_renderer(std::string name, std::vector<std::string> metrics) {
  return [name, metrics](const RenderContext& ctx, const std::vector<SummaryRow>& rows) {
    std::vector<fs::path> files;
    const std::vector<EnsembleStatistic> stats = ensemble_statistics(rows);
    files.push_back(suites::write_text_file(ctx, name + "-statistics.csv", ensemble_statistics_csv(stats)));
    const bool timed = std::find(metrics.begin(), metrics.end(), "time") != metrics.end();
    const auto chosen = [&](const char* m) { return std::find(metrics.begin(), metrics.end(), m) != metrics.end(); };

    std::vector<std::string> groups;
    for (const EnsembleStatistic& s : stats) {
      if (std::find(groups.begin(), groups.end(), s.group) == groups.end()) groups.push_back(s.group);
    }
    std::string md = "# " + name + ": statistics over the samples\n\n"
                     "Per scene (and horizon), method and setting: the median, the 5/25/75/95% quantiles "
                     "(definition 7 of Hyndman and Fan 1996, numpy's default) and the maximum over the samples "
                     "that completed (n of N), the failures by status and the samples that failed. All numbers: "
                     + name + "-statistics.csv.\n";
    for (const std::string& group : groups) {
      md += "\n## " + group + "\n";
      for (const StudyMetricView& v : kStudyMetricViews) {
        if (!chosen(v.metric)) continue;
        bool any = false;
        std::string table = "\n### " + std::string(v.what) +
                            "\n\n| method | setting | n / N | median | 5% | 25% | 75% | 95% | max | failures (samples) |\n"
                            "|---|---|---|---|---|---|---|---|---|---|\n";
        for (const EnsembleStatistic& s : stats) {
          if (s.group != group || s.metric != v.column) continue;
          any = true;
          table += "| " + s.label + " | " + setting_text(s) + " | " + std::to_string(s.count) + " / " +
                   std::to_string(s.samples) + " | " + suites::fmt(s.median) + " | " + suites::fmt(s.q05) + " | " +
                   suites::fmt(s.q25) + " | " + suites::fmt(s.q75) + " | " + suites::fmt(s.q95) + " | " +
                   suites::fmt(s.max) + " | " +
                   (s.failures.empty() ? std::string() : s.failures + " (" + s.failing_samples + ")") + " |\n";
        }
        if (any) md += table;
      }
      // The banded work-precision figures and the cheapest methods.
      std::vector<std::pair<std::string, std::string>> axes = {{"evaluations", "evaluations"}};
      if (timed) axes.insert(axes.begin(), {"integrator_seconds_min", "time"});
      for (const StudyMetricView& v : kStudyMetricViews) {
        if (!chosen(v.metric)) continue;
        for (const auto& [cost, suffix] : axes) {
          std::vector<BandCurve> curves;
          for (const EnsembleStatistic& s : stats) {
            if (s.group != group || s.metric != v.column || s.count == 0) continue;
            const EnsembleStatistic* c = find_metric(stats, s, cost);
            if (c == nullptr || c->count == 0) continue;
            auto it = std::find_if(curves.begin(), curves.end(), [&](const BandCurve& b) { return b.label == s.label; });
            if (it == curves.end()) {
              const SummaryRow* row = nullptr;
              for (const SummaryRow& r : rows) {
                if (r.text("group") == s.group && r.text("label") == s.label) {
                  row = &r;
                  break;
                }
              }
              curves.push_back({s.label, row != nullptr ? suites::row_style(*row) : plot_style(s.label), {}});
              it = curves.end() - 1;
            }
            it->points.push_back({c->median, s.median, s.q05, s.q25, s.q75, s.q95});
          }
          const std::string xlabel = suffix == "time" ? "median integrator wall time per run [s]"
                                                      : "median evaluations (baselines: RHS calls; LGVI: substeps)";
          const fs::path png = plot_bands(ctx, group + "-" + v.file + "-bands-" + suffix,
                                          group + ": " + v.what + " vs cost over the samples (median, 25-75%, "
                                                  "5-95%)",
                                          xlabel, v.ylabel, curves);
          if (!png.empty()) files.push_back(png);
        }
        if (std::string_view(v.metric) == "orthogonality") continue;
        for (const bool by_q95 : {false, true}) {
          md += "\n### Cheapest method per level of the " + std::string(v.what) + ", by " +
                (by_q95 ? "95% quantile" : "median") + "\n\n";
          for (const auto& [cost, suffix] : axes) {
            md += "| scene | " + std::string(by_q95 ? "95% quantile" : "median") + " <= | cheapest by median " +
                  (suffix == "time" ? "time per run" : "evaluations") + " | median " +
                  (suffix == "time" ? "time [s]" : "evaluations") + " | " + (by_q95 ? "95% quantile" : "median") +
                  " |\n|---|---|---|---|---|\n" + cheapest_rows(stats, group, v.column, cost, by_q95) + "\n";
          }
        }
      }
    }
    md += "\nRanked: the methods and settings whose every sample completed, by the median of their cost over the "
          "samples.\n";
    files.push_back(suites::write_text_file(ctx, name + "-statistics.md", md));
    return files;
  };
}

}  // namespace lgvi::experiments
