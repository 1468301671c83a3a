// `lgvi-testbed validate`: the regression gate of the accuracy metrics.
//
// A curated, fast set of metrics (validation/metrics.cpp) is computed and compared
// with the accepted values in validation/accepted-quick.txt (or accepted-full.txt): one sorted,
// reviewed text file per form, one line per metric, with the `git describe` it was accepted at.
// Every metric has a kind, and the kind's rule decides the verdict (judge() below):
//
//   order       observed order of accuracy (log-log slope of successive differences).
//               pass within +-0.05 absolute of the accepted order: a least-squares slope over
//               steps halving three times resolves the order to ~0.01 in the asymptotic regime,
//               and a defect (a lost symmetric term, a misplaced impulse) moves it by >= 0.5.
//               Outside the band: `improved` when nearer the nominal order, else REGRESSED.
//   truncation  an error dominated by the discretization (energy error of a fixed-step run, an
//               error against an exact or finer solution): the same discretization reproduces
//               it to round-off times the trajectory's amplification (< 1e6 on the horizons
//               used: ~1e-10 relative), while any change of the scheme, its tolerance or chart
//               changes its leading digits. pass within relative 1e-6 plus 10 x the metric's
//               round-off floor where it has one (its round-off share moves with the operation
//               order: energy errors eps sqrt(N), errors against an exact solution eps N);
//               larger: REGRESSED, smaller: improved.
//   round-off   an error at the round-off floor (orthogonality, momentum maps of the LGVI, a
//               renormalized quaternion's norm, a converged violation): it random-walks with
//               the operation order, so it is gated by a factor over its floor: REGRESSED above
//               10 x max(accepted, floor), improved below accepted / 10 (when accepted > floor).
//   cost        an optimal cost of a fixed discretization: the optimizer's tolerance (violation
//               1e-10..1e-12, cost stationarity) fixes it to ~1e-12 relative; pass within
//               relative 1e-9, larger: REGRESSED, smaller: improved (a better local optimum).
//   count       iterations (Newton per step, shooting, SQP): a round-off change may flip one
//               stopping test; pass within 5% + 0.5 of the accepted count, more: REGRESSED,
//               fewer: improved.
//   condition   a condition number: its singular values move by round-off relative to the
//               largest one; gated by a factor 10 (REGRESSED above, improved below).
// Round-off floors follow how the error grows (metrics.cpp, round_off_floor): a quantity
// rounded afresh each step random-walks, eps sqrt(N) after N steps; one whose rounding is
// carried or removed each step (the cart-pendulum's compensated attitude sum, a quaternion
// renormalized every step) stays bounded, 4 eps whatever N: a lost compensation or
// renormalization then shows as a random walk, sqrt(N) = 100 times that floor at 10^4 steps.
// Two-sided metrics: a metric that measures a reference as much as a method (an error against
// an exact solution or a stored literature reference, the closed forms against a tight run)
// fails when it moves beyond its band in either direction: `CHANGED` instead of `improved`.
// A reference that drifts like the methods lowers their errors; only a reviewed --accept
// takes such a move.
// Metrics new since acceptance are `new`, accepted ones not computed now `missing`; neither
// fails the gate by itself (a metric that silently disappears is reported, and `--accept`
// drops it), but a run in which no metric has an accepted value gates nothing and fails
// (a mistyped --accepted file must not pass). Timings are reported in their own column and
// never gated.
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "experiments/input/literature_references.hpp"
#include "lgvi/inertia.hpp"  // InvalidInput

namespace lgvi::experiments {

enum class MetricKind { Order, Truncation, RoundOff, Cost, Count, Condition };
const char* to_string(MetricKind kind);
/// Throws InvalidInput("kind", ...) for an unknown name.
MetricKind parse_metric_kind(const std::string& name);

/// One measured metric. Names are stable paths "GROUP/SUBJECT/..." (e.g.
/// "order/pendulum-controlled/lgvi-yoshida4"); the first component is the group.
struct Metric {
  std::string name;
  MetricKind kind = MetricKind::Truncation;
  double value = 0.0;
  double floor = 0.0;                  ///< round-off kind: the floor of the metric (absolute)
  std::optional<double> nominal;       ///< order kind: the method's theoretical order
  std::optional<double> paper;         ///< the paper's value, where it reports one
  /// The metric measures a reference as much as a method: a move beyond its band either way
  /// fails (CHANGED), see the rule above.
  bool two_sided = false;
  double seconds = 0.0;                ///< wall time to compute it (reported, never gated)
  std::string detail;                  ///< one line: what was run
};

/// CHANGED: a two-sided metric moved beyond its band downwards (fails like REGRESSED).
enum class Verdict { Pass, Regressed, Improved, Changed, New, Missing };
const char* to_string(Verdict v);

/// The verdict of `now` against `accepted` for a metric of `kind` (see the rules above). A
/// non-finite value now (a failed run) is REGRESSED unless accepted was non-finite too. A
/// two-sided metric's `improved` is CHANGED.
Verdict judge(MetricKind kind, double accepted, double now, double floor, std::optional<double> nominal,
              bool two_sided = false);

struct AcceptedValue {
  MetricKind kind = MetricKind::Truncation;
  double value = 0.0;
};

struct AcceptedFile {
  std::string accepted_at;  ///< git describe at acceptance
  std::string form;         ///< "quick" or "full"
  std::map<std::string, AcceptedValue> values;
};

/// Reads an accepted-values file. A missing file is InvalidInput(FILE, "does not exist") unless
/// `missing_is_empty` (--accept creating a new file: an empty set). Throws
/// InvalidInput("FILE: line N", ...) for a malformed line.
AcceptedFile read_accepted(const std::filesystem::path& file, bool missing_is_empty = false);
/// Writes the metrics as the accepted set (sorted by name; values round-trip), atomically.
void write_accepted(const std::filesystem::path& file, const std::vector<Metric>& metrics, const std::string& form,
                    const std::string& accepted_at);

/// A defect `validate --degrade NAME` plants on purpose, to show that the gate catches its kind
/// of bug (tests/validation/test_validate.cpp plants each and expects exit 4 naming the metrics
/// that must catch it). The list and what each plants: degradations().
enum class Degradation {
  RotationUpdate,         ///< single-body LGVIs: rotation-update tolerance 1e-9, no polishing step
  ExactReference,         ///< the closed forms evaluated at t (1 - 1e-9): a reference drifting in phase
  ControlTiming,          ///< every scene control late by one step, u(t - h): a misplaced impulse
  UncompensatedAttitude,  ///< the cart-pendulum LGVI's attitude sum without its compensation
};
struct DegradationInfo {
  Degradation id;
  const char* name;       ///< --degrade NAME
  const char* plants;     ///< what it changes
  const char* caught_by;  ///< the metrics that must fail
};
/// Every degradation, in the order of the enum.
const std::vector<DegradationInfo>& degradations();
/// Throws InvalidInput("--degrade", ...) naming the known ones.
Degradation parse_degradation(const std::string& name);

/// Options of a validate run.
struct ValidateOptions {
  bool quick = false;
  std::vector<std::string> only;          ///< groups to run (empty: all)
  std::filesystem::path scenes_dir;
  /// Defects planted on purpose (--degrade); never with --accept.
  std::vector<Degradation> degraded;
  bool degrades(Degradation d) const;
};

/// Metric groups, in the order they run: name and one-line description.
const std::vector<std::pair<std::string, std::string>>& metric_groups();

/// The literature problems' references (validation/literature_references.toml), computed again
/// from the shipped scenes in `scenes_dir`: each scene's closed form at its t_final, checked
/// against a gsl-rk8pd run at rtol 1e-13 (the agreement and the digits it gives). Throws
/// std::runtime_error when a check run fails.
std::vector<LiteratureReference> compute_literature_references(const std::filesystem::path& scenes_dir);

/// Computes the metrics of the selected groups. Progress (one line per group) goes to `log`.
/// Throws InvalidInput for an unknown group.
std::vector<Metric> compute_metrics(const ValidateOptions& options, std::ostream& log);

/// One row of the comparison.
struct MetricComparison {
  std::string name;
  MetricKind kind = MetricKind::Truncation;
  std::optional<double> paper;
  std::optional<double> accepted;
  std::optional<double> now;
  Verdict verdict = Verdict::Pass;
  double seconds = 0.0;
  std::string detail;
};

struct ValidateReport {
  std::string form;
  std::string accepted_at;
  std::string version;  ///< git describe now
  std::vector<MetricComparison> rows;  ///< sorted by name
  std::size_t count(Verdict v) const;
  /// Rows compared with an accepted value (neither new nor missing).
  std::size_t gated() const;
  /// The gate fails: a metric REGRESSED or CHANGED, or no metric had an accepted value.
  bool failed() const { return count(Verdict::Regressed) + count(Verdict::Changed) > 0 || gated() == 0; }
};

/// Compares metrics with an accepted set. `groups` restricts which accepted metrics can be
/// `missing` (those of groups not run are left out).
ValidateReport compare(const std::vector<Metric>& metrics, const AcceptedFile& accepted,
                       const std::vector<std::string>& groups);

/// The table: metric, kind, paper, accepted, now, ratio, verdict, seconds.
void print_report(const ValidateReport& report, std::ostream& out);
/// JSON: {"version", "form", "accepted_at", "summary": {...}, "metrics": [{...}, ...]}.
void write_report_json(const ValidateReport& report, const std::filesystem::path& file);
/// Markdown table of the report (docs/validate.md's validation table is generated from this).
void write_report_markdown(const ValidateReport& report, const std::filesystem::path& file);
/// The lines that --accept changes: "name: old -> new" (added, removed, changed), sorted.
std::vector<std::string> accepted_diff(const AcceptedFile& before, const std::vector<Metric>& metrics);

/// The default accepted-values file of a form: validation/accepted-quick.txt or accepted-full.txt
/// in the source tree.
std::filesystem::path default_accepted_file(bool quick);

/// Where `validate --accept` writes: `given` (the --accepted option) when not empty; otherwise
/// the form's default file when it is the source tree's (a checkout's reviewed file). An
/// installed lgvi-testbed's default (PREFIX/share/lgvi/validation) belongs to the installation:
/// refused with InvalidInput("--accepted", ...) asking for a file of the user's.
std::filesystem::path accept_destination(const std::filesystem::path& given, bool quick);
/// The rule of accept_destination with the default file and where it lives given (for tests).
std::filesystem::path accept_destination(const std::filesystem::path& given, const std::filesystem::path& default_file,
                                         bool default_is_installed);

/// Group of a metric name: its first path component.
std::string metric_group(const std::string& name);

}  // namespace lgvi::experiments
