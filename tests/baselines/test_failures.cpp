// Failures surface as statuses with the time reached (CVODE's flags, GSL's and odeint's step
// failures, the step budget), bad settings as InvalidInput naming the option, and nothing prints.
#include <gtest/gtest.h>

#include "baseline_cases.hpp"

namespace lgvi::test {
namespace {

const Pendulum3D& pendulum() {
  static const Pendulum3D p = Pendulum3D::paper();
  return p;
}

Trajectory run_pendulum(const std::string& method, CoordinateModel model, const SolverSettings& s,
                        double T = 2.0) {
  return run_attitude(method, model, pendulum(), {}, pendulum_R0(), pendulum_Omega0(), uniform_times(T, 20), s);
}

/// Settings the solvers refuse: InvalidInput naming `field`, its message holding `words`.
void expect_invalid(const std::string& method, CoordinateModel model, const SolverSettings& s, const std::string& field,
                    const std::string& words) {
  try {
    run_pendulum(method, model, s);
    ADD_FAILURE() << method << ": no InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.field(), field) << e.what();
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

TEST(CvodeFailure, StepBudgetIsAStatusWithTheTimeReached) {
  // CVODE steps one step per call (CV_ONE_STEP), so the run's budget is counted here, as for the
  // other libraries, not by CVODE's per-call mxstep (CV_TOO_MUCH_WORK).
  for (const std::string method : {"cvode-adams", "cvode-bdf"}) {
    SolverSettings s = adaptive(1e-10);
    s.max_steps = 10;
    const Trajectory tr = run_pendulum(method, CoordinateModel::Quaternion, s);
    std::cout << "[ status   ] " << tr.stats.brief() << "\n";
    EXPECT_EQ(tr.stats.status, IntegrationStatus::SolverFailed);
    EXPECT_NE(tr.stats.failure_detail.find(method + ": step budget of 10 steps exhausted"), std::string::npos)
        << tr.stats.failure_detail;
    EXPECT_EQ(tr.stats.steps, 10u);
    // The time CVODE reached after its 10 steps: past the start, before the first output.
    EXPECT_GT(tr.stats.failed_time, 0.0);
    EXPECT_LT(tr.stats.failed_time, 0.1);
    EXPECT_EQ(tr.t.size(), 1u);  // only the initial sample
    EXPECT_NE(tr.stats.brief().find("solver failed at t = "), std::string::npos);
  }
}

TEST(Tolerances, BelowRoundOffIsRefusedBeforeAnyStep) {
  // Issue 34, N12: a tolerance below round-off used to reach the solvers, which spent their step
  // budget (odeint-rkf78 with atol = 1e-300: 5e7 steps at t = 0, 28.6 s; the pendulum longer)
  // or stopped on CVODE's CV_TOO_MUCH_ACC. The one range of every adaptive method
  // (baselines/tolerance.hpp) refuses it up front, naming the option and why.
  for (const baselines::SolverInfo& info : baselines::solver_list()) {
    if (info.step_control == baselines::StepControl::Fixed) continue;
    const CoordinateModel model = CoordinateModel::Quaternion;
    expect_invalid(info.name, model, adaptive(1e-300), "rtol", "is below round-off");
    SolverSettings only_atol = adaptive(1e-6);
    only_atol.atol = 1e-300;
    expect_invalid(info.name, model, only_atol, "atol", "is below round-off");
    SolverSettings loose = adaptive(2.0);
    expect_invalid(info.name, model, loose, "rtol", "must be a number in [1e-14, 0.1] (got 2)");
  }
}

TEST(Tolerances, TheFloorItselfEndsPromptlyOnEveryAdaptiveMethod) {
  // At rtol = atol = kMinTolerance every adaptive method completes the pendulum's 2 s: the floor
  // is reachable, not merely accepted.
  for (const baselines::SolverInfo& info : baselines::solver_list()) {
    if (info.step_control == baselines::StepControl::Fixed) continue;
    const Trajectory tr = run_pendulum(info.name, CoordinateModel::Quaternion, adaptive(baselines::kMinTolerance));
    EXPECT_TRUE(tr.stats.ok()) << info.name << ": " << tr.stats.brief();
    EXPECT_LT(tr.stats.wall_seconds, 2.0) << info.name;
  }
}

TEST(StepBudget, EveryLibraryReportsIt) {
  for (const std::string method : {"odeint-rk4", "odeint-dopri5", "odeint-rkf78", "odeint-bs", "gsl-rk8pd",
                                   "gsl-rk4imp", "gsl-msbdf", "arkode-erk", "arkode-dirk"}) {
    SolverSettings s = is_fixed_step(method) ? fixed(1e-3) : adaptive(1e-10);
    s.max_steps = 7;
    const Trajectory tr = run_pendulum(method, CoordinateModel::Quaternion, s);
    EXPECT_EQ(tr.stats.status, IntegrationStatus::SolverFailed) << method;
    EXPECT_NE(tr.stats.failure_detail.find(method + ": step budget of 7 steps exhausted"), std::string::npos)
        << tr.stats.failure_detail;
    EXPECT_EQ(tr.stats.steps, 7u) << method;
    EXPECT_GT(tr.stats.failed_time, 0.0) << method;
  }
}

TEST(Observer, CanStopTheRun) {
  const FreeRigidBody body = free_body();
  using Mech = baselines::AttitudeMechanics<FreeRigidBody>;
  const baselines::CoordinateOde<baselines::QuaternionChart, Mech> ode{Mech(body)};
  const auto y0 = ode.initial_state({free_body_R0()}, {free_body_Omega0()});
  const std::vector<double> times = uniform_times(1.0, 10);
  for (const std::string& method : baselines::solver_names()) {
    std::size_t calls = 0;
    const Stats stats = baselines::integrate(method, ode, std::span<const double>(y0.data(), y0.size()), times,
                                             is_fixed_step(method) ? fixed(0.01) : adaptive(1e-8),
                                             [&](std::size_t i, double, const double*) {
                                               ++calls;
                                               return i < 3;
                                             });
    EXPECT_EQ(stats.status, IntegrationStatus::ObserverStopped) << method;
    EXPECT_EQ(calls, 4u) << method;
  }
}

TEST(Settings, BadCombinationsAreRejectedNamingTheOption) {
  expect_invalid("odeint-rk4", CoordinateModel::Quaternion, SolverSettings{}, "h", "fixed-step method: it needs a step h");
  expect_invalid("gsl-rk4imp", CoordinateModel::Matrix, adaptive(1e-8), "h", "fixed-step");
  SolverSettings both = fixed(0.01);
  both.rtol = 1e-8;
  expect_invalid("odeint-rk4", CoordinateModel::Quaternion, both, "rtol", "takes a step h, not tolerances");
  expect_invalid("cvode-bdf", CoordinateModel::Quaternion, fixed(0.01), "h", "adaptive method");
  expect_invalid("gsl-rk8pd", CoordinateModel::Quaternion, adaptive(-1.0), "rtol", "[1e-14, 0.1] (got -1)");
  expect_invalid("odeint-rk4", CoordinateModel::Quaternion, fixed(0.0), "h", "> 0");
  expect_invalid("odeint-rk4", CoordinateModel::Quaternion, fixed(0.03), "h", "not on the grid");
  for (const std::string method : {"cvode-adams", "gsl-msbdf", "arkode-erk", "arkode-dirk"}) {
    expect_invalid(method, CoordinateModel::QuaternionRenormalized, adaptive(1e-8), "model", "no post-step hook");
  }
  SolverSettings dq = adaptive(1e-8);
  dq.jacobian = baselines::JacobianSource::DifferenceQuotient;
  expect_invalid("gsl-msbdf", CoordinateModel::Quaternion, dq, "jacobian", "only CVODE");
  expect_invalid("rk45", CoordinateModel::Quaternion, adaptive(1e-8), "method", "unknown method 'rk45' (known: cvode-adams");
  EXPECT_THROW(baselines::parse_coordinate_model("euler-123"), InvalidInput);
}

TEST(Settings, DefaultsAreDocumented) {
  using Mech = baselines::AttitudeMechanics<Pendulum3D>;
  const baselines::CoordinateOde<baselines::QuaternionChart, Mech> ode{Mech(pendulum())};
  const SolverSettings s = baselines::resolve_settings(baselines::solver_info("cvode-bdf"), SolverSettings{}, ode);
  EXPECT_EQ(*s.rtol, baselines::kDefaultRtol);
  EXPECT_EQ(*s.atol, baselines::kDefaultRtol);
}

}  // namespace
}  // namespace lgvi::test
