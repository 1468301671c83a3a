// `lgvi-testbed ocp`: the three output files, their content, and bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "experiments/cli/cli_support.hpp"
#include "test_support.hpp"

namespace lgvi::test {
namespace {

TEST(OcpCli, PendulumWritesHistoryTrajectoryAndSummary) {
  TempDir dir;
  const CliResult r = run_testbed(dir, {"ocp", "pendulum", "--out", "out"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("converged"), std::string::npos) << r.out;
  const fs::path out = dir.work() / "out";
  const std::string json = read_text(out / "ocp-pendulum-summary.json");
  for (const char* key : {"\"cost\": 7.32", "\"status\": \"converged\"", "\"outer_iterations\"", "\"inner_iterations\"",
                          "\"cond_min\"", "\"cond_max\"", "\"wall_seconds\"", "\"violation\"", "\"form\": \"printed\""}) {
    EXPECT_NE(json.find(key), std::string::npos) << key << " not in " << json;
  }
  const std::string history = read_text(out / "ocp-pendulum-history.csv");
  EXPECT_NE(history.find("iteration,violation,cost,step_length,backtracks,cond_sensitivity"), std::string::npos);
  const std::vector<std::string> trajectory = lines_of(read_text(out / "ocp-pendulum-trajectory.csv"));
  std::size_t data = 0, header = 0;
  for (const std::string& line : trajectory) {
    if (line.rfind("t,R11", 0) == 0) ++header;
    else if (!line.empty() && line[0] != '#') ++data;
  }
  EXPECT_EQ(header, 1u);
  EXPECT_EQ(data, 1001u);  // nodes 0..1000
  // Nothing but the three files (no temporaries left).
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(out)) {
    EXPECT_NE(e.path().filename().string()[0], '.') << e.path();
    ++files;
  }
  EXPECT_EQ(files, 3u);
}

TEST(OcpCli, NoDecompositionRecordsTheFailure) {
  TempDir dir;
  const CliResult r = run_testbed(dir, {"ocp", "pendulum", "--no-decomposition", "--out", "."});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  ASSERT_EQ(r.err_lines().size(), 1u) << r.err;
  const std::string json = read_text(dir.work() / "ocp-pendulum-summary.json");
  EXPECT_NE(json.find("\"decomposition\": false"), std::string::npos) << json;
  EXPECT_NE(json.find("\"converged\": false"), std::string::npos) << json;
}

TEST(OcpCli, BadInputIsOneErrorLineAndNoFiles) {
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"ocp", "pendulum", "--h", "0.0003", "--out", "."},
        std::vector<std::string>{"ocp", "pendulum", "--guess", "1,2", "--out", "."},
        std::vector<std::string>{"ocp", "pendulum", "--form", "leapfrog", "--out", "."},
        std::vector<std::string>{"ocp", "rocket", "--out", "."}}) {
    TempDir dir;
    const CliResult r = run_testbed(dir, args);
    EXPECT_EQ(r.exit_code, 1) << args[2] << ": " << r.err;
    EXPECT_EQ(r.err_lines().size(), 1u) << r.err;
    EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << r.err;
    EXPECT_TRUE(dir.work_entries().empty());
  }
}

}  // namespace
}  // namespace lgvi::test

namespace lgvi::test {
namespace {

TEST(OcpCli, CartPendulumDirectWritesHistoryTrajectoryAndSummary) {
  TempDir dir;
  const CliResult r = run_testbed(dir, {"ocp", "cart-pendulum", "--out", "out"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const fs::path out = dir.work() / "out";
  const std::string json = read_text(out / "ocp-cart-pendulum-summary.json");
  for (const char* key : {"\"status\": \"converged\"", "\"spline\": \"not-a-knot\"", "\"gradients\": \"exact\"",
                          "\"iterations\"", "\"gradient_evaluations\"", "\"wall_seconds\"", "\"knot_values\"",
                          "\"violation\"", "\"paper_cost\": 297.43"}) {
    EXPECT_NE(json.find(key), std::string::npos) << key << " not in " << json;
  }
  EXPECT_NE(read_text(out / "ocp-cart-pendulum-history.csv").find("start,evaluation,iteration,gradient,cost,violation"),
            std::string::npos);
  std::size_t data = 0, header = 0;
  for (const std::string& line : lines_of(read_text(out / "ocp-cart-pendulum-trajectory.csv"))) {
    if (line.rfind("t,R11,", 0) == 0) ++header;
    else if (!line.empty() && line[0] != '#') ++data;
  }
  EXPECT_EQ(header, 1u);
  EXPECT_EQ(data, 201u);  // nodes 0..200

  // The knots file: one row per knot, and the spline passes through its knots. The knots at
  // t = 0, 1, 2 s are nodes 0, 100, 200 of the trajectory, whose controls must equal them up to
  // the round-off of the spline's linear map: a sum over the 7 knots of the largest knot value.
  const CsvParts knots = read_csv(out / "ocp-cart-pendulum-knots.csv");
  ASSERT_EQ(knots.header, (std::vector<std::string>{"t", "u1", "u2"}));
  ASSERT_EQ(knots.rows.size(), 7u);
  const CsvParts trajectory = read_csv(out / "ocp-cart-pendulum-trajectory.csv");
  double largest = 0.0;
  for (const auto& row : knots.rows) largest = std::max({largest, std::abs(row[1]), std::abs(row[2])});
  for (const auto& [knot, node] : {std::pair{0, 0}, std::pair{3, 100}, std::pair{6, 200}}) {
    const std::vector<double>& k = knots.rows[static_cast<std::size_t>(knot)];
    const std::vector<double>& n = trajectory.rows[static_cast<std::size_t>(node)];
    EXPECT_NEAR(k[0], n[trajectory.column("t")], 1e-12);
    EXPECT_NEAR(k[1], n[trajectory.column("u1")], roundoff(largest, 7)) << "knot " << knot;
    EXPECT_NEAR(k[2], n[trajectory.column("u2")], roundoff(largest, 7)) << "knot " << knot;
  }
}

// A capped run: not converged (exit 2), the status says why, the files are still written.
TEST(OcpCli, ConnectedBodiesEvaluationLimitIsReportedWithFiles) {
  TempDir dir;
  const CliResult r =
      run_testbed(dir, {"ocp", "connected-bodies", "--starts", "1", "--max-iterations", "5", "--out", "."});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  ASSERT_EQ(r.err_lines().size(), 1u) << r.err;
  const std::string json = read_text(dir.work() / "ocp-connected-bodies-summary.json");
  for (const char* key : {"\"status\": \"evaluation limit\"", "\"nlopt_result\": \"NLOPT_MAXEVAL_REACHED\"",
                          "\"converged\": false", "\"constraints\": 9", "\"paper_cost\": 0.574"}) {
    EXPECT_NE(json.find(key), std::string::npos) << key << " not in " << json;
  }
  EXPECT_NE(read_text(dir.work() / "ocp-connected-bodies-trajectory.csv").find("t,R1_11,"), std::string::npos);
}

TEST(OcpCli, DirectBadInputIsOneErrorLineAndNoFiles) {
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"ocp", "cart-pendulum", "--spline", "clamped", "--out", "."},
        std::vector<std::string>{"ocp", "connected-bodies", "--gradients", "adjoint", "--out", "."},
        std::vector<std::string>{"ocp", "cart-pendulum", "--knots", "2", "--out", "."},
        std::vector<std::string>{"ocp", "cart-pendulum", "--guess", "1,2", "--out", "."}}) {
    TempDir dir;
    const CliResult r = run_testbed(dir, args);
    EXPECT_EQ(r.exit_code, 1) << args[2] << ": " << r.err;
    EXPECT_EQ(r.err_lines().size(), 1u) << r.err;
    EXPECT_TRUE(dir.work_entries().empty());
  }
}

// Issue 34, N9: a non-finite value in a solver's history or result is a named failure, never a
// success with an inf in its files. The reproducer: the pendulum held at rest (target = initial
// state) with W = 1e50 I from a tiny guess converges at once, but the condition number of the
// sensitivity overflows; it used to end "converged", exit 0, with inf in the history.
TEST(OcpCli, ANonFiniteValueInTheHistoryIsANamedFailure) {
  TempDir dir;
  std::string text = edited_scene("ocp-pendulum", "R = [[-1, 0, 0], [0, -1, 0], [0, 0, 1]]", "R = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]");
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"W = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]",
                                                                     "W = [[1e50, 0, 0], [0, 1e50, 0], [0, 0, 1e50]]"},
                                 std::pair<std::string, std::string>{"multiplier_guess = [1, 1, 1, 1, 1, 1]",
                                                                     "multiplier_guess = [0, 0, 0, 1e-100, 0, 0]"}}) {
    const std::size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  }
  write_text(dir.capture() / "rest.toml", text);
  const CliResult r = run_testbed(dir, {"ocp", (dir.capture() / "rest.toml").string(), "--out", "out"});
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  ASSERT_EQ(r.err_lines().size(), 1u) << r.err;
  EXPECT_NE(r.err.find("non-finite value"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("= inf at outer iteration 0"), std::string::npos) << r.err;
  const std::string json = read_text(dir.work() / "out" / "ocp-rest-summary.json");
  EXPECT_NE(json.find("\"status\": \"non-finite value\""), std::string::npos) << json;
  EXPECT_NE(json.find("\"converged\": false"), std::string::npos) << json;
}

// --solver ddp: the history (one row per iLQR iteration), the trajectory and the summary, no
// knots file; an option of the other solvers is an error naming it.
TEST(OcpCli, DdpWritesHistoryTrajectoryAndSummary) {
  TempDir dir;
  const CliResult r = run_testbed(dir, {"ocp", "cart-pendulum", "--solver", "ddp", "--h", "0.02", "--out", "out"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const fs::path out = dir.work() / "out";
  const std::string json = read_text(out / "ocp-cart-pendulum-summary.json");
  for (const char* key : {"\"solver\": \"ddp\"", "\"status\": \"converged\"", "\"outer_iterations\"",
                          "\"cpu_seconds\"", "\"violation\"", "\"start_statuses\": \"converged\""}) {
    EXPECT_NE(json.find(key), std::string::npos) << key << " not in " << json;
  }
  EXPECT_NE(read_text(out / "ocp-cart-pendulum-history.csv").find("start,iteration,outer,cost,violation"),
            std::string::npos);
  std::size_t data = 0;
  for (const std::string& line : lines_of(read_text(out / "ocp-cart-pendulum-trajectory.csv"))) {
    if (!line.empty() && line[0] != '#' && line.rfind("t,", 0) != 0) ++data;
  }
  EXPECT_EQ(data, 101u);  // nodes 0..100
  EXPECT_FALSE(fs::exists(out / "ocp-cart-pendulum-knots.csv"));
  TempDir bad;
  const CliResult e = run_testbed(bad, {"ocp", "cart-pendulum", "--solver", "ddp", "--hessian", "cost", "--out", "."});
  EXPECT_EQ(e.exit_code, 1);
  EXPECT_NE(e.err.find("--hessian"), std::string::npos) << e.err;
}

}  // namespace
}  // namespace lgvi::test

namespace lgvi::test {
namespace {

TEST(OcpCli, EverySummaryCarriesTheReplayedYardstick) {
  TempDir dir;
  const CliResult r = run_testbed(dir, {"ocp", "pendulum", "--steps", "100", "--out", "."});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string json = read_text(dir.work() / "ocp-pendulum-summary.json");
  for (const char* key : {"\"replay_interpolation\": \"zero-order-hold\"", "\"replayed_cost\": 7.", "\"replayed_violation\"",
                          "\"replay_status\": \"ok\"", "\"replayed_quaternion_drift\""}) {
    EXPECT_NE(json.find(key), std::string::npos) << key << " not in " << json;
  }
}

TEST(OcpCli, CollocationOfTheMultibodySystemsWritesTheStateAndTheReplay) {
  TempDir dir;
  const CliResult r =
      run_testbed(dir, {"ocp", "cart-pendulum", "--solver", "collocation", "--intervals", "20", "--out", "out"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const fs::path out = dir.work() / "out";
  const std::string json = read_text(out / "ocp-cart-pendulum-summary.json");
  for (const char* key : {"\"solver\": \"collocation\"", "\"status\": \"converged\"", "\"violation_velocity\"",
                          "\"replay_interpolation\": \"piecewise-quadratic\"", "\"replay_status\": \"ok\""}) {
    EXPECT_NE(json.find(key), std::string::npos) << key << " not in " << json;
  }
  const std::vector<std::string> rows = lines_of(read_text(out / "ocp-cart-pendulum-trajectory.csv"));
  std::size_t data = 0;
  bool header = false;
  for (const std::string& line : rows) {
    if (line.rfind("t,q0,q1,q2,q3,x,y,Pi1,Pi2,Pi3,px,py,quaternion_norm_error,ux,uy", 0) == 0) header = true;
    if (!line.empty() && line[0] != '#' && line.rfind("t,", 0) != 0) ++data;
  }
  EXPECT_TRUE(header);
  EXPECT_EQ(data, 21u);  // nodes 0..20
}

TEST(OcpCli, CollocationWritesItsFilesAndRefusesTheDiscreteOptions) {
  TempDir dir;
  const CliResult r = run_testbed(dir, {"ocp", "pendulum", "--solver", "collocation", "--intervals", "20", "--out", "out"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const fs::path out = dir.work() / "out";
  const std::string json = read_text(out / "ocp-pendulum-summary.json");
  // --hessian: exact by default; limited-memory (L-BFGS) on request
  EXPECT_NE(json.find("\"hessian\": \"exact\""), std::string::npos) << json;
  const CliResult lbfgs = run_testbed(dir, {"ocp", "pendulum", "--solver", "collocation", "--intervals", "20",
                                            "--hessian", "limited-memory", "--out", "lbfgs"});
  ASSERT_EQ(lbfgs.exit_code, 0) << lbfgs.err;
  const std::string lbfgs_json = read_text(dir.work() / "lbfgs" / "ocp-pendulum-summary.json");
  EXPECT_NE(lbfgs_json.find("\"hessian\": \"limited-memory\""), std::string::npos) << lbfgs_json;
  EXPECT_NE(lbfgs_json.find("\"hessian_nonzeros\": 0,"), std::string::npos) << lbfgs_json;
  for (const char* key : {"\"solver\": \"collocation\"", "\"status\": \"converged\"", "\"intervals\": 20",
                          "\"max_defect\"", "\"quaternion_drift\"", "\"replay_interpolation\": \"piecewise-quadratic\"",
                          "\"replay_status\": \"ok\""}) {
    EXPECT_NE(json.find(key), std::string::npos) << key << " not in " << json;
  }
  std::size_t data = 0;
  for (const std::string& line : lines_of(read_text(out / "ocp-pendulum-trajectory.csv"))) {
    if (!line.empty() && line[0] != '#' && line.rfind("t,", 0) != 0) ++data;
  }
  EXPECT_EQ(data, 21u);  // nodes 0..20
  for (const auto& [args, option] :
       {std::pair{std::vector<std::string>{"ocp", "pendulum", "--solver", "collocation", "--knots", "5", "--out", "."},
                  "--knots"},
        std::pair{std::vector<std::string>{"ocp", "pendulum", "--solver", "collocation", "--intervals", "1", "--out", "."},
                  "--intervals"},
        std::pair{std::vector<std::string>{"ocp", "pendulum", "--intervals", "10", "--out", "."}, "--intervals"},
        std::pair{std::vector<std::string>{"ocp", "cart-pendulum", "--solver", "collocation", "--knots", "5", "--out", "."},
                  "--knots"},
        std::pair{std::vector<std::string>{"ocp", "pendulum", "--solver", "collocation", "--hessian", "newton", "--out", "."},
                  "--hessian"}}) {
    TempDir bad;
    const CliResult e = run_testbed(bad, args);
    EXPECT_EQ(e.exit_code, 1) << e.err;
    EXPECT_EQ(e.err.rfind(std::string("error: ") + option, 0), 0u) << e.err;
    EXPECT_TRUE(bad.work_entries().empty());
  }
}

}  // namespace
}  // namespace lgvi::test
