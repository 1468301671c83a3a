// Every numeric option of `lgvi-testbed ocp` (and of Python's solve_ocp, which runs the same
// run_ocp_command) out of its stated range (issue 34, N7; N5 for the steps): each is refused
// before anything is solved or written, naming the option and its range, which is the range the
// [ocp] table's key has (the options structs' Ranges, lgvi/ocp/indirect.hpp, direct.hpp). A 0 is a
// value like any other: it used to mean "the scene's" and was accepted silently. In process
// (run_ocp_command), so the 60-odd cases take well under a second; the CLI's one error line and
// exit status 1 are tests/experiments/cli/test_cli.cpp's (CliBadArguments).
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "experiments/cli/cli_support.hpp"
#include "experiments/ocp/ocp_command.hpp"
#include "experiments/scene/ocp_scene.hpp"
#include "experiments/scene/scene.hpp"

namespace lgvi::test {
namespace {

using experiments::OcpCommand;

struct BadOption {
  const char* what;
  const char* system;
  std::function<void(OcpCommand&)> set;
  std::string field;                 ///< the error's field: the option (or the scene's key)
  std::vector<std::string> needles;  ///< the range and the value
};

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

class OcpBadOption : public ::testing::TestWithParam<BadOption> {};

TEST_P(OcpBadOption, IsRefusedNamingTheOptionAndItsRange) {
  const BadOption& b = GetParam();
  TempDir dir;
  OcpCommand cmd;
  cmd.system = b.system;
  cmd.out = (dir.work() / "out").string();
  b.set(cmd);
  std::ostringstream out, err;
  std::string field, message;
  try {
    const int code = experiments::run_ocp_command(cmd, "test", out, err);
    ADD_FAILURE() << b.what << ": accepted (exit " << code << "): " << out.str() << err.str();
  } catch (const InvalidInput& e) {
    field = e.field();
    message = e.what();
  } catch (const experiments::SceneError& e) {
    field = e.field();
    message = e.what();
  }
  EXPECT_EQ(field, b.field) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  for (const std::string& n : b.needles) EXPECT_NE(message.find(n), std::string::npos) << "'" << n << "' not in: " << message;
  EXPECT_FALSE(fs::exists(dir.work() / "out")) << "nothing may be written";
}

// Indirect (pendulum, dumbbell; h = 1e-3 over 1 s, 1000 steps) and direct (cart-pendulum).
INSTANTIATE_TEST_SUITE_P(
    All, OcpBadOption,
    ::testing::Values(
        // Steps and horizon (N5: 10^7 steps took 3.8 GB, 10^8 ended in std::bad_alloc).
        BadOption{"h_zero", "pendulum", [](OcpCommand& c) { c.h = 0.0; }, "--h", {"(0, 1e100]", "(got 0)"}},
        BadOption{"h_negative", "pendulum", [](OcpCommand& c) { c.h = -1e-3; }, "--h", {"(0, 1e100]"}},
        BadOption{"h_nan", "pendulum", [](OcpCommand& c) { c.h = kNan; }, "--h", {"(0, 1e100]", "nan"}},
        BadOption{"h_huge", "pendulum", [](OcpCommand& c) { c.h = 1e101; }, "--h", {"(0, 1e100]"}},
        BadOption{"h_too_many_steps", "pendulum", [](OcpCommand& c) { c.h = 1e-7; }, "integration.h (--h)",
                  {"ocp-pendulum.toml", "gives 10000000 steps", "at most 1000000"}},
        BadOption{"steps_zero", "pendulum", [](OcpCommand& c) { c.steps = 0; }, "--steps", {"[1, 1000000]", "(got 0)"}},
        BadOption{"steps_negative", "pendulum", [](OcpCommand& c) { c.steps = -5; }, "--steps", {"[1, 1000000]"}},
        BadOption{"steps_huge", "pendulum", [](OcpCommand& c) { c.steps = 100000000; }, "--steps",
                  {"[1, 1000000]", "(got 100000000)"}},
        BadOption{"h_and_steps", "pendulum", [](OcpCommand& c) { c.h = 1e-3; c.steps = 1000; }, "--h", {"not both"}},
        BadOption{"t_final_zero", "dumbbell", [](OcpCommand& c) { c.t_final = 0.0; }, "--t-final", {"(0, 1e100]"}},
        BadOption{"t_final_inf", "dumbbell", [](OcpCommand& c) { c.t_final = kInf; }, "--t-final", {"(0, 1e100]"}},
        BadOption{"t_final_too_many_steps", "pendulum", [](OcpCommand& c) { c.t_final = 2000.0; },
                  "integration.t_final (--t-final)", {"gives 2000000 steps", "at most 1000000"}},
        // The indirect method's settings ([ocp.indirect]'s ranges).
        BadOption{"max_iterations_zero", "pendulum", [](OcpCommand& c) { c.max_iterations = 0; }, "--max-iterations",
                  {"must be an integer in [1, 1000000] (got 0)"}},
        BadOption{"max_iterations_negative", "pendulum", [](OcpCommand& c) { c.max_iterations = -3; },
                  "--max-iterations", {"[1, 1000000]"}},
        BadOption{"max_iterations_huge", "dumbbell", [](OcpCommand& c) { c.max_iterations = 10000000; },
                  "--max-iterations", {"[1, 1000000]"}},
        BadOption{"lm_damping_zero", "dumbbell",
                  [](OcpCommand& c) { c.globalization = "levenberg-marquardt"; c.lm_damping = 0.0; }, "--lm-damping",
                  {"must be a number in (0, 1e10] (got 0)"}},
        BadOption{"lm_damping_huge", "dumbbell", [](OcpCommand& c) { c.lm_damping = 1e300; }, "--lm-damping",
                  {"(0, 1e10]"}},
        BadOption{"lm_damping_nan", "dumbbell", [](OcpCommand& c) { c.lm_damping = kNan; }, "--lm-damping",
                  {"(0, 1e10]"}},
        BadOption{"nonmonotone_memory_zero", "pendulum", [](OcpCommand& c) { c.nonmonotone_memory = 0; },
                  "--nonmonotone-memory", {"[1, 1000]", "(got 0)"}},
        BadOption{"nonmonotone_memory_huge", "pendulum", [](OcpCommand& c) { c.nonmonotone_memory = 5000000000LL; },
                  "--nonmonotone-memory", {"[1, 1000]"}},
        BadOption{"guess_nan", "pendulum", [](OcpCommand& c) { c.guess = {1, 1, kNan, 1, 1, 1}; }, "--guess",
                  {"must be finite"}},
        BadOption{"guess_inf", "pendulum", [](OcpCommand& c) { c.guess = {1, 1, 1, 1, 1, kInf}; }, "--guess",
                  {"must be finite"}},
        BadOption{"guess_huge", "pendulum", [](OcpCommand& c) { c.guess = {1e300, 1, 1, 1, 1, 1}; }, "--guess",
                  {"magnitude between 1e-100 and 1e100"}},
        BadOption{"guess_tiny", "pendulum", [](OcpCommand& c) { c.guess = {1e-300, 1, 1, 1, 1, 1}; }, "--guess",
                  {"magnitude between 1e-100 and 1e100"}},
        BadOption{"guess_count", "pendulum", [](OcpCommand& c) { c.guess = {1, 2}; }, "--guess", {"needs 6 values"}},
        BadOption{"sphere_radius_zero", "dumbbell", [](OcpCommand& c) { c.sphere_radius = 0.0; }, "--sphere-radius",
                  {"(0, 1e100]"}},
        BadOption{"sphere_radius_negative", "dumbbell", [](OcpCommand& c) { c.sphere_radius = -0.05; },
                  "--sphere-radius", {"(0, 1e100]"}},
        BadOption{"sphere_radius_huge", "dumbbell", [](OcpCommand& c) { c.sphere_radius = 1e200; }, "--sphere-radius",
                  {"(0, 1e100]"}},
        BadOption{"sphere_radius_not_dumbbell", "pendulum", [](OcpCommand& c) { c.sphere_radius = 0.05; },
                  "--sphere-radius", {"dumbbell"}},
        // The direct method's settings ([ocp.direct]'s ranges).
        BadOption{"knots_two", "cart-pendulum", [](OcpCommand& c) { c.knots = 2; }, "--knots",
                  {"must be an integer in [3, 1000] (got 2)"}},
        BadOption{"knots_zero", "cart-pendulum", [](OcpCommand& c) { c.knots = 0; }, "--knots", {"[3, 1000]"}},
        BadOption{"knots_huge", "cart-pendulum", [](OcpCommand& c) { c.knots = 1000000; }, "--knots", {"[3, 1000]"}},
        BadOption{"knots_past_the_grid", "cart-pendulum", [](OcpCommand& c) { c.knots = 1000; c.steps = 100; },
                  "--knots", {"at most the grid's 101 nodes"}},
        BadOption{"tolerance_zero", "cart-pendulum", [](OcpCommand& c) { c.tolerance = 0.0; }, "--tolerance",
                  {"must be a number in (0, 0.1] (got 0)"}},
        BadOption{"tolerance_negative", "cart-pendulum", [](OcpCommand& c) { c.tolerance = -1e-10; }, "--tolerance",
                  {"(0, 0.1]"}},
        BadOption{"tolerance_loose", "cart-pendulum", [](OcpCommand& c) { c.tolerance = 1e300; }, "--tolerance",
                  {"(0, 0.1]"}},
        BadOption{"tolerance_nan", "cart-pendulum", [](OcpCommand& c) { c.tolerance = kNan; }, "--tolerance",
                  {"(0, 0.1]"}},
        BadOption{"starts_zero", "cart-pendulum", [](OcpCommand& c) { c.starts = 0; }, "--starts",
                  {"must be an integer in [1, 10000] (got 0)"}},
        BadOption{"starts_huge", "cart-pendulum", [](OcpCommand& c) { c.starts = 1000000000; }, "--starts",
                  {"[1, 10000]"}},
        BadOption{"seed_negative", "cart-pendulum", [](OcpCommand& c) { c.seed = -1; }, "--seed", {"[0, 2147483647]"}},
        BadOption{"seed_huge", "cart-pendulum", [](OcpCommand& c) { c.seed = 1LL << 40; }, "--seed",
                  {"[0, 2147483647]"}},
        BadOption{"first_start_negative", "cart-pendulum", [](OcpCommand& c) { c.first_start = -1; }, "--first-start",
                  {"[0, 1000000]"}},
        BadOption{"first_start_huge", "connected-bodies", [](OcpCommand& c) { c.first_start = 2000000000; },
                  "--first-start", {"[0, 1000000]"}},
        BadOption{"max_evaluations_zero", "cart-pendulum", [](OcpCommand& c) { c.max_iterations = 0; },
                  "--max-iterations", {"must be an integer in [1, 100000000] (got 0)"}},
        BadOption{"max_evaluations_huge", "connected-bodies", [](OcpCommand& c) { c.max_iterations = 1000000000000LL; },
                  "--max-iterations", {"[1, 100000000]"}},
        BadOption{"shooting_interval_zero", "cart-pendulum",
                  [](OcpCommand& c) { c.solver = "ipopt"; c.shooting_interval = 0; }, "--shooting-interval",
                  {"[1, 1000000]", "(got 0)"}},
        BadOption{"shooting_interval_huge", "cart-pendulum",
                  [](OcpCommand& c) { c.solver = "ipopt"; c.shooting_interval = 10000000; }, "--shooting-interval",
                  {"[1, 1000000]"}},
        BadOption{"shooting_interval_with_slsqp", "cart-pendulum", [](OcpCommand& c) { c.shooting_interval = 10; },
                  "--shooting-interval", {"--solver ipopt only"}},
        BadOption{"hessian_with_slsqp", "cart-pendulum", [](OcpCommand& c) { c.hessian = "cost"; }, "--hessian",
                  {"--solver ipopt only"}},
        BadOption{"state_guess_with_slsqp", "cart-pendulum", [](OcpCommand& c) { c.state_guess = "simulated"; },
                  "--state-guess", {"--solver ipopt only"}},
        // Options of the other method.
        BadOption{"starts_for_indirect", "pendulum", [](OcpCommand& c) { c.starts = 0; }, "--starts",
                  {"direct method only"}},
        BadOption{"first_start_for_indirect", "pendulum", [](OcpCommand& c) { c.first_start = 2; }, "--first-start",
                  {"direct method only"}},
        BadOption{"lm_damping_for_direct", "cart-pendulum", [](OcpCommand& c) { c.lm_damping = 1e-3; }, "--lm-damping",
                  {"indirect method only"}}),
    [](const ::testing::TestParamInfo<BadOption>& info) { return std::string(info.param.what); });

// N14: what the solver itself refuses is named as the option that set it ("globalization: ..."
// named the solver's field, not the option given), and without one as the solver's field.
TEST(OcpOptions, TheSolversRefusalNamesTheOptionThatSetIt) {
  TempDir dir;
  OcpCommand cmd;
  cmd.system = "pendulum";
  cmd.out = (dir.work() / "out").string();
  cmd.globalization = "homotopy";
  std::ostringstream out, err;
  EXPECT_EQ(experiments::run_ocp_command(cmd, "test", out, err), 1);
  EXPECT_EQ(err.str().rfind("error: --globalization: homotopy inverts the full sensitivity", 0), 0u) << err.str();
  EXPECT_FALSE(fs::exists(dir.work() / "out"));
}

// The options at the ends of their ranges are accepted (the ranges are the stated ones, not
// narrower): checked without solving, through the scene with the command's values in it.
TEST(OcpOptions, TheStepCapItselfLoads) {
  experiments::SceneOverrides o;
  o.h = 1e-6;  // 10^6 steps of the pendulum's 1 s
  const experiments::Scene s =
      experiments::load_scene(experiments::resolve_ocp_scene("pendulum", experiments::default_scenes_dir()), o);
  EXPECT_EQ(s.horizon.steps, 1000000u);
}

}  // namespace
}  // namespace lgvi::test
