// Optimal control problems from scene files ([ocp] tables, experiments/scene/ocp_scene.hpp): the
// shipped examples hold the paper's problems, a user's free-body slew with its own W converges,
// and every [ocp] field's bad input is one SceneError naming the file, the field and the reason.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "experiments/cli/cli_support.hpp"
#include "experiments/scene/ocp_scene.hpp"
#include "experiments/scene/scene.hpp"
#include "lgvi/ocp/direct.hpp"
#include "lgvi/ocp/indirect.hpp"
#include "test_support.hpp"

namespace lgvi::test {
namespace {

using experiments::load_scene;
using experiments::OcpMethod;
using experiments::parse_scene;
using experiments::Scene;
using experiments::SceneError;

Scene ocp_scene(const std::string& name) { return load_scene(default_scene_file(name)); }

// The library's records of the paper's problems (lgvi/ocp) and the shipped scene files are two
// writings of the same data: they must agree bit for bit (the scenes reproduce `ocp SYSTEM`).
TEST(OcpScenes, PaperExamplesMatchTheLibraryRecordsExactly) {
  {
    const Scene s = ocp_scene("ocp-pendulum");
    ASSERT_TRUE(s.ocp);
    const auto& m = std::get<experiments::PendulumModel>(s.model);
    const auto& target = std::get<experiments::AttitudeInitial>(s.ocp->target);
    const ocp::TransferProblem p = ocp::TransferProblem::pendulum_paper();
    const Pendulum3D paper = Pendulum3D::paper();
    EXPECT_EQ(m.system.inertia.J, paper.inertia.J);
    EXPECT_EQ(m.system.rho, paper.rho);
    EXPECT_EQ(m.system.mass * m.system.gravity, paper.mass * paper.gravity);
    EXPECT_EQ(m.initial.R, p.R0);
    EXPECT_EQ(target.R, p.Rf);
    EXPECT_EQ(s.horizon.t_final, p.t_final);
    EXPECT_EQ(s.horizon.h, 1e-3);
    EXPECT_EQ(s.form, LgviForm::Printed);
    EXPECT_EQ(s.ocp->method, OcpMethod::Indirect);
    EXPECT_EQ(s.ocp->indirect.initial_multiplier, Eigen::VectorXd::Ones(6));
  }
  {
    const Scene s = ocp_scene("ocp-dumbbell");
    const auto& m = std::get<experiments::DumbbellModel>(s.model);
    const auto& target = std::get<experiments::RigidBodyInitial>(s.ocp->target);
    const ocp::TransferProblem p = ocp::TransferProblem::dumbbell_paper();
    EXPECT_EQ(m.system.inertia.J, DumbbellSpacecraft::paper().inertia.J);
    EXPECT_EQ(m.initial.R, p.R0);
    EXPECT_EQ(m.initial.x, p.x0);
    EXPECT_EQ(m.initial.v, p.v0);
    EXPECT_EQ(m.initial.Omega, p.Omega0);
    EXPECT_EQ(target.R, p.Rf);
    EXPECT_EQ(target.x, p.xf);
    EXPECT_EQ(target.v, p.vf);
    EXPECT_EQ(target.Omega, p.Omegaf);
    EXPECT_EQ(s.horizon.t_final, p.t_final);
    EXPECT_EQ(s.horizon.h, p.t_final / 1000.0);
    EXPECT_EQ(s.horizon.steps, 1000u);
  }
  {
    const Scene s = ocp_scene("ocp-cart-pendulum");
    const auto& target = std::get<experiments::CartPendulumInitial>(s.ocp->target);
    const ocp::CartPendulumTransfer p = ocp::CartPendulumTransfer::paper();
    EXPECT_EQ(std::get<experiments::CartPendulumModel>(s.model).system.inertia.J, CartPendulum::paper().inertia.J);
    EXPECT_EQ(target.R, p.Rf);
    EXPECT_EQ(s.horizon.t_final, p.t_final);
    EXPECT_EQ(s.ocp->method, OcpMethod::Direct);
    EXPECT_EQ(s.ocp->direct.starts, 1);
  }
  {
    const Scene s = ocp_scene("ocp-connected-bodies");
    const auto& target = std::get<experiments::ConnectedBodiesInitial>(s.ocp->target);
    const ocp::ConnectedBodiesTransfer p = ocp::ConnectedBodiesTransfer::paper();
    EXPECT_EQ(target.R1, p.R1_f);
    EXPECT_EQ(target.R2, p.R2_f);
    EXPECT_EQ(s.horizon.t_final, p.t_final);
    EXPECT_EQ(s.ocp->direct.starts, 8);
  }
}

/// The shipped free-body slew, with W replaced by `W` when given, run by the CLI.
CliResult run_slew(const TempDir& dir, const std::string& W) {
  std::string text = read_text(default_scene_file("ocp-free-body-slew"));
  if (!W.empty()) {
    const std::string from = "W = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]";
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos);
    text.replace(at, from.size(), "W = " + W);
  }
  write_text(dir.work() / "slew.toml", text);
  return run_testbed(dir, {"ocp", "./slew.toml", "--out", "out"});
}

TEST(OcpScenes, FreeBodySlewConvergesWithTheShippedAndAUsersW) {
  // The shipped scene by name, then a user's copy with a full (non-diagonal) W: both reach the
  // shooting's tolerance (1e-12 on |r|); the cost changes with W (a different problem).
  TempDir shipped;
  const CliResult a = run_testbed(shipped, {"ocp", "free-body-slew", "--out", "out"});
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const std::string ja = read_text(shipped.work() / "out" / "ocp-free-body-slew-summary.json");
  EXPECT_NE(ja.find("\"converged\": true"), std::string::npos) << ja;
  // W as numbers (row by row), not as text.
  EXPECT_NE(ja.find("\"W\": [1, 0, 0, 0, 1, 0, 0, 0, 1]"), std::string::npos) << ja;

  TempDir user;
  const CliResult b = run_slew(user, "[[2.0, 0.5, 0.0], [0.5, 1.0, 0.2], [0.0, 0.2, 3.0]]");
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const std::string jb = read_text(user.work() / "out" / "ocp-slew-summary.json");
  EXPECT_NE(jb.find("\"converged\": true"), std::string::npos) << jb;
  EXPECT_NE(jb.find("\"W\": [2, 0.5, 0, 0.5, 1, 0.2, 0, 0.2, 3]"), std::string::npos) << jb;
  const auto number = [](const std::string& json, const std::string& key) {
    const std::size_t at = json.find("\"" + key + "\": ");
    EXPECT_NE(at, std::string::npos) << key;
    return std::stod(json.substr(at + key.size() + 4));
  };
  EXPECT_LT(number(jb, "violation"), 1e-12);
  EXPECT_NE(number(ja, "cost"), number(jb, "cost"));

  // --weight on the shipped scene is the same problem as the edited file: the same cost, to the
  // shooting's tolerance (both runs take the same Newton steps from the same guess: to rounding).
  TempDir flag;
  const CliResult c =
      run_testbed(flag, {"ocp", "free-body-slew", "--weight", "2,0.5,0,0.5,1,0.2,0,0.2,3", "--out", "out"});
  ASSERT_EQ(c.exit_code, 0) << c.err;
  const std::string jc = read_text(flag.work() / "out" / "ocp-free-body-slew-summary.json");
  EXPECT_NEAR(number(jc, "cost"), number(jb, "cost"), 1e-12 * number(jb, "cost"));
  for (const auto& [weight, reason] : {std::pair{"1,2", "needs 3 values"}, std::pair{"1,2,-3", "not positive definite"},
                                       std::pair{"1,2,0,0,1,0,0,0,1", "not symmetric"}}) {
    TempDir bad;
    const CliResult e = run_testbed(bad, {"ocp", "free-body-slew", "--weight", weight, "--out", "out"});
    EXPECT_EQ(e.exit_code, 1) << weight;
    EXPECT_NE(e.err.find("--weight"), std::string::npos) << e.err;
    EXPECT_NE(e.err.find(reason), std::string::npos) << e.err;
  }

  // The trajectory ends at rest at the target: the violation's parts, recomputed from the CSV.
  const CsvParts t = read_csv(user.work() / "out" / "ocp-slew-trajectory.csv");
  ASSERT_FALSE(t.rows.empty());
  const std::vector<double>& last = t.rows.back();
  for (const char* c : {"Omega1", "Omega2", "Omega3"}) EXPECT_LT(std::abs(last[t.column(c)]), 1e-12) << c;
  EXPECT_NEAR(last[t.column("R11")], 1.0 / 3.0, 1e-12);
}

struct BadOcp {
  const char* what;
  const char* scene;  ///< shipped scene edited
  const char* from;
  const char* to;
  std::vector<std::string> needles;  ///< in the one-line message (the field first)
};

class OcpSceneBadInput : public ::testing::TestWithParam<BadOcp> {};

TEST_P(OcpSceneBadInput, OneSceneErrorNamingFileFieldAndReason) {
  const BadOcp& c = GetParam();
  const std::string text = edited_scene(c.scene, c.from, c.to);
  try {
    (void)parse_scene(text, "user/bad.toml");
    ADD_FAILURE() << "accepted: " << c.what;
  } catch (const SceneError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_EQ(message.rfind("user/bad.toml: ", 0), 0u) << message;
    EXPECT_EQ(e.field(), c.needles.front()) << message;
    for (const std::string& n : c.needles) EXPECT_NE(message.find(n), std::string::npos) << n << " not in " << message;
  }
}

INSTANTIATE_TEST_SUITE_P(
    All, OcpSceneBadInput,
    ::testing::Values(
        BadOcp{"unknown_key", "ocp-pendulum", "paper =", "papers =", {"ocp.papers", "unknown key"}},
        BadOcp{"method_unknown", "ocp-pendulum", "method = \"indirect\"", "method = \"shooting\"",
               {"ocp.method", "'indirect'", "shooting"}},
        BadOcp{"method_missing_for_system", "ocp-cart-pendulum", "method = \"direct\"", "method = \"indirect\"",
               {"ocp.method", "'direct'", "cart-pendulum"}},
        BadOcp{"method_not_string", "ocp-pendulum", "method = \"indirect\"", "method = 1", {"ocp.method", "string"}},
        BadOcp{"paper_unknown", "ocp-pendulum", "paper = \"pendulum_reorientation\"", "paper = \"pendulum\"",
               {"ocp.paper", "unknown example", "pendulum_reorientation"}},
        BadOcp{"W_not_symmetric", "ocp-pendulum", "W = [[1, 0, 0]", "W = [[1, 0.5, 0]", {"ocp.W", "not symmetric"}},
        BadOcp{"W_indefinite", "ocp-pendulum", "W = [[1, 0, 0]", "W = [[-1, 0, 0]", {"ocp.W", "not positive definite"}},
        BadOcp{"W_semidefinite", "ocp-pendulum", "W = [[1, 0, 0]", "W = [[0, 0, 0]", {"ocp.W", "not positive definite"}},
        BadOcp{"W_wrong_size", "ocp-cart-pendulum", "W = [[1, 0], [0, 1]]", "W = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]",
               {"ocp.W", "2x2"}},
        BadOcp{"W_not_finite", "ocp-pendulum", "W = [[1, 0, 0]", "W = [[nan, 0, 0]", {"ocp.W[0][0]", "finite"}},
        BadOcp{"target_missing", "ocp-pendulum", "[ocp.target]", "[ocp.goal]", {"ocp.goal", "unknown key"}},
        BadOcp{"target_not_rotation", "ocp-pendulum", "R = [[-1, 0, 0]", "R = [[-2, 0, 0]", {"ocp.target.R"}},
        BadOcp{"target_unknown_key", "ocp-pendulum", "Omega = [0.0, 0.0, 0.0]\n\n[ocp.indirect]",
               "Omega = [0.0, 0.0, 0.0]\nx = [0, 0, 0]\n\n[ocp.indirect]", {"ocp.target.x", "unknown key"}},
        BadOcp{"target_wrong_shape", "ocp-cart-pendulum", "q = [0.0, 0.0]\nq_dot = [0.0, 0.0]\n\n[ocp.direct]",
               "q = [0.0]\nq_dot = [0.0, 0.0]\n\n[ocp.direct]", {"ocp.target.q", "2 numbers"}},
        BadOcp{"other_method_table", "ocp-pendulum", "[ocp.indirect]", "[ocp.direct]", {"ocp.direct", "indirect"}},
        BadOcp{"guess_wrong_length", "ocp-pendulum", "multiplier_guess = [1, 1, 1, 1, 1, 1]",
               "multiplier_guess = [1, 1, 1]", {"ocp.indirect.multiplier_guess", "6 numbers"}},
        BadOcp{"globalization_unknown", "ocp-pendulum", "max_iterations = 300", "globalization = \"trust-region\"",
               {"ocp.indirect.globalization", "newton-armijo", "trust-region"}},
        BadOcp{"lm_damping_zero", "ocp-pendulum", "max_iterations = 300", "lm_damping = 0",
               {"ocp.indirect.lm_damping", "must be a number in (0, 1e10] (got 0)"}},
        // The ranges are the options structs' (lgvi/ocp), the ocp command's too (test_ocp_options.cpp).
        BadOcp{"lm_damping_huge", "ocp-pendulum", "max_iterations = 300", "lm_damping = 1e11",
               {"ocp.indirect.lm_damping", "(0, 1e10]"}},
        BadOcp{"max_iterations_huge", "ocp-pendulum", "max_iterations = 300", "max_iterations = 10000000000",
               {"ocp.indirect.max_iterations", "[1, 1000000]", "(got 1e10)"}},
        BadOcp{"indirect_tolerance_loose", "ocp-pendulum", "max_iterations = 300", "tolerance = 0.5",
               {"ocp.indirect.tolerance", "(0, 0.1]"}},
        BadOcp{"guess_huge", "ocp-pendulum", "multiplier_guess = [1, 1, 1, 1, 1, 1]",
               "multiplier_guess = [1, 1, 1e300, 1, 1, 1]", {"ocp.indirect.multiplier_guess[2]", "magnitude"}},
        // N5: the step cap of `ocp --steps` (10^7 steps took 3.8 GB and wrote a 4.3 GB CSV, 10^8
        // ended in std::bad_alloc), whichever key sets the steps.
        BadOcp{"too_many_steps_h", "ocp-pendulum", "h = 0.001", "h = 1e-7",
               {"integration.h", "gives 10000000 steps", "at most 1000000"}},
        BadOcp{"too_many_steps_t_final", "ocp-pendulum", "t_final = 1.0", "t_final = 100000.0",
               {"integration.h", "gives 100000000 steps", "at most 1000000"}},
        BadOcp{"nonmonotone_memory_zero", "ocp-pendulum", "max_iterations = 300", "nonmonotone_memory = 0",
               {"ocp.indirect.nonmonotone_memory", "[1, 1000]"}},
        BadOcp{"merit_unknown", "ocp-pendulum", "max_iterations = 300", "merit = \"energy\"",
               {"ocp.indirect.merit", "velocity"}},
        BadOcp{"decomposition_not_bool", "ocp-pendulum", "max_iterations = 300", "decomposition = 1",
               {"ocp.indirect.decomposition", "true or false"}},
        BadOcp{"max_iterations_zero", "ocp-pendulum", "max_iterations = 300", "max_iterations = 0",
               {"ocp.indirect.max_iterations", "[1, 1000000]"}},
        BadOcp{"indirect_tolerance_negative", "ocp-pendulum", "max_iterations = 300", "tolerance = -1e-12",
               {"ocp.indirect.tolerance", "must be a number in (0, 0.1] (got -1e-12)"}},
        BadOcp{"indirect_unknown_key", "ocp-pendulum", "max_iterations = 300", "knots = 7",
               {"ocp.indirect.knots", "unknown key"}},
        BadOcp{"knots_two", "ocp-cart-pendulum", "knots = 7", "knots = 2", {"ocp.direct.knots", "[3, 1000]"}},
        BadOcp{"spline_unknown", "ocp-cart-pendulum", "spline = \"not-a-knot\"", "spline = \"clamped\"",
               {"ocp.direct.spline", "natural", "clamped"}},
        BadOcp{"gradients_unknown", "ocp-cart-pendulum", "starts = 1", "gradients = \"adjoint\"",
               {"ocp.direct.gradients", "finite-difference"}},
        BadOcp{"direct_tolerance_zero", "ocp-cart-pendulum", "starts = 1", "tolerance = 0",
               {"ocp.direct.tolerance", "(0, 0.1]", "(got 0)"}},
        BadOcp{"direct_tolerance_loose", "ocp-cart-pendulum", "starts = 1", "tolerance = 0.5",
               {"ocp.direct.tolerance", "(0, 0.1]"}},
        BadOcp{"starts_huge", "ocp-cart-pendulum", "starts = 1", "starts = 1000000", {"ocp.direct.starts", "[1, 10000]"}},
        BadOcp{"seed_huge", "ocp-connected-bodies", "seed = 1", "seed = 2147483648", {"ocp.direct.seed", "[0, 2147483647]"}},
        BadOcp{"max_evaluations_huge", "ocp-cart-pendulum", "starts = 1", "max_evaluations = 1000000000",
               {"ocp.direct.max_evaluations", "[1, 100000000]"}},
        BadOcp{"knots_huge", "ocp-cart-pendulum", "knots = 7", "knots = 1001", {"ocp.direct.knots", "[3, 1000]"}},
        BadOcp{"starts_zero", "ocp-cart-pendulum", "starts = 1", "starts = 0", {"ocp.direct.starts", "[1, 10000]"}},
        BadOcp{"seed_negative", "ocp-connected-bodies", "seed = 1", "seed = -1", {"ocp.direct.seed", "[0, "}},
        BadOcp{"solver_unknown", "ocp-cart-pendulum", "solver = \"slsqp\"", "solver = \"snopt\"",
               {"ocp.direct.solver", "ipopt", "snopt"}},
        BadOcp{"max_evaluations_zero", "ocp-cart-pendulum", "starts = 1", "max_evaluations = 0",
               {"ocp.direct.max_evaluations", "[1, "}},
        BadOcp{"initial_knots_wrong_length", "ocp-cart-pendulum", "starts = 1", "initial_knots = [0, 0, 0]",
               {"ocp.direct.initial_knots", "14 numbers"}},
        BadOcp{"hessian_with_slsqp", "ocp-cart-pendulum", "starts = 1", "hessian = \"cost\"",
               {"ocp.direct.hessian", "ipopt"}},
        BadOcp{"hessian_unknown", "ocp-cart-pendulum", "solver = \"slsqp\"", "solver = \"ipopt\"\nhessian = \"newton\"",
               {"ocp.direct.hessian", "limited-memory", "newton"}},
        BadOcp{"state_guess_unknown", "ocp-cart-pendulum", "solver = \"slsqp\"",
               "solver = \"ipopt\"\nstate_guess = \"random\"", {"ocp.direct.state_guess", "geodesic"}},
        BadOcp{"shooting_interval_zero", "ocp-cart-pendulum", "solver = \"slsqp\"",
               "solver = \"ipopt\"\nshooting_interval = 0", {"ocp.direct.shooting_interval", "[1, "}},
        BadOcp{"direct_unknown_key", "ocp-cart-pendulum", "starts = 1", "multiplier_guess = [1]",
               {"ocp.direct.multiplier_guess", "unknown key"}},
        BadOcp{"ocp_not_a_table", "free-body", "[parameters]", "ocp = 1\n\n[parameters]", {"ocp", "must be a table"}}),
    [](const ::testing::TestParamInfo<BadOcp>& info) { return std::string(info.param.what); });

TEST(OcpScenes, CliBadInputIsOneLineNamingTheFile) {
  // A scene without [ocp], and a bad [ocp] field in a user's file: exit 1, one line, no files.
  {
    TempDir dir;
    expect_bad_input(dir, run_testbed(dir, {"ocp", "free-body", "--out", "."}), {"free-body.toml", "ocp", "is required"});
  }
  {
    TempDir dir;
    write_text(dir.capture() / "bad.toml", edited_scene("ocp-pendulum", "W = [[1, 0, 0]", "W = [[1, 0.5, 0]"));
    expect_bad_input(dir, run_testbed(dir, {"ocp", (dir.capture() / "bad.toml").string(), "--out", "."}),
                     {"bad.toml", "ocp.W", "not symmetric"});
  }
  {
    TempDir dir;
    expect_bad_input(dir, run_testbed(dir, {"ocp", "pendulum", "--knots", "5", "--out", "."}),
                     {"--knots", "direct method only", "ocp.method is 'indirect'"});
  }
}

}  // namespace
}  // namespace lgvi::test
