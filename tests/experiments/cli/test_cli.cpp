// lgvi-testbed end to end: error paths (exit 1, exactly one stderr line naming the field, no
// file left), successful runs (metadata, header, row counts), a failed rotation update (exit 2,
// CSV up to the last good step), scenes, suite.
#include <algorithm>
#include <cmath>
#include <numeric>

#include <gtest/gtest.h>

#include "experiments/cli/cli_support.hpp"

namespace lgvi::test {
namespace {

struct BadFile {
  const char* what;
  const char* scene;
  const char* from;
  const char* to;
  std::vector<std::string> needles;  ///< the field (and reason) the error line must name
};

class CliBadSceneFile : public ::testing::TestWithParam<BadFile> {};

TEST_P(CliBadSceneFile, ExitsOneWithOneLineAndNoOutput) {
  const BadFile& b = GetParam();
  TempDir dir;
  const fs::path file = dir.scenes() / "bad.toml";
  write_text(file, edited_scene(b.scene, b.from, b.to));
  // Default output name (bad.csv in the working directory) and an explicit one.
  for (const std::vector<std::string>& extra : {std::vector<std::string>{}, {"--out", "out.csv"}}) {
    std::vector<std::string> args = {"simulate", file.string()};
    args.insert(args.end(), extra.begin(), extra.end());
    std::vector<std::string> needles = b.needles;
    needles.push_back(file.string());
    expect_bad_input(dir, run_testbed(dir, args), needles);
  }
}

INSTANTIATE_TEST_SUITE_P(
    All, CliBadSceneFile,
    ::testing::Values(
        BadFile{"malformed_toml", "pendulum", "mass = 1.0", "mass = = 1.0", {"line ", "column "}},
        BadFile{"unknown_key", "pendulum", "gravity =", "gravty =", {"parameters.gravty", "unknown key"}},
        BadFile{"h_zero", "pendulum", "h = 1e-3", "h = 0", {"integration.h", "> 0"}},
        BadFile{"h_negative", "pendulum", "h = 1e-3", "h = -0.001", {"integration.h", "> 0"}},
        BadFile{"t_final_not_multiple", "pendulum", "t_final = 20.0", "t_final = 20.0005",
                {"integration.t_final", "whole number of steps"}},
        BadFile{"inertia_not_spd", "pendulum", "inertia = [0.13, 0.28, 0.17]",
                "inertia = [[1, 2, 0], [2, 1, 0], [0, 0, 1]]", {"parameters.inertia", "positive definite"}},
        BadFile{"inertia_triangle", "free-body", "inertia = [0.13, 0.28, 0.17]", "inertia = [0.1, 0.1, 0.5]",
                {"parameters.inertia", "triangle inequality"}},
        BadFile{"R_not_orthonormal", "pendulum", "R = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]",
                "R = [[1, 0, 0], [0, 1, 0.2], [0, 0, 1]]", {"initial.R", "rotation"}},
        BadFile{"nan_value", "pendulum", "Omega = [4.14, 4.14, 4.14]", "Omega = [4.14, 4.14, nan]",
                {"initial.Omega", "finite"}},
        BadFile{"wrong_shape", "pendulum", "rho = [0.0, 0.0, 0.3]", "rho = [[0.0, 0.0, 0.3]]",
                {"parameters.rho", "array of 3 numbers"}},
        BadFile{"wrong_type", "dumbbell", "mu = 1.0", "mu = true", {"parameters.mu", "must be a number"}},
        BadFile{"bad_form_in_file", "pendulum", "\"symmetric\"", "\"implicit\"", {"integration.form"}},
        BadFile{"cart_q_wrong_shape", "cart-pendulum", "q = [0.0, 0.0]", "q = [0.0, 0.0, 0.0]",
                {"initial.q", "array of 2 numbers"}},
        BadFile{"cart_mass_negative", "cart-pendulum", "cart_mass = 1.0", "cart_mass = -1.0",
                {"parameters.cart_mass", "> 0"}},
        BadFile{"bodies_inertia_not_symmetric", "connected-bodies", "[0.32, 1.88, -0.06]", "[0.33, 1.88, -0.06]",
                {"parameters.inertia1", "not symmetric"}},
        BadFile{"bodies_unknown_key", "connected-bodies", "d2 =", "d3 =", {"parameters.d3", "unknown key"}}),
    [](const ::testing::TestParamInfo<BadFile>& info) { return std::string(info.param.what); });

struct BadArgs {
  const char* what;
  std::vector<std::string> args;
  std::vector<std::string> needles;
};

class CliBadArguments : public ::testing::TestWithParam<BadArgs> {};

TEST_P(CliBadArguments, ExitOneWithOneLineAndNoOutput) {
  TempDir dir;
  expect_bad_input(dir, run_testbed(dir, GetParam().args), GetParam().needles);
}

INSTANTIATE_TEST_SUITE_P(
    All, CliBadArguments,
    ::testing::Values(
        // Options out of their stated ranges, and options of the other ocp method: rejected
        // (they used to mean "the default" silently, end in std::bad_alloc, or be ignored).
        BadArgs{"ocp_h_zero", {"ocp", "pendulum", "--h", "0"}, {"--h", "(0, 1e100]"}},
        BadArgs{"ocp_steps_zero", {"ocp", "pendulum", "--steps", "0"}, {"--steps", "[1, 1000000]"}},
        BadArgs{"ocp_steps_huge", {"ocp", "pendulum", "--steps", "1e8"}, {"--steps", "[1, 1000000]"}},
        BadArgs{"ocp_t_final_zero", {"ocp", "dumbbell", "--t-final", "0"}, {"--t-final", "(0, 1e100]"}},
        BadArgs{"ocp_direct_option_indirect", {"ocp", "pendulum", "--knots", "5"}, {"--knots", "direct method only"}},
        BadArgs{"ocp_indirect_option_direct", {"ocp", "cart-pendulum", "--guess", "1,2"},
                {"--guess", "indirect method only"}},
        BadArgs{"rtol_huge", {"simulate", "free-body", "--method", "odeint-dopri5", "--model", "quaternion", "--rtol",
                              "1e308"}, {"--rtol", "[1e-14, 0.1]"}},
        BadArgs{"rtol_rkmk45_loose", {"simulate", "free-body", "--method", "rkmk45", "--rtol", "2"},
                {"--rtol", "must be a number in [1e-14, 0.1] (got 2)"}},
        BadArgs{"atol_below_round_off", {"simulate", "free-body", "--method", "odeint-rkf78", "--model", "quaternion",
                                         "--atol", "1e-300"}, {"--atol", "is below round-off"}},
        BadArgs{"merge_no_manifest", {"merge", "merged", "/nonexistent-shard"}, {"suite-run.json", "cannot be read"}},
        BadArgs{"unknown_scene", {"simulate", "pendulm"},
                {"pendulm", "unknown scene", "dumbbell", "free-body", "pendulum-controlled"}},
        BadArgs{"missing_file", {"simulate", "./nothing.toml"}, {"./nothing.toml", "cannot read"}},
        BadArgs{"bad_form", {"simulate", "pendulum", "--form", "implicit"}, {"--form", "implicit"}},
        BadArgs{"h_override_zero", {"simulate", "pendulum", "--h", "0"}, {"integration.h (--h)"}},
        BadArgs{"h_override_not_multiple", {"simulate", "pendulum", "--h", "0.003"},
                {"integration.t_final (h from --h)"}},
        BadArgs{"t_final_override_nan", {"simulate", "pendulum", "--t-final", "nan"}, {"integration.t_final"}},
        BadArgs{"every_zero", {"simulate", "pendulum", "--every", "0"}, {"integration.output_every (--every)"}},
        BadArgs{"h_not_a_number", {"simulate", "pendulum", "--h", "abc"}, {"--h"}},
        BadArgs{"unknown_option", {"simulate", "pendulum", "--bogus"}, {"--bogus"}},
        BadArgs{"no_scene", {"simulate"}, {"SCENE"}},
        BadArgs{"no_subcommand", {}, {"subcommand"}},
        BadArgs{"unknown_suite", {"suite", "nope", "--out", "res"}, {"suite", "nope", "default", "work-precision"}},
        BadArgs{"shard_index_past_count", {"suite", "extremes", "--quick", "--shard", "3/2", "--out", "res"},
                {"--shard", "3/2", "less than N"}},
        BadArgs{"shard_zero_count", {"suite", "extremes", "--quick", "--shard", "0/0", "--out", "res"},
                {"--shard", "0/0", "at least 1"}},
        BadArgs{"shard_not_a_fraction", {"suite", "extremes", "--shard", "1-2", "--list"}, {"--shard", "1-2"}},
        BadArgs{"shard_negative", {"suite", "extremes", "--shard", "-1/2", "--list"}, {"--shard", "-1/2"}},
        BadArgs{"jobs_zero", {"suite", "extremes", "--quick", "--jobs", "0", "--out", "res"}, {"--jobs"}},
        BadArgs{"timing_jobs_zero", {"suite", "work-precision", "--quick", "--timing-jobs", "0", "--out", "res"}, {"--timing-jobs"}},
        BadArgs{"composed_lgvi_with_model", {"simulate", "pendulum", "--method", "lgvi-yoshida4", "--model", "matrix"},
                {"model", "no coordinate model"}},
        BadArgs{"unknown_composition", {"simulate", "pendulum", "--method", "lgvi-yoshida5"},
                {"lgvi-yoshida5", "lgvi-kahan-li6"}},
        BadArgs{"composed_lgvi_printed_form", {"simulate", "pendulum", "--method", "lgvi-suzuki4", "--form", "printed"},
                {"--form", "composed lgvi-* are symmetric"}}),
    [](const ::testing::TestParamInfo<BadArgs>& info) { return std::string(info.param.what); });

TEST(CliSuite, BadSceneInTheScenesDirStopsBeforeWritingAnything) {
  TempDir dir;
  write_text(dir.scenes() / "good.toml", read_text(default_scene_file("free-body")));
  write_text(dir.scenes() / "typo.toml", edited_scene("pendulum", "rho =", "rh0 ="));
  const CliResult r = run_testbed(dir, {"--scenes-dir", dir.scenes().string(), "suite", "default", "--out", "res"});
  expect_bad_input(dir, r, {"typo.toml", "parameters.rh0"});
}

// --- successful runs ---------------------------------------------------------------------------

const std::vector<std::string> kMetadataKeys = {
    "scene", "scene_file", "system", "method", "form", "rotation_update_tolerance", "h", "grid_steps", "t_final",
    "output_every", "momentum_map", "units", "error_columns", "version", "git_describe", "command_line", "status",
    "solver_steps", "rejected_steps", "output_rows"};

std::vector<std::string> expected_header(const std::string& system) {
  std::vector<std::string> h = {"t"};
  if (system == "connected-bodies") {
    for (const char* body : {"R1_", "R2_"}) {
      for (const char* ij : {"11", "12", "13", "21", "22", "23", "31", "32", "33"}) h.push_back(body + std::string(ij));
    }
    for (const char* c : {"Omega1_1", "Omega1_2", "Omega1_3", "Omega2_1", "Omega2_2", "Omega2_3"}) h.push_back(c);
  } else {
    for (const char* c : {"R11", "R12", "R13", "R21", "R22", "R23", "R31", "R32", "R33", "Omega1", "Omega2", "Omega3"}) {
      h.push_back(c);
    }
  }
  if (system == "dumbbell") {
    for (const char* c : {"x1", "x2", "x3", "v1", "v2", "v3"}) h.push_back(c);
  }
  if (system == "cart-pendulum") {
    for (const char* c : {"x", "y", "xdot", "ydot"}) h.push_back(c);
  }
  for (const char* c : {"energy", "energy_error", "orthogonality_error", "determinant_error"}) h.push_back(c);
  if (system == "free-body") {
    for (const char* c : {"spatial_momentum1", "spatial_momentum2", "spatial_momentum3"}) h.push_back(c);
  } else if (system == "pendulum" || system == "cart-pendulum") {
    h.push_back("vertical_momentum");
  } else {
    for (const char* c : {"angular_momentum1", "angular_momentum2", "angular_momentum3"}) h.push_back(c);
  }
  h.push_back("momentum_error");
  h.push_back("newton_iterations");
  return h;
}

struct ShortRun {
  const char* scene;
  const char* system;
  const char* t_final;
  std::size_t steps;
  std::size_t rows;  ///< k = 0, every, 2 every, ... plus the last step
};

class CliSimulate : public ::testing::TestWithParam<ShortRun> {};

TEST_P(CliSimulate, WritesTheCsvAsSpecified) {
  const ShortRun& run = GetParam();
  TempDir dir;
  const CliResult r = run_testbed(dir, {"simulate", run.scene, "--t-final", run.t_final});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  ASSERT_EQ(lines_of(r.out).size(), 1u) << r.out;
  EXPECT_EQ(r.out.rfind("completed " + std::to_string(run.steps) + " steps", 0), 0u) << r.out;
  const std::string csv_name = std::string(run.scene) + ".csv";
  EXPECT_EQ(dir.work_entries(), std::vector<std::string>{csv_name});

  const CsvParts csv = read_csv(dir.work() / csv_name);
  std::vector<std::string> keys;
  for (const auto& [k, v] : csv.metadata) keys.push_back(k);
  EXPECT_EQ(keys, kMetadataKeys);
  EXPECT_EQ(csv.meta("scene"), run.scene);
  EXPECT_EQ(csv.meta("system"), run.system);
  EXPECT_EQ(csv.meta("method"), "lgvi");
  EXPECT_EQ(csv.meta("form"), "symmetric");
  EXPECT_EQ(csv.meta("grid_steps"), std::to_string(run.steps));
  EXPECT_EQ(csv.meta("solver_steps"), std::to_string(run.steps));
  EXPECT_EQ(csv.meta("rejected_steps"), "0");
  EXPECT_EQ(csv.meta("output_rows"), std::to_string(run.rows));
  EXPECT_EQ(std::stod(csv.meta("t_final")), std::stod(run.t_final));
  EXPECT_NE(csv.meta("command_line").find("--t-final"), std::string::npos);
  EXPECT_EQ(csv.meta("status").rfind("completed", 0), 0u);
  EXPECT_EQ(csv.header, expected_header(run.system));

  ASSERT_EQ(csv.rows.size(), run.rows);
  const std::vector<double>& first = csv.rows.front();
  EXPECT_EQ(first[csv.column("t")], 0.0);
  EXPECT_EQ(first[csv.column("energy_error")], 0.0);
  EXPECT_EQ(first[csv.column("momentum_error")], 0.0);
  EXPECT_EQ(first[csv.column("newton_iterations")], 0.0);
  const std::vector<double>& last = csv.rows.back();
  EXPECT_NEAR(last[csv.column("t")], std::stod(run.t_final), 1e-12);
  EXPECT_GT(last[csv.column("newton_iterations")], 0.0);
  const std::size_t every = std::stoul(csv.meta("output_every"));
  const double h = std::stod(csv.meta("h"));
  EXPECT_NEAR(csv.rows[1][csv.column("t")], static_cast<double>(every) * h, 1e-12);
  for (const auto& row : csv.rows) {
    EXPECT_LT(row[csv.column("orthogonality_error")], 1e-13);
    EXPECT_LT(row[csv.column("momentum_error")], 1e-12);  // conserved by every default scene
  }
}

INSTANTIATE_TEST_SUITE_P(All, CliSimulate,
                         ::testing::Values(ShortRun{"free-body", "free-body", "0.5", 100, 11},
                                           ShortRun{"pendulum", "pendulum", "0.1", 100, 6},
                                           ShortRun{"pendulum-controlled", "pendulum", "0.105", 105, 7},
                                           ShortRun{"dumbbell", "dumbbell", "1", 100, 14},
                                           ShortRun{"cart-pendulum", "cart-pendulum", "0.1", 100, 6},
                                           ShortRun{"connected-bodies", "connected-bodies", "1", 100, 26}),
                         [](const ::testing::TestParamInfo<ShortRun>& info) {
                           std::string n = info.param.scene;
                           std::replace(n.begin(), n.end(), '-', '_');
                           return n;
                         });

TEST(CliSimulate, OverridesReachTheMetadata) {
  TempDir dir;
  const CliResult r = run_testbed(
      dir, {"simulate", "pendulum", "--h", "0.002", "--t-final", "0.1", "--form", "printed", "--every", "5",
            "--out", "p.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const CsvParts csv = read_csv(dir.work() / "p.csv");
  EXPECT_EQ(csv.meta("form"), "printed");
  EXPECT_EQ(csv.meta("h"), "0.002");
  EXPECT_EQ(csv.meta("grid_steps"), "50");
  EXPECT_EQ(csv.meta("output_every"), "5");
  EXPECT_EQ(csv.rows.size(), 11u);
}

TEST(CliSimulate, SceneFileByPath) {
  TempDir dir;
  write_text(dir.scenes() / "mine.toml", edited_scene("free-body", "t_final = 50.0", "t_final = 0.05"));
  const CliResult r = run_testbed(dir, {"simulate", (dir.scenes() / "mine.toml").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const CsvParts csv = read_csv(dir.work() / "mine.csv");
  EXPECT_EQ(csv.meta("scene"), "mine");
  EXPECT_EQ(csv.rows.size(), 2u);  // k = 0 and the last step k = 10
}

TEST(CliSimulate, FailedRotationUpdateWritesTheCompletedSteps) {
  // The pendulum's rotation update has no solution (or Newton fails) once |h J Omega| nears
  // the domain bound; with h = 0.125 this happens at step 6 (t = 0.75).
  TempDir dir;
  const CliResult r = run_testbed(
      dir, {"simulate", "pendulum", "--h", "0.125", "--t-final", "20", "--every", "4", "--out", "fail.csv"});
  EXPECT_EQ(r.exit_code, 2);
  const std::vector<std::string> lines = r.err_lines();
  ASSERT_EQ(lines.size(), 1u) << r.err;
  EXPECT_NE(lines[0].find("rotation update failed at step 6 (t = 0.75)"), std::string::npos) << lines[0];
  EXPECT_EQ(dir.work_entries(), std::vector<std::string>{"fail.csv"});
  const CsvParts csv = read_csv(dir.work() / "fail.csv");
  EXPECT_EQ(csv.meta("status").rfind("rotation update failed at step 6 (t = 0.75)", 0), 0u) << csv.meta("status");
  ASSERT_EQ(csv.rows.size(), 3u);  // k = 0, 4 and the last good step 6
  EXPECT_EQ(csv.rows.back()[csv.column("t")], 0.75);
  EXPECT_GT(csv.rows.back()[csv.column("newton_iterations")], 0.0);  // step 6's, kept though not written
  EXPECT_EQ(csv.meta("solver_steps"), "6");
  EXPECT_EQ(csv.meta("output_rows"), "3");
}

TEST(CliSimulate, TheOutputGridDoesNotChangeTheLgvi) {
  // The LGVI hands the recorder only the written steps; the rows it writes are the same numbers
  // on any grid (the steps are the same), including the last step when K does not divide them.
  TempDir dir;
  const CliResult every1 =
      run_testbed(dir, {"simulate", "pendulum-controlled", "--t-final", "0.105", "--every", "1", "--out", "a.csv"});
  const CliResult every20 =
      run_testbed(dir, {"simulate", "pendulum-controlled", "--t-final", "0.105", "--every", "20", "--out", "b.csv"});
  ASSERT_EQ(every1.exit_code, 0) << every1.err;
  ASSERT_EQ(every20.exit_code, 0) << every20.err;
  const CsvParts a = read_csv(dir.work() / "a.csv");
  const CsvParts b = read_csv(dir.work() / "b.csv");
  ASSERT_EQ(a.rows.size(), 106u);
  ASSERT_EQ(b.rows.size(), 7u);  // k = 0, 20, ..., 100 and 105
  for (std::size_t i = 0; i < b.rows.size(); ++i) {
    const std::size_t k = i + 1 < b.rows.size() ? 20 * i : 105;
    EXPECT_EQ(a.rows[k], b.rows[i]) << "k = " << k;
  }
  EXPECT_EQ(a.meta("solver_steps"), "105");
  EXPECT_EQ(b.meta("solver_steps"), "105");
  EXPECT_EQ(a.meta("output_rows"), "106");
  EXPECT_EQ(b.meta("output_rows"), "7");
}

TEST(CliSimulate, FailureAtTheFirstStepKeepsTheInitialRow) {
  TempDir dir;
  const CliResult r = run_testbed(dir, {"simulate", "pendulum", "--h", "1.0"});
  EXPECT_EQ(r.exit_code, 2);
  ASSERT_EQ(r.err_lines().size(), 1u) << r.err;
  EXPECT_NE(r.err.find("outside the rotation update's domain"), std::string::npos) << r.err;
  const CsvParts csv = read_csv(dir.work() / "pendulum.csv");
  ASSERT_EQ(csv.rows.size(), 1u);
  EXPECT_EQ(csv.rows[0][0], 0.0);
}

TEST(CliSimulate, UnwritableOutputExitsThreeAndLeavesNothing) {
  TempDir dir;
  const CliResult r = run_testbed(dir, {"simulate", "pendulum", "--t-final", "0.01", "--out", "no/such/dir/x.csv"});
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_EQ(r.err_lines().size(), 1u) << r.err;
  EXPECT_TRUE(dir.work_entries().empty());
}

// A run whose CSV cannot fit in the free space is refused before anything is written (10^12 steps
// written every step: at least 10^12 rows, over a petabyte), in milliseconds.
TEST(CliSimulate, ARunLargerThanTheFreeSpaceIsRefusedBeforeWriting) {
  TempDir dir;
  const CliResult r = run_testbed(dir, {"simulate", "pendulum", "--h", "1e-13", "--t-final", "0.1", "--every", "1",
                                        "--out", "big.csv"});
  EXPECT_EQ(r.exit_code, 3) << r.err;
  ASSERT_EQ(r.err_lines().size(), 1u) << r.err;
  EXPECT_NE(r.err.find("big.csv: not enough space"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--every"), std::string::npos) << r.err;
  EXPECT_TRUE(dir.work_entries().empty());
}

// --- scenes, help, suite -------------------------------------------------------------------------

TEST(CliScenes, ListsEveryDefaultSceneWithItsDescription) {
  TempDir dir;
  const CliResult r = run_testbed(dir, {"scenes"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<std::string> lines = lines_of(r.out);
  const std::vector<std::string> names = {"anchored-spring",     "attitude-spring",     "cart-pendulum",       "connected-bodies",
                                          "connected-bodies-controlled",                 "detest-b5",
                                          "dumbbell",            "free-body",            "hlw-rigid-body",
                                          "lagrange-top",        "magnetic-dipole",      "manifold-rigid-body",  "ocp-cart-pendulum",
                                          "ocp-connected-bodies", "ocp-dumbbell",        "ocp-free-body-slew",
                                          "ocp-pendulum",        "pendulum",             "pendulum-controlled",
                                          "spacecraft-tumble",   "symmetric-top",        "uniform-gravity"};
  ASSERT_EQ(lines.size(), names.size()) << r.out;
  for (std::size_t i = 0; i < names.size(); ++i) {
    EXPECT_EQ(lines[i].rfind(std::string(names[i]) + " ", 0), 0u) << lines[i];
    EXPECT_GT(lines[i].size(), 30u) << lines[i];
  }
}

TEST(CliHelp, ExitsZero) {
  TempDir dir;
  const CliResult r = run_testbed(dir, {"--help"});
  EXPECT_EQ(r.exit_code, 0);
  for (const char* word : {"scenes", "simulate", "suite", "Exit status"}) {
    EXPECT_NE(r.out.find(word), std::string::npos) << word;
  }
}

TEST(CliSuite, DefaultSuiteWritesCsvsSummaryAndPlots) {
  TempDir dir;
  const CliResult r = run_testbed(dir, {"suite", "default", "--out", "res"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(dir.work() / "res")) files.push_back(e.path().filename().string());
  std::sort(files.begin(), files.end());
  std::vector<std::string> expected = {"summary.csv", "summary.jsonl", "suite-journal.jsonl", "suite-run.json"};
  for (const char* scene : {"anchored-spring", "attitude-spring", "cart-pendulum", "connected-bodies",
                            "connected-bodies-controlled", "detest-b5", "dumbbell", "free-body", "hlw-rigid-body",
                            "lagrange-top", "magnetic-dipole", "manifold-rigid-body", "pendulum", "pendulum-controlled",
                            "spacecraft-tumble", "symmetric-top", "uniform-gravity"}) {
    for (const char* suffix : {"-symmetric.csv", "-printed.csv", "-energy.png", "-orthogonality.png", "-momentum.png"}) {
      expected.push_back(scene + std::string(suffix));
    }
  }
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(files, expected);  // and no temporaries

  const std::vector<std::string> summary = lines_of(read_text(dir.work() / "res" / "summary.jsonl"));
  ASSERT_EQ(summary.size(), 34u);  // one JSON object per run: 17 scenes, 2 forms
  // The metadata lines ('#') state the units and what each error column is; then header + 34 rows.
  const std::vector<std::string> csv = lines_of(read_text(dir.work() / "res" / "summary.csv"));
  const auto metadata_end = std::find_if(csv.begin(), csv.end(), [](const std::string& l) { return !l.starts_with("#"); });
  EXPECT_EQ(csv.end() - metadata_end, 35);
  const std::string metadata = std::accumulate(csv.begin(), metadata_end, std::string());
  for (const char* line : {"# suite: default", "# form: full", "# units: ", "# errors: ",
                           "# columns.max_energy_error_relative: ", "# columns.max_energy_error_absolute: ",
                           "# columns.max_momentum_drift_absolute: "}) {
    EXPECT_NE(metadata.find(line), std::string::npos) << line << " not in " << metadata;
  }
  ASSERT_NE(metadata_end, csv.end());
  EXPECT_NE(metadata_end->find(",max_energy_error_relative,max_energy_error_absolute,"), std::string::npos)
      << *metadata_end;
  for (std::size_t i = 0; i < 16; ++i) {
    for (const char* key : {"\"scene\": ", "\"method\": \"lgvi\"", "\"form\": ", "\"status\": \"completed\"",
                            "\"newton_iterations\": ", "\"max_newton_iterations\": ", "\"wall_seconds\": ",
                            "\"potential_evaluations\": ", "\"max_energy_error\": ",
                            "\"energy_error_normalization\": \"relative to |E0|\"", "\"max_orthogonality_error\": ",
                            "\"max_momentum_drift\": "}) {
      EXPECT_NE(summary[i].find(key), std::string::npos) << key << " not in " << summary[i];
    }
  }
  for (const std::string& f : files) {
    if (f.ends_with(".png")) {
      EXPECT_EQ(read_text(dir.work() / "res" / f).substr(1, 3), "PNG") << f;
    }
  }
}

TEST(CliSuite, NoPlotsWithACustomScenesDir) {
  TempDir dir;
  write_text(dir.scenes() / "tiny.toml", edited_scene("pendulum", "t_final = 20.0", "t_final = 0.02"));
  const CliResult r = run_testbed(
      dir, {"--scenes-dir", dir.scenes().string(), "suite", "default", "--out", "res", "--no-plots"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(dir.work() / "res")) files.push_back(e.path().filename().string());
  std::sort(files.begin(), files.end());
  EXPECT_EQ(files,
            (std::vector<std::string>{"suite-journal.jsonl", "suite-run.json", "summary.csv", "summary.jsonl",
                                      "tiny-printed.csv", "tiny-symmetric.csv"}));
}

}  // namespace
}  // namespace lgvi::test
