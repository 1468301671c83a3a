// DDP (iLQR with an augmented Lagrangian, lgvi/ocp/ddp.hpp) on the direct method's discrete
// problems: the backward pass's gradient and expected change against central differences, the
// paper's two problems solved and compared with SLSQP on the same grid, bad options, an iteration
// cap.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "lgvi/ocp/ddp.hpp"
#include "lgvi/ocp/direct.hpp"
#include "test_support.hpp"

namespace lgvi::test {
namespace {

// The augmented-Lagrangian objective Phi = J + lambda^T r + mu/2 |r|^2 of the rolled-out node
// controls: the backward pass's exact gradient in u_0..u_N (adjoint) and its expected first-order
// change sum k^T Q_v (= dPhi/dalpha of the forward pass at alpha = 0, ddp.hpp) against central
// differences. Step a = kOcpFdStep (1 + |x|), bound kOcpFdTolerance relative (test_support.hpp:
// truncation a^2 |Phi'''| / 6 ~ 1e-12, round-off eps |Phi| / a ~ 2e-10 relative, margin ~1e3).
template <class Model>
void check_backward_pass(const typename Model::System& system, const typename Model::Transfer& problem,
                         const ocp::DdpOptions& o, const Eigen::VectorXd& knots, double rho) {
  const ocp::Ddp<Model> ddp(system, problem, o);
  auto nominal = ddp.make_trajectory(), trial = ddp.make_trajectory();
  auto gains = ddp.make_gains();
  nominal.controls = ddp.transcription().node_controls(knots);
  ASSERT_TRUE(ddp.rollout(nominal)) << nominal.failure;
  typename Model::VecR lambda;
  for (int i = 0; i < lambda.size(); ++i) lambda(i) = 0.1 * std::sin(1.0 + i);  // generic multipliers
  const double mu = 10.0;
  ASSERT_TRUE(ddp.backward(nominal, lambda, mu, rho, gains));
  const double phi = ddp.objective(nominal, lambda, mu);

  // (a) dPhi/dalpha of the forward pass.
  const double a = kOcpFdStep;
  ASSERT_TRUE(ddp.forward(nominal, gains, a, trial));
  const double plus = ddp.objective(trial, lambda, mu);
  ASSERT_TRUE(ddp.forward(nominal, gains, -a, trial));
  const double minus = ddp.objective(trial, lambda, mu);
  const double slope_fd = (plus - minus) / (2.0 * a);
  std::cout << "[ slope    ] expected " << gains.expected_linear << ", central differences " << slope_fd << "\n";
  EXPECT_LT(gains.expected_linear, 0.0);
  EXPECT_LE(std::abs(gains.expected_linear - slope_fd), kOcpFdTolerance * std::abs(gains.expected_linear));

  // (b) the gradient in the node controls (every 7th node, all components, both ends).
  Eigen::MatrixXd g_fd = Eigen::MatrixXd::Zero(Model::nu, nominal.controls.cols());
  Eigen::MatrixXd g_exact = g_fd;
  const Eigen::Index N = nominal.controls.cols() - 1;
  for (Eigen::Index j = 0; j <= N; j = (j + 7 > N && j < N) ? N : j + 7) {
    for (int c = 0; c < Model::nu; ++c) {
      const double x = nominal.controls(c, j), step = kOcpFdStep * (1.0 + std::abs(x));
      trial.controls = nominal.controls;
      trial.controls(c, j) = x + step;
      ASSERT_TRUE(ddp.rollout(trial));
      const double p = ddp.objective(trial, lambda, mu);
      trial.controls(c, j) = x - step;
      ASSERT_TRUE(ddp.rollout(trial));
      const double m = ddp.objective(trial, lambda, mu);
      g_fd(c, j) = (p - m) / (2.0 * step);
      g_exact(c, j) = gains.gradient(c, j);
    }
  }
  EXPECT_LE((g_exact - g_fd).norm(), kOcpFdTolerance * g_exact.norm()) << "exact\n" << g_exact << "\nfd\n" << g_fd;
  EXPECT_GT(std::abs(phi), 0.0);
}

TEST(DdpBackwardPass, CartPendulumGradientAndExpectedChangeMatchCentralDifferences) {
  const CartPendulum system = CartPendulum::paper();
  ocp::CartPendulumTransfer p = ocp::CartPendulumTransfer::paper();
  p.t_final = 1.0;  // short horizon, a generic point far from the optimum
  for (LgviForm form : {LgviForm::Printed, LgviForm::Symmetric}) {
    for (double rho : {0.0, 1e-3}) {
      SCOPED_TRACE(std::string(to_string(form)) + ", rho " + std::to_string(rho));
      ocp::DdpOptions o;
      o.form = form;
      o.h = 0.02;
      check_backward_pass<ocp::CartPendulumDirectModel>(system, p, o, ocp::default_initial_knots(system, o.knots), rho);
    }
  }
}

TEST(DdpBackwardPass, ConnectedBodiesGradientAndExpectedChangeMatchCentralDifferences) {
  const ConnectedBodies system = ConnectedBodies::paper();
  ocp::ConnectedBodiesTransfer p = ocp::ConnectedBodiesTransfer::paper();
  p.t_final = 1.0;
  for (LgviForm form : {LgviForm::Printed, LgviForm::Symmetric}) {
    SCOPED_TRACE(to_string(form));
    ocp::DdpOptions o;
    o.form = form;
    o.h = 0.02;
    check_backward_pass<ocp::ConnectedBodiesDirectModel>(system, p, o, ocp::default_initial_knots(system, o.knots),
                                                         0.0);
  }
}

// The node controls are a superset of the 7-knot splines' (u_j = S_j c), so on the same grid a
// DDP optimum in the basin of a spline optimum costs at most as much. Asserted: violation <= 1e-8
// and cost <= the spline optimum times (1 + 1e-6) (the solvers' own stopping tolerances: DDP's
// gradient test 1e-6 relative moves the cost by ~1e-7 relative, measured 254.48266..254.48269).
template <class Result>
void expect_converged(const Result& ddp) {
  std::cout << "[ ddp      ] " << ddp.summary.brief() << "\n";
  EXPECT_EQ(ddp.summary.status, ocp::DdpStatus::Converged) << ddp.summary.brief();
  EXPECT_LE(ddp.summary.violation, 1e-8);
  ASSERT_EQ(ddp.states.size(), ddp.summary.steps + 1);
  ASSERT_EQ(ddp.controls.cols(), static_cast<Eigen::Index>(ddp.summary.steps + 1));
}

// Cart-pendulum at h = 0.02 (100 steps), DDP and SLSQP from the default guess: measured 254.4827
// against SLSQP's 282.7390 (the spline's 7 knots are the restriction), 0.04 s and 0.07 s.
TEST(DdpSolve, CartPendulumConvergesBelowTheSplineCost) {
  const CartPendulum system = CartPendulum::paper();
  ocp::DdpOptions o;
  o.h = 0.02;
  ocp::DirectOptions d = o.direct();
  d.tolerance = 1e-10;
  const auto ddp = ocp::solve_ddp(system, ocp::CartPendulumTransfer::paper(), o);
  const auto slsqp = ocp::solve_direct(system, ocp::CartPendulumTransfer::paper(), d);
  std::cout << "[ slsqp    ] " << slsqp.summary.brief() << "\n";
  expect_converged(ddp);
  ASSERT_EQ(slsqp.summary.status, ocp::DirectStatus::Converged) << slsqp.summary.brief();
  EXPECT_LE(ddp.summary.cost, slsqp.summary.cost * (1.0 + 1e-6));
}

// Connected bodies at the paper's h = 0.01 from random start 1 (seed 1; about 0.3 s). On coarser
// grids SLSQP's starts mostly fail (h = 0.04: 2 of 8 feasible, at 3.46 and 14.67; h = 0.02: 1 of
// 8, 11.40), so the reference is the lowest spline optimum known at h = 0.01: 0.065091, reached by
// IPOPT (geodesic guess) from 6 of its 8 starts (README "Multiple shooting with IPOPT"; SLSQP's
// 8 starts reach 0.2496 at best). Measured 0.064808.
TEST(DdpSolve, ConnectedBodiesConvergesBelowTheSplineCost) {
  const ConnectedBodies system = ConnectedBodies::paper();
  ocp::DdpOptions o;
  o.first_start = 1;
  const auto ddp = ocp::solve_ddp(system, ocp::ConnectedBodiesTransfer::paper(), o);
  expect_converged(ddp);
  EXPECT_LE(ddp.summary.cost, 0.065091 * (1.0 + 1e-6));
  EXPECT_LE(ddp.summary.residual.tail<3>().norm(), 1e-8);  // Omega2_N, not imposed, implied
}

TEST(DdpSolve, BadOptionIsAStatusNamingIt) {
  const CartPendulum system = CartPendulum::paper();
  ocp::DdpOptions o;
  o.max_iterations = 0;
  auto r = ocp::solve_ddp(system, ocp::CartPendulumTransfer::paper(), o);
  EXPECT_EQ(r.summary.status, ocp::DdpStatus::InvalidInput);
  EXPECT_NE(r.summary.message.find("max_iterations"), std::string::npos) << r.summary.message;
  o = {};
  o.penalty_factor = 0.5;
  r = ocp::solve_ddp(system, ocp::CartPendulumTransfer::paper(), o);
  EXPECT_NE(r.summary.message.find("penalty_factor"), std::string::npos) << r.summary.message;
  o = {};
  o.h = 0.003;
  r = ocp::solve_ddp(system, ocp::CartPendulumTransfer::paper(), o);
  EXPECT_EQ(r.summary.status, ocp::DdpStatus::InvalidInput);
  EXPECT_NE(r.summary.message.find("h:"), std::string::npos) << r.summary.message;
}

// One iteration cannot reach 1e-8 from the default guess: max-iterations, finite numbers, output.
TEST(DdpSolve, OneIterationReportsMaxIterations) {
  const ConnectedBodies system = ConnectedBodies::paper();
  ocp::DdpOptions o;
  o.h = 0.04;
  o.max_iterations = 1;
  o.starts = 2;
  const auto r = ocp::solve_ddp(system, ocp::ConnectedBodiesTransfer::paper(), o);
  std::cout << "[ result   ] " << r.summary.brief() << "\n";
  EXPECT_EQ(r.summary.status, ocp::DdpStatus::MaxIterations) << r.summary.brief();
  ASSERT_EQ(r.summary.starts.size(), 2u);
  for (const ocp::DdpStart& st : r.summary.starts) {
    EXPECT_EQ(st.status, ocp::DdpStatus::MaxIterations);
    EXPECT_EQ(st.iterations, 1);
    EXPECT_TRUE(std::isfinite(st.cost) && std::isfinite(st.violation));
    EXPECT_TRUE(st.controls.allFinite());
  }
  EXPECT_TRUE(std::isfinite(r.summary.cost) && std::isfinite(r.summary.violation));
  EXPECT_EQ(r.states.size(), r.summary.steps + 1);
}

}  // namespace
}  // namespace lgvi::test
