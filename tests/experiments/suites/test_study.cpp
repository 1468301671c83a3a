// Study files (experiments/suites/study.hpp, experiments/studies/README.md) end to end: every kind of bad
// input is one line naming the study file, the field and the reason with nothing written; a tiny
// study lists its cases, runs them (one summary row per case, graded against the exact
// solution at the order of the method), and its shards' union is the whole; the shipped studies
// load, and the work-precision and long-horizon suites are the shipped study files' cases.
#include <algorithm>
#include <cmath>
#include <map>

#include <gtest/gtest.h>

#include "experiments/cli/cli_support.hpp"
#include "experiments/systems/exact_reference.hpp"
#include "experiments/scene/scene.hpp"
#include "experiments/suites/study.hpp"
#include "experiments/suites/jobs.hpp"

namespace lgvi::test {
namespace {

/// A tiny study: the free body over 1 s (|Omega0| = 3 rad/s) with the LGVI of order 2 and 4 at
/// two steps and CVODE BDF at one tolerance, graded against the exact solution. 5 cases.
const std::string kTinyStudy = R"(name = "tiny"
scenes = ["free-body"]
methods = ["lgvi", "lgvi-yoshida4", { method = "cvode-bdf", model = "quaternion" }]
horizons = [1.0]
h = [0.01, 0.005]
tolerances = [1e-8]
reference = "exact"
metrics = ["final-error", "energy"]
samples = 10
)";

const std::vector<std::string> kTinyCases = {
    "free-body-lgvi-h0.01",          "free-body-lgvi-h0.005", "free-body-lgvi-yoshida4-h0.01",
    "free-body-lgvi-yoshida4-h0.005", "free-body-cvode-bdf-quaternion-rtol1e-08"};

/// kTinyStudy (or `text`) with the first occurrence of `from` replaced by `to` (which must exist).
std::string tiny_with(const std::string& from, const std::string& to, std::string text = kTinyStudy) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

struct BadStudy {
  const char* what;
  std::string text;
  std::vector<std::string> needles;  ///< the field and the reason the error line must name
  bool quick = false;
};

class StudyBadInput : public ::testing::TestWithParam<BadStudy> {};

TEST_P(StudyBadInput, ExitsOneWithOneLineNamingFileFieldAndReasonAndWritesNothing) {
  const BadStudy& b = GetParam();
  TempDir dir;
  const fs::path file = dir.scenes() / "bad-study.toml";
  write_text(file, b.text);
  std::vector<std::string> args = {"study", file.string(), "--out", "res"};
  if (b.quick) args.push_back("--quick");
  std::vector<std::string> needles = b.needles;
  needles.push_back(file.string());
  expect_bad_input(dir, run_testbed(dir, args), needles);
  // --list validates the same way.
  args.push_back("--list");
  expect_bad_input(dir, run_testbed(dir, args), needles);
}

INSTANTIATE_TEST_SUITE_P(
    All, StudyBadInput,
    ::testing::Values(
        BadStudy{"unknown_method", tiny_with("\"lgvi-yoshida4\"", "\"lgvi-yoshida5\""),
                 {"methods[1]", "unknown method 'lgvi-yoshida5'", "lgvi-kahan-li6"}},
        BadStudy{"unknown_model", tiny_with("model = \"quaternion\"", "model = \"quaternions\""),
                 {"methods[2].model", "quaternions"}},
        BadStudy{"model_on_the_lgvi", tiny_with("\"lgvi\",", "{ method = \"lgvi\", model = \"matrix\" },"),
                 {"methods[0].model", "no coordinate model"}},
        BadStudy{"method_listed_twice", tiny_with("\"lgvi-yoshida4\"", "\"lgvi\""), {"methods[1]", "twice"}},
        BadStudy{"unknown_trait", tiny_with("\"lgvi-yoshida4\"", "{ where = \"on_group and not varitional\" }"),
                 {"methods[1].where", "unknown trait 'varitional'", "stays_on_group"}},
        BadStudy{"trait_query_matches_nothing", tiny_with("\"lgvi-yoshida4\"", "{ where = \"adaptive and fixed_step\" }"),
                 {"methods[1].where", "matches no method"}},
        BadStudy{"trait_query_with_a_method", tiny_with("\"lgvi-yoshida4\"", "{ where = \"on_group\", method = \"lgvi\" }"),
                 {"methods[1].method", "does not go with 'where'"}},
        BadStudy{"trait_query_repeats_a_method", tiny_with("\"lgvi-yoshida4\"", "{ where = \"variational\" }"),
                 {"methods[1]", "lists lgvi twice"}},
        BadStudy{"no_methods", tiny_with("methods = [\"lgvi\", \"lgvi-yoshida4\", { method = \"cvode-bdf\", model = "
                                         "\"quaternion\" }]",
                                         "methods = []"),
                 {"methods", "empty sweep"}},
        BadStudy{"unknown_scene", tiny_with("\"free-body\"", "\"free-bdy\""),
                 {"scenes[0]", "'free-bdy'", "unknown scene", "pendulum"}},
        BadStudy{"missing_scene_file", tiny_with("\"free-body\"", "\"nowhere/my.toml\""),
                 {"nowhere/my.toml", "cannot read the scene file"}},
        BadStudy{"scene_key_typo", tiny_with("\"free-body\"", "{ scene = \"free-body\", horizon = [1.0] }"),
                 {"scenes[0].horizon", "unknown key"}},
        BadStudy{"empty_h_sweep", tiny_with("h = [0.01, 0.005]", "h = []"), {"h", "empty sweep"}},
        BadStudy{"empty_tolerances", tiny_with("tolerances = [1e-8]", "tolerances = []"),
                 {"tolerances", "empty sweep"}},
        BadStudy{"negative_h", tiny_with("h = [0.01, 0.005]", "h = [0.01, -0.005]"), {"h[1]", "must be > 0"}},
        BadStudy{"zero_h", tiny_with("h = [0.01, 0.005]", "h = [0.0]"), {"h[0]", "must be > 0"}},
        // The adaptive methods' one range (baselines/tolerance.hpp), as `simulate --rtol` checks it.
        BadStudy{"zero_rtol", tiny_with("tolerances = [1e-8]", "tolerances = [0.0]"),
                 {"tolerances[0]", "must be a number in [1e-14, 0.1] (got 0)"}},
        BadStudy{"rtol_too_large", tiny_with("tolerances = [1e-8]", "tolerances = [0.5]"),
                 {"tolerances[0]", "[1e-14, 0.1]", "(got 0.5)"}},
        BadStudy{"rtol_below_round_off", tiny_with("tolerances = [1e-8]", "tolerances = [1e-8, 1e-300]"),
                 {"tolerances[1]", "below round-off", "(got 1e-300)"}},
        BadStudy{"reference_rtol_below_round_off",
                 tiny_with("reference = \"exact\"", "reference = { method = \"gsl-rk8pd\", rtol = 1e-16 }"),
                 {"reference.rtol", "below round-off", "[1e-14, 0.1]"}},
        BadStudy{"zero_steps", tiny_with("h = [0.01, 0.005]", "steps = [100, 0]"), {"steps[1]", "integer >= 1"}},
        BadStudy{"h_and_steps", tiny_with("h = [0.01, 0.005]", "h = [0.01]\nsteps = [100]"), {"steps", "not both"}},
        BadStudy{"horizon_not_whole_steps", tiny_with("h = [0.01, 0.005]", "h = [0.3]"),
                 {"h", "horizon T = 1", "h = 0.3", "whole number of steps"}},
        BadStudy{"negative_horizon", tiny_with("horizons = [1.0]", "horizons = [-1.0]"), {"horizons[0]", "must be > 0"}},
        BadStudy{"unknown_metric", tiny_with("\"energy\"]", "\"energy\", \"speed\"]"),
                 {"metrics[2]", "unknown metric 'speed'", "orthogonality"}},
        BadStudy{"final_error_without_reference", tiny_with("reference = \"exact\"", "reference = \"none\""),
                 {"metrics", "final-error needs a reference"}},
        BadStudy{"unknown_reference", tiny_with("reference = \"exact\"", "reference = \"perfect\""),
                 {"reference", "unknown reference 'perfect'"}},
        BadStudy{"exact_reference_without_exact_solution", tiny_with("\"free-body\"", "\"pendulum\""),
                 {"reference", "exact", "scene 'pendulum'", "no exact solution"}},
        BadStudy{"reference_run_without_step",
                 tiny_with("reference = \"exact\"", "reference = { method = \"lgvi-kahan-li6\" }"),
                 {"reference.h", "is required"}},
        BadStudy{"reference_run_unknown_method",
                 tiny_with("reference = \"exact\"", "reference = { method = \"rk45\", h = 1e-3 }"),
                 {"reference.method", "unknown method 'rk45'"}},
        BadStudy{"adaptive_without_tolerances", tiny_with("tolerances = [1e-8]\n", ""),
                 {"tolerances", "is required", "cvode-bdf"}},
        BadStudy{"unknown_top_key", tiny_with("samples = 10", "sample = 10"), {"sample", "unknown key"}},
        BadStudy{"zero_samples", tiny_with("samples = 10", "samples = 0"),
                 {"samples", "must be an integer in [1, 10000000] (got 0)", "rows written per fixed-step run"}},
        // N14: what adaptive_samples is for and what it allows, in its own name (a grid of
        // 10^13 intervals was refused naming the scene file's integration.t_final).
        BadStudy{"zero_adaptive_samples", tiny_with("samples = 10", "samples = 10\nadaptive_samples = 0"),
                 {"adaptive_samples", "must be an integer in [1, 10000000] (got 0)", "adaptive runs' output grid"}},
        BadStudy{"huge_adaptive_samples", tiny_with("samples = 10", "samples = 10\nadaptive_samples = 10000000000000"),
                 {"adaptive_samples", "[1, 10000000]", "(got 1e13)"}},
        BadStudy{"float_adaptive_samples", tiny_with("samples = 10", "samples = 10\nadaptive_samples = 2.5"),
                 {"adaptive_samples", "must be an integer (got a float)"}},
        BadStudy{"negative_probes", tiny_with("samples = 10", "samples = 10\nprobes = -1"),
                 {"probes", "[0, 1000]", "probes"}},
        BadStudy{"malformed_toml", tiny_with("h = [0.01, 0.005]", "h = [0.01,, 0.005]"), {"line 5, column"}},
        BadStudy{"bad_quick_value", kTinyStudy + "[quick]\ntolerances = [-1e-6]\n",
                 {"quick.tolerances[0]", "[1e-14, 0.1]"}, true},
        BadStudy{"unknown_quick_key", kTinyStudy + "[quick]\nname = \"x\"\n", {"quick.name", "unknown key"}}),
    [](const ::testing::TestParamInfo<BadStudy>& info) { return std::string(info.param.what); });

/// kTinyStudy as an ensemble of 4 random free bodies (experiments/studies/README.md, "The
/// ensemble table"; the ensembles' runs: test_ensemble.cpp).
const std::string kTinyEnsemble = kTinyStudy +
                                  "ensemble.samples = 4\nensemble.seed = 7\nensemble.attitude = \"uniform\"\n"
                                  "ensemble.omega = { norm = [1.0, 3.0] }\nensemble.moments = { range = [0.5, 2.0] }\n";
/// kTinyEnsemble on another scene, graded against nothing.
std::string tiny_ensemble_of(const std::string& scene) {
  return tiny_with("scenes = [\"free-body\"]", "scenes = [\"" + scene + "\"]",
                   tiny_with("reference = \"exact\"\nmetrics = [\"final-error\", \"energy\"]", "metrics = [\"energy\"]",
                             kTinyEnsemble));
}

INSTANTIATE_TEST_SUITE_P(
    Ensemble, StudyBadInput,
    ::testing::Values(
        BadStudy{"no_samples", tiny_with("ensemble.samples = 4", "ensemble.samples = 0", kTinyEnsemble),
                 {"ensemble.samples", "[1, 10000000]"}},
        BadStudy{"no_seed", tiny_with("ensemble.seed = 7\n", "", kTinyEnsemble), {"ensemble.seed", "is required"}},
        BadStudy{"empty_range", tiny_with("norm = [1.0, 3.0]", "norm = [3.0, 1.0]", kTinyEnsemble),
                 {"ensemble.omega.norm", "empty range"}},
        BadStudy{"negative_spread",
                 tiny_with("ensemble.attitude = \"uniform\"",
                           "ensemble.attitude = { law = \"about-nominal\", spread = -0.1 }", kTinyEnsemble),
                 {"ensemble.attitude.spread", "negative spread"}},
        BadStudy{"negative_standard_deviation",
                 tiny_with("ensemble.omega = { norm = [1.0, 3.0] }",
                           "ensemble.values = { \"initial.Omega[2]\" = { normal = [3.0, -1.0] } }", kTinyEnsemble),
                 {"ensemble.values.\"initial.Omega[2]\".normal[1]", "negative spread"}},
        BadStudy{"unknown_law", tiny_with("\"uniform\"", "\"gaussian\"", kTinyEnsemble),
                 {"ensemble.attitude", "unknown law 'gaussian'"}},
        BadStudy{"non_positive_moments", tiny_with("range = [0.5, 2.0]", "range = [0.0, 2.0]", kTinyEnsemble),
                 {"ensemble.moments.range[0]", "must be > 0"}},
        BadStudy{"moments_of_a_system_without_them", tiny_ensemble_of("dumbbell"),
                 {"ensemble.moments", "dumbbell", "no [parameters] inertia"}},
        BadStudy{"attitude_of_a_system_without_one",
                 tiny_with("ensemble.moments = { range = [0.5, 2.0] }\n", "", tiny_ensemble_of("connected-bodies")),
                 {"ensemble.attitude", "connected-bodies", "cannot take it"}},
        BadStudy{"a_value_the_scene_file_does_not_give",
                 kTinyEnsemble + "ensemble.values = { \"parameters.mass\" = { uniform = [1.0, 2.0] } }\n",
                 {"ensemble.values.\"parameters.mass\"", "has no number at parameters.mass"}},
        BadStudy{"a_value_drawn_twice",
                 kTinyEnsemble + "ensemble.values = { \"initial.Omega[0]\" = { uniform = [1.0, 2.0] } }\n",
                 {"ensemble.values.\"initial.Omega[0]\"", "is drawn by ensemble.omega already"}},
        BadStudy{"unknown_key", kTinyEnsemble + "ensemble.sample = 3\n", {"ensemble.sample", "unknown key"}},
        BadStudy{"quick_samples", kTinyEnsemble + "quick.ensemble.samples = -1\n",
                 {"quick.ensemble.samples", "[1, 10000000]"}, true}),
    [](const ::testing::TestParamInfo<BadStudy>& info) { return std::string(info.param.what); });

TEST(StudyBadInput, AMissingStudyFileIsNamed) {
  TempDir dir;
  expect_bad_input(dir, run_testbed(dir, {"study", "./no-such-study.toml", "--out", "res"}),
                   {"./no-such-study.toml", "cannot read the study file"});
}

/// The lines of a summary.csv after its metadata: header first.
std::vector<std::string> summary_table(const fs::path& file) {
  std::vector<std::string> lines = lines_of(read_text(file));
  lines.erase(lines.begin(), std::find_if(lines.begin(), lines.end(), [](const std::string& l) { return !l.starts_with("#"); }));
  return lines;
}

/// The cells of `column` in a summary table (header first).
std::vector<std::string> column_of(const std::vector<std::string>& table, const std::string& column) {
  std::vector<std::string> cells;
  if (table.empty()) return cells;
  const std::vector<std::string> header = split(table.front(), ',');
  const auto at = static_cast<std::size_t>(std::find(header.begin(), header.end(), column) - header.begin());
  EXPECT_LT(at, header.size()) << column;
  for (std::size_t i = 1; i < table.size(); ++i) {
    const std::vector<std::string> cells_of_row = split(table[i], ',');
    cells.push_back(at < cells_of_row.size() ? cells_of_row[at] : "");
  }
  return cells;
}

TEST(StudyRun, ListPrintsTheCasesInOrder) {
  TempDir dir;
  const fs::path file = dir.scenes() / "tiny.toml";
  write_text(file, kTinyStudy);
  const CliResult r = run_testbed(dir, {"study", file.string(), "--list"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(lines_of(r.out), kTinyCases);
  EXPECT_TRUE(dir.work_entries().empty());
}

TEST(StudyRun, ATinyStudyRunsEveryCaseAgainstTheExactSolutionAndDrawsItsFigures) {
  TempDir dir;
  const fs::path file = dir.scenes() / "tiny.toml";
  write_text(file, kTinyStudy);
  const CliResult r = run_testbed(dir, {"study", file.string(), "--out", "res", "--jobs", "2"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<std::string> table = summary_table(dir.work() / "res" / "summary.csv");
  ASSERT_EQ(table.size(), kTinyCases.size() + 1);  // header + one row per case
  EXPECT_EQ(column_of(table, "case"), kTinyCases);
  for (const std::string& status : column_of(table, "status")) EXPECT_EQ(status, "completed");
  // The exact solution's description, its comma written as ';' in the CSV cell.
  for (const std::string& reference : column_of(table, "reference")) {
    EXPECT_TRUE(reference.starts_with("exact (closed form")) << reference;
  }
  const std::vector<std::string> errors = column_of(table, "final_error");
  ASSERT_EQ(errors.size(), 5u);
  // Graded against the exact solution, halving h divides the LGVI's final error by 2^p (p = 2,
  // 4); +-25% leaves room for the next term of the error expansion at h |Omega0| = 0.03.
  const double order2 = std::stod(errors[0]) / std::stod(errors[1]);
  const double order4 = std::stod(errors[2]) / std::stod(errors[3]);
  EXPECT_NEAR(order2, 4.0, 1.0) << errors[0] << " " << errors[1];
  EXPECT_NEAR(order4, 16.0, 4.0) << errors[2] << " " << errors[3];
  const std::string csv = read_text(dir.work() / "res" / "summary.csv");
  EXPECT_NE(csv.find("# suite: tiny"), std::string::npos);
  for (const char* png : {"free-body-error-evaluations.png", "free-body-energy-evaluations.png"}) {
    EXPECT_EQ(read_text(dir.work() / "res" / png).substr(1, 3), "PNG") << png;
  }
  EXPECT_TRUE(fs::exists(dir.work() / "res" / "tiny-table.md"));
  // The energy error over time of each method's finest run beside the work-precision figures;
  // not the momentum map's or orthogonality's, which the metrics do not name.
  EXPECT_EQ(read_text(dir.work() / "res" / "free-body-energy-over-time.png").substr(1, 3), "PNG");
  EXPECT_FALSE(fs::exists(dir.work() / "res" / "free-body-momentum-over-time.png"));
  EXPECT_FALSE(fs::exists(dir.work() / "res" / "free-body-orthogonality-over-time.png"));
  // No "time" metric: nothing timed serially, no timing columns.
  EXPECT_EQ(table.front().find("integrator_seconds_min"), std::string::npos);
}

// reference = "exact-or-none": the free body is graded against its closed form (final error and
// the phase fit), the pendulum (no closed form at its state) against nothing; every case has its
// energy trend. A symmetric method's error over 2 s of the free body is mostly a time shift: the
// shape error left after the fitted shift is below the final error.
TEST(StudyRun, ExactOrNoneGradesWhereAClosedFormExistsAndFitsThePhase) {
  TempDir dir;
  const fs::path file = dir.scenes() / "mixed.toml";
  write_text(file, R"(name = "mixed"
scenes = ["free-body", "pendulum"]
methods = ["lgvi"]
horizons = [2.0]
h = [0.01]
reference = "exact-or-none"
metrics = ["energy"]
samples = 20
)");
  const CliResult r = run_testbed(dir, {"study", file.string(), "--out", "res"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<std::string> table = summary_table(dir.work() / "res" / "summary.csv");
  ASSERT_EQ(table.size(), 3u);
  EXPECT_EQ(column_of(table, "case"), (std::vector<std::string>{"free-body-lgvi-h0.01", "pendulum-lgvi-h0.01"}));
  const std::vector<std::string> reference = column_of(table, "reference");
  EXPECT_TRUE(reference[0].starts_with("exact (closed form")) << reference[0];
  EXPECT_EQ(reference[1], "");
  const std::vector<std::string> final_error = column_of(table, "final_error");
  const std::vector<std::string> shape = column_of(table, "shape_error");
  const std::vector<std::string> shift = column_of(table, "phase_shift");
  ASSERT_FALSE(shape[0].empty());
  EXPECT_LT(std::stod(shape[0]), std::stod(final_error[0]));
  EXPECT_LT(std::abs(std::stod(shift[0])), 1e-3);  // h^2 |Omega|^2 t ~ 2e-3 s at most
  EXPECT_EQ(final_error[1], "");
  EXPECT_EQ(shift[1], "");
  for (const std::string& trend : column_of(table, "energy_trend")) EXPECT_EQ(trend, "bounded");
}

TEST(StudyRun, ScenePathsAreRelativeToTheStudyFileAndNamedByTheirStem) {
  TempDir dir;
  write_text(dir.scenes() / "my-body.toml", edited_scene("free-body", "t_final = 50.0", "t_final = 0.5"));
  const fs::path file = dir.scenes() / "mine.toml";
  write_text(file, "scenes = [\"my-body.toml\"]\nmethods = [\"lgvi\"]\nreference = \"none\"\n");
  const CliResult r = run_testbed(dir, {"study", file.string(), "--out", "res", "--no-plots"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<std::string> table = summary_table(dir.work() / "res" / "summary.csv");
  ASSERT_EQ(table.size(), 2u);
  // The scene's own h (0.005) and horizon (0.5) without a sweep; named after the file.
  EXPECT_EQ(column_of(table, "case"), std::vector<std::string>{"my-body-lgvi-h0.005"});
  EXPECT_EQ(column_of(table, "scene"), std::vector<std::string>{"my-body"});
  EXPECT_EQ(column_of(table, "t_final"), std::vector<std::string>{"0.5"});
  EXPECT_EQ(read_text(dir.work() / "res" / "summary.csv").find(dir.scenes().string()), std::string::npos)
      << "the summary names the scene, not the machine's path";
}

// --resume continues only the run of the same study file and the same scene files: an edit
// to either (even one that leaves the case ids alone) is refused, naming the file.
TEST(StudyRun, ResumeRefusesAnEditedStudyOrSceneFile) {
  TempDir dir;
  const std::string scene = edited_scene("free-body", "t_final = 50.0", "t_final = 0.5");
  write_text(dir.scenes() / "my-body.toml", scene);
  const fs::path file = dir.scenes() / "mine.toml";
  const std::string study = "scenes = [\"my-body.toml\"]\nmethods = [\"lgvi\"]\nreference = \"none\"\n";
  write_text(file, study);
  const std::vector<std::string> resume = {"study", file.string(), "--out", "res", "--no-plots", "--resume"};
  ASSERT_EQ(run_testbed(dir, {"study", file.string(), "--out", "res", "--no-plots"}).exit_code, 0);
  // The same files: resumed (the finished case kept).
  const CliResult same = run_testbed(dir, resume);
  EXPECT_EQ(same.exit_code, 0) << same.err;

  write_text(file, study + "description = \"edited\"\n");
  const CliResult edited_study = run_testbed(dir, resume);
  EXPECT_NE(edited_study.exit_code, 0);
  EXPECT_NE(edited_study.err.find("the study file mine.toml with other contents"), std::string::npos)
      << edited_study.err;

  write_text(file, study);
  write_text(dir.scenes() / "my-body.toml", scene + "# edited\n");
  const CliResult edited_scene_file = run_testbed(dir, resume);
  EXPECT_NE(edited_scene_file.exit_code, 0);
  EXPECT_NE(edited_scene_file.err.find("the scene file my-body.toml with other contents"), std::string::npos)
      << edited_scene_file.err;
}

// A scene's control samples (a piecewise-linear [control]'s CSV) are part of what the run
// computed: an edit to them is refused on --resume like an edit to the scene file.
TEST(StudyRun, ResumeRefusesEditedControlSamples) {
  TempDir dir;
  write_text(dir.scenes() / "driven.toml", edited_scene("pendulum", "t_final = 20.0", "t_final = 0.1") +
                                               "\n[control]\ntype = \"piecewise-linear\"\nfile = \"u.csv\"\n");
  write_text(dir.scenes() / "u.csv", "t,u1,u2,u3\n0,0,0,0\n1,0.1,0,0\n");
  const fs::path file = dir.scenes() / "mine.toml";
  write_text(file, "scenes = [\"driven.toml\"]\nmethods = [\"lgvi\"]\nreference = \"none\"\n");
  const std::vector<std::string> resume = {"study", file.string(), "--out", "res", "--no-plots", "--resume"};
  const CliResult first = run_testbed(dir, {"study", file.string(), "--out", "res", "--no-plots"});
  ASSERT_EQ(first.exit_code, 0) << first.err;
  const CliResult same = run_testbed(dir, resume);
  EXPECT_EQ(same.exit_code, 0) << same.err;
  write_text(dir.scenes() / "u.csv", "t,u1,u2,u3\n0,0,0,0\n1,0.2,0,0\n");
  const CliResult edited = run_testbed(dir, resume);
  EXPECT_NE(edited.exit_code, 0);
  EXPECT_NE(edited.err.find("the control samples file u.csv with other contents"), std::string::npos) << edited.err;
}

TEST(StudyRun, TheShardsUnionIsTheWholeStudy) {
  TempDir dir;
  const fs::path file = dir.scenes() / "tiny.toml";
  write_text(file, kTinyStudy);
  std::vector<std::string> listed;
  for (const char* shard : {"0/3", "1/3", "2/3"}) {
    const CliResult r = run_testbed(dir, {"study", file.string(), "--list", "--shard", shard});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    for (const std::string& id : lines_of(r.out)) listed.push_back(id);
  }
  EXPECT_EQ(listed, kTinyCases);
  // Run as two shards: their summaries' rows concatenate to every case, each once.
  std::vector<std::string> ran;
  for (const char* shard : {"0/2", "1/2"}) {
    const std::string out = std::string("shard") + shard[0];
    const CliResult r = run_testbed(dir, {"study", file.string(), "--shard", shard, "--out", out});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    for (const std::string& line : lines_of(read_text(dir.work() / out / "summary.csv"))) {
      if (line.starts_with("#") || line.starts_with("index,")) continue;
      ran.push_back(split(line, ',')[1]);
    }
  }
  EXPECT_EQ(ran, kTinyCases);
}

// --- the shipped studies -------------------------------------------------------------------------

std::vector<std::string> ids(const experiments::Suite& s) {
  std::vector<std::string> v;
  for (const auto& c : s.cases) v.push_back(c.id);
  return v;
}

TEST(StudyShipped, EveryShippedStudyLoadsInBothForms) {
  for (const auto& entry : fs::directory_iterator(experiments::default_studies_dir())) {
    if (entry.path().extension() != ".toml") continue;
    for (const bool quick : {true, false}) {
      const experiments::Suite s =
          experiments::load_study(entry.path(), {quick, experiments::default_scenes_dir()});
      EXPECT_FALSE(s.cases.empty()) << entry.path();
    }
  }
}

// The shipped work-precision and long-horizon studies select the Lie group methods by trait
// ({ where = "on_group and not variational" }): every registered method with those traits has
// cases in both forms of both studies, fixed-step ones by h or steps and adaptive ones by rtol.
TEST(StudyShipped, TheComparisonStudiesTakeEveryOtherMethodOnTheGroupByTrait) {
  const auto picked = experiments::methods_matching("on_group and not variational");
  ASSERT_FALSE(picked.empty());
  for (const char* name : {"work-precision", "long-horizon"}) {
    for (const bool quick : {false, true}) {
      const experiments::Suite s = experiments::load_study(
          experiments::default_studies_dir() / (std::string(name) + ".toml"), {quick, experiments::default_scenes_dir()});
      for (const experiments::MethodInfo* info : picked) {
        // Case ids end in -h<h> or -n<steps> (fixed step), -rtol<rtol> (adaptive).
        const std::vector<std::string> tags =
            info->fixed_step() ? std::vector<std::string>{"-h", "-n"} : std::vector<std::string>{"-rtol"};
        const bool found = std::any_of(s.cases.begin(), s.cases.end(), [&](const experiments::SuiteCase& c) {
          return std::any_of(tags.begin(), tags.end(), [&](const std::string& tag) {
            return c.id.find("-" + info->name + tag) != std::string::npos;
          });
        });
        EXPECT_TRUE(found) << name << (quick ? " --quick" : "") << ": no case of " << info->name;
      }
    }
  }
}

TEST(StudyShipped, TheWorkPrecisionAndLongHorizonSuitesAreTheirStudyFiles) {
  for (const char* name : {"work-precision", "long-horizon"}) {
    for (const bool quick : {true, false}) {
      const experiments::SuiteParams params{quick, experiments::default_scenes_dir()};
      const experiments::Suite suite = experiments::make_suite(name, params);
      const experiments::Suite study =
          experiments::load_study(experiments::default_studies_dir() / (std::string(name) + ".toml"), params);
      EXPECT_EQ(ids(suite), ids(study)) << name;
      EXPECT_EQ(suite.columns, study.columns) << name;
    }
  }
}

TEST(StudyShipped, SpacecraftTumbleComparesTheLgviOrdersWithTheBaselinesAgainstTheExactSolution) {
  const experiments::SuiteParams params{false, experiments::default_scenes_dir()};
  const experiments::Suite s =
      experiments::load_study(experiments::default_studies_dir() / "spacecraft-tumble.toml", params);
  std::map<std::string, std::size_t> sweep;  // method label -> points
  for (const auto& c : s.cases) {
    const auto* job = dynamic_cast<const experiments::SimulateJob*>(c.job.get());
    ASSERT_NE(job, nullptr);
    EXPECT_EQ(*job->spec().overrides.t_final, 1e4) << c.id;
    EXPECT_TRUE(job->spec().timed) << c.id;
    for (const auto& f : c.labels) {
      if (f.key == "label") ++sweep[std::get<std::string>(f.value)];
    }
  }
  for (const char* m : {"LGVI order 2", "LGVI order 4 (yoshida4)", "LGVI order 6 (kahan-li6)", "cvode-bdf (quaternion)",
                        "odeint-dopri5 (quaternion)", "gsl-rk8pd (quaternion)"}) {
    EXPECT_GE(sweep[m], 4u) << m;
  }
  // The scene: J = diag(1200, 900, 600) kg m^2, spun about the intermediate axis, 10^4 s.
  const experiments::Scene scene = experiments::load_scene(experiments::default_scenes_dir() / "spacecraft-tumble.toml");
  EXPECT_EQ(scene.horizon.t_final, 1e4);
  EXPECT_EQ(std::string(scene.system()), "free-body");
}

}  // namespace
}  // namespace lgvi::test
