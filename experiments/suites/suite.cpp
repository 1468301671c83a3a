#include "experiments/suites/suite.hpp"

#include <gsl/gsl_errno.h>
#include <sched.h>
#include <signal.h>
#include <time.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <fstream>
#include <limits>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <exception>
#include <thread>

#include <nlohmann/json.hpp>

#include "experiments/input/read_file.hpp"
#include "experiments/output/atomic_file.hpp"
#include "experiments/output/csv_writer.hpp"
#include "experiments/output/interrupt.hpp"
#include "experiments/scene/scene.hpp"
#include "experiments/methods/simulate.hpp"
#include "experiments/suites/journal.hpp"
#include "experiments/suites/summary_metadata.hpp"

namespace lgvi::experiments {

namespace fs = std::filesystem;

const char* to_string(Expectation e) {
  switch (e) {
    case Expectation::Complete: return "complete";
    case Expectation::Fail: return "fail";
    case Expectation::Either: return "either";
  }
  return "?";
}

const std::string& SummaryRow::text(const std::string& column) const {
  static const std::string empty;
  const auto it = cells_.find(column);
  return it == cells_.end() ? empty : it->second;
}

std::optional<double> SummaryRow::number(const std::string& column) const {
  const std::string& s = text(column);
  if (s.empty()) return std::nullopt;
  double x = 0.0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), x);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(x)) return std::nullopt;
  return x;
}

std::vector<std::pair<std::string, std::string>> suite_list() {
  std::vector<std::pair<std::string, std::string>> list;
  for (const SuiteEntry& e : suite_registry()) list.emplace_back(e.name, e.description);
  return list;
}

Suite make_suite(const std::string& name, const SuiteParams& params) {
  for (const SuiteEntry& e : suite_registry()) {
    if (e.name != name) continue;
    Suite s = e.make(params);
    if (s.cases.empty()) throw InvalidInput("suite", name + ": no cases (no scenes in " + params.scenes_dir.string() + "?)");
    std::set<std::string> ids;
    for (const SuiteCase& c : s.cases) {
      if (!ids.insert(c.id).second) throw InvalidInput("suite", name + ": duplicate case id '" + c.id + "'");
    }
    return s;
  }
  std::string known;
  for (const auto& [n, d] : suite_list()) known += (known.empty() ? "" : ", ") + n;
  throw InvalidInput("suite", "unknown suite '" + name + "' (known: " + known + ")");
}

Suite make_suite(const std::string& name, const fs::path& scenes_dir) {
  return make_suite(name, SuiteParams{false, scenes_dir});
}

Shard parse_shard(const std::string& text) {
  const auto bad = [&](const std::string& why) {
    return InvalidInput("--shard", "'" + text + "': " + why + " (expected i/N with 0 <= i < N, e.g. 0/4)");
  };
  const std::size_t slash = text.find('/');
  if (slash == std::string::npos) throw bad("no '/'");
  const auto parse = [&](std::string_view part, const char* what) {
    std::size_t v = 0;
    const auto [end, ec] = std::from_chars(part.data(), part.data() + part.size(), v);
    if (part.empty() || ec != std::errc() || end != part.data() + part.size()) {
      throw bad(std::string(what) + " is not a non-negative integer");
    }
    return v;
  };
  const std::string_view all(text);
  Shard s;
  s.index = parse(all.substr(0, slash), "i");
  s.count = parse(all.substr(slash + 1), "N");
  if (s.count == 0) throw bad("N must be at least 1");
  if (s.index >= s.count) throw bad("i must be less than N");
  return s;
}

std::vector<std::size_t> shard_cases(std::size_t cases, const Shard& shard) {
  // In 128 bits: i n overflows 64 bits for N near 2^60 (and picked the wrong block).
  __extension__ typedef unsigned __int128 Wide;  // a GCC and Clang extension
  const auto bound = [&](std::size_t i) {
    return static_cast<std::size_t>(static_cast<Wide>(i) * cases / shard.count);
  };
  const std::size_t begin = bound(shard.index);
  const std::size_t end = bound(shard.index + 1);
  std::vector<std::size_t> idx;
  for (std::size_t i = begin; i < end; ++i) idx.push_back(i);
  return idx;
}

const std::vector<std::string>& harness_columns() {
  static const std::vector<std::string> columns = {"index",  "case",        "group",  "expected",
                                                   "status", "as_expected", "detail", "case_seconds"};
  return columns;
}

std::size_t SuiteResult::unexpected() const {
  return static_cast<std::size_t>(
      std::count_if(cases.begin(), cases.end(), [](const CaseOutcome& c) { return !c.as_expected; }));
}

namespace {

/// The repetitions of one timed computation so far.
class TimingRecord {
 public:
  void add(const TimedRun& r) {
    const double wall = std::max(0.0, r.wall_seconds - r.uncounted_seconds);
    walls_.push_back(wall);
    measured_ += wall;
    // Not descheduled (the CPU bracket encloses the wall bracket, so CPU >= wall otherwise): the
    // uncounted part, timed by the wall clock, was CPU time too.
    if (r.wall_seconds - r.cpu_seconds <= 1e-6 + 1e-3 * r.wall_seconds) {
      clean_cpu_min_ = std::min(clean_cpu_min_, std::max(0.0, r.cpu_seconds - r.uncounted_seconds));
    }
    if (wall < least_disturbed_wall_) {
      least_disturbed_wall_ = wall;
      least_disturbed_cpu_ = r.wall_seconds > 0.0 ? r.cpu_seconds * wall / r.wall_seconds : 0.0;
    }
  }
  double measured() const { return measured_; }
  void fail(std::string error) { error_ = std::move(error); }
  bool failed() const { return !error_.empty(); }

  Timing timing() const {
    Timing t;
    t.repetitions = walls_.size();
    t.error = error_;
    if (walls_.empty()) return t;
    std::vector<double> w = walls_;
    const auto mid = w.begin() + static_cast<std::ptrdiff_t>(w.size() / 2);
    std::nth_element(w.begin(), mid, w.end());
    t.wall_seconds_median = *mid;  // the upper median for an even count
    t.wall_seconds_min = *std::min_element(walls_.begin(), walls_.end());
    t.cpu_seconds_min = std::isfinite(clean_cpu_min_) ? clean_cpu_min_ : least_disturbed_cpu_;
    return t;
  }

 private:
  std::vector<double> walls_;
  double measured_ = 0.0;
  double clean_cpu_min_ = std::numeric_limits<double>::infinity();
  double least_disturbed_wall_ = std::numeric_limits<double>::infinity();
  double least_disturbed_cpu_ = 0.0;
  std::string error_;
};

}  // namespace

std::vector<Timing> time_in_passes(const std::vector<std::function<TimedRun()>>& runs, const TimingPolicy& policy,
                                   const std::function<void(std::size_t, std::size_t)>& progress) {
  using Clock = std::chrono::steady_clock;
  const std::size_t rounds = std::max<std::size_t>(1, policy.rounds);
  const std::size_t max_per_round = std::max<std::size_t>(1, policy.max_repetitions / rounds);
  const std::size_t threads = std::max<std::size_t>(1, std::min(policy.threads, runs.size()));
  std::vector<TimingRecord> records(runs.size());
  std::mutex progress_mutex;
  for (std::size_t round = 0; round < rounds; ++round) {
    // Each pass brings every computation's measured total to (round + 1) / rounds of the target.
    const double target = policy.min_measured_seconds * static_cast<double>(round + 1) / static_cast<double>(rounds);
    std::atomic<std::size_t> next{0};
    const auto time_the_rest_of_the_pass = [&] {
      for (std::size_t i = next++; i < runs.size(); i = next++) {
        TimingRecord& rec = records[i];
        if (!runs[i] || rec.failed()) continue;
        const auto start = Clock::now();
        std::size_t n = 0;
        try {
          do {
            rec.add(runs[i]());
            ++n;
          } while (rec.measured() < target && n < max_per_round &&
                   std::chrono::duration<double>(Clock::now() - start).count() <
                       policy.max_elapsed_seconds / static_cast<double>(rounds));
        } catch (const std::exception& e) {
          rec.fail(e.what());
        } catch (...) {
          rec.fail("unknown exception");
        }
        if (progress) {
          const std::lock_guard lock(progress_mutex);
          progress(round, i);
        }
      }
    };
    // The pass ends when every thread has ended it: passes never overlap.
    std::vector<std::jthread> helpers;
    for (std::size_t t = 1; t < threads; ++t) helpers.emplace_back(time_the_rest_of_the_pass);
    time_the_rest_of_the_pass();
  }
  std::vector<Timing> out;
  out.reserve(records.size());
  for (const TimingRecord& r : records) out.push_back(r.timing());
  return out;
}

std::size_t timing_threads(unsigned jobs) {
  std::size_t cores = 0;
  cpu_set_t allowed;
  CPU_ZERO(&allowed);
  if (sched_getaffinity(0, sizeof allowed, &allowed) == 0) {
    std::set<std::string> sibling_sets;  // one per core
    for (int cpu = 0; cpu < CPU_SETSIZE; ++cpu) {
      if (!CPU_ISSET(cpu, &allowed)) continue;
      std::ifstream in("/sys/devices/system/cpu/cpu" + std::to_string(cpu) + "/topology/thread_siblings_list");
      std::string siblings;
      if (!std::getline(in, siblings) || siblings.empty()) siblings = "cpu" + std::to_string(cpu);
      sibling_sets.insert(siblings);
    }
    cores = sibling_sets.size();
  }
  if (cores == 0) cores = std::max(1u, std::thread::hardware_concurrency());
  return std::max<std::size_t>(1, std::min<std::size_t>(jobs, cores));
}

std::string summary_cell(const std::string& text) {
  std::string s = text;
  for (char& c : s) {
    if (c == ',') c = ';';
    if (c == '\n' || c == '\r') c = ' ';
    if (c == '"') c = '\'';
  }
  return s;
}

namespace {

using Clock = std::chrono::steady_clock;

bool as_expected(Expectation e, const JobResult& r) {
  if (r.status == "error") return false;  // an exception is never an expected outcome
  switch (e) {
    case Expectation::Complete: return r.completed;
    case Expectation::Fail: return !r.completed;
    case Expectation::Either: return true;
  }
  return false;
}

std::string format_duration(double seconds) {
  char buf[32];
  if (seconds < 60) {
    std::snprintf(buf, sizeof buf, "%.0f s", seconds);
  } else {
    std::snprintf(buf, sizeof buf, "%d min %02d s", static_cast<int>(seconds) / 60, static_cast<int>(seconds) % 60);
  }
  return buf;
}

/// The harness fields of an outcome, then the case's labels, then the job's fields (first
/// occurrence of a key wins).
Fields row_fields(const SuiteCase& c, const CaseOutcome& o) {
  Fields f = {{"index", static_cast<std::int64_t>(o.index)},
              {"case", c.id},
              {"group", c.group},
              {"expected", std::string(to_string(c.expect))},
              {"status", o.result.status},
              {"as_expected", o.as_expected},
              {"detail", o.result.detail},
              {"case_seconds", o.seconds}};
  std::set<std::string> keys;
  for (const Field& x : f) keys.insert(x.key);
  for (const Fields* more : {&c.labels, &o.result.fields}) {
    for (const Field& x : *more) {
      if (keys.insert(x.key).second) f.push_back(x);
    }
  }
  return f;
}

std::vector<std::string> summary_columns(const Suite& suite) {
  std::vector<std::string> cols = harness_columns();
  for (const std::string& c : suite.columns) {
    if (std::find(cols.begin(), cols.end(), c) == cols.end()) cols.push_back(c);
  }
  return cols;
}

std::string header_line(const Suite& suite) {
  std::string header;
  for (const std::string& c : summary_columns(suite)) header += (header.empty() ? "" : ",") + c;
  return header;
}

/// The summary.csv and summary.jsonl lines (no newline) of one finished case.
std::pair<std::string, std::string> summary_lines(const Suite& suite, const SuiteCase& c, const CaseOutcome& o,
                                                  const SuiteOptions& options) {
  const std::vector<std::string> cols = summary_columns(suite);
  Fields f = row_fields(c, o);
  // Provenance of every row (summary.jsonl only): `suite --check-against` refuses to compare
  // rows of another suite or form, and reports the versions compared.
  const auto provenance = [&f](const std::string& key, FieldValue value) {
    const auto same = [&key](const Field& x) { return x.key == key; };
    f.erase(std::remove_if(f.begin(), f.end(), same), f.end());
    f.push_back({key, std::move(value)});
  };
  provenance("suite", suite.name);
  provenance("quick", options.quick);
  provenance("git_describe", std::string(git_describe()));
  std::string line;
  for (std::size_t j = 0; j < cols.size(); ++j) {
    const auto it = std::find_if(f.begin(), f.end(), [&](const Field& x) { return x.key == cols[j]; });
    if (j > 0) line += ",";
    if (it != f.end()) {
      const auto* d = std::get_if<double>(&it->value);
      line += (d != nullptr && !std::isfinite(*d)) ? std::string() : summary_cell(to_text(it->value));
    }
  }
  return {line, to_json(f)};
}

/// The outcome of a case kept from the journal, from its summary.jsonl line (no fields).
CaseOutcome resumed_outcome(const JournalEntry& e) {
  CaseOutcome o;
  o.index = e.index;
  o.id = e.id;
  const nlohmann::json j = nlohmann::json::parse(e.jsonl_line, nullptr, false);
  if (j.is_object()) {
    o.result.status = j.value("status", std::string());
    o.result.detail = j.value("detail", std::string());
    o.result.completed = o.result.status == "completed";
    o.as_expected = j.value("as_expected", false);
    o.seconds = j.value("case_seconds", 0.0);
  }
  return o;
}

/// Expected cost of a case for the ETA; a job that cannot estimate counts as the mean of those
/// that can (1 when none can).
std::vector<double> expected_costs(const Suite& suite, const std::vector<std::size_t>& indices,
                                   const fs::path& scenes_dir) {
  std::vector<double> cost(indices.size(), 0.0);
  double sum = 0.0;
  std::size_t known = 0;
  for (std::size_t k = 0; k < indices.size(); ++k) {
    try {
      cost[k] = suite.cases[indices[k]].job->expected_cost(scenes_dir);
    } catch (const std::exception&) {
      cost[k] = 0.0;
    }
    if (std::isfinite(cost[k]) && cost[k] > 0.0) {
      sum += cost[k];
      ++known;
    } else {
      cost[k] = 0.0;
    }
  }
  const double fallback = known > 0 ? sum / static_cast<double>(known) : 1.0;
  for (double& c : cost) {
    if (c == 0.0) c = fallback;
  }
  return cost;
}

}  // namespace

std::vector<SummaryRow> read_summary_csv(const fs::path& file) {
  std::istringstream in;
  try {
    in.str(read_regular_file(file, kMaxJournalFileBytes, "the suite summary"));
  } catch (const UnreadableFile& e) {
    throw OutputError(file.string() + ": cannot read the suite summary: " + e.reason());
  }
  std::string line;
  bool more = static_cast<bool>(std::getline(in, line));
  std::size_t comment_lines = 0;  // the `# key: value` metadata before the header
  while (more && line.starts_with("#")) {
    more = static_cast<bool>(std::getline(in, line));
    ++comment_lines;
  }
  if (!more || line.rfind("index,", 0) != 0) {
    throw OutputError(file.string() + ": no header line 'index,...' (concatenate shard 0 first)");
  }
  const std::vector<std::string> header = split_csv_row(line);
  std::vector<SummaryRow> rows;
  for (std::size_t n = comment_lines + 2; std::getline(in, line); ++n) {
    if (line.empty()) continue;
    const std::vector<std::string> cells = split_csv_row(line);
    if (cells.size() != header.size()) {
      throw OutputError(file.string() + ": line " + std::to_string(n) + " has " + std::to_string(cells.size()) +
                        " cells, the header " + std::to_string(header.size()));
    }
    std::map<std::string, std::string> m;
    for (std::size_t j = 0; j < header.size(); ++j) m[header[j]] = cells[j];
    rows.emplace_back(std::move(m));
  }
  return rows;
}

std::vector<fs::path> render_suite(const Suite& suite, const SuiteOptions& options) {
  if (!suite.render) return {};
  const std::vector<SummaryRow> rows = read_summary_csv(options.out_dir / "summary.csv");
  // One pass per format, up to `jobs` of them at once: each pass's gnuplot processes and
  // temporaries are its own, and a table two passes write is the same text renamed into place.
  const std::size_t n = options.formats.size();
  std::vector<std::vector<fs::path>> drawn(n);
  std::vector<std::exception_ptr> errors(n);
  const auto pass = [&](std::size_t i) {
    try {
      drawn[i] = suite.render({options.out_dir, options.out_dir, options.plots_dir, options.gnuplot, options.formats[i]}, rows);
    } catch (...) {
      errors[i] = std::current_exception();
    }
  };
  const std::size_t at_once = std::max<std::size_t>(1, std::min<std::size_t>(options.jobs, n));
  for (std::size_t first = 0; first < n; first += at_once) {
    std::vector<std::thread> others;
    for (std::size_t i = first + 1; i < std::min(n, first + at_once); ++i) others.emplace_back(pass, i);
    pass(first);
    for (std::thread& t : others) t.join();
  }
  for (const std::exception_ptr& e : errors) {
    if (e) std::rethrow_exception(e);
  }
  std::vector<fs::path> files;
  for (std::vector<fs::path>& pass_files : drawn) {
    for (fs::path& f : pass_files) {
      // Empty: a figure without data.
      if (!f.empty() && std::find(files.begin(), files.end(), f) == files.end()) files.push_back(std::move(f));
    }
  }
  return files;
}

namespace {

/// With --resume: the journal's entries of this shard whose run matches and whose files verify.
/// Throws InvalidInput when OUT holds another run (suite, form, version, cases, scenes, shard).
std::map<std::size_t, JournalEntry> resumable_entries(const Suite& suite, const SuiteOptions& options,
                                                      const std::vector<std::size_t>& indices,
                                                      const std::string& fingerprint, std::ostream& progress) {
  const SuiteManifest m = read_manifest(options.out_dir);
  const auto refuse = [&](const std::string& what) {
    return InvalidInput("--resume", manifest_path(options.out_dir).string() + " records " + what +
                                        "; resume only the same run (or choose another --out)");
  };
  if (m.suite != suite.name) throw refuse("suite '" + m.suite + "', not '" + suite.name + "'");
  if (m.quick != options.quick) throw refuse(std::string("the ") + (m.quick ? "quick" : "full") + " form");
  if (m.git_describe != git_describe()) throw refuse("version " + m.git_describe + ", this is " + git_describe());
  if (m.shard_index != options.shard.index || m.shard_count != options.shard.count) {
    throw refuse("shard " + std::to_string(m.shard_index) + "/" + std::to_string(m.shard_count));
  }
  // A study's own files first: name the one that changed.
  for (const SuiteInput& in : suite.inputs) {
    const auto recorded = std::find_if(m.inputs.begin(), m.inputs.end(),
                                       [&](const SuiteInput& r) { return r.what == in.what; });
    if (recorded == m.inputs.end()) throw refuse("no " + in.what + " among the files its run was made from");
    if (recorded->digest != in.digest) {
      throw refuse(in.what + " with other contents (digest " + recorded->digest + ", now " + in.digest +
                   "): the file was edited since");
    }
  }
  if (m.fingerprint != fingerprint) throw refuse("other cases or scene files (fingerprint " + m.fingerprint + ")");
  std::map<std::size_t, JournalEntry> kept;
  std::size_t dropped = 0;
  for (auto& [index, entry] : read_journal(options.out_dir)) {
    std::string why;
    if (std::find(indices.begin(), indices.end(), index) == indices.end() || entry.id != suite.cases[index].id) {
      why = "not a case of this shard";
    } else if (entry.fingerprint != fingerprint) {
      why = "recorded by another run";
    } else {
      why = verify_files(options.out_dir, entry);
    }
    if (why.empty()) {
      kept.emplace(index, std::move(entry));
    } else {
      ++dropped;
      progress << "resume: running " << entry.id << " again (" << why << ")\n";
    }
  }
  progress << "resume: " << kept.size() << " of " << indices.size() << " cases finished and verified"
           << (dropped > 0 ? ", " + std::to_string(dropped) + " dropped" : std::string()) << "\n"
           << std::flush;
  return kept;
}

}  // namespace

SuiteResult run_suite(const Suite& suite, const SuiteOptions& options, std::ostream& progress) {
  const std::vector<std::size_t> indices = shard_cases(suite.cases.size(), options.shard);
  // Every case is checked before anything runs or is written.
  for (const std::size_t i : indices) suite.cases[i].job->validate(options.scenes_dir);

  std::error_code ec;
  fs::create_directories(options.out_dir, ec);
  if (ec) throw OutputError(options.out_dir.string() + ": cannot create the output directory: " + ec.message());
  for (const std::size_t i : indices) {
    const fs::path parent = (options.out_dir / suite.cases[i].id).parent_path();
    fs::create_directories(parent, ec);
    if (ec) throw OutputError(parent.string() + ": cannot create the output directory: " + ec.message());
  }
  if (const std::size_t stale = remove_stale_temporaries(options.out_dir); stale > 0) {
    progress << "removed " << stale << " temporary files left by killed runs in " << options.out_dir.string() << "\n";
  }

  const std::string fingerprint = suite_fingerprint(suite, options.quick, options.scenes_dir);
  // Shard 0's summary.csv starts with the metadata (units, column meanings), then the header.
  const std::string header =
      options.shard.index == 0
          ? metadata_lines(summary_metadata(suite, summary_columns(suite), options.quick)) + header_line(suite)
          : std::string();
  std::map<std::size_t, JournalEntry> finished_entries;  // by index in the suite
  if (options.resume) finished_entries = resumable_entries(suite, options, indices, fingerprint, progress);
  SuiteManifest manifest{suite.name, options.quick, git_describe(), fingerprint,
                         options.shard.index, options.shard.count, suite.cases.size(), indices.size(),
                         finished_entries.size(), false, "", suite.inputs};
  if (options.resume) rewrite_journal(options.out_dir, finished_entries);
  write_manifest(options.out_dir, manifest);
  JournalWriter journal(options.out_dir, /*truncate=*/!options.resume);

  // GSL's error handler is a process-wide pointer that the GSL adapter switches off and back on
  // around each run; switched off here once, before any worker starts, every run restores "off"
  // and concurrent runs never meet GSL's aborting default handler.
  gsl_set_error_handler_off();

  const auto context = [&options](const SuiteCase& c) -> JobContext {
    return {options.out_dir, options.scenes_dir, c.id, options.command_line};
  };
  // The cases still to run (positions k in `todo`, indices in the suite todo[k]).
  std::vector<std::size_t> todo;
  for (const std::size_t i : indices) {
    if (finished_entries.count(i) == 0) todo.push_back(i);
  }
  const std::size_t total = todo.size();
  const std::vector<double> cost = expected_costs(suite, todo, options.scenes_dir);
  double cost_left = 0.0;
  for (const double c : cost) cost_left += c;
  double cost_done = 0.0;
  std::vector<CaseOutcome> outcomes(total);
  std::atomic<std::size_t> next{0};
  std::atomic<bool> abandoned{false};  // the workers take no further case
  std::vector<char> output_failed(total, 0);  // case k's results could not be written
  std::mutex mutex;
  std::condition_variable done_cv;
  std::deque<std::size_t> finished;             // positions in `todo`, in completion order
  std::map<std::size_t, Clock::time_point> running;  // positions in `todo` -> start

  // Records a finished case in the journal (this thread only).
  const auto record = [&](std::size_t k) {
    const SuiteCase& c = suite.cases[todo[k]];
    const auto lines = summary_lines(suite, c, outcomes[k], options);
    JournalEntry e{todo[k], c.id, fingerprint, lines.first, lines.second, {}};
    e.files = digest_case_files(options.out_dir, e.jsonl_line);
    journal.append(e);
    finished_entries[todo[k]] = std::move(e);
  };
  // On SIGINT/SIGTERM (this thread): the summaries of what finished, then exit.
  const auto end_interrupted = [&](int signo) {
    manifest.finished = finished_entries.size();
    manifest.interrupted_by = signal_name(signo);
    try {
      write_summaries_from(options.out_dir, header, finished_entries);
      write_manifest(options.out_dir, manifest);
    } catch (const std::exception& e) {
      progress << "interrupted: " << e.what() << "\n";
    }
    remove_live_temporaries();
    progress << "interrupted by " << signal_name(signo) << ": " << finished_entries.size() << " of "
             << indices.size() << " cases finished, in " << (options.out_dir / "summary.csv").string()
             << "; 'suite " << suite.name << " --resume' (same options) runs the rest\n"
             << std::flush;
    std::_Exit(128 + signo);
  };

  // SIGINT/SIGTERM (interrupt.hpp): this runner checks for them and ends the run itself
  // (end_interrupted) during the cases and their timing; the figures check them while gnuplot runs.
  const InterruptScope interrupt_scope;
  std::optional<CooperativeInterrupts> cooperative(std::in_place);
  const auto worker = [&]() {
    for (std::size_t k = next++; k < total && interrupt_signal() == 0 && !abandoned; k = next++) {
      const SuiteCase& c = suite.cases[todo[k]];
      CaseOutcome& o = outcomes[k];
      o.index = todo[k];
      o.id = c.id;
      const auto start = Clock::now();
      {
        const std::lock_guard lock(mutex);
        running[k] = start;
      }
      try {
        o.result = c.job->run(context(c));
      } catch (const OutputError& e) {
        // Its results could not be written (a full disk): no other case's can be; the suite
        // stops (below) with exit status 3, not a case "not as expected".
        o.result = JobResult{false, "error", e.what(), {}};
        output_failed[k] = 1;
        abandoned = true;
      } catch (const std::exception& e) {
        o.result = JobResult{false, "error", e.what(), {}};
      } catch (...) {
        o.result = JobResult{false, "error", "unknown exception", {}};
      }
      o.seconds = std::chrono::duration<double>(Clock::now() - start).count();
      o.as_expected = as_expected(c.expect, o.result);
      {
        const std::lock_guard lock(mutex);
        running.erase(k);
        finished.push_back(k);
      }
      done_cv.notify_one();
    }
  };
  const unsigned threads = static_cast<unsigned>(std::max<std::size_t>(1, std::min<std::size_t>(options.jobs, total)));
  const auto start = Clock::now();
  std::vector<std::thread> pool;
  // An error of this thread (the journal cannot be written: a full disk) leaves the loop below
  // by an exception; the workers finish the cases they run and are joined before it propagates
  // (a joinable std::thread destroyed would end the process in std::terminate).
  struct JoinWorkers {
    std::vector<std::thread>& pool;
    std::atomic<bool>& abandoned;
    ~JoinWorkers() {
      abandoned = true;
      for (std::thread& t : pool) {
        if (t.joinable()) t.join();
      }
    }
  } join_workers{pool, abandoned};
  for (unsigned t = 0; t < threads && total > 0; ++t) pool.emplace_back(worker);

  // Progress, the journal and the summaries from this thread only.
  progress << "suite " << suite.name << ": " << total << " cases"
           << (options.shard.whole() ? std::string()
                                     : " (shard " + std::to_string(options.shard.index) + "/" +
                                           std::to_string(options.shard.count) + " of " +
                                           std::to_string(suite.cases.size()) + ")")
           << (finished_entries.empty() ? std::string()
                                        : " to run, " + std::to_string(finished_entries.size()) + " resumed")
           << " on " << threads << " thread" << (threads == 1 ? "" : "s") << "\n"
           << std::flush;
  constexpr double kHeartbeatSeconds = 5.0;   // at most one heartbeat line per this interval
  constexpr double kLongCaseSeconds = 3.0;    // about cases running longer than this
  auto last_output = Clock::now();
  for (std::size_t done = 0; done < total;) {
    std::unique_lock lock(mutex);
    done_cv.wait_for(lock, std::chrono::milliseconds(100), [&] { return !finished.empty(); });
    if (const int signo = interrupt_signal(); signo != 0) {
      // Cases finished but not yet recorded count as finished.
      std::deque<std::size_t> pending = finished;
      finished.clear();
      lock.unlock();
      for (const std::size_t k : pending) {
        if (!suite.cases[todo[k]].job->timed() || outcomes[k].result.status == "error") record(k);
      }
      end_interrupted(signo);
    }
    const auto now = Clock::now();
    if (finished.empty()) {
      if (std::chrono::duration<double>(now - last_output).count() < kHeartbeatSeconds) continue;
      std::string longest;
      for (const auto& [k, since] : running) {
        const double secs = std::chrono::duration<double>(now - since).count();
        if (secs >= kLongCaseSeconds) {
          longest += (longest.empty() ? "" : ", ") + suite.cases[todo[k]].id + " (" + format_duration(secs) + ")";
        }
      }
      lock.unlock();
      if (!longest.empty()) {
        progress << "  ... " << format_duration(std::chrono::duration<double>(now - start).count())
                 << " elapsed, running: " << longest << "\n"
                 << std::flush;
      }
      last_output = now;
      continue;
    }
    const std::size_t k = finished.front();
    finished.pop_front();
    lock.unlock();
    ++done;
    const SuiteCase& c = suite.cases[todo[k]];
    if (output_failed[k]) {
      // Not journaled: --resume runs it again once there is room. The cases journaled so far
      // keep their files.
      throw OutputError(outcomes[k].result.detail + " (suite " + suite.name + " stopped: " + std::to_string(finished_entries.size()) +
                        " cases journaled; free space, then run it again with --resume)");
    }
    // A timed case is recorded once timed (below); an interrupted run runs it again.
    if (!c.job->timed() || outcomes[k].result.status == "error") record(k);
    cost_done += cost[k];
    cost_left -= cost[k];
    const double elapsed = std::chrono::duration<double>(now - start).count();
    // Remaining: the time per unit of expected cost so far, times the cost of the cases left.
    const double remaining = cost_done > 0.0 ? elapsed / cost_done * std::max(0.0, cost_left) : 0.0;
    const CaseOutcome& o = outcomes[k];
    progress << "[" << done + (indices.size() - total) << "/" << indices.size() << "] " << format_duration(elapsed)
             << " elapsed, ~" << format_duration(remaining) << " left  " << o.id << ": "
             << (o.as_expected ? "" : "UNEXPECTED ") << o.result.status << " (" << o.result.detail << ")\n"
             << std::flush;
    last_output = now;
  }
  for (std::thread& t : pool) t.join();

  // Timed cases with nothing else of the suite running (see the header), one per core: their
  // cost is measured apart from the parallel runs above.
  std::vector<std::size_t> timed;  // positions in `todo`
  std::vector<std::function<TimedRun()>> timed_runs;
  for (std::size_t k = 0; k < total; ++k) {
    const SuiteCase& c = suite.cases[todo[k]];
    CaseOutcome& o = outcomes[k];
    if (!c.job->timed() || o.result.status == "error") continue;
    // An exception while timing turns the case into an error row; the other cases go on.
    std::string error;
    try {
      std::function<TimedRun()> run = c.job->prepare_timing(context(c), o.result);
      if (!run) {
        record(k);
        continue;
      }
      timed.push_back(k);
      timed_runs.push_back(std::move(run));
    } catch (const std::exception& e) {
      error = e.what();
    } catch (...) {
      error = "unknown exception";
    }
    if (!error.empty()) {
      o.result = JobResult{false, "error", "timing: " + error, {}};
      o.as_expected = false;
      record(k);
    }
  }
  if (const int signo = interrupt_signal(); signo != 0) end_interrupted(signo);
  if (!timed.empty()) {
    // Those timed alone (Job::timed_alone) last; the others the most expensive first (by their
    // runs above), so that a pass on several threads ends soon after its longest case.
    std::vector<std::size_t> order(timed.size());
    for (std::size_t n = 0; n < order.size(); ++n) order[n] = n;
    const auto alone = [&](std::size_t n) { return suite.cases[todo[timed[n]]].job->timed_alone(); };
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      if (alone(a) != alone(b)) return alone(b);
      return outcomes[timed[a]].seconds > outcomes[timed[b]].seconds;
    });
    const auto first_alone = static_cast<std::size_t>(
        std::find_if(order.begin(), order.end(), [&](std::size_t n) { return alone(n); }) - order.begin());
    std::vector<std::size_t> timed_in_order;
    std::vector<std::function<TimedRun()>> shared_runs, alone_runs;
    for (std::size_t m = 0; m < order.size(); ++m) {
      timed_in_order.push_back(timed[order[m]]);
      (m < first_alone ? shared_runs : alone_runs).push_back(std::move(timed_runs[order[m]]));
    }
    timed = std::move(timed_in_order);
    TimingPolicy policy;
    policy.threads = timing_threads(options.timing_jobs != 0 ? options.timing_jobs : options.jobs);
    progress << "timing " << timed.size() << " case" << (timed.size() == 1 ? "" : "s") << " in " << policy.rounds
             << " passes on " << policy.threads << " thread" << (policy.threads == 1 ? "" : "s")
             << ", one case per thread" << (alone_runs.empty() ? "" : " (" + std::to_string(alone_runs.size()) + " alone)")
             << " (nothing else runs; each repeated until " << policy.min_measured_seconds * 1e3
             << " ms are measured)\n"
             << std::flush;
    const auto timing_start = Clock::now();
    std::size_t done = 0;
    std::size_t last_reported = 0;
    const auto report = [&](std::size_t, std::size_t) {
      if (const int signo = interrupt_signal(); signo != 0) end_interrupted(signo);
      // One progress line per pass and per tenth of it.
      ++done;
      const std::size_t all = policy.rounds * timed.size();
      if (done != all && done * 10 / all == last_reported * 10 / all) return;
      last_reported = done;
      const double elapsed = std::chrono::duration<double>(Clock::now() - timing_start).count();
      progress << "[timing " << done << "/" << all << "] " << format_duration(elapsed) << " elapsed, ~"
               << format_duration(elapsed / static_cast<double>(done) * static_cast<double>(all - done)) << " left\n"
               << std::flush;
    };
    std::vector<Timing> timings = time_in_passes(shared_runs, policy, report);
    TimingPolicy one_at_a_time = policy;
    one_at_a_time.threads = 1;
    for (Timing& t : time_in_passes(alone_runs, one_at_a_time, report)) timings.push_back(std::move(t));
    for (std::size_t n = 0; n < timed.size(); ++n) {
      const SuiteCase& c = suite.cases[todo[timed[n]]];
      CaseOutcome& o = outcomes[timed[n]];
      if (timings[n].error.empty()) {
        const Fields more = c.job->timing_fields(timings[n]);
        o.result.fields.insert(o.result.fields.end(), more.begin(), more.end());
      } else {
        o.result = JobResult{false, "error", "timing: " + timings[n].error, {}};
      }
      o.as_expected = as_expected(c.expect, o.result);
      if (!o.as_expected) {
        progress << "timing " << o.id << ": UNEXPECTED " << o.result.status << " (" << o.result.detail << ")\n";
      }
      record(timed[n]);
    }
  }

  write_summaries_from(options.out_dir, header, finished_entries);
  cooperative.reset();
  manifest.finished = finished_entries.size();
  manifest.complete = true;
  write_manifest(options.out_dir, manifest);
  progress << "wrote " << (options.out_dir / "summary.csv").string() << " and summary.jsonl\n";

  SuiteResult result;
  result.resumed = indices.size() - total;
  for (const std::size_t i : indices) {
    const auto at = std::find(todo.begin(), todo.end(), i);
    result.cases.push_back(at != todo.end() ? std::move(outcomes[static_cast<std::size_t>(at - todo.begin())])
                                            : resumed_outcome(finished_entries.at(i)));
  }
  if (options.plots && options.shard.whole()) {
    result.files = render_suite(suite, options);
    progress << "wrote " << result.files.size() << " figures and tables in " << options.out_dir.string() << "\n";
  } else if (options.plots) {
    progress << "sharded run: no figures; 'lgvi-testbed merge MERGED SHARD_DIR...' joins the shards, then run 'suite "
             << suite.name << " --render-only --out MERGED' (see docs/suites.md, Sharding)\n";
  }
  return result;
}

}  // namespace lgvi::experiments
