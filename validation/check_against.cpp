// `suite NAME --check-against DIR`: a suite's summary.jsonl against an accepted one, case by
// case and field by field, with the verdicts and rules of `validate` (validation/validate.hpp).
#include "validation/check_against.hpp"

#include <cmath>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "experiments/input/read_file.hpp"
#include "lgvi/inertia.hpp"

namespace lgvi::experiments {

namespace fs = std::filesystem;

namespace {

using Row = nlohmann::json;

/// Rows of a summary.jsonl by case id. Throws InvalidInput naming the file and line.
std::map<std::string, Row> read_rows(const fs::path& dir) {
  const fs::path file = dir / "summary.jsonl";
  std::error_code ec;
  if (!fs::exists(file, ec)) {
    throw InvalidInput(file.string(), "cannot be read (run the suite with --out " + dir.string() + " first)");
  }
  std::istringstream in(read_regular_file(file, kMaxJournalFileBytes, "the suite summary"));
  std::map<std::string, Row> rows;
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (line.empty()) continue;
    Row row = Row::parse(line, nullptr, false);
    if (row.is_discarded() || !row.is_object() || !row.contains("case") || !row["case"].is_string()) {
      throw InvalidInput(file.string() + ": line " + std::to_string(n), "not a summary row (JSON object with \"case\")");
    }
    const std::string id = row["case"].get<std::string>();
    rows[id] = std::move(row);
  }
  if (rows.empty()) throw InvalidInput(file.string(), "has no rows");
  return rows;
}

/// The value of a provenance field shared by all rows, or "" when absent (older summaries).
std::string provenance(const std::map<std::string, Row>& rows, const char* key) {
  for (const auto& [id, row] : rows) {
    if (!row.contains(key)) return "";
    return row[key].is_string() ? row[key].get<std::string>() : row[key].dump();
  }
  return "";
}

/// Fields that are not metrics: identity, free text, provenance, and timings (never gated).
bool ignored(const std::string& key) {
  static const char* const names[] = {"index", "case", "group", "expected", "detail", "csv_path", "csv",
                                      "suite", "quick", "git_describe", "command_line", "reference",
                                      "status_detail", "label", "version", "units"};
  for (const char* n : names) {
    if (key == n) return true;
  }
  const auto has = [&key](const char* part) { return key.find(part) != std::string::npos; };
  return has("seconds") || has("time") || has("timing");
}

bool contains_any(const std::string& key, std::initializer_list<const char*> parts) {
  for (const char* p : parts) {
    if (key.find(p) != std::string::npos) return true;
  }
  return false;
}

/// The kind of a numeric summary field, from its name and (for errors) its accepted size: an
/// error at or below 1e-11 of these O(1)-scaled quantities is at the round-off floor of a
/// 10^4..10^7-step run (eps sqrt(N) .. eps N), anything larger is truncation.
MetricKind field_kind(const std::string& key, double accepted) {
  if (contains_any(key, {"order"})) return MetricKind::Order;
  if (key == "cost") return MetricKind::Cost;
  if (contains_any(key, {"cond"})) return MetricKind::Condition;
  if (contains_any(key, {"iterations", "evaluations", "steps", "sweeps", "integrations", "rows", "backtracks",
                         "fallbacks", "repetitions"})) {
    return MetricKind::Count;
  }
  if (contains_any(key, {"error", "drift", "difference", "violation", "residual", "fd_"})) {
    return std::abs(accepted) <= 1e-11 ? MetricKind::RoundOff : MetricKind::Truncation;
  }
  return MetricKind::Truncation;
}

std::string text(const Row& v) { return v.is_string() ? v.get<std::string>() : v.dump(); }

}  // namespace

ValidateReport check_suite_against(const fs::path& run_dir, const fs::path& accepted_dir, const std::string& suite,
                                   bool quick) {
  const auto now = read_rows(run_dir);
  const auto accepted = read_rows(accepted_dir);
  const std::string form = quick ? "quick" : "full";
  for (const auto* rows : {&now, &accepted}) {
    const fs::path& dir = rows == &now ? run_dir : accepted_dir;
    const std::string s = provenance(*rows, "suite");
    const std::string q = provenance(*rows, "quick");
    if (s.empty() || q.empty()) {
      throw InvalidInput((dir / "summary.jsonl").string(),
                         "records no suite name or form (written before provenance was recorded): rerun it");
    }
    if (s != suite) {
      throw InvalidInput((dir / "summary.jsonl").string(), "is a summary of suite '" + s + "', not '" + suite + "'");
    }
    if ((q == "true") != quick) {
      throw InvalidInput((dir / "summary.jsonl").string(),
                         std::string("is the ") + (q == "true" ? "quick" : "full") + " form; this run is the " + form +
                             " form (" + (quick ? "with" : "without") + " --quick)");
    }
  }
  ValidateReport report;
  report.form = form;
  report.accepted_at = provenance(accepted, "git_describe");
  report.version = provenance(now, "git_describe");
  const auto add = [&report](const std::string& name, MetricKind kind, std::optional<double> a, std::optional<double> n,
                             Verdict v, const std::string& detail) {
    MetricComparison c;
    c.name = name;
    c.kind = kind;
    c.accepted = a;
    c.now = n;
    c.verdict = v;
    c.detail = detail;
    report.rows.push_back(std::move(c));
  };
  for (const auto& [id, row] : accepted) {
    const auto it = now.find(id);
    for (const auto& [key, value] : row.items()) {
      if (ignored(key)) continue;
      const std::string name = id + "/" + key;
      if (it == now.end() || !it->second.contains(key)) {
        add(name, MetricKind::Truncation, value.is_number() ? std::optional<double>(value.get<double>()) : std::nullopt,
            std::nullopt, Verdict::Missing, it == now.end() ? "case not in this run" : "field not in this run");
        continue;
      }
      const Row& current = it->second[key];
      if (value.is_number() && (current.is_number() || current.is_null())) {
        const double a = value.get<double>();
        const double n = current.is_null() ? std::nan("") : current.get<double>();
        const MetricKind kind = field_kind(key, a);
        add(name, kind, a, n, judge(kind, a, n, 4.0 * 2.220446049250313e-16, std::nullopt), "");
      } else if (value.is_null() && current.is_null()) {
        continue;
      } else if (text(value) != text(current)) {
        // Statuses, flags and labels: any change is a regression to look at.
        add(name, MetricKind::Truncation, std::nullopt, std::nullopt, Verdict::Regressed,
            "was '" + text(value) + "', now '" + text(current) + "'");
      }
    }
  }
  for (const auto& [id, row] : now) {
    if (!accepted.count(id)) add(id, MetricKind::Truncation, std::nullopt, std::nullopt, Verdict::New, "case not in the accepted summary");
  }
  std::sort(report.rows.begin(), report.rows.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  return report;
}

}  // namespace lgvi::experiments
