// The replayed yardstick (baselines/ocp_replay.hpp): closed forms of a free body under a constant
// and a ramped moment, rest states of the multibody examples, bad input, and the replayed
// violation of converged discrete solutions shrinking like h^2 (symmetric form).
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <vector>

#include "baselines/ocp_replay.hpp"
#include "lgvi/ocp/indirect.hpp"
#include "lgvi/so3.hpp"
#include "test_support.hpp"

namespace lgvi {
namespace {

using baselines::ReplayControls;
using baselines::ReplayInterpolation;
using baselines::ReplayResult;

// The replay's solver keeps the local error below 1e-13 (relative and absolute) in each of its
// intervals; the global error of these O(1) states over a few dozen intervals stays within a few
// hundred times that (the baselines' tests measure global errors a modest multiple of rtol).
constexpr double kReplayTolerance = 1e-10;

const FreeRigidBody kBody(Vec3(1.2, 0.9, 0.6).asDiagonal());

/// A free body at rest spun about its principal axis e1 by the moment e1 m(t) = e1 (a + b t):
/// Omega_1 = (a t + b t^2 / 2) / J1, angle (a t^2 / 2 + b t^3 / 6) / J1. The target is that state
/// at T, so the exact replay's violation is 0.
ocp::TransferProblem spin_up(double a, double b, double T) {
  const double J1 = kBody.inertia.J(0, 0);
  ocp::TransferProblem p;
  p.R0 = Mat3::Identity();
  p.Omega0 = Vec3::Zero();
  p.Rf = so3::exp(Vec3((a * T * T / 2 + b * T * T * T / 6) / J1, 0, 0));
  p.Omegaf = Vec3((a * T + b * T * T / 2) / J1, 0, 0);
  p.t_final = T;
  return p;
}

ReplayControls nodes(int N, double T, ReplayInterpolation kind, const std::function<Vec3(double)>& u) {
  ReplayControls c;
  c.h = T / N;
  c.interpolation = kind;
  c.u.resize(3, N + 1);
  for (int j = 0; j <= N; ++j) c.u.col(j) = u(j * c.h);
  return c;
}

TEST(Replay, ConstantMomentOnAFreeBodyMatchesItsClosedFormInBothInterpolations) {
  const double a = 0.7, T = 2.0;
  for (const ReplayInterpolation kind : {ReplayInterpolation::ZeroOrderHold, ReplayInterpolation::PiecewiseLinear}) {
    const ReplayControls c = nodes(10, T, kind, [&](double) { return Vec3(a, 0, 0); });
    const ReplayResult r = baselines::replay(kBody, spin_up(a, 0.0, T), c);
    ASSERT_TRUE(r.ok) << r.message;
    std::cout << "[ replay   ] " << to_string(kind) << ": violation " << r.violation << ", cost " << r.cost
              << ", |q| drift " << r.quaternion_drift << ", " << r.steps << " steps\n";
    EXPECT_LT(r.violation, kReplayTolerance);
    EXPECT_NEAR(r.cost, a * a * T / 2, 1e-14 * a * a * T);  // int |u|^2 / 2
    EXPECT_LT(r.quaternion_drift, kReplayTolerance);
    EXPECT_EQ(r.residual.size(), 6);
  }
}

TEST(Replay, RampedMomentIsExactPiecewiseLinearAndAStaircaseZeroOrderHold) {
  const double b = 0.5, T = 2.0;
  const int N = 8;
  const auto ramp = [&](double t) { return Vec3(b * t, 0, 0); };
  {  // the linear interpolant of a linear control is that control
    const ReplayResult r =
        baselines::replay(kBody, spin_up(0.0, b, T), nodes(N, T, ReplayInterpolation::PiecewiseLinear, ramp));
    ASSERT_TRUE(r.ok) << r.message;
    EXPECT_LT(r.violation, kReplayTolerance);
    EXPECT_NEAR(r.cost, b * b * T * T * T / 6, 1e-14 * b * b * T * T * T);
  }
  {  // the hold u_{k+1} on (t_k, t_{k+1}]: a staircase of moments; the residual is the staircase's
     // closed form (summed interval by interval) minus the ramp's
    const ReplayControls c = nodes(N, T, ReplayInterpolation::ZeroOrderHold, ramp);
    const ReplayResult r = baselines::replay(kBody, spin_up(0.0, b, T), c);
    ASSERT_TRUE(r.ok) << r.message;
    const double h = T / N, J1 = kBody.inertia.J(0, 0);
    double angle = 0.0, omega = 0.0, cost = 0.0;  // the staircase exactly, interval by interval
    for (int k = 0; k < N; ++k) {
      const double m = b * (k + 1) * h;
      angle += omega * h + m * h * h / (2 * J1);
      omega += m * h / J1;
      cost += m * m * h / 2;
    }
    const double exact_angle = b * T * T * T / (6 * J1), exact_omega = b * T * T / (2 * J1);
    EXPECT_NEAR(r.residual(0), angle - exact_angle, kReplayTolerance);
    EXPECT_NEAR(r.residual(3), omega - exact_omega, kReplayTolerance);
    EXPECT_NEAR(r.cost, cost, 1e-14 * cost);
    EXPECT_GT(std::abs(angle - exact_angle), 1e3 * kReplayTolerance);  // the case tells the two apart
  }
}

TEST(Replay, MultibodyRestStatesStayAtRestUnderZeroControl) {
  {
    ocp::CartPendulumTransfer p;  // upright at rest: an equilibrium (unstable; 2 s grow round-off ~e^6)
    p.Rf = p.R0;
    ReplayControls c;
    c.h = 0.05;
    c.u = Eigen::MatrixXd::Zero(2, 41);
    const ReplayResult r = baselines::replay(CartPendulum::paper(), p, c);
    ASSERT_TRUE(r.ok) << r.message;
    EXPECT_LT(r.violation, kReplayTolerance);
    EXPECT_EQ(r.cost, 0.0);
    EXPECT_EQ(r.residual.size(), 10);
  }
  {
    ocp::ConnectedBodiesTransfer p;  // no potential: rest stays rest
    p.R1_0 = so3::exp(Vec3(0.3, -0.2, 0.1));
    p.R1_f = p.R1_0;
    p.R2_f = p.R2_0;
    ReplayControls c;
    c.h = 0.1;
    c.u = Eigen::MatrixXd::Zero(3, 41);
    const ReplayResult r = baselines::replay(ConnectedBodies::paper(), p, c);
    ASSERT_TRUE(r.ok) << r.message;
    EXPECT_LT(r.violation, kReplayTolerance);
    EXPECT_EQ(r.residual.size(), 12);
  }
}

TEST(Replay, BadControlsAreNamedErrors) {
  const ocp::TransferProblem p = spin_up(1.0, 0.0, 1.0);
  ReplayControls c = nodes(4, 1.0, ReplayInterpolation::ZeroOrderHold, [](double) { return Vec3(1, 0, 0); });
  const auto expect_field = [&](const ReplayControls& bad, const std::string& field) {
    try {
      baselines::replay(kBody, p, bad);
      ADD_FAILURE() << "no error for " << field;
    } catch (const InvalidInput& e) {
      EXPECT_EQ(e.field(), field) << e.what();
    }
  };
  ReplayControls bad = c;
  bad.u = Eigen::MatrixXd::Zero(2, 5);
  expect_field(bad, "controls");
  bad = c;
  bad.u.resize(3, 1);
  bad.u.setZero();
  expect_field(bad, "controls");
  bad = c;
  bad.u(1, 2) = std::nan("");
  expect_field(bad, "controls");
  bad = c;
  bad.h = 0.0;
  expect_field(bad, "controls");
  bad = c;
  bad.W = Eigen::MatrixXd::Identity(2, 2);
  expect_field(bad, "W");
  ReplayResult r;
  EXPECT_THROW(r = baselines::replay(kBody, p, c, {.method = "gsl-rk8pd", .rtol = 1e-20, .atol = 1e-20}),
               InvalidInput);
}

TEST(Replay, AnExhaustedStepBudgetIsAFailedReplayWithItsReason) {
  const ReplayControls c = nodes(10, 2.0, ReplayInterpolation::ZeroOrderHold, [](double) { return Vec3(1, 0, 0); });
  baselines::ReplayOptions o;
  o.max_steps = 5;  // the free body's spin-up takes 3 steps per interval here
  const ReplayResult r = baselines::replay(kBody, spin_up(1.0, 0.0, 2.0), c, o);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.message.find("step"), std::string::npos) << r.message;
  EXPECT_TRUE(std::isnan(r.violation));
}

/// The pendulum's reorientation (section 3.2) solved in the symmetric form at N steps, its
/// control replayed piecewise linearly.
ReplayResult replayed_pendulum(int N) {
  const ocp::TransferProblem problem = ocp::TransferProblem::pendulum_paper();
  ocp::ShootingOptions o;
  o.form = LgviForm::Symmetric;
  o.h = problem.t_final / N;
  o.initial_multiplier = Eigen::VectorXd::Ones(6);
  o.max_iterations = 300;
  const Pendulum3D pendulum = Pendulum3D::paper();
  const auto result = ocp::solve_indirect(pendulum, problem, o);
  EXPECT_TRUE(result.summary.converged()) << result.summary.brief();
  ReplayControls c;
  c.h = o.h;
  c.interpolation = baselines::replay_interpolation(o.form);
  c.u.resize(3, N + 1);
  for (int j = 0; j <= N; ++j) c.u.col(j) = result.sweep.controls[static_cast<std::size_t>(j)];
  const ReplayResult r = baselines::replay(pendulum, problem, c);
  EXPECT_TRUE(r.ok) << r.message;
  std::cout << "[ replay   ] pendulum, symmetric, N = " << N << ": own violation " << result.summary.violation
            << ", cost " << result.summary.cost << "; replayed violation " << r.violation << ", cost " << r.cost
            << "\n";
  return r;
}

TEST(Replay, ReplayedViolationOfTheSymmetricFormShrinksLikeHSquared) {
  // A second-order discretization: the replayed terminal state is off by O(h^2), so halving h
  // divides the violation by 4 (2^order; accepted within orders 1.7..2.3) and the cost difference
  // between the replayed and the discrete cost likewise shrinks.
  const ReplayResult coarse = replayed_pendulum(50), fine = replayed_pendulum(100), finer = replayed_pendulum(200);
  for (const auto& [a, b] : {std::pair{coarse, fine}, std::pair{fine, finer}}) {
    const double order = std::log2(a.violation / b.violation);
    std::cout << "[ replay   ] observed order " << order << "\n";
    EXPECT_GT(order, 1.7);
    EXPECT_LT(order, 2.3);
  }
}

}  // namespace
}  // namespace lgvi
