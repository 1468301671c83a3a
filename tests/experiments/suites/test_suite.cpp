// The suite harness: case lists per suite (quick and full), sharding (disjoint blocks whose
// union is the suite, summaries that merge by concatenation), atomic outputs (a failing or
// killed case leaves no truncated file), one quick suite end to end, the composed LGVIs as
// methods.
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <random>
#include <set>
#include <thread>

#include "experiments/output/atomic_file.hpp"
#include "experiments/output/csv_writer.hpp"
#include "experiments/output/plot.hpp"
#include "experiments/scene/scene.hpp"
#include "experiments/suites/suite.hpp"
#include "experiments/suites/jobs.hpp"
#include "tests/experiments/cli/cli_support.hpp"

namespace lgvi::test {
namespace {

using experiments::Expectation;
using experiments::Suite;
using experiments::SuiteCase;
using experiments::SuiteParams;

std::string label(const SuiteCase& c, const std::string& key) {
  for (const experiments::Field& f : c.labels) {
    if (f.key == key) return experiments::to_text(f.value);
  }
  return "";
}

Suite suite(const std::string& name, bool quick) {
  return experiments::make_suite(name, SuiteParams{quick, experiments::default_scenes_dir()});
}

const std::vector<std::string> kSuites = {"energy-drift", "orthogonality", "momentum", "work-precision",
                                          "long-horizon", "extremes",      "soak",     "sensitivity",
                                          "shooting",     "ocp-comparison", "ensemble-bodies"};

// --- case lists ----------------------------------------------------------------------------------

TEST(SuiteCases, EverySuiteHasUniqueIdsAndTheQuickFormIsASmallerOrShorterList) {
  for (const std::string& name : kSuites) {
    const Suite q = suite(name, true);
    const Suite f = suite(name, false);
    EXPECT_FALSE(q.cases.empty()) << name;
    // The soak suite's quick form is the same cases over fewer steps.
    if (name == "soak") {
      EXPECT_EQ(q.cases.size(), f.cases.size());
    } else {
      EXPECT_LT(q.cases.size(), f.cases.size()) << name;
    }
    for (const Suite* s : {&q, &f}) {
      std::set<std::string> ids;
      for (const SuiteCase& c : s->cases) {
        EXPECT_TRUE(ids.insert(c.id).second) << name << ": duplicate " << c.id;
        EXPECT_NE(c.job, nullptr) << c.id;
        EXPECT_FALSE(c.group.empty()) << c.id;
      }
      EXPECT_TRUE(static_cast<bool>(s->render)) << name;
    }
  }
}

TEST(SuiteCases, AllIsTheUnionOfTheSuitesEachInItsSubdirectory) {
  for (const bool quick : {true, false}) {
    const Suite all = suite("all", quick);
    std::vector<std::string> expected;
    for (const SuiteCase& c : suite("default", quick).cases) expected.push_back("default/" + c.id);
    for (const std::string& name : kSuites) {
      for (const SuiteCase& c : suite(name, quick).cases) expected.push_back(name + "/" + c.id);
    }
    std::vector<std::string> ids;
    for (const SuiteCase& c : all.cases) ids.push_back(c.id);
    EXPECT_EQ(ids, expected);
  }
}

TEST(SuiteCases, EnergyDriftRunsEveryRosterMethodOnTheThreeUncontrolledScenes) {
  const Suite s = suite("energy-drift", true);
  std::map<std::string, std::set<std::string>> methods;  // scene -> method (model)
  for (const SuiteCase& c : s.cases) methods[label(c, "scene")].insert(label(c, "label"));
  EXPECT_EQ(methods.size(), 3u);
  for (const char* scene : {"free-body", "pendulum", "dumbbell"}) {
    ASSERT_TRUE(methods.count(scene)) << scene;
    EXPECT_EQ(methods[scene], methods["free-body"]) << scene;  // the same roster everywhere
    for (const char* m : {"LGVI order 2", "LGVI order 4 (yoshida4)", "LGVI order 6 (kahan-li6)", "cvode-bdf (quaternion)",
                          "odeint-rk4 (matrix)"}) {
      EXPECT_TRUE(methods[scene].count(m)) << scene << ": " << m;
    }
  }
  // The full form runs every solver on every model it accepts.
  std::set<std::string> full;
  for (const SuiteCase& c : suite("energy-drift", false).cases) full.insert(label(c, "label"));
  for (const char* m : {"gsl-msbdf (euler)", "odeint-bs (matrix)", "cvode-bdf (quaternion-renormalized)",
                        "LGVI order 4 (suzuki4)", "LGVI order 6 (yoshida6)"}) {
    EXPECT_TRUE(full.count(m)) << m;
  }
}

TEST(SuiteCases, WorkPrecisionCoversTheRequiredMethodsOnPendulumFreeBodyAndLagrangeTop) {
  const Suite s = suite("work-precision", true);
  std::map<std::string, std::map<std::string, std::set<std::string>>> sweep;  // scene -> method -> h or rtol
  for (const SuiteCase& c : s.cases) {
    sweep[label(c, "scene")][label(c, "label")].insert(label(c, "rtol").empty() ? label(c, "h") : label(c, "rtol"));
  }
  for (const char* scene : {"pendulum", "free-body", "lagrange-top"}) {
    for (const char* m : {"LGVI order 2", "LGVI order 4 (yoshida4)", "LGVI order 6 (kahan-li6)",
                          "cvode-adams (quaternion)", "cvode-bdf (quaternion)", "odeint-rk4 (quaternion)",
                          "odeint-rk4 (matrix)", "odeint-dopri5 (quaternion)", "odeint-dopri5 (matrix)",
                          "gsl-rk8pd (quaternion)", "gsl-rk4imp (quaternion)"}) {
      ASSERT_TRUE(sweep[scene].count(m)) << scene << ": " << m;
      EXPECT_GE(sweep[scene][m].size(), 5u) << scene << ": " << m << " needs a sweep";
    }
  }
}

TEST(SuiteCases, LongHorizonSweepsStepsAndTolerancesOfEveryRosterMethodOverTheLongHorizon) {
  for (const bool quick : {true, false}) {
    const Suite s = suite("long-horizon", quick);
    const double t_final = quick ? 1e3 : 1e4;
    // scene -> label -> swept h (fixed-step) or rtol (adaptive), with the expectation of each h
    std::map<std::string, std::map<std::string, std::map<double, Expectation>>> sweep;
    for (const SuiteCase& c : s.cases) {
      const auto* job = dynamic_cast<const experiments::SimulateJob*>(c.job.get());
      ASSERT_NE(job, nullptr) << c.id;
      const experiments::SimulateSpec& spec = job->spec();
      EXPECT_TRUE(spec.timed) << c.id;
      EXPECT_EQ(spec.overrides.t_final, t_final) << c.id;
      // 1000 samples (every K-th step), within rounding of K: enough to catch the maximum errors.
      const double samples = t_final / *spec.overrides.h / static_cast<double>(*spec.overrides.output_every);
      EXPECT_GE(samples, 1000.0) << c.id;
      EXPECT_LT(samples, 2000.0) << c.id;
      const bool adaptive = !label(c, "rtol").empty();
      const double x = std::stod(adaptive ? label(c, "rtol") : label(c, "h"));
      sweep[label(c, "scene")][label(c, "label")][adaptive ? -x : x] = c.expect;  // rtol negated: apart from h
    }
    EXPECT_EQ(sweep.size(), 3u);
    for (const char* scene : {"free-body", "pendulum", "dumbbell"}) {
      for (const char* m : {"LGVI order 2", "LGVI order 4 (yoshida4)", "LGVI order 6 (kahan-li6)",
                            "odeint-rk4 (quaternion)", "odeint-rk4 (quaternion-renormalized)", "odeint-rk4 (matrix)",
                            "cvode-adams (quaternion)", "cvode-bdf (quaternion)", "odeint-dopri5 (quaternion)",
                            "gsl-rk8pd (quaternion)"}) {
        ASSERT_TRUE(sweep[scene].count(m)) << scene << ": " << m;
        const auto& values = sweep[scene][m];
        EXPECT_GE(values.size(), 3u) << scene << ": " << m << " needs a sweep";
        if (values.begin()->first < 0.0) {  // adaptive: must complete at every tolerance
          for (const auto& [rtol, e] : values) EXPECT_EQ(e, Expectation::Complete) << scene << ": " << m;
          continue;
        }
        // Fixed step: the two largest steps are probes (may fail), the smaller ones must complete.
        std::size_t n = 0;
        for (auto it = values.rbegin(); it != values.rend(); ++it, ++n) {
          EXPECT_EQ(it->second, n < 2 ? Expectation::Either : Expectation::Complete) << scene << ": " << m << " h "
                                                                                     << it->first;
        }
        EXPECT_GE(values.size(), quick ? 4u : 8u) << scene << ": " << m;
      }
    }
  }
}

TEST(SuiteCases, ExtremesExpectGimbalLockToStopTheEulerModelAndSmallStepsToWork) {
  const Suite s = suite("extremes", true);
  std::size_t euler = 0;
  for (const SuiteCase& c : s.cases) {
    if (c.group == "gimbal-lock" && label(c, "model") == "euler") {
      ++euler;
      EXPECT_EQ(c.expect, Expectation::Fail) << c.id;
    }
    if (c.group == "step-size" && c.id.find("-hw0.01-") != std::string::npos) {
      EXPECT_EQ(c.expect, Expectation::Complete) << c.id;
    }
  }
  EXPECT_GE(euler, 3u);
  std::set<std::string> groups;
  for (const SuiteCase& c : s.cases) groups.insert(c.group);
  EXPECT_EQ(groups, (std::set<std::string>{"step-size", "fast-spin", "inertia", "tiny-steps", "gimbal-lock"}));
}

// --- sharding -----------------------------------------------------------------------------------

TEST(SuiteShards, TheShardsAreDisjointContiguousAndTheirUnionIsEveryCase) {
  for (std::size_t n = 0; n <= 40; ++n) {
    for (std::size_t count = 1; count <= 9; ++count) {
      std::vector<std::size_t> merged;
      std::size_t smallest = n, largest = 0;
      for (std::size_t i = 0; i < count; ++i) {
        const auto part = experiments::shard_cases(n, {i, count});
        smallest = std::min(smallest, part.size());
        largest = std::max(largest, part.size());
        merged.insert(merged.end(), part.begin(), part.end());
      }
      std::vector<std::size_t> all(n);
      for (std::size_t k = 0; k < n; ++k) all[k] = k;
      EXPECT_EQ(merged, all) << n << " cases, " << count << " shards";  // in order: no overlap, no gap
      EXPECT_LE(largest - std::min(smallest, largest), 1u) << n << " cases, " << count << " shards";
    }
  }
}

TEST(SuiteShards, BlocksAreExactForShardCountsNear2To62) {
  // i n / N in 128 bits: with 64 bits, i * 14 overflows for i >= 2^64 / 14 (~1.14 * 2^60): shard
  // 2^62 - 1 of 2^62 got case 1 instead of 13.
  const std::size_t n = std::size_t{1} << 62;
  EXPECT_EQ(experiments::shard_cases(14, {n - 1, n}), std::vector<std::size_t>{13});
  EXPECT_EQ(experiments::shard_cases(14, {n / 2 - 1, n}), std::vector<std::size_t>{6});
  EXPECT_TRUE(experiments::shard_cases(14, {n / 2, n}).empty());
  EXPECT_TRUE(experiments::shard_cases(14, {n - 2, n}).empty());
  EXPECT_EQ(experiments::parse_shard("4611686018427387903/4611686018427387904").index, n - 1);
}

TEST(SuiteShards, ParsesIOverNAndRejectsTheRest) {
  const experiments::Shard s = experiments::parse_shard("2/5");
  EXPECT_EQ(s.index, 2u);
  EXPECT_EQ(s.count, 5u);
  for (const char* bad : {"3/2", "2/2", "0/0", "1", "/2", "1/", "a/2", "1/2/3", "-1/2", "1 /2"}) {
    EXPECT_THROW(experiments::parse_shard(bad), InvalidInput) << bad;
  }
}

TEST(SuiteShards, ListedShardsConcatenateToTheWholeList) {
  TempDir dir;
  const CliResult whole = run_testbed(dir, {"suite", "work-precision", "--quick", "--list"});
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  EXPECT_EQ(lines_of(whole.out).size(), suite("work-precision", true).cases.size());
  std::string merged;
  for (int i = 0; i < 3; ++i) {
    const CliResult part =
        run_testbed(dir, {"suite", "work-precision", "--quick", "--list", "--shard", std::to_string(i) + "/3"});
    ASSERT_EQ(part.exit_code, 0) << part.err;
    merged += part.out;
  }
  EXPECT_EQ(merged, whole.out);
  EXPECT_TRUE(dir.work_entries().empty());
}

/// summary.csv without the columns that measure time (they differ between runs).
std::vector<std::vector<std::string>> untimed(const std::string& csv) {
  std::vector<std::vector<std::string>> rows;
  std::vector<std::size_t> timed;
  for (const std::string& line : lines_of(csv)) {
    if (line.starts_with("#")) continue;  // the metadata (shard 0): compared whole by the caller
    std::vector<std::string> cells = split(line + ",", ',');
    if (rows.empty()) {
      for (std::size_t j = 0; j < cells.size(); ++j) {
        if (cells[j].find("seconds") != std::string::npos || cells[j] == "detail") timed.push_back(j);
      }
    }
    for (const std::size_t j : timed) {
      if (j < cells.size()) cells[j] = "";
    }
    rows.push_back(cells);
  }
  return rows;
}

TEST(SuiteShards, ShardSummariesMergeByConcatenationAndRenderAfterwards) {
  // Three tiny scenes through the default suite: 6 cases, in 4 shards (block sizes 1 and 2).
  TempDir dir;
  for (const char* name : {"a", "b", "c"}) {
    write_text(dir.scenes() / (std::string(name) + ".toml"),
               edited_scene("pendulum", "t_final = 20.0", "t_final = 0.1"));
  }
  const std::vector<std::string> base = {"--scenes-dir", dir.scenes().string(), "suite", "default"};
  auto args = [&](std::vector<std::string> more) {
    std::vector<std::string> a = base;
    a.insert(a.end(), more.begin(), more.end());
    return a;
  };
  const CliResult whole = run_testbed(dir, args({"--out", "whole", "--jobs", "2", "--no-plots"}));
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  std::string csv, jsonl;
  for (int i = 0; i < 4; ++i) {
    const CliResult r = run_testbed(dir, args({"--out", "merged", "--shard", std::to_string(i) + "/4", "--jobs", "2"}));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    // Each shard's summaries, collected before the next shard overwrites them in "merged".
    csv += read_text(dir.work() / "merged" / "summary.csv");
    jsonl += read_text(dir.work() / "merged" / "summary.jsonl");
    // Shard 0 alone starts with the metadata and the header.
    const std::string first = lines_of(read_text(dir.work() / "merged" / "summary.csv")).front();
    EXPECT_EQ(first.starts_with("# suite: default"), i == 0) << first;
    EXPECT_FALSE(first.starts_with("index,")) << first;
  }
  EXPECT_EQ(untimed(csv), untimed(read_text(dir.work() / "whole" / "summary.csv")));
  const auto metadata = [](const std::string& text) {
    std::string m;
    for (const std::string& line : lines_of(text)) m += line.starts_with("#") ? line + "\n" : "";
    return m;
  };
  EXPECT_EQ(metadata(csv), metadata(read_text(dir.work() / "whole" / "summary.csv")));
  EXPECT_EQ(lines_of(jsonl).size(), 6u);
  EXPECT_EQ(lines_of(read_text(dir.work() / "whole" / "summary.jsonl")).size(), 6u);
  // Merged: every case CSV from the shards and the concatenated summary; then the figures.
  write_text(dir.work() / "merged" / "summary.csv", csv);
  const CliResult render = run_testbed(dir, args({"--out", "merged", "--render-only"}));
  ASSERT_EQ(render.exit_code, 0) << render.err;
  for (const char* name : {"a", "b", "c"}) {
    for (const char* kind : {"-energy.png", "-orthogonality.png", "-momentum.png"}) {
      EXPECT_EQ(read_text(dir.work() / "merged" / (std::string(name) + kind)).substr(1, 3), "PNG") << name << kind;
    }
  }
  EXPECT_EQ(experiments::read_summary_csv(dir.work() / "merged" / "summary.csv").size(), 6u);
}

TEST(SuiteShards, RenderingWithoutTheFirstShardsHeaderNamesTheProblem) {
  TempDir dir;
  fs::create_directories(dir.work() / "res");
  write_text(dir.work() / "res" / "summary.csv", "3,a-symmetric,a,complete\n");
  const CliResult r = run_testbed(dir, {"suite", "default", "--out", "res", "--render-only"});
  EXPECT_EQ(r.exit_code, 3);
  ASSERT_EQ(r.err_lines().size(), 1u) << r.err;
  EXPECT_NE(r.err.find("no header line"), std::string::npos) << r.err;
}

// --- atomic outputs ----------------------------------------------------------------------------

/// Names in `dir` (recursively) that are temporaries (hidden files).
std::vector<std::string> hidden_files(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.path().filename().string().front() == '.') names.push_back(e.path().string());
  }
  return names;
}

TEST(SuiteAtomic, AWriterThatDiesMidWriteLeavesNoFile) {
  TempDir dir;
  const fs::path target = dir.work() / "case.csv";
  try {
    experiments::CsvWriter csv(target, {"t", "x"});
    for (int k = 0; k < 1000; ++k) {
      const double row[] = {k * 0.1, 1.0};
      csv.write_row(row);
    }
    throw std::runtime_error("the case failed mid-write");
  } catch (const std::runtime_error&) {
  }
  EXPECT_TRUE(dir.work_entries().empty());
}

/// Every visible CSV in `dir` is complete: metadata with the final status, a header, and rows
/// with as many cells as the header.
void expect_complete_csvs(const fs::path& dir) {
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.front() == '.' || e.path().extension() != ".csv" || name == "summary.csv") continue;
    const std::string text = read_text(e.path());
    ASSERT_FALSE(text.empty()) << name;
    EXPECT_EQ(text.back(), '\n') << name;
    const CsvParts csv = read_csv(e.path());  // checks the cell count of every row
    EXPECT_NE(csv.meta("status"), "<missing>") << name;
    EXPECT_FALSE(csv.rows.empty()) << name;
  }
}

TEST(SuiteAtomic, AKilledSuiteLeavesOnlyCompleteFiles) {
  TempDir dir;
  const fs::path out = dir.work() / "res";
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    const int null = ::open("/dev/null", O_WRONLY);
    dup2(null, 1);
    dup2(null, 2);
    execl(testbed_exe(), testbed_exe(), "suite", "energy-drift", "--quick", "--no-plots", "--jobs", "2", "--out",
          out.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  // Kill it while cases are being written: once the first case CSV has appeared.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  bool some = false;
  while (!some && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    std::error_code ec;
    if (fs::is_directory(out, ec)) {
      for (const auto& e : fs::directory_iterator(out)) some = some || e.path().filename().string().front() != '.';
    }
  }
  kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(some) << "no case finished within 60 s";
  ASSERT_TRUE(WIFSIGNALED(status)) << "the suite finished before it was killed: the test proves nothing";
  expect_complete_csvs(out);
  EXPECT_FALSE(fs::exists(out / "summary.csv"));  // written after all cases
}

// --- resume and merge ----------------------------------------------------------------------------

/// summary.jsonl rows without the fields that measure time or quote it (they differ between
/// runs): each row's `"key": value` parts (split before every ', "'), the timed keys dropped.
std::vector<std::vector<std::string>> untimed_jsonl(const std::string& jsonl) {
  std::vector<std::vector<std::string>> rows;
  for (const std::string& line : lines_of(jsonl)) {
    std::vector<std::string> kept;
    std::size_t start = 1;  // after '{'
    while (start < line.size()) {
      std::size_t next = line.find(", \"", start);
      if (next == std::string::npos) next = line.size() - 1;  // before '}'
      const std::string field = line.substr(start, next - start);
      const std::string key = field.substr(1, field.find("\":") - 1);
      const bool timed = key.find("seconds") != std::string::npos || key == "detail" || key == "status_detail" ||
                         key.find("cpu") != std::string::npos || key == "timing_repetitions";
      if (!timed) kept.push_back(field);
      start = next + 2;
    }
    rows.push_back(kept);
  }
  return rows;
}

/// The text of a manifest (suite-run.json), searched for "key": value pairs.
struct ManifestText {
  std::string text;
  bool has(const std::string& part) const { return text.find(part) != std::string::npos; }
};

/// Journal lines with the completion marker.
std::size_t journaled(const fs::path& out) {
  std::size_t n = 0;
  for (const std::string& line : lines_of(read_text(out / "suite-journal.jsonl"))) {
    const std::string marker = "\"done\":true}";
    if (line.size() >= marker.size() && line.compare(line.size() - marker.size(), marker.size(), marker) == 0) ++n;
  }
  return n;
}

/// Temporaries of lgvi-testbed left under `dir`.
std::vector<std::string> temporaries(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.path().filename().string().rfind(".lgvi-tmp-", 0) == 0) names.push_back(e.path().string());
  }
  return names;
}

/// `count` copies of the pendulum scene (20,000 LGVI steps, ~10-30 ms per case), named s00...
void pendulum_copies(const TempDir& dir, int count, const std::string& from = "t_final = 20.0",
                     const std::string& to = "t_final = 20.0") {
  for (int i = 0; i < count; ++i) {
    const std::string name = std::string("s") + (i < 10 ? "0" : "") + std::to_string(i);
    write_text(dir.scenes() / (name + ".toml"), edited_scene("pendulum", from, to));
  }
}

TEST(SuiteResume, ARunKilledAtRandomPointsAndResumedEqualsAnUninterruptedOne) {
  // 24 cases (12 scenes x 2 forms) killed three times, by SIGKILL, SIGTERM and SIGINT, once the
  // journal holds a random number of finished cases (seeded), resumed each time, then finished.
  TempDir dir;
  pendulum_copies(dir, 12);
  const std::vector<std::string> base = {"--scenes-dir", dir.scenes().string(), "suite", "default", "--no-plots",
                                         "--jobs", "2"};
  auto args = [&](std::vector<std::string> more) {
    std::vector<std::string> a = base;
    a.insert(a.end(), more.begin(), more.end());
    return a;
  };
  const CliResult whole = run_testbed(dir, args({"--out", "whole"}));
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  const std::size_t total = 24;
  ASSERT_EQ(lines_of(read_text(dir.work() / "whole" / "summary.jsonl")).size(), total);

  const fs::path out = dir.work() / "res";
  std::mt19937 rng(16);
  int interrupted = 0;
  for (const int signo : {SIGKILL, SIGTERM, SIGINT}) {
    const std::size_t before = fs::exists(out) ? journaled(out) : 0;
    std::uniform_int_distribution<std::size_t> pick(before + 1, before + 6);
    const std::size_t target = std::min(pick(rng), total - 1);
    const pid_t pid =
        spawn_testbed(dir, signo == SIGKILL ? args({"--out", "res"}) : args({"--out", "res", "--resume"}));
    ASSERT_GT(pid, 0);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    int status = 0;
    bool exited = false;
    while (std::chrono::steady_clock::now() < deadline) {
      if (waitpid(pid, &status, WNOHANG) == pid) {
        exited = true;
        break;
      }
      if (fs::exists(out / "suite-journal.jsonl") && journaled(out) >= target) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    if (!exited) {
      kill(pid, signo);
      waitpid(pid, &status, 0);
    }
    const ManifestText m{read_text(out / "suite-run.json")};
    if (signo == SIGKILL) {
      if (WIFSIGNALED(status)) ++interrupted;
    } else if (WIFEXITED(status) && WEXITSTATUS(status) == 128 + signo) {
      // Ended cleanly: the summary holds exactly the cases the manifest counts as finished.
      ++interrupted;
      EXPECT_TRUE(m.has("\"complete\": false")) << m.text;
      EXPECT_TRUE(m.has(signo == SIGTERM ? "\"SIGTERM\"" : "\"SIGINT\"")) << m.text;
      const std::vector<std::string> lines = lines_of(read_text(out / "summary.csv"));
      // Rows: the lines after the metadata ('#') and the header.
      const auto data_rows = std::count_if(lines.begin(), lines.end(), [](const std::string& l) { return !l.starts_with("#"); }) - 1;
      const std::size_t rows = static_cast<std::size_t>(data_rows);
      EXPECT_TRUE(m.has("\"finished\": " + std::to_string(rows))) << m.text;
      EXPECT_EQ(rows, journaled(out));
      EXPECT_TRUE(temporaries(out).empty()) << temporaries(out).front();
    }
  }
  EXPECT_GE(interrupted, 2) << "the runs ended before they were killed: the test proves little";
  const CliResult rest = run_testbed(dir, args({"--out", "res", "--resume"}));
  ASSERT_EQ(rest.exit_code, 0) << rest.err;
  EXPECT_NE(rest.out.find("resume: "), std::string::npos) << rest.out;
  EXPECT_EQ(untimed(read_text(out / "summary.csv")), untimed(read_text(dir.work() / "whole" / "summary.csv")));
  EXPECT_EQ(untimed_jsonl(read_text(out / "summary.jsonl")),
            untimed_jsonl(read_text(dir.work() / "whole" / "summary.jsonl")));
  EXPECT_TRUE(temporaries(out).empty()) << temporaries(out).front();  // SIGKILL's are cleaned
  EXPECT_NE(read_text(out / "suite-run.json").find("\"complete\": true"), std::string::npos);
}

TEST(SuiteResume, ResumeRerunsACaseWhoseFileChangedAndRefusesAnotherRun) {
  TempDir dir;
  pendulum_copies(dir, 2, "t_final = 20.0", "t_final = 0.1");
  const std::vector<std::string> base = {"--scenes-dir", dir.scenes().string(), "suite", "default", "--no-plots",
                                         "--out", "res"};
  auto args = [&](std::vector<std::string> more) {
    std::vector<std::string> a = base;
    a.insert(a.end(), more.begin(), more.end());
    return a;
  };
  ASSERT_EQ(run_testbed(dir, base).exit_code, 0);
  const std::string summary = read_text(dir.work() / "res" / "summary.csv");
  // A case file cut short (a disk that filled, an edit): that case runs again, the others not.
  const fs::path csv = dir.work() / "res" / "s00-symmetric.csv";
  const std::string text = read_text(csv);
  write_text(csv, text.substr(0, text.size() / 2));
  const CliResult r = run_testbed(dir, args({"--resume"}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("running s00-symmetric again"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("3 of 4 cases finished and verified"), std::string::npos) << r.out;
  EXPECT_EQ(lines_of(read_text(csv)).size(), lines_of(text).size());  // written again, whole
  EXPECT_EQ(untimed(read_text(dir.work() / "res" / "summary.csv")), untimed(summary));
  // Another suite, form or scene file: refused, nothing run.
  const CliResult quick = run_testbed(dir, args({"--resume", "--quick"}));
  EXPECT_EQ(quick.exit_code, 1) << quick.err;
  EXPECT_NE(quick.err.find("full form"), std::string::npos) << quick.err;
  write_text(dir.scenes() / "s01.toml", edited_scene("pendulum", "t_final = 20.0", "t_final = 0.2"));
  const CliResult edited = run_testbed(dir, args({"--resume"}));
  EXPECT_EQ(edited.exit_code, 1) << edited.err;
  EXPECT_NE(edited.err.find("other cases or scene files"), std::string::npos) << edited.err;
  const CliResult other = run_testbed(dir, {"suite", "energy-drift", "--quick", "--out", "res", "--resume"});
  EXPECT_EQ(other.exit_code, 1) << other.err;
  EXPECT_NE(other.err.find("suite 'default', not 'energy-drift'"), std::string::npos) << other.err;
}

// A disk that fills during a suite (issue 34): the files lgvi-testbed writes are capped at
// 64 KiB by RLIMIT_FSIZE (a write past it fails with EFBIG, as one past a full disk fails with
// ENOSPC; SIGXFSZ ignored). Four short cases write ~6 KiB each and are journaled; the fifth
// scene's cases write 370 KiB and cannot. The suite stops with exit 3, results could not be
// written (not 2, "cases did not end as expected", and not std::terminate with its workers
// running), naming the file and the way on; --resume with room finishes the run as one
// uninterrupted run would have.
TEST(SuiteOutput, AFullDiskStopsTheSuiteWithExitThreeAndResumeFinishesIt) {
  TempDir dir;
  pendulum_copies(dir, 2, "t_final = 20.0", "t_final = 0.1");
  write_text(dir.scenes() / "s02.toml", edited_scene("pendulum", "t_final = 20.0", "t_final = 20.0"));
  const std::vector<std::string> args = {"--scenes-dir", dir.scenes().string(), "suite", "default", "--no-plots",
                                         "--jobs", "1", "--out", "res"};
  const CliResult whole = run_testbed(dir, {"--scenes-dir", dir.scenes().string(), "suite", "default",
                                            "--no-plots", "--jobs", "1", "--out", "whole"});
  ASSERT_EQ(whole.exit_code, 0) << whole.err;

  const pid_t pid = spawn_testbed(dir, args, dir.work() / "stderr.txt", [] {
    const rlimit cap{64 * 1024, 64 * 1024};
    signal(SIGXFSZ, SIG_IGN);
    if (setrlimit(RLIMIT_FSIZE, &cap) != 0) _exit(127);
  });
  ASSERT_GT(pid, 0);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  const std::string err = read_text(dir.work() / "stderr.txt");
  ASSERT_TRUE(WIFEXITED(status)) << "ended by signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0) << ": " << err;
  EXPECT_EQ(WEXITSTATUS(status), 3) << err;
  const std::vector<std::string> lines = lines_of(err);
  ASSERT_EQ(lines.size(), 1u) << err;
  EXPECT_NE(lines[0].find("s02-"), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find("suite default stopped: 4 cases journaled"), std::string::npos) << lines[0];
  EXPECT_EQ(journaled(dir.work() / "res"), 4u);
  EXPECT_TRUE(temporaries(dir.work() / "res").empty()) << temporaries(dir.work() / "res").front();

  std::vector<std::string> resume = args;
  resume.push_back("--resume");
  const CliResult rest = run_testbed(dir, resume);
  ASSERT_EQ(rest.exit_code, 0) << rest.err;
  EXPECT_EQ(untimed(read_text(dir.work() / "res" / "summary.csv")), untimed(read_text(dir.work() / "whole" / "summary.csv")));
}

// The scenes directory's scenes with their control samples: an edited CSV is another run.
TEST(SuiteResume, RefusesARunWhoseSceneReadsEditedControlSamples) {
  TempDir dir;
  write_text(dir.scenes() / "driven.toml", edited_scene("pendulum", "t_final = 20.0", "t_final = 0.1") +
                                               "\n[control]\ntype = \"piecewise-linear\"\nfile = \"u.csv\"\n");
  write_text(dir.scenes() / "u.csv", "t,u1,u2,u3\n0,0,0,0\n1,0.1,0,0\n");
  const std::vector<std::string> run = {"--scenes-dir", dir.scenes().string(), "suite", "default", "--no-plots",
                                        "--out", "res"};
  std::vector<std::string> resume = run;
  resume.push_back("--resume");
  const CliResult first = run_testbed(dir, run);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  const CliResult same = run_testbed(dir, resume);
  EXPECT_EQ(same.exit_code, 0) << same.err;
  write_text(dir.scenes() / "u.csv", "t,u1,u2,u3\n0,0,0,0\n1,0.2,0,0\n");
  const CliResult edited = run_testbed(dir, resume);
  EXPECT_EQ(edited.exit_code, 1) << edited.err;
  EXPECT_NE(edited.err.find("other cases or scene files"), std::string::npos) << edited.err;
}

TEST(SuiteMerge, ShardsMergeIntoTheUnshardedRunAndIncompleteOrMismatchedShardsAreRefused) {
  TempDir dir;
  pendulum_copies(dir, 3, "t_final = 20.0", "t_final = 0.1");
  const std::vector<std::string> base = {"--scenes-dir", dir.scenes().string(), "suite", "default"};
  auto args = [&](std::vector<std::string> more) {
    std::vector<std::string> a = base;
    a.insert(a.end(), more.begin(), more.end());
    return a;
  };
  ASSERT_EQ(run_testbed(dir, args({"--out", "whole", "--no-plots"})).exit_code, 0);
  for (int i = 0; i < 3; ++i) {
    const std::string s = std::to_string(i);
    ASSERT_EQ(run_testbed(dir, args({"--out", "shard-" + s, "--shard", s + "/3"})).exit_code, 0);
  }
  const auto merge = [&](const std::vector<std::string>& shards) {
    std::vector<std::string> a = {"merge", "merged"};
    a.insert(a.end(), shards.begin(), shards.end());
    return run_testbed(dir, a);
  };
  // A shard missing, a shard given twice: refused, nothing written.
  const CliResult missing = merge({"shard-0", "shard-2"});
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("shards missing of 3: 1"), std::string::npos) << missing.err;
  const CliResult twice = merge({"shard-0", "shard-1", "shard-1", "shard-2"});
  EXPECT_EQ(twice.exit_code, 1);
  EXPECT_NE(twice.err.find("shard 1 is also"), std::string::npos) << twice.err;
  // An incomplete shard (as an interrupted run leaves its manifest).
  const fs::path manifest = dir.work() / "shard-1" / "suite-run.json";
  const std::string complete = read_text(manifest);
  std::string incomplete = complete;
  incomplete.replace(incomplete.find("\"complete\": true"), 16, "\"complete\": false");
  write_text(manifest, incomplete);
  const CliResult partial = merge({"shard-0", "shard-1", "shard-2"});
  EXPECT_EQ(partial.exit_code, 1);
  EXPECT_NE(partial.err.find("is incomplete"), std::string::npos) << partial.err;
  EXPECT_NE(partial.err.find("--resume"), std::string::npos) << partial.err;
  write_text(manifest, complete);
  // A case file changed after its shard finished.
  const fs::path csv = dir.work() / "shard-1" / "s01-symmetric.csv";
  const std::string text = read_text(csv);
  write_text(csv, text + "\n");
  const CliResult changed = merge({"shard-0", "shard-1", "shard-2"});
  EXPECT_EQ(changed.exit_code, 1);
  EXPECT_NE(changed.err.find("s01-symmetric.csv has"), std::string::npos) << changed.err;
  write_text(csv, text);
  // A shard of another run (a scene file edited before it ran).
  write_text(dir.scenes() / "s02.toml", edited_scene("pendulum", "t_final = 20.0", "t_final = 0.2"));
  ASSERT_EQ(run_testbed(dir, args({"--out", "other-2", "--shard", "2/3"})).exit_code, 0);
  const CliResult mismatched = merge({"shard-0", "shard-1", "other-2"});
  EXPECT_EQ(mismatched.exit_code, 1);
  EXPECT_NE(mismatched.err.find("fingerprint"), std::string::npos) << mismatched.err;
  EXPECT_FALSE(fs::exists(dir.work() / "merged"));
  // The shards of one run, in any order: the unsharded run's summaries and files; then figures.
  const CliResult merged = merge({"shard-2", "shard-0", "shard-1"});
  ASSERT_EQ(merged.exit_code, 0) << merged.err;
  EXPECT_EQ(untimed(read_text(dir.work() / "merged" / "summary.csv")),
            untimed(read_text(dir.work() / "whole" / "summary.csv")));
  EXPECT_EQ(untimed_jsonl(read_text(dir.work() / "merged" / "summary.jsonl")),
            untimed_jsonl(read_text(dir.work() / "whole" / "summary.jsonl")));
  for (int i = 0; i < 3; ++i) {
    for (const char* form : {"-symmetric.csv", "-printed.csv"}) {
      const std::string name = "s0" + std::to_string(i) + form;
      EXPECT_EQ(read_text(dir.work() / "merged" / name), read_text(dir.work() / ("shard-" + std::to_string(i)) / name))
          << name;
    }
  }
  const CliResult render = run_testbed(dir, {"--scenes-dir", dir.scenes().string(), "suite", "default", "--out",
                                             "merged", "--render-only"});
  ASSERT_EQ(render.exit_code, 0) << render.err;
  EXPECT_EQ(read_text(dir.work() / "merged" / "s00-energy.png").substr(1, 3), "PNG");
}

TEST(SuiteAtomic, TemporaryNamesAreShortAndThoseOfDeadProcessesAreRemoved) {
  TempDir dir;
  // A 254-byte name (the file-name limit is 255): its temporary must fit too.
  const fs::path target = dir.work() / (std::string(250, 'a') + ".csv");
  experiments::AtomicFile f(target);
  f.write("x\n");
  EXPECT_LT(f.temp_path().filename().string().size(), 64u);
  f.commit();
  EXPECT_EQ(read_text(target), "x\n");
  // A temporary of a process that has exited is stale; one of a live process (the parent of
  // this test) is not.
  const pid_t child = fork();
  if (child == 0) _exit(0);
  waitpid(child, nullptr, 0);
  const fs::path stale = dir.work() / (".lgvi-tmp-" + std::to_string(child) + "-0.csv");
  const fs::path live = dir.work() / (".lgvi-tmp-" + std::to_string(getppid()) + "-0.csv");
  write_text(stale, "partial");
  write_text(live, "partial");
  EXPECT_EQ(experiments::remove_stale_temporaries(dir.work()), 1u);
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(live));
}

// --- end to end ----------------------------------------------------------------------------------

TEST(SuiteEndToEnd, QuickExtremesRunsRecordsAndPlots) {
  TempDir dir;
  const CliResult r = run_testbed(dir, {"suite", "extremes", "--quick", "--out", "res", "--jobs", "2"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  const Suite s = suite("extremes", true);
  const fs::path res = dir.work() / "res";
  // Progress: one line per case with done/total.
  EXPECT_NE(r.out.find("[" + std::to_string(s.cases.size()) + "/" + std::to_string(s.cases.size()) + "]"),
            std::string::npos);
  EXPECT_TRUE(hidden_files(res).empty()) << hidden_files(res).front();
  expect_complete_csvs(res);

  const auto rows = experiments::read_summary_csv(res / "summary.csv");
  ASSERT_EQ(rows.size(), s.cases.size());
  EXPECT_EQ(lines_of(read_text(res / "summary.jsonl")).size(), s.cases.size());
  std::size_t singular = 0, failed_large_steps = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i].text("case"), s.cases[i].id);  // case order
    EXPECT_EQ(rows[i].text("as_expected"), "true") << s.cases[i].id;
    if (rows[i].text("status") == "completed") {
      EXPECT_TRUE(fs::is_regular_file(res / rows[i].text("csv_path"))) << s.cases[i].id;
      EXPECT_TRUE(rows[i].number("max_energy_error_relative").has_value()) << s.cases[i].id;
    }
    if (rows[i].text("group") == "gimbal-lock" && rows[i].text("model") == "euler") {
      singular += rows[i].text("status") == "coordinate singularity" ? 1 : 0;
    }
    if (rows[i].text("group") == "step-size" && rows[i].text("status") != "completed") ++failed_large_steps;
  }
  EXPECT_GE(singular, 3u);
  EXPECT_GT(failed_large_steps, 0u) << "the step sweep should reach past some method's domain";
  for (const char* f : {"step-size-energy.png", "step-size-orthogonality.png", "tiny-steps-energy.png",
                        "fast-spin-energy.png"}) {
    EXPECT_EQ(read_text(res / f).substr(1, 3), "PNG") << f;
  }
  const std::string table = read_text(res / "extremes-table.md");
  EXPECT_NE(table.find("coordinate singularity"), std::string::npos);
}

// The soak suite, quick form (10^5 steps per system): every system completes, conserves what
// its LGVI conserves, and reports the memory the run needed, measured in the serial timing pass.
TEST(SuiteEndToEnd, QuickSoakRunsEverySystemAndReportsItsMemory) {
  TempDir dir;
  const CliResult r = run_testbed(dir, {"suite", "soak", "--quick", "--out", "res", "--jobs", "2"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const fs::path res = dir.work() / "res";
  const auto rows = experiments::read_summary_csv(res / "summary.csv");
  ASSERT_EQ(rows.size(), 5u);
  std::set<std::string> systems;
  for (const auto& row : rows) {
    EXPECT_EQ(row.text("status"), "completed") << row.text("case");
    EXPECT_EQ(row.number("grid_steps"), 100'000.0) << row.text("case");
    systems.insert(row.text("system"));
    // The LGVI keeps R orthogonal to round-off: R_{k+1} = R_k F_k with F_k orthogonal to a few
    // eps, so the error grows at most linearly, 10^5 steps x 10 eps = 2.2e-10 (a random walk
    // would give ~1e-12); the bound is that worst case times ~5.
    const std::optional<double> orthogonality = row.number("max_orthogonality_error");
    ASSERT_TRUE(orthogonality.has_value()) << row.text("case");
    EXPECT_LT(*orthogonality, 1e-9) << row.text("case");
    // Memory: measured, and the run needed little beyond what the process held. The integration
    // allocates nothing per step; 64 MiB would mean ~670 bytes a step leaked over 10^5 steps.
    ASSERT_TRUE(row.number("peak_rss_mb").has_value()) << row.text("case");
    EXPECT_GT(*row.number("peak_rss_mb"), 0.0);
    if (row.text("peak_reset") == "yes") {
      ASSERT_TRUE(row.number("rss_growth_mb").has_value());
      EXPECT_LT(*row.number("rss_growth_mb"), 64.0) << row.text("case");
    }
  }
  EXPECT_EQ(systems, (std::set<std::string>{"free-body", "pendulum", "dumbbell", "cart-pendulum", "connected-bodies"}));
  const std::string table = read_text(res / "soak-table.md");
  EXPECT_NE(table.find("connected-bodies"), std::string::npos);
  EXPECT_EQ(read_text(res / "soak-energy.png").substr(1, 3), "PNG");
}

TEST(SuiteEndToEnd, LongHorizonTinyRunTimesEveryCaseAndDrawsItsFiguresAndTables) {
  // Four cheap cases of the quick suite, with its renderer: the free body over 10^3 s at the
  // sweep's two largest steps (the LGVI fails at 0.4, completes at 0.2), RK4 and rk8pd.
  const Suite quick = suite("long-horizon", true);
  Suite s = quick;
  s.cases.clear();
  const std::vector<std::string> ids = {"free-body-lgvi-h0.4", "free-body-lgvi-h0.2",
                                        "free-body-odeint-rk4-quaternion-h0.2",
                                        "free-body-gsl-rk8pd-quaternion-rtol1e-06"};
  for (const std::string& id : ids) {
    const auto it =
        std::find_if(quick.cases.begin(), quick.cases.end(), [&](const SuiteCase& c) { return c.id == id; });
    ASSERT_NE(it, quick.cases.end()) << id;
    s.cases.push_back(*it);
  }
  TempDir dir;
  experiments::SuiteOptions options;
  options.out_dir = dir.work() / "res";
  options.scenes_dir = experiments::default_scenes_dir();
  options.plots_dir = experiments::default_plots_dir();
  options.gnuplot = experiments::default_gnuplot();
  options.jobs = 2;
  std::ostringstream progress;
  const experiments::SuiteResult r = experiments::run_suite(s, options, progress);
  EXPECT_TRUE(r.all_ok()) << progress.str();
  const auto rows = experiments::read_summary_csv(options.out_dir / "summary.csv");
  ASSERT_EQ(rows.size(), ids.size());
  EXPECT_EQ(rows[0].text("status"), "rotation update failed");  // beyond the LGVI's largest step
  for (const auto& row : rows) {
    const std::string& id = row.text("case");
    // Every case that ran is timed: 3 passes (at least one repetition each), min <= median.
    ASSERT_TRUE(row.number("timing_repetitions").has_value()) << id;
    EXPECT_GE(*row.number("timing_repetitions"), 3.0) << id;
    EXPECT_GT(row.number("integrator_seconds_min").value_or(0.0), 0.0) << id;
    EXPECT_LE(*row.number("integrator_seconds_min"), *row.number("integrator_seconds_median")) << id;
    EXPECT_GT(row.number("integrator_cpu_seconds").value_or(0.0), 0.0) << id;
    if (row.text("status") != "completed") continue;
    // ... and recorded once: the case CSV holds the 1000 samples and the initial state.
    EXPECT_EQ(read_csv(options.out_dir / row.text("csv_path")).rows.size(), 1001u) << id;
    EXPECT_TRUE(row.number("max_energy_error_relative").has_value()) << id;
    EXPECT_TRUE(row.number("max_momentum_drift_absolute").has_value()) << id;
  }
  for (const char* f : {"free-body-energy-time.png", "free-body-energy-evaluations.png", "free-body-momentum-time.png",
                        "free-body-orthogonality-time.png"}) {
    EXPECT_EQ(read_text(options.out_dir / f).substr(1, 3), "PNG") << f;
  }
  const std::string table = read_text(options.out_dir / "long-horizon-table.md");
  EXPECT_NE(table.find("| free-body | 0.01 | "), std::string::npos) << table;
  EXPECT_NE(table.find("| free-body | LGVI order 2 | 0.2 | "), std::string::npos) << table;
  EXPECT_NE(table.find("h = 0.4: rotation update failed"), std::string::npos) << table;
}

TEST(SuiteEndToEnd, ACaseThatDoesNotEndAsExpectedMakesTheExitStatusTwo) {
  // The pendulum's rotation update fails at h = 0.125 (see CliSimulate): the default suite
  // expects every run to complete.
  TempDir dir;
  write_text(dir.scenes() / "ok.toml", edited_scene("pendulum", "t_final = 20.0", "t_final = 0.1"));
  std::string bad = edited_scene("pendulum", "h = 1e-3", "h = 0.125");
  write_text(dir.scenes() / "bad.toml", bad);
  const CliResult r =
      run_testbed(dir, {"--scenes-dir", dir.scenes().string(), "suite", "default", "--out", "res", "--no-plots"});
  EXPECT_EQ(r.exit_code, 2);
  ASSERT_EQ(r.err_lines().size(), 1u) << r.err;
  EXPECT_NE(r.err.find("2 of 4 cases did not end as expected (bad-symmetric, bad-printed"), std::string::npos) << r.err;
  const auto rows = experiments::read_summary_csv(dir.work() / "res" / "summary.csv");
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[0].text("status"), "rotation update failed");
  EXPECT_EQ(rows[0].text("as_expected"), "false");
  EXPECT_EQ(rows[2].text("as_expected"), "true");
}

// --- any job as a case ----------------------------------------------------------------------------

/// A case that is not a scene x method run (as the optimal-control suites will be): writes one
/// small file, or throws, or reports a failure.
class ToyJob final : public experiments::Job {
 public:
  enum class Kind { Writes, Throws, Fails };
  explicit ToyJob(Kind kind) : kind_(kind) {}
  void validate(const fs::path&) const override {}
  experiments::JobResult run(const experiments::JobContext& ctx) const override {
    if (kind_ == Kind::Throws) {
      experiments::CsvWriter half(ctx.out_dir / (ctx.case_id + ".csv"), {"k"});
      const double row[] = {1.0};
      half.write_row(row);
      throw std::runtime_error("stalled at iteration 3");  // before commit: no file
    }
    experiments::AtomicFile f(ctx.out_dir / (ctx.case_id + ".txt"));
    f.write("iterations 7\n");
    f.commit();
    if (kind_ == Kind::Fails) return {false, "shooting-stalled", "no descent at iteration 7", {{"iterations", 7.0}}};
    return {true, "completed", "converged in 7 iterations", {{"iterations", 7.0}, {"residual", 1e-12}}};
  }

 private:
  Kind kind_;
};

TEST(SuiteJobs, AnyJobRunsRecordsAndAnExceptionBecomesAnErrorRow) {
  TempDir dir;
  Suite s;
  s.name = "toy";
  s.columns = {"iterations", "residual"};
  const auto add = [&](const std::string& id, ToyJob::Kind kind, Expectation e) {
    s.cases.push_back({id, "toy", {}, e, std::make_shared<ToyJob>(kind)});
  };
  add("writes", ToyJob::Kind::Writes, Expectation::Complete);
  add("throws", ToyJob::Kind::Throws, Expectation::Either);
  add("fails", ToyJob::Kind::Fails, Expectation::Fail);
  add("fails-unexpectedly", ToyJob::Kind::Fails, Expectation::Complete);
  experiments::SuiteOptions options;
  options.out_dir = dir.work() / "res";
  options.jobs = 3;
  std::ostringstream progress;
  const experiments::SuiteResult r = experiments::run_suite(s, options, progress);
  ASSERT_EQ(r.cases.size(), 4u);
  EXPECT_EQ(r.unexpected(), 2u);  // the exception is never expected; nor a failure expected to complete
  EXPECT_TRUE(r.cases[0].as_expected);
  EXPECT_FALSE(r.cases[1].as_expected);
  EXPECT_EQ(r.cases[1].result.status, "error");
  EXPECT_EQ(r.cases[1].result.detail, "stalled at iteration 3");
  EXPECT_TRUE(r.cases[2].as_expected);
  EXPECT_FALSE(r.cases[3].as_expected);
  EXPECT_FALSE(fs::exists(dir.work() / "res" / "throws.csv"));
  EXPECT_TRUE(hidden_files(dir.work() / "res").empty());
  const auto rows = experiments::read_summary_csv(dir.work() / "res" / "summary.csv");
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[0].number("iterations"), 7.0);
  EXPECT_EQ(rows[0].number("residual"), 1e-12);
  EXPECT_EQ(rows[1].text("status"), "error");
  EXPECT_EQ(rows[2].text("status"), "shooting-stalled");
  EXPECT_FALSE(rows[2].number("residual").has_value());
  EXPECT_NE(progress.str().find("[4/4]"), std::string::npos) << progress.str();
  EXPECT_NE(progress.str().find("UNEXPECTED"), std::string::npos) << progress.str();
}

TEST(SuiteSummary, AllSuitesPartsEachGetTheirOwnSummaryOfTheirRows) {
  TempDir dir;
  Suite s;
  s.name = "all";
  s.columns = {"iterations", "residual"};
  for (const std::string part : {"first", "second"}) {
    fs::create_directories(dir.work() / "res" / part);
    s.cases.push_back({part + "/writes", part, {}, Expectation::Complete, std::make_shared<ToyJob>(ToyJob::Kind::Writes)});
    s.cases.push_back({part + "/fails", part, {}, Expectation::Fail, std::make_shared<ToyJob>(ToyJob::Kind::Fails)});
  }
  experiments::SuiteOptions options;
  options.out_dir = dir.work() / "res";
  options.jobs = 2;
  std::ostringstream progress;
  ASSERT_EQ(experiments::run_suite(s, options, progress).unexpected(), 0u) << progress.str();
  const auto all = experiments::read_summary_csv(dir.work() / "res" / "summary.csv");
  ASSERT_EQ(all.size(), 4u);
  for (const std::string part : {"first", "second"}) {
    const auto rows = experiments::read_summary_csv(dir.work() / "res" / part / "summary.csv");
    ASSERT_EQ(rows.size(), 2u) << part;
    EXPECT_EQ(rows[0].text("case"), part + "/writes");
    EXPECT_EQ(rows[0].number("iterations"), 7.0);
    EXPECT_EQ(rows[1].text("case"), part + "/fails");
    EXPECT_EQ(rows[1].text("status"), "shooting-stalled");
    const std::string jsonl = read_text(dir.work() / "res" / part / "summary.jsonl");
    EXPECT_EQ(std::count(jsonl.begin(), jsonl.end(), '\n'), 2) << jsonl;
    EXPECT_NE(jsonl.find(part + "/fails"), std::string::npos) << jsonl;
  }
}

// --- timing -------------------------------------------------------------------------------------

TEST(SuiteTiming, PassesInterleaveTheComputationsAndRepeatShortOnesUntil20msAreMeasured) {
  // Computations that report fixed times (no clock): 2^-10 s counted of 2^-9 s (the rest
  // uncounted; powers of two keep the sums exact), and 50 ms, whose CPU time says it was
  // descheduled in every other repetition.
  int calls_long = 0;
  int calls_throwing = 0;
  const double q = std::ldexp(1.0, -10);
  const std::vector<std::function<experiments::TimedRun()>> runs = {
      [q] { return experiments::TimedRun{2 * q, 2 * q, q}; },
      {},  // nothing to time
      [&] {
        ++calls_long;
        return calls_long % 2 == 1 ? experiments::TimedRun{0.050, 0.040, 0.0}
                                   : experiments::TimedRun{0.051, 0.051, 0.0};
      },
      [&]() -> experiments::TimedRun {
        ++calls_throwing;
        throw std::runtime_error("scene file vanished");
      },
  };
  std::vector<std::pair<std::size_t, std::size_t>> order;
  const experiments::TimingPolicy policy;  // 20 ms in 3 passes
  const auto t = experiments::time_in_passes(
      runs, policy, [&](std::size_t round, std::size_t i) { order.emplace_back(round, i); });
  ASSERT_EQ(t.size(), 4u);
  // Passes over all computations, not one computation at a stretch: a slow spell of the machine
  // spoils at most one pass of each. The one that threw is left out after its first pass.
  EXPECT_EQ(order, (std::vector<std::pair<std::size_t, std::size_t>>{
                       {0, 0}, {0, 2}, {0, 3}, {1, 0}, {1, 2}, {2, 0}, {2, 2}}));
  // Passes end once 20/3, 40/3 and 20 ms are measured: after 7, 14 and 21 runs of 0.98 ms.
  EXPECT_EQ(t[0].repetitions, 21u);
  EXPECT_EQ(t[0].wall_seconds_min, q);
  EXPECT_EQ(t[0].cpu_seconds_min, q);  // the uncounted part taken out of both clocks
  EXPECT_EQ(t[1].repetitions, 0u);
  // Longer than 20 ms: once per pass; CPU only from the repetitions that were not descheduled.
  EXPECT_EQ(t[2].repetitions, 3u);
  EXPECT_DOUBLE_EQ(t[2].wall_seconds_min, 0.050);
  EXPECT_DOUBLE_EQ(t[2].wall_seconds_median, 0.050);
  EXPECT_DOUBLE_EQ(t[2].cpu_seconds_min, 0.051);
  // One that throws is reported and not run again.
  EXPECT_EQ(calls_throwing, 1);
  EXPECT_EQ(t[3].error, "scene file vanished");
  EXPECT_TRUE(t[0].error.empty());
}

TEST(SuiteTiming, ThreadsTimeOneComputationEachAndPassesNeverOverlap) {
  // 6 computations on 2 threads: each waits (up to 2 s) until two of its pass run at once, so
  // the pool must run two at a time; none may see a third, and none may start before every
  // computation of the previous pass has ended.
  constexpr int kRuns = 6;
  std::mutex m;
  int running = 0;
  int most_running = 0;
  int started_early = 0;
  std::vector<int> ended_in_pass(3, 0);
  std::vector<int> calls(static_cast<std::size_t>(kRuns), 0);
  std::vector<std::function<experiments::TimedRun()>> runs;
  for (std::size_t i = 0; i < static_cast<std::size_t>(kRuns); ++i) {
    runs.push_back([&, i] {
      int pass = 0;
      {
        const std::lock_guard lock(m);
        pass = calls[i]++;
        for (int p = 0; p < pass; ++p) started_early += ended_in_pass[static_cast<std::size_t>(p)] != kRuns;
        most_running = std::max(most_running, ++running);
      }
      const auto start = std::chrono::steady_clock::now();
      for (;;) {
        {
          const std::lock_guard lock(m);
          if (most_running >= 2) break;
        }
        if (std::chrono::steady_clock::now() - start > std::chrono::seconds(2)) break;
        std::this_thread::sleep_for(std::chrono::microseconds(100));
      }
      const std::lock_guard lock(m);
      --running;
      ++ended_in_pass[static_cast<std::size_t>(pass)];
      return experiments::TimedRun{0.1, 0.1, 0.0};  // longer than 20 ms: once per pass
    });
  }
  experiments::TimingPolicy policy;
  policy.threads = 2;
  std::size_t progress_calls = 0;
  const auto t = experiments::time_in_passes(runs, policy, [&](std::size_t, std::size_t) { ++progress_calls; });
  EXPECT_EQ(most_running, 2);
  EXPECT_EQ(started_early, 0);
  EXPECT_EQ(ended_in_pass, (std::vector<int>{kRuns, kRuns, kRuns}));
  EXPECT_EQ(progress_calls, 3u * kRuns);
  for (const experiments::Timing& x : t) EXPECT_EQ(x.repetitions, 3u);
}

TEST(SuiteTiming, TimingThreadsAreAtMostTheJobsAndAtLeastOne) {
  EXPECT_EQ(experiments::timing_threads(1), 1u);
  EXPECT_EQ(experiments::timing_threads(0), 1u);
  EXPECT_LE(experiments::timing_threads(1000), std::max(1u, std::thread::hardware_concurrency()));
  EXPECT_GE(experiments::timing_threads(1000), 1u);
}

/// A timed toy case: run() takes a few milliseconds; its timed computation checks that it runs
/// after every case's run() and alone.
class TimedToyJob final : public experiments::Job {
 public:
  struct Shared {
    std::atomic<int> running{0};   // run()s in progress
    std::atomic<int> finished{0};  // run()s done
    std::atomic<int> timing{0};    // timed computations in progress
    std::atomic<int> violations{0};
    int total = 0;
    int timing_limit = 1;  // computations timed at once
    std::atomic<int> alone_timing{0};  // timed-alone computations in progress
  };
  TimedToyJob(Shared& shared, bool timed, bool alone = false) : shared_(shared), timed_(timed), alone_(alone) {}
  void validate(const fs::path&) const override {}
  experiments::JobResult run(const experiments::JobContext&) const override {
    ++shared_.running;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    --shared_.running;
    ++shared_.finished;
    return {true, "completed", "slept", {}};
  }
  bool timed() const override { return timed_; }
  bool timed_alone() const override { return alone_; }
  std::function<experiments::TimedRun()> prepare_timing(const experiments::JobContext&,
                                                        const experiments::JobResult&) const override {
    return [this] {
      if (alone_) ++shared_.alone_timing;
      const int at_once = ++shared_.timing;
      if (shared_.running != 0 || shared_.finished != shared_.total || at_once > shared_.timing_limit ||
          (shared_.alone_timing != 0 && at_once != 1)) {
        ++shared_.violations;
      }
      const auto start = std::chrono::steady_clock::now();
      const double cpu = lgvi::thread_cpu_seconds();
      while (std::chrono::steady_clock::now() - start < std::chrono::microseconds(500)) {
      }
      const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const double cpu_used = lgvi::thread_cpu_seconds() - cpu;
      --shared_.timing;
      if (alone_) --shared_.alone_timing;
      return experiments::TimedRun{wall, cpu_used, 0.0};
    };
  }
  experiments::Fields timing_fields(const experiments::Timing& t) const override {
    return {{"seconds_min", t.wall_seconds_min}, {"repetitions", static_cast<std::int64_t>(t.repetitions)}};
  }

 private:
  Shared& shared_;
  bool timed_;
  bool alone_;
};

TEST(SuiteTiming, TimedCasesAreTimedAfterEveryCaseHasRunAtMostOnePerCoreAndSomeAlone) {
  TempDir dir;
  TimedToyJob::Shared shared;
  Suite s;
  s.name = "toy";
  s.columns = {"seconds_min", "repetitions"};
  for (int i = 0; i < 8; ++i) {
    // Case 4 measures the whole process (as the soak's memory): timed alone.
    s.cases.push_back({"case" + std::to_string(i), "toy", {}, Expectation::Complete,
                       std::make_shared<TimedToyJob>(shared, i % 2 == 0, i == 4)});
  }
  shared.total = static_cast<int>(s.cases.size());
  shared.timing_limit = static_cast<int>(experiments::timing_threads(3));
  experiments::SuiteOptions options;
  options.out_dir = dir.work() / "res";
  options.jobs = 3;
  std::ostringstream progress;
  const experiments::SuiteResult r = experiments::run_suite(s, options, progress);
  EXPECT_TRUE(r.all_ok());
  EXPECT_EQ(shared.violations, 0);
  const auto rows = experiments::read_summary_csv(options.out_dir / "summary.csv");
  ASSERT_EQ(rows.size(), 8u);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (i % 2 == 0) {
      // A busy 0.5 ms per run, at least once per pass.
      EXPECT_GE(rows[i].number("seconds_min").value_or(0.0), 500e-6) << i;
      EXPECT_GE(rows[i].number("repetitions").value_or(0.0), 3.0) << i;
    } else {
      EXPECT_EQ(rows[i].text("repetitions"), "") << i;  // untimed
    }
  }
  EXPECT_NE(progress.str().find("timing 4 cases"), std::string::npos) << progress.str();
  EXPECT_NE(progress.str().find("(1 alone)"), std::string::npos) << progress.str();

  // --timing-jobs 1: one at a time, whatever the jobs.
  shared.finished = 0;
  shared.timing_limit = 1;
  options.out_dir = dir.work() / "serial";
  options.timing_jobs = 1;
  std::ostringstream serial;
  EXPECT_TRUE(experiments::run_suite(s, options, serial).all_ok());
  EXPECT_EQ(shared.violations, 0);
  EXPECT_NE(serial.str().find("timing 4 cases in 3 passes on 1 thread,"), std::string::npos) << serial.str();
}

TEST(SuiteJobs, FinalStateErrorIsTheLargestRelativeDifference) {
  const experiments::Scene scene = experiments::load_scene(default_scene_file("free-body"));
  using experiments::FreeBodyModel;
  experiments::Sample ref = experiments::sample_of<FreeBodyModel>();
  ref.t = 2.0;
  experiments::state_of<FreeBodyModel>(ref).Omega = Vec3(3.0, 0.0, 4.0);  // |Omega| = 5
  experiments::Sample s = ref;
  experiments::state_of<FreeBodyModel>(s).Omega.x() += 0.05;  // relative 0.01
  experiments::state_of<FreeBodyModel>(s).R(0, 1) = 1e-3;
  // 3.05 - 3 is 0.05 to a few ulps of 3: the tolerance is that rounding, relative to 5.
  EXPECT_NEAR(experiments::final_state_error(scene.model, s, ref), 0.01, 8 * 3.0 * 2.2e-16 / 5.0);
  experiments::state_of<FreeBodyModel>(s).R(0, 1) = 0.5;
  EXPECT_DOUBLE_EQ(experiments::final_state_error(scene.model, s, ref), 0.5);
  s.t = 1.0;  // a run that stopped early has no final-state error
  EXPECT_TRUE(std::isnan(experiments::final_state_error(scene.model, s, ref)));
}

TEST(SuiteSummary, AMalformedRowIsNamedByItsLine) {
  TempDir dir;
  write_text(dir.work() / "summary.csv", "index,case,status\n0,a,completed\n1,b\n");
  try {
    experiments::read_summary_csv(dir.work() / "summary.csv");
    ADD_FAILURE() << "no error";
  } catch (const experiments::OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("line 3 has 2 cells, the header 3"), std::string::npos) << e.what();
  }
}

// --- composed LGVIs as methods -----------------------------------------------------------------

TEST(SuiteMethods, ComposedLgvisRunFromSimulateAndConvergeAtTheirOrder) {
  // Free body over 1 s: the error against the order-6 run at h/4 falls by ~2^p when h halves.
  TempDir dir;
  auto final_row = [&](const std::string& method, const std::string& h) {
    const std::string file = method + "-" + h + ".csv";
    const CliResult r =
        run_testbed(dir, {"simulate", "free-body", "--method", method, "--h", h, "--t-final", "1", "--out", file});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    const CsvParts csv = read_csv(dir.work() / file);
    if (method != "lgvi") {
      EXPECT_EQ(csv.meta("composition"), method.substr(5));
    }
    return csv.rows.back();
  };
  const std::vector<double> ref = final_row("lgvi-kahan-li6", "0.003125");
  for (const auto& method_order : std::vector<std::pair<std::string, int>>{
           {"lgvi", 2}, {"lgvi-yoshida4", 4}, {"lgvi-suzuki4", 4}, {"lgvi-yoshida6", 6}}) {
    // (Named, not a structured binding: clang 14, the sanitizer job's compiler, does not let a
    // lambda capture a structured binding.)
    const std::string& method = method_order.first;
    const int order = method_order.second;
    auto error = [&](const std::string& h) {
      const std::vector<double> row = final_row(method, h);
      double e = 0.0;
      for (std::size_t j = 1; j <= 12; ++j) e = std::max(e, std::abs(row[j] - ref[j]));  // R, Omega
      return e;
    };
    const double ratio = error("0.05") / error("0.025");
    // Asymptotic ratio 2^p; allow a factor 1.5 either way for the pre-asymptotic range.
    EXPECT_GT(ratio, std::pow(2.0, order) / 1.5) << method;
    EXPECT_LT(ratio, std::pow(2.0, order) * 1.5) << method;
  }
}

}  // namespace
}  // namespace lgvi::test
