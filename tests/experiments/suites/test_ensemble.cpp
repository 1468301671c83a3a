// Ensembles in study files (experiments/suites/ensemble.hpp, ensemble_statistics.hpp,
// experiments/studies/README.md "[ensemble]"): the laws draw inside their ranges, a sample is the
// same whatever N, `study --sample K` re-runs sample K's rows bit for bit, a draw the scene refuses
// is a counted failure, the statistics are the quantiles of the rows, and the statistics of merged
// shards equal those of one run. A bad distribution (one error line naming the file, field and
// reason): test_study.cpp, StudyBadInput's instantiation Ensemble.
#include <algorithm>
#include <cmath>
#include <map>

#include <gtest/gtest.h>

#include "experiments/cli/cli_support.hpp"
#include "experiments/scene/scene.hpp"
#include "experiments/suites/ensemble.hpp"
#include "experiments/suites/ensemble_statistics.hpp"
#include "experiments/suites/study.hpp"
#include "lgvi/types.hpp"

namespace lgvi::test {
namespace {

/// A tiny ensemble: 4 random free bodies (attitude uniform on SO(3), |Omega| in [1, 3] rad/s in a
/// uniform direction, moments in [0.5, 2]) over 0.5 s, the LGVI at one step and Dormand-Prince
/// at one tolerance, graded against the exact solution. 8 cases.
const std::string kEnsembleStudy = R"(name = "ens"
scenes = ["free-body"]
methods = ["lgvi", { method = "odeint-dopri5", model = "quaternion" }]
horizons = [0.5]
h = [0.05]
reference = "exact"
metrics = ["final-error", "energy", "momentum"]
samples = 5
ensemble.samples = 4
ensemble.seed = 7
ensemble.attitude = "uniform"
ensemble.omega = { norm = [1.0, 3.0] }
ensemble.moments = { range = [0.5, 2.0] }
tolerances = [1e-6]
)";

std::string ensemble_with(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

experiments::Suite parse_ensemble(const std::string& text, bool quick = false, std::optional<std::size_t> sample = {}) {
  return experiments::parse_study(text, "ens.toml", {quick, experiments::default_scenes_dir(), sample});
}

/// The value of label `key` of a case (as text).
std::string case_label(const experiments::SuiteCase& c, const std::string& key) {
  for (const auto& f : c.labels) {
    if (f.key == key) return experiments::to_text(f.value);
  }
  return "";
}
double case_number(const experiments::SuiteCase& c, const std::string& key) { return std::stod(case_label(c, key)); }

TEST(Ensemble, TheLawsDrawInsideTheirRangesAndASampleIsTheSameWhateverN) {
  const experiments::Suite big = parse_ensemble(ensemble_with(kEnsembleStudy, "ensemble.samples = 4", "ensemble.samples = 300"));
  const experiments::Suite small = parse_ensemble(kEnsembleStudy);
  ASSERT_EQ(big.cases.size(), 600u);
  ASSERT_EQ(small.cases.size(), 8u);
  // The cases of a sample are contiguous, sample-major: case 2k is sample k's LGVI.
  for (std::size_t k = 0; k < 4; ++k) {
    for (const char* key : {"sample", "sample_seed", "initial.quaternion[0]", "initial.Omega[2]", "parameters.inertia[1]"}) {
      EXPECT_EQ(case_label(big.cases[2 * k], key), case_label(small.cases[2 * k], key)) << k << " " << key;
    }
  }
  EXPECT_EQ(small.cases[2].id, "free-body-s1-lgvi-h0.05");
  EXPECT_NE(case_label(big.cases[0], "sample_seed"), case_label(big.cases[2], "sample_seed"));
  double min_norm = 10.0, max_norm = 0.0, mean_z = 0.0;
  for (std::size_t k = 0; k < 300; ++k) {
    const experiments::SuiteCase& c = big.cases[2 * k];
    EXPECT_EQ(case_label(c, "sample"), std::to_string(k));
    const Eigen::Vector4d q(case_number(c, "initial.quaternion[0]"), case_number(c, "initial.quaternion[1]"),
                            case_number(c, "initial.quaternion[2]"), case_number(c, "initial.quaternion[3]"));
    EXPECT_NEAR(q.norm(), 1.0, 1e-15) << k;  // normalized in double: |q| - 1 a few ulp (2.2e-16)
    EXPECT_GE(q(0), 0.0);
    const Vec3 w(case_number(c, "initial.Omega[0]"), case_number(c, "initial.Omega[1]"), case_number(c, "initial.Omega[2]"));
    min_norm = std::min(min_norm, w.norm());
    max_norm = std::max(max_norm, w.norm());
    mean_z += w.z() / w.norm() / 300.0;
    const Vec3 J(case_number(c, "parameters.inertia[0]"), case_number(c, "parameters.inertia[1]"),
                 case_number(c, "parameters.inertia[2]"));
    for (int i = 0; i < 3; ++i) {
      EXPECT_GE(J(i), 0.5);
      EXPECT_LE(J(i), 2.0);
      EXPECT_LE(J(i), J.sum() - J(i)) << "triangle inequality, sample " << k;
    }
  }
  // |Omega| uniform in [1, 3]: 300 draws reach within 0.1 of each end (probability of missing
  // one end 0.95^300 < 1e-6); the mean of a uniform direction's z is 0 with standard deviation
  // sqrt(1/3 / 300) = 0.033: 5 of them.
  EXPECT_GE(min_norm, 1.0 - 1e-12);
  EXPECT_LE(max_norm, 3.0 + 1e-12);
  EXPECT_LT(min_norm, 1.1);
  EXPECT_GT(max_norm, 2.9);
  EXPECT_LT(std::abs(mean_z), 5 * 0.033);
}

TEST(Ensemble, SampleSeedsDependOnSeedAndIndexOnly) {
  EXPECT_EQ(experiments::sample_seed(7, 3), experiments::sample_seed(7, 3));
  EXPECT_NE(experiments::sample_seed(7, 3), experiments::sample_seed(7, 4));
  EXPECT_NE(experiments::sample_seed(7, 3), experiments::sample_seed(8, 3));
  // The recorded seed is sample_seed(seed, k).
  const experiments::Suite s = parse_ensemble(kEnsembleStudy);
  EXPECT_EQ(case_label(s.cases[6], "sample_seed"), std::to_string(experiments::sample_seed(7, 3)));
}

TEST(Ensemble, SampleOptionBuildsOnlyThatSamplesCasesWithTheSameDraws) {
  const experiments::Suite whole = parse_ensemble(kEnsembleStudy);
  const experiments::Suite one = parse_ensemble(kEnsembleStudy, false, 2);
  ASSERT_EQ(one.cases.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(one.cases[i].id, whole.cases[4 + i].id);
    ASSERT_EQ(one.cases[i].labels.size(), whole.cases[4 + i].labels.size());
    for (std::size_t f = 0; f < one.cases[i].labels.size(); ++f) {
      EXPECT_EQ(one.cases[i].labels[f].key, whole.cases[4 + i].labels[f].key);
      EXPECT_EQ(experiments::to_text(one.cases[i].labels[f].value), experiments::to_text(whole.cases[4 + i].labels[f].value));
    }
  }
}

/// The lines of a CSV without its `#` metadata.
std::vector<std::string> csv_data_lines(const fs::path& file) {
  std::vector<std::string> lines;
  for (const std::string& l : lines_of(read_text(file))) {
    if (!l.starts_with("#")) lines.push_back(l);
  }
  return lines;
}

/// A summary's rows as column -> cell, timings and the harness's wall-clock cells left out.
std::vector<std::map<std::string, std::string>> summary_rows_without_timings(const fs::path& summary) {
  const std::vector<std::string> lines = csv_data_lines(summary);
  std::vector<std::map<std::string, std::string>> rows;
  if (lines.empty()) return rows;
  const std::vector<std::string> header = split(lines.front(), ',');
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const std::vector<std::string> cells = split(lines[i], ',');
    std::map<std::string, std::string> row;
    for (std::size_t c = 0; c < header.size() && c < cells.size(); ++c) {
      const std::string& h = header[c];
      if (h == "index" || h == "detail" || h.find("seconds") != std::string::npos) continue;
      row[h] = cells[c];
    }
    rows.push_back(row);
  }
  return rows;
}

TEST(Ensemble, StudySampleKReproducesItsRowsAndCsvsBitForBit) {
  TempDir dir;
  const fs::path file = dir.scenes() / "ens.toml";
  write_text(file, kEnsembleStudy);
  const CliResult all = run_testbed(dir, {"study", file.string(), "--out", "all", "--no-plots"});
  ASSERT_EQ(all.exit_code, 0) << all.err;
  const CliResult one = run_testbed(dir, {"study", file.string(), "--sample", "2", "--out", "one", "--no-plots"});
  ASSERT_EQ(one.exit_code, 0) << one.err;
  const auto whole = summary_rows_without_timings(dir.work() / "all" / "summary.csv");
  const auto again = summary_rows_without_timings(dir.work() / "one" / "summary.csv");
  ASSERT_EQ(whole.size(), 8u);
  ASSERT_EQ(again.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(again[i], whole[4 + i]);
    EXPECT_EQ(again[i].at("sample"), "2");
    EXPECT_EQ(again[i].at("status"), "completed");
    EXPECT_FALSE(again[i].at("final_error").empty());
    const std::string csv = again[i].at("csv_path");
    EXPECT_EQ(csv_data_lines(dir.work() / "one" / csv), csv_data_lines(dir.work() / "all" / csv)) << csv;
    // The sample's seed and drawn values are in the case CSV's metadata.
    const std::string text = read_text(dir.work() / "one" / csv);
    EXPECT_NE(text.find("# sample_seed: " + std::to_string(experiments::sample_seed(7, 2))), std::string::npos);
    EXPECT_NE(text.find("# parameters.inertia[2]: "), std::string::npos);
  }
}

TEST(Ensemble, MergedShardsRenderTheStatisticsOfOneRun) {
  TempDir dir;
  const fs::path file = dir.scenes() / "ens.toml";
  write_text(file, kEnsembleStudy);
  const CliResult all = run_testbed(dir, {"study", file.string(), "--out", "all"});
  ASSERT_EQ(all.exit_code, 0) << all.err;
  for (const char* shard : {"0/3", "1/3", "2/3"}) {
    const CliResult r = run_testbed(dir, {"study", file.string(), "--shard", shard, "--out", std::string("s") + shard[0]});
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  ASSERT_EQ(run_testbed(dir, {"merge", "merged", "s0", "s1", "s2"}).exit_code, 0);
  const CliResult render = run_testbed(dir, {"study", file.string(), "--render-only", "--out", "merged"});
  ASSERT_EQ(render.exit_code, 0) << render.err;
  // Every statistic but the wall times'.
  const auto without_times = [](const fs::path& f) {
    std::vector<std::string> v;
    for (const std::string& l : csv_data_lines(f)) {
      if (l.find(",integrator_seconds") == std::string::npos) v.push_back(l);
    }
    return v;
  };
  const auto one = without_times(dir.work() / "all" / "ens-statistics.csv");
  EXPECT_EQ(without_times(dir.work() / "merged" / "ens-statistics.csv"), one);
  // 2 methods x (final error, energy, momentum, evaluations, ...): a header and rows.
  EXPECT_GT(one.size(), 6u);
  EXPECT_EQ(read_text(dir.work() / "all" / "free-body-error-bands-evaluations.png").substr(1, 3), "PNG");
  const std::string md = read_text(dir.work() / "all" / "ens-statistics.md");
  EXPECT_NE(md.find("by 95% quantile"), std::string::npos);
}

// A normal law may draw what the scene refuses (a mass <= 0): those samples' cases are
// rejected-input (the study exits 2, the others complete), counted among the failures with their
// sample numbers.
TEST(Ensemble, DrawsTheSceneRefusesAreRejectedInputAndCountedAsFailures) {
  TempDir dir;
  const fs::path file = dir.scenes() / "tops.toml";
  write_text(file, R"(name = "tops"
scenes = ["lagrange-top"]
methods = ["lgvi"]
horizons = [0.1]
h = [0.01]
metrics = ["energy"]
ensemble.samples = 12
ensemble.seed = 5
ensemble.values = { "parameters.mass" = { normal = [0.0, 1.0] } }
)");
  const CliResult r = run_testbed(dir, {"study", file.string(), "--out", "res", "--no-plots"});
  const auto rows = summary_rows_without_timings(dir.work() / "res" / "summary.csv");
  ASSERT_EQ(rows.size(), 12u) << r.err;
  std::string rejected;
  for (const auto& row : rows) {
    const bool refused = std::stod(row.at("parameters.mass")) <= 0.0;
    EXPECT_EQ(row.at("status"), refused ? "rejected-input" : "completed") << row.at("parameters.mass");
    if (refused) rejected += (rejected.empty() ? "" : " ") + row.at("sample");
  }
  EXPECT_EQ(r.exit_code, rejected.empty() ? 0 : 2) << r.err;
  std::vector<experiments::SummaryRow> summary = experiments::read_summary_csv(dir.work() / "res" / "summary.csv");
  const auto stats = experiments::ensemble_statistics(summary);
  ASSERT_FALSE(stats.empty());
  EXPECT_EQ(stats.front().failing_samples, rejected);
  const std::size_t n = rejected.empty() ? 0 : static_cast<std::size_t>(std::count(rejected.begin(), rejected.end(), ' ') + 1);
  EXPECT_EQ(stats.front().completed, 12u - n);
  EXPECT_EQ(stats.front().failures, n == 0 ? std::string() : "rejected-input: " + std::to_string(n));
}

// The bad [ensemble] tables: test_study.cpp (StudyBadInput, instantiation Ensemble).

TEST(EnsembleBadInput, SampleOutsideTheEnsembleOrWithoutOneIsNamed) {
  TempDir dir;
  const fs::path file = dir.scenes() / "ens.toml";
  write_text(file, kEnsembleStudy);
  expect_bad_input(dir, run_testbed(dir, {"study", file.string(), "--sample", "4", "--out", "res"}),
                   {"--sample", "[0, 3]", "got 4"});
  const fs::path plain = dir.scenes() / "plain.toml";
  write_text(plain, ensemble_with(kEnsembleStudy, "ensemble.samples = 4\nensemble.seed = 7\nensemble.attitude = \"uniform\"\n"
                                         "ensemble.omega = { norm = [1.0, 3.0] }\nensemble.moments = { range = [0.5, 2.0] }\n",
                         ""));
  expect_bad_input(dir, run_testbed(dir, {"study", plain.string(), "--sample", "0", "--out", "res"}),
                   {"--sample", "has no [ensemble]"});
}

TEST(EnsembleStatistics, QuantilesAreHyndmanFanDefinitionSeven) {
  // numpy.quantile([1, 2, 3, 4], p) (its default, method "linear"): 1.75, 2.5, 3.85, 1.15.
  const std::vector<double> x = {1, 2, 3, 4};
  EXPECT_DOUBLE_EQ(experiments::quantile(x, 0.25), 1.75);
  EXPECT_DOUBLE_EQ(experiments::quantile(x, 0.5), 2.5);
  EXPECT_DOUBLE_EQ(experiments::quantile(x, 0.95), 3.85);
  EXPECT_DOUBLE_EQ(experiments::quantile(x, 0.05), 1.15);
  EXPECT_DOUBLE_EQ(experiments::quantile(x, 1.0), 4.0);
  EXPECT_DOUBLE_EQ(experiments::quantile({5.0}, 0.95), 5.0);
}

TEST(EnsembleStatistics, PerMethodAndSettingOverTheCompletedSamplesWithTheFailuresListed) {
  std::vector<experiments::SummaryRow> rows;
  const auto row = [&](int sample, const char* label, const char* h, const char* status, const char* error) {
    rows.emplace_back(std::map<std::string, std::string>{{"group", "g"}, {"label", label}, {"method", label},
                                                         {"h", h}, {"status", status}, {"final_error", error},
                                                         {"sample", std::to_string(sample)}});
  };
  for (int k = 0; k < 5; ++k) {
    row(k, "a", "0.1", k == 3 ? "non-finite" : "completed", k == 3 ? "" : std::to_string(k + 1).c_str());
    row(k, "b", "0.1", "completed", "7");
  }
  const std::vector<experiments::EnsembleStatistic> stats = experiments::ensemble_statistics(rows);
  ASSERT_EQ(stats.size(), 2u);  // one metric (final_error) per block
  const experiments::EnsembleStatistic& a = stats[0];
  EXPECT_EQ(a.label, "a");
  EXPECT_EQ(a.metric, "final_error");
  EXPECT_EQ(a.samples, 5u);
  EXPECT_EQ(a.completed, 4u);
  EXPECT_EQ(a.count, 4u);
  // The completed values 1, 2, 3, 5.
  EXPECT_DOUBLE_EQ(a.median, 2.5);
  EXPECT_DOUBLE_EQ(a.q25, 1.75);
  EXPECT_DOUBLE_EQ(a.q95, 3.0 + 0.85 * 2.0);
  EXPECT_DOUBLE_EQ(a.max, 5.0);
  EXPECT_EQ(a.failures, "non-finite: 1");
  EXPECT_EQ(a.failing_samples, "3");
  EXPECT_EQ(stats[1].failures, "");
  EXPECT_DOUBLE_EQ(stats[1].q05, 7.0);
}

}  // namespace
}  // namespace lgvi::test
