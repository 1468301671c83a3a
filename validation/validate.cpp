#include "validation/validate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "experiments/input/read_file.hpp"
#include "experiments/output/atomic_file.hpp"
#include "experiments/output/data_dir.hpp"
#include "experiments/output/fields.hpp"
#include "lgvi/inertia.hpp"

namespace lgvi::experiments {

namespace fs = std::filesystem;

namespace {

// The rules of the kinds (validate.hpp states their derivation).
constexpr double kOrderBand = 0.05;
constexpr double kTruncationRelative = 1e-6;
constexpr double kRoundOffFactor = 10.0;
constexpr double kCostRelative = 1e-9;
constexpr double kCountRelative = 0.05;
constexpr double kCountAbsolute = 0.5;
constexpr double kConditionFactor = 10.0;

struct KindName {
  MetricKind kind;
  const char* name;
};
constexpr KindName kKindNames[] = {
    {MetricKind::Order, "order"},         {MetricKind::Truncation, "truncation"},
    {MetricKind::RoundOff, "round-off"},  {MetricKind::Cost, "cost"},
    {MetricKind::Count, "count"},         {MetricKind::Condition, "condition"},
};

std::string number(double x) {
  if (!std::isfinite(x)) return std::isnan(x) ? "nan" : (x > 0 ? "inf" : "-inf");
  return shortest(x);
}

/// Short human form for the table: 4 significant digits.
std::string brief(std::optional<double> x) {
  if (!x) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", *x);
  return buf;
}

double parse_number(const std::string& text, const std::string& where) {
  if (text == "nan") return std::nan("");
  if (text == "inf") return INFINITY;
  if (text == "-inf") return -INFINITY;
  std::size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size()) throw InvalidInput(where, "'" + text + "' is not a number");
  return v;
}

}  // namespace

const char* to_string(MetricKind kind) {
  for (const KindName& k : kKindNames) {
    if (k.kind == kind) return k.name;
  }
  return "unknown";
}

MetricKind parse_metric_kind(const std::string& name) {
  for (const KindName& k : kKindNames) {
    if (name == k.name) return k.kind;
  }
  throw InvalidInput("kind", "unknown metric kind '" + name + "' (order, truncation, round-off, cost, count, condition)");
}

const char* to_string(Verdict v) {
  switch (v) {
    case Verdict::Pass: return "pass";
    case Verdict::Regressed: return "REGRESSED";
    case Verdict::Improved: return "improved";
    case Verdict::Changed: return "CHANGED";
    case Verdict::New: return "new";
    case Verdict::Missing: return "missing";
  }
  return "unknown";
}

namespace {

/// The rules of the kinds (validate.hpp), moves down being `improved`.
Verdict judge_one_sided(MetricKind kind, double accepted, double now, double floor, std::optional<double> nominal) {
  if (!std::isfinite(now) || !std::isfinite(accepted)) {
    if (!std::isfinite(now) && !std::isfinite(accepted)) return Verdict::Pass;
    return std::isfinite(now) ? Verdict::Improved : Verdict::Regressed;
  }
  switch (kind) {
    case MetricKind::Order: {
      if (std::abs(now - accepted) <= kOrderBand) return Verdict::Pass;
      if (nominal && std::abs(now - *nominal) < std::abs(accepted - *nominal)) return Verdict::Improved;
      return Verdict::Regressed;
    }
    case MetricKind::Truncation:
    case MetricKind::Cost: {
      const double rel = kind == MetricKind::Cost ? kCostRelative : kTruncationRelative;
      // A truncation error also carries a round-off share, which moves with the operation order:
      // its band adds the round-off factor times the metric's floor (0 where none is given).
      const double band = rel * std::abs(accepted) + (kind == MetricKind::Truncation ? kRoundOffFactor * floor : 0.0);
      if (std::abs(now - accepted) <= band) return Verdict::Pass;
      return now > accepted ? Verdict::Regressed : Verdict::Improved;
    }
    case MetricKind::RoundOff: {
      const double reference = std::max(accepted, floor);
      if (now > kRoundOffFactor * reference) return Verdict::Regressed;
      if (accepted > floor && now < accepted / kRoundOffFactor) return Verdict::Improved;
      return Verdict::Pass;
    }
    case MetricKind::Count: {
      const double band = kCountRelative * std::abs(accepted) + kCountAbsolute;
      if (now > accepted + band) return Verdict::Regressed;
      if (now < accepted - band) return Verdict::Improved;
      return Verdict::Pass;
    }
    case MetricKind::Condition: {
      if (now > kConditionFactor * accepted) return Verdict::Regressed;
      if (now < accepted / kConditionFactor) return Verdict::Improved;
      return Verdict::Pass;
    }
  }
  return Verdict::Regressed;
}

}  // namespace

Verdict judge(MetricKind kind, double accepted, double now, double floor, std::optional<double> nominal,
              bool two_sided) {
  const Verdict one_sided = judge_one_sided(kind, accepted, now, floor, nominal);
  return two_sided && one_sided == Verdict::Improved ? Verdict::Changed : one_sided;
}

const std::vector<DegradationInfo>& degradations() {
  static const std::vector<DegradationInfo> list = {
      {Degradation::RotationUpdate, "rotation-update",
       "the single-body LGVIs' rotation update with relative tolerance 1e-9 instead of 16 eps and no polishing step",
       "conservation: energy, momentum and Newton counts of the single-body LGVIs (the badly conditioned body's most)"},
      {Degradation::ExactReference, "exact-reference",
       "the closed forms (free body, Lagrange top, literature problems) evaluated at t (1 - 1e-9): a reference "
       "drifting in phase, which lowers some methods' errors",
       "exact and literature: the closed forms against gsl-rk8pd and the stored references, and the methods' "
       "errors (two-sided)"},
      {Degradation::ControlTiming, "control-timing",
       "every scene control late by one step, u(t - h): the impulses of both LGVI forms misplaced by one step",
       "order and final-state metrics of the controlled scenes (every system, both forms)"},
      {Degradation::UncompensatedAttitude, "uncompensated-attitude",
       "the cart-pendulum LGVI's attitude sum R_k + R_k (F - I) without its compensation",
       "conservation: orthogonality of the cart-pendulum's LGVIs (floor 4 eps: a bounded error)"},
  };
  return list;
}

Degradation parse_degradation(const std::string& name) {
  std::string known;
  for (const DegradationInfo& d : degradations()) {
    if (name == d.name) return d.id;
    known += (known.empty() ? "" : ", ") + std::string(d.name);
  }
  throw InvalidInput("--degrade", "unknown degradation '" + name + "' (known: " + known + ")");
}

bool ValidateOptions::degrades(Degradation d) const {
  return std::find(degraded.begin(), degraded.end(), d) != degraded.end();
}

fs::path default_accepted_file(bool quick) {
  return data_dir("validation", "validation") / (quick ? "accepted-quick.txt" : "accepted-full.txt");
}

fs::path accept_destination(const fs::path& given, const fs::path& default_file, bool default_is_installed) {
  if (!given.empty()) return given;
  if (default_is_installed) {
    throw InvalidInput("--accepted", "--accept writes the accepted values to a file you name: the default " +
                                         default_file.string() +
                                         " belongs to the installation (give --accepted FILE, then compare "
                                         "later runs with validate --accepted FILE)");
  }
  return default_file;
}

fs::path accept_destination(const fs::path& given, bool quick) {
  return accept_destination(given, default_accepted_file(quick), data_dir_is_installed("validation"));
}

// File format: '#' comment lines, "# accepted_at: DESCRIBE", "# form: quick|full", then one
// line per metric "NAME KIND VALUE", sorted by name. Names contain no blanks.
AcceptedFile read_accepted(const fs::path& file, bool missing_is_empty) {
  AcceptedFile a;
  std::error_code ec;
  if (!fs::exists(file, ec)) {
    if (missing_is_empty) return a;
    throw InvalidInput(file.string(), "does not exist (the accepted values to compare with: validation/accepted-quick.txt "
                                      "or accepted-full.txt, or a file written by validate --accept --accepted FILE)");
  }
  // A regular file of at most 64 MiB (read_file.hpp): a FIFO or a device is refused, not read.
  std::istringstream in(read_regular_file(file, kMaxDataFileBytes, "the accepted values"));
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    const std::string where = file.string() + ": line " + std::to_string(n);
    if (line.empty()) continue;
    if (line[0] == '#') {
      const auto key = [&](const std::string& k) { return line.rfind("# " + k + ": ", 0) == 0; };
      if (key("accepted_at")) a.accepted_at = line.substr(std::string("# accepted_at: ").size());
      if (key("form")) a.form = line.substr(std::string("# form: ").size());
      continue;
    }
    std::istringstream fields(line);
    std::string name, kind, value, extra;
    if (!(fields >> name >> kind >> value) || (fields >> extra)) {
      throw InvalidInput(where, "expected 'NAME KIND VALUE'");
    }
    if (a.values.count(name)) throw InvalidInput(where, "metric '" + name + "' appears twice");
    try {
      a.values[name] = AcceptedValue{parse_metric_kind(kind), parse_number(value, where)};
    } catch (const InvalidInput& e) {
      throw InvalidInput(where, e.what());
    }
  }
  return a;
}

void write_accepted(const fs::path& file, const std::vector<Metric>& metrics, const std::string& form,
                    const std::string& accepted_at) {
  std::vector<const Metric*> sorted;
  for (const Metric& m : metrics) sorted.push_back(&m);
  std::sort(sorted.begin(), sorted.end(), [](const Metric* a, const Metric* b) { return a->name < b->name; });
  std::string text =
      "# Accepted accuracy metrics of `lgvi-testbed validate" + std::string(form == "quick" ? " --quick" : "") +
      "` (validation/validate.hpp states each kind's rule).\n"
      "# Regenerate with `lgvi-testbed validate" + (form == "quick" ? std::string(" --quick") : std::string()) +
      " --accept` in the commit that changes them, after reading what changed.\n"
      "# accepted_at: " + accepted_at + "\n# form: " + form + "\n";
  for (const Metric* m : sorted) text += m->name + " " + to_string(m->kind) + " " + number(m->value) + "\n";
  AtomicFile out(file);
  out.write(text);
  out.commit();
}


ValidateReport compare(const std::vector<Metric>& metrics, const AcceptedFile& accepted,
                       const std::vector<std::string>& groups) {
  ValidateReport r;
  r.form = accepted.form;
  r.accepted_at = accepted.accepted_at;
  std::set<std::string> seen;
  for (const Metric& m : metrics) {
    MetricComparison c;
    c.name = m.name;
    c.kind = m.kind;
    c.paper = m.paper;
    c.now = m.value;
    c.seconds = m.seconds;
    c.detail = m.detail;
    const auto it = accepted.values.find(m.name);
    if (it == accepted.values.end()) {
      c.verdict = Verdict::New;
    } else {
      c.accepted = it->second.value;
      c.verdict = judge(m.kind, it->second.value, m.value, m.floor, m.nominal, m.two_sided);
    }
    seen.insert(m.name);
    r.rows.push_back(std::move(c));
  }
  for (const auto& [name, value] : accepted.values) {
    if (seen.count(name)) continue;
    if (!groups.empty() && std::find(groups.begin(), groups.end(), metric_group(name)) == groups.end()) continue;
    MetricComparison c;
    c.name = name;
    c.kind = value.kind;
    c.accepted = value.value;
    c.verdict = Verdict::Missing;
    r.rows.push_back(std::move(c));
  }
  std::sort(r.rows.begin(), r.rows.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  return r;
}

std::size_t ValidateReport::count(Verdict v) const {
  return static_cast<std::size_t>(std::count_if(rows.begin(), rows.end(), [v](const auto& c) { return c.verdict == v; }));
}

std::size_t ValidateReport::gated() const { return rows.size() - count(Verdict::New) - count(Verdict::Missing); }

namespace {

std::string ratio_text(const MetricComparison& c) {
  if (!c.accepted || !c.now || *c.accepted == 0.0) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", *c.now / *c.accepted);
  return buf;
}

std::string summary_line(const ValidateReport& r) {
  std::ostringstream s;
  s << r.rows.size() << " metrics: " << r.count(Verdict::Pass) << " pass, " << r.count(Verdict::Regressed)
    << " REGRESSED, " << r.count(Verdict::Changed) << " CHANGED, " << r.count(Verdict::Improved) << " improved, "
    << r.count(Verdict::New) << " new, "
    << r.count(Verdict::Missing) << " missing";
  return s.str();
}

}  // namespace

void print_report(const ValidateReport& report, std::ostream& out) {
  std::size_t width = 6;
  for (const auto& c : report.rows) width = std::max(width, c.name.size());
  char buf[512];
  std::snprintf(buf, sizeof buf, "%-*s  %-10s  %-10s  %-10s  %-10s  %-8s  %-9s  %s\n", static_cast<int>(width),
                "metric", "kind", "paper", "accepted", "now", "ratio", "verdict", "seconds (not gated)");
  out << buf;
  for (const auto& c : report.rows) {
    std::snprintf(buf, sizeof buf, "%-*s  %-10s  %-10s  %-10s  %-10s  %-8s  %-9s  %.3g\n", static_cast<int>(width),
                  c.name.c_str(), to_string(c.kind), brief(c.paper).c_str(), brief(c.accepted).c_str(),
                  brief(c.now).c_str(), ratio_text(c).c_str(), to_string(c.verdict), c.seconds);
    out << buf;
  }
  out << summary_line(report) << " (accepted at " << (report.accepted_at.empty() ? "-" : report.accepted_at)
      << ", now " << report.version << ")\n";
  if (report.count(Verdict::Regressed) + report.count(Verdict::Changed) > 0) {
    out << "regressed:";
    for (const auto& c : report.rows) {
      if (c.verdict == Verdict::Regressed || c.verdict == Verdict::Changed) out << " " << c.name;
    }
    out << "\n";
    out << "next: read each metric's detail (--json FILE), find the change that moved it; if the change is "
           "intended, re-accept in the same commit with validate"
        << (report.form == "quick" ? " --quick" : "") << " --accept and name the metrics in the commit message\n";
  }
  if (report.gated() == 0) {
    out << "no metric has an accepted value (" << report.rows.size()
        << " new): nothing was gated, so the gate fails; check --accepted and the form (--quick)\n";
  }
}

void write_report_json(const ValidateReport& report, const fs::path& file) {
  using nlohmann::json;
  const auto opt = [](std::optional<double> x) -> json {
    if (!x || !std::isfinite(*x)) return nullptr;
    return *x;
  };
  json j;
  j["version"] = report.version;
  j["form"] = report.form;
  j["accepted_at"] = report.accepted_at;
  j["summary"] = {{"metrics", report.rows.size()},
                  {"pass", report.count(Verdict::Pass)},
                  {"regressed", report.count(Verdict::Regressed)},
                  {"improved", report.count(Verdict::Improved)},
                  {"changed", report.count(Verdict::Changed)},
                  {"new", report.count(Verdict::New)},
                  {"missing", report.count(Verdict::Missing)}};
  json rows = json::array();
  for (const auto& c : report.rows) {
    rows.push_back({{"metric", c.name},
                    {"kind", to_string(c.kind)},
                    {"paper", opt(c.paper)},
                    {"accepted", opt(c.accepted)},
                    {"now", opt(c.now)},
                    {"verdict", to_string(c.verdict)},
                    {"seconds", c.seconds},
                    {"detail", c.detail}});
  }
  j["metrics"] = rows;
  AtomicFile out(file);
  out.write(j.dump(1) + "\n");
  out.commit();
}

void write_report_markdown(const ValidateReport& report, const fs::path& file) {
  // First the metrics the paper reports a value for (docs/validate.md splices this part, up to the
  // "all metrics" marker, into its validation table), then every metric.
  std::string t = "| metric | kind | paper | accepted | now | verdict | what was run |\n|---|---|---|---|---|---|---|\n";
  for (const auto& c : report.rows) {
    if (!c.paper) continue;
    t += "| `" + c.name + "` | " + to_string(c.kind) + " | " + brief(c.paper) + " | " + brief(c.accepted) + " | " +
         brief(c.now) + " | " + to_string(c.verdict) + " | " + c.detail + " |\n";
  }
  t.append("\n").append(summary_line(report)).append(" (every metric: validation/validation-table.md, below the marker).\n\n<!-- all metrics -->\n\n");
  t += "| metric | kind | paper | accepted | now | verdict | what was run |\n|---|---|---|---|---|---|---|\n";
  for (const auto& c : report.rows) {
    t += "| `" + c.name + "` | " + to_string(c.kind) + " | " + brief(c.paper) + " | " + brief(c.accepted) + " | " +
         brief(c.now) + " | " + to_string(c.verdict) + " | " + c.detail + " |\n";
  }
  // Appends only: GCC 12 warns falsely (-Wrestrict) on "literal" + std::string.
  t.append("\n").append(summary_line(report)).append("; `lgvi-testbed validate");
  t.append(report.form == "quick" ? " --quick" : "").append("` at ").append(report.version).append(".\n");
  AtomicFile out(file);
  out.write(t);
  out.commit();
}

std::vector<std::string> accepted_diff(const AcceptedFile& before, const std::vector<Metric>& metrics) {
  std::vector<std::string> lines;
  std::set<std::string> now;
  for (const Metric& m : metrics) {
    now.insert(m.name);
    const auto it = before.values.find(m.name);
    if (it == before.values.end()) {
      lines.push_back("+ " + m.name + ": " + number(m.value));
    } else if (number(it->second.value) != number(m.value) || it->second.kind != m.kind) {
      lines.push_back("~ " + m.name + ": " + number(it->second.value) + " -> " + number(m.value));
    }
  }
  for (const auto& [name, v] : before.values) {
    if (!now.count(name)) lines.push_back("- " + name + ": " + number(v.value));
  }
  std::sort(lines.begin(), lines.end(), [](const std::string& a, const std::string& b) {
    return a.substr(2) < b.substr(2);
  });
  return lines;
}

}  // namespace lgvi::experiments
