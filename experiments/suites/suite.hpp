// Suites: named lists of independent cases that the harness runs (in parallel), records and
// plots. A case is any runnable Job (a scene integrated by a method, or later an optimal-control
// run): it writes its own files under the output directory and returns one summary row.
//
// Outputs of `run_suite` in OUT:
//   <case id>.csv      (and whatever else the job writes), each written atomically;
//   summary.csv        one row per case in case order, the header line only in shard 0 (and in
//                      an unsharded run), so that `cat` of the shards' summaries in shard order
//                      is the unsharded summary; before the header, shard 0 writes `# key: value`
//                      metadata: suite, form, version, units and the columns' meanings
//                      (summary_metadata.hpp; read_summary_csv skips it);
//   summary.jsonl      one JSON object per case per line (every field the job reported), which
//                      concatenates the same way; the all suite also writes both for each
//                      suite's rows into its subdirectory (write_summaries_from);
//   figures/tables     rendered from summary.csv read back (render_suite), so a merged sharded
//                      run is rendered by `suite NAME --render-only --out MERGED`;
//   suite-run.json, suite-journal.jsonl   the manifest and the per-case journal from which
//                      --resume continues an interrupted run and `merge` joins shards
//                      (experiments/suites/journal.hpp, experiments/suites/merge.hpp).
//
// Timing: a case whose cost is a result (Job::timed(): the work-precision and long-horizon
// cases) runs like any other in the pool of `--jobs` threads, which writes its files. Once every
// case has run, the harness times the timed cases with nothing else of the suite running, one
// case per thread and at most one thread per core (time_in_passes, TimingPolicy,
// timing_threads): each case's bare computation (Job::prepare_timing, nothing written) in 3
// passes over all timed cases, repeated within a pass until 20 ms / 3 are measured, reporting the
// minimum per run of the wall time (steady_clock) and of the thread CPU time
// (Job::timing_fields). Timed in parallel with the other cases' runs by one clock-read pair, the
// same case's time varied by up to 61x between runs; see experiments/benchmarks/timing_stability.py
// and docs/suites.md (Timing).
//
// Sharding: `--shard i/N` (0 <= i < N) takes the i-th of N contiguous blocks of the case list
// (block sizes differ by at most one), so the shards are disjoint, their union is the suite and
// concatenating them in order keeps the case order.
//
// Adding a suite (e.g. the optimal-control sensitivity and shooting suites): implement Job for
// the new kind of case, write a SuiteFactory that builds the Suite (cases, summary columns and
// a renderer), and add one line to suite_registry() in experiments/suites/registry.cpp.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "experiments/output/fields.hpp"
#include "experiments/output/plot.hpp"
#include "experiments/suites/journal.hpp"
#include "lgvi/cpu_time.hpp"

namespace lgvi::experiments {

/// What a case is expected to do; the exit status of `suite` says whether every case did.
enum class Expectation {
  Complete,  ///< must reach its end (status "completed")
  Fail,      ///< must stop with a reported failure (e.g. Euler angles through gimbal lock)
  Either,    ///< a probe of where a method breaks: any recorded outcome is as expected
};
const char* to_string(Expectation e);

/// Where a job writes and what it records.
struct JobContext {
  std::filesystem::path out_dir;     ///< the suite's output directory (exists)
  std::filesystem::path scenes_dir;  ///< named scenes
  std::string case_id;               ///< file stem of the case's outputs (may contain '/')
  std::string command_line;          ///< recorded in file metadata
};

/// What a job reports. `fields` are free key-value pairs (all go to summary.jsonl; those named in
/// the suite's columns also to summary.csv).
struct JobResult {
  bool completed = false;  ///< the run reached its end
  std::string status;      ///< "completed" or the failure's name ("rotation-update-failed", ...)
  std::string detail;      ///< one line: what happened, where, at which cost
  Fields fields;
};

/// One execution of a timed computation: wall (std::chrono::steady_clock) and thread CPU time
/// (thread_cpu_seconds) over the same bracket, and the part of it that does not count (e.g. the
/// recording of an integration, measured by the job's own wall clock).
struct TimedRun {
  double wall_seconds = 0.0;
  double cpu_seconds = 0.0;
  double uncounted_seconds = 0.0;
};

/// How timed computations are repeated: in `rounds` passes over all of them, each pass running a
/// computation until it has measured min_measured_seconds / rounds of wall time (at least once;
/// at most max_repetitions times in all, or for max_elapsed_seconds / rounds per pass when its
/// counted part is nearly nothing). A run longer than 20 ms is thus timed once per pass, and a
/// disturbance of the machine (measured: stretches of a second or more in which everything runs
/// ~1.5x slower, CPU time included) spoils at most one pass.
/// `threads` computations are timed at once, each on its own thread, in the order given (the
/// caller puts the most expensive first); a pass ends when all of its computations have ended, so
/// passes never overlap. Only as many threads as the machine has cores (timing_threads): two
/// threads sharing a core (SMT) slow each other down, while on separate cores two copies of the
/// step benchmark ran within 3% of one alone (CPU time; docs/suites.md, Timing).
struct TimingPolicy {
  double min_measured_seconds = 0.02;
  std::size_t rounds = 3;
  std::size_t max_repetitions = 100000;
  double max_elapsed_seconds = 0.5;
  std::size_t threads = 1;
};

/// Threads for timing when `jobs` are asked for: at most one per core this process may run on
/// (hardware threads sharing a core, listed in Linux's
/// /sys/devices/system/cpu/cpuN/topology/thread_siblings_list, count once; where that cannot be
/// read, every hardware thread counts as a core), at least 1.
std::size_t timing_threads(unsigned jobs);

/// What the repetitions of one computation measured, counted part only (TimedRun minus its
/// uncounted part): the minimum wall time (the run least disturbed by the rest of the machine),
/// the median wall time, the minimum CPU time over the repetitions the thread was not
/// descheduled in (wall - CPU below 1 us + 0.1%: there the wall-clock uncounted part is also
/// CPU time; when every repetition was, CPU x counted / total wall of the least disturbed one),
/// and the number of repetitions.
struct Timing {
  double wall_seconds_min = 0.0;
  double wall_seconds_median = 0.0;
  double cpu_seconds_min = 0.0;
  std::size_t repetitions = 0;
  std::string error;  ///< the computation threw (its message): it was not run again
};

/// Times each computation of `runs` as `policy` says (on the calling thread when policy.threads
/// is 1); calls `progress(round, index)` after each computation of each round, one call at a
/// time (may be empty). Returns one Timing per computation (empty computations: repetitions = 0;
/// one that threw: its error).
std::vector<Timing> time_in_passes(const std::vector<std::function<TimedRun()>>& runs, const TimingPolicy& policy,
                                   const std::function<void(std::size_t, std::size_t)>& progress = {});

/// One runnable case. Jobs are shared between threads: run() is const and thread-safe.
class Job {
 public:
  virtual ~Job() = default;
  /// Checks the inputs (scene files, method names) before anything runs or is written. Throws
  /// SceneError or InvalidInput.
  virtual void validate(const std::filesystem::path& scenes_dir) const = 0;
  /// Runs the case, writing its files as ctx.out_dir / (ctx.case_id + extension). Failures of
  /// the computation are statuses in the result; an exception is recorded by the harness as
  /// status "error" with its message (the suite goes on).
  virtual JobResult run(const JobContext& ctx) const = 0;
  /// True for a case whose cost is a result (work-precision): after every case of the shard has
  /// run, the harness times it with nothing else of the suite running (see the header).
  virtual bool timed() const { return false; }
  /// Timed jobs that measure the whole process (the soak's resident memory): timed after the
  /// others, one at a time, whatever --timing-jobs says.
  virtual bool timed_alone() const { return false; }
  /// Timed jobs: the case's computation prepared for timing (inputs loaded), as a function that
  /// runs it once without writing anything and returns what it measured; empty when there is
  /// nothing to time (e.g. the run was rejected). `result` is this case's run() result. Called
  /// only for timed jobs whose run() returned; an exception is recorded as status "error".
  virtual std::function<TimedRun()> prepare_timing(const JobContext& ctx, const JobResult& result) const {
    (void)ctx;
    (void)result;
    return {};
  }
  /// The case's expected cost in arbitrary units proportional to its run time (integrator
  /// cases: steps x force evaluations per step), for the ETA. The default, 1, counts cases.
  virtual double expected_cost(const std::filesystem::path& scenes_dir) const {
    (void)scenes_dir;
    return 1.0;
  }
  /// Timed jobs: the summary fields reporting `timing` (appended to the run's fields).
  virtual Fields timing_fields(const Timing& timing) const {
    (void)timing;
    return {};
  }
};

struct SuiteCase {
  std::string id;                  ///< unique in the suite; file stem ("free-body-lgvi-h0.01")
  std::string group;               ///< figures gather the cases of one group (e.g. the scene)
  Fields labels;                   ///< known before the run: scene, method, model, h, rtol, ...
  Expectation expect = Expectation::Complete;
  std::shared_ptr<const Job> job;
};

/// A row of summary.csv read back: column -> text ("" when empty).
class SummaryRow {
 public:
  explicit SummaryRow(std::map<std::string, std::string> cells) : cells_(std::move(cells)) {}
  /// The cell's text, "" for a missing column.
  const std::string& text(const std::string& column) const;
  /// The cell as a number; nullopt when empty or not a finite number.
  std::optional<double> number(const std::string& column) const;
  /// A copy with one cell replaced.
  SummaryRow with(const std::string& column, std::string value) const {
    SummaryRow r = *this;
    r.cells_[column] = std::move(value);
    return r;
  }

 private:
  std::map<std::string, std::string> cells_;
};

struct RenderContext {
  std::filesystem::path out_dir;    ///< where figures and tables go
  std::filesystem::path data_dir;   ///< what the rows' csv_path is relative to
  std::filesystem::path plots_dir;  ///< gnuplot scripts
  std::string gnuplot;
  FigureFormat format = FigureFormat::Png;  ///< the figures' file format

  /// out_dir / (name + the format's extension): the file of the figure `name`.
  std::filesystem::path figure(const std::string& name) const { return out_dir / (name + figure_extension(format)); }
};

/// Draws a suite's figures and writes its tables from the summary rows (case order) and the
/// case files; returns the files written. Throws OutputError.
using SuiteRenderer =
    std::function<std::vector<std::filesystem::path>(const RenderContext&, const std::vector<SummaryRow>&)>;

struct Suite {
  std::string name;
  std::string description;
  std::vector<SuiteCase> cases;
  /// The files a study read (empty for the built-in suites, whose code is the version).
  std::vector<SuiteInput> inputs;
  /// summary.csv columns after the harness's own (index, case, group, expected, status,
  /// as_expected, detail); every case of the suite has them, empty where they do not apply.
  std::vector<std::string> columns;
  SuiteRenderer render;  ///< may be empty (no figures)
  /// A study file's warnings (truncation_warning: no final newline); load_study prints them.
  std::vector<std::string> warnings;
};

struct SuiteParams {
  bool quick = false;
  std::filesystem::path scenes_dir;
  /// A study with an [ensemble]: only the cases of this sample (`study FILE --sample K`).
  std::optional<std::size_t> sample = std::nullopt;
};

using SuiteFactory = std::function<Suite(const SuiteParams&)>;

struct SuiteEntry {
  std::string name;
  std::string description;
  SuiteFactory make;
};

/// Every suite, in the order `suite --help` lists them (experiments/suites/registry.cpp).
const std::vector<SuiteEntry>& suite_registry();

/// Known suite names with one-line descriptions.
std::vector<std::pair<std::string, std::string>> suite_list();

/// The cases of a suite. Throws InvalidInput("suite", ...) for an unknown name, listing the
/// known ones, and for a suite without cases.
Suite make_suite(const std::string& name, const SuiteParams& params);
/// Full form with the given scenes directory.
Suite make_suite(const std::string& name, const std::filesystem::path& scenes_dir);

/// A shard "i/N": the i-th (0-based) of N contiguous blocks.
struct Shard {
  std::size_t index = 0;
  std::size_t count = 1;
  bool whole() const { return count == 1; }
};
/// Parses "i/N" with 0 <= i < N, N >= 1. Throws InvalidInput("--shard", ...).
Shard parse_shard(const std::string& text);
/// Indices of the cases of `shard` among `cases` cases: [floor(i n / N), floor((i+1) n / N)).
std::vector<std::size_t> shard_cases(std::size_t cases, const Shard& shard);

/// The harness's own summary columns, before the suite's.
const std::vector<std::string>& harness_columns();

struct SuiteOptions {
  std::filesystem::path out_dir;
  std::filesystem::path scenes_dir;
  std::filesystem::path plots_dir;
  std::string gnuplot;
  /// The figures' file formats (--format png,pdf): every figure drawn in each.
  std::vector<FigureFormat> formats = {FigureFormat::Png};
  bool plots = true;  ///< render figures after the run (sharded runs never do)
  std::string command_line;
  Shard shard;
  unsigned jobs = 1;  ///< worker threads (>= 1)
  /// Timed cases measured at once (0: as jobs), at most one per core (timing_threads).
  unsigned timing_jobs = 0;
  bool quick = false;  ///< the suite's form, recorded in summary.jsonl
  /// Keep the cases OUT's journal records as finished whose files verify (same suite, form,
  /// version, fingerprint and shard; see suite_journal.hpp) and run the others.
  bool resume = false;
};

struct CaseOutcome {
  std::size_t index = 0;  ///< in the whole suite
  std::string id;
  JobResult result;
  bool as_expected = false;
  double seconds = 0.0;
};

struct SuiteResult {
  std::vector<CaseOutcome> cases;  ///< the shard's cases, in case order (resumed ones: no fields)
  std::size_t resumed = 0;         ///< cases kept from the journal (--resume)
  std::vector<std::filesystem::path> files;  ///< figures and tables
  std::size_t unexpected() const;
  bool all_ok() const { return unexpected() == 0; }
};

/// Validates every case of the shard first (SceneError / InvalidInput before anything runs or
/// is written), removes temporaries left in OUT by killed runs, writes the manifest and starts
/// the journal (suite_journal.hpp; with options.resume keeps the verified finished cases), then
/// runs the others on `options.jobs` threads, appending each finished case to the journal and
/// printing one progress line per finished case on `progress` (done/total, elapsed, remaining
/// estimated from the remaining cases' expected cost) and a heartbeat after 5 s without output naming cases
/// running for more than 3 s; writes summary.csv and summary.jsonl in case order and, unless
/// sharded or options.plots is false, renders.
/// SIGINT or SIGTERM during the cases (and their timing): no new case starts; the summaries of
/// the finished cases and the manifest (complete = false, interrupted_by) are written, this
/// process's temporaries removed, and the process ends with status 128 + signal (std::_Exit:
/// the running cases cannot be joined); `--resume` finishes the run. During the figures (the
/// summaries and manifest complete): gnuplot is stopped, no partial figure is published, and
/// Interrupted (interrupt.hpp) is thrown.
/// Throws SceneError, InvalidInput (also: --resume on a directory of another run), OutputError,
/// Interrupted.
SuiteResult run_suite(const Suite& suite, const SuiteOptions& options, std::ostream& progress);

/// Reads OUT/summary.csv (of a run or of concatenated shards) and renders the suite's figures.
/// Throws OutputError (missing or malformed summary, gnuplot failure).
std::vector<std::filesystem::path> render_suite(const Suite& suite, const SuiteOptions& options);

/// A summary.csv cell: the summary is read by gnuplot and by read_summary_csv, which split on
/// commas without quoting, so commas become ';', line breaks spaces and double quotes single ones.
std::string summary_cell(const std::string& text);

/// Reads a summary.csv: header line, then rows. Throws OutputError.
std::vector<SummaryRow> read_summary_csv(const std::filesystem::path& file);

}  // namespace lgvi::experiments
