// Continuous necessary conditions of the pendulum and the dumbbell (baselines/pontryagin.hpp): the costate
// equations against finite differences of the Hamiltonian, the analytic Jacobian of the
// state-costate ODE, the shooting Jacobian (sensitivities vs differences), convergence on the
// paper's transfer and agreement of the cost with the discrete optimum within its O(h^2)
// discretization error, and named failures.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <random>
#include <vector>

#include "baselines/pontryagin.hpp"
#include "lgvi/ocp/indirect.hpp"
#include "lgvi/so3.hpp"
#include "test_support.hpp"

namespace lgvi::test {
namespace {

using baselines::ContinuousShootingOptions;
using baselines::PendulumPontryaginOde;
using baselines::Vec6;
using ocp::ShootingStatus;
using ocp::TransferProblem;

Vec6 random6(std::mt19937_64& rng, double scale) {
  std::normal_distribution<double> n(0.0, scale);
  Vec6 v;
  for (int i = 0; i < 6; ++i) v(i) = n(rng);
  return v;
}

void expect_no_nan(const ocp::ShootingSummary& S) {
  EXPECT_FALSE(std::isnan(S.cost));
  EXPECT_FALSE(std::isnan(S.violation));
  EXPECT_TRUE(S.multiplier.allFinite());
  for (const auto& r : S.history) {
    EXPECT_FALSE(std::isnan(r.violation) || std::isnan(r.cost) || std::isnan(r.cond_inverted) || std::isnan(r.step_norm));
  }
  EXPECT_FALSE(S.message.empty() && !S.converged()) << "a failure must say what failed";
}

/// The discrete optimum of the paper's pendulum transfer (symmetric form, step h), from the
/// discrete solver's documented guess.
ocp::ShootingSummary discrete(double h) {
  ocp::ShootingOptions o;
  o.form = LgviForm::Symmetric;
  o.h = h;
  o.initial_multiplier = Eigen::VectorXd::Ones(6);
  return ocp::solve_indirect(Pendulum3D::paper(), TransferProblem::pendulum_paper(), o).summary;
}

// lambda_R' = lambda_R x Omega - dH/deta (left trivialization: the coadjoint term), lambda_Pi' =
// -dH/dPi, the state equations Omega = dH/dlambda_R, Pi' = dH/dlambda_Pi, and dH/du = 0 at the
// optimal control; central differences with step kFdStep, tolerance kFdTolerance relative.
TEST(Pontryagin, CostateEquationsMatchHamiltonianDerivatives) {
  auto rng = make_rng(31);
  const Pendulum3D p = Pendulum3D::paper();
  Mat3 W;
  W << 2.0, 0.3, 0.0, 0.3, 1.0, -0.2, 0.0, -0.2, 1.5;
  const PendulumPontryaginOde ode(p, W);
  for (int trial = 0; trial < 10; ++trial) {
    const Mat3 R = so3::random_rotation(rng);
    const Vec3 Pi = random6(rng, 1.0).head<3>();
    const Vec6 lambda = random6(rng, 2.0);
    const Vec3 u = ode.control(R, lambda);
    const double a = kFdStep;
    Vec6 dH_eta_Pi;  // [dH/deta; dH/dPi]
    Vec6 dH_lambda;
    Vec3 dH_u;
    for (int i = 0; i < 3; ++i) {
      const Vec3 e = a * Vec3::Unit(i);
      dH_eta_Pi(i) = (ode.hamiltonian(R * so3::exp(e), Pi, lambda, u) - ode.hamiltonian(R * so3::exp(-e), Pi, lambda, u)) / (2 * a);
      dH_eta_Pi(3 + i) = (ode.hamiltonian(R, Pi + e, lambda, u) - ode.hamiltonian(R, Pi - e, lambda, u)) / (2 * a);
      dH_u(i) = (ode.hamiltonian(R, Pi, lambda, u + e) - ode.hamiltonian(R, Pi, lambda, u - e)) / (2 * a);
    }
    for (int i = 0; i < 6; ++i) {
      const Vec6 e = a * Vec6::Unit(i);
      dH_lambda(i) = (ode.hamiltonian(R, Pi, lambda + e, u) - ode.hamiltonian(R, Pi, lambda - e, u)) / (2 * a);
    }
    const Vec6 rate = ode.costate_rate(R, Pi, lambda);
    Vec6 expected;
    expected << lambda.head<3>().cross(p.inertia.J_inverse * Pi) - dH_eta_Pi.head<3>(), -dH_eta_Pi.tail<3>();
    EXPECT_LT((rate - expected).norm(), kFdTolerance * (1.0 + expected.norm())) << "trial " << trial;
    // The state part of the canonical equations.
    typename PendulumPontryaginOde::State y;
    y << baselines::QuaternionChart::from_rotation(R), Pi, lambda, 0.0;
    typename PendulumPontryaginOde::State ydot;
    ode.rhs(0.0, y.data(), ydot.data());
    EXPECT_LT((dH_lambda.head<3>() - p.inertia.J_inverse * Pi).norm(), kFdTolerance * (1.0 + Pi.norm()));
    EXPECT_LT((dH_lambda.tail<3>() - ydot.segment<3>(PendulumPontryaginOde::kPi)).norm(),
              kFdTolerance * (1.0 + ydot.norm()));
    EXPECT_LT(dH_u.norm(), kFdTolerance * (1.0 + u.norm() + lambda.norm())) << "dH/du = 0 at the optimal control";
    EXPECT_LT((ydot.segment<6>(PendulumPontryaginOde::kLambdaR) - rate).norm(), roundoff(1.0 + rate.norm(), 64));
  }
}

TEST(Pontryagin, OdeJacobianMatchesFiniteDifferences) {
  auto rng = make_rng(32);
  const Pendulum3D p = Pendulum3D::paper();
  Mat3 W;
  W << 2.0, 0.3, 0.0, 0.3, 1.0, -0.2, 0.0, -0.2, 1.5;
  const PendulumPontryaginOde ode(p, W);
  constexpr int n = PendulumPontryaginOde::kDim;
  for (int trial = 0; trial < 5; ++trial) {
    typename PendulumPontryaginOde::State y;
    y << baselines::QuaternionChart::from_rotation(so3::random_rotation(rng)), random6(rng, 1.0).head<3>(),
        random6(rng, 2.0), 0.3;
    y.head<4>() *= 1.01;  // off the unit sphere, where the integrator's quaternion drifts
    typename PendulumPontryaginOde::Jacobian J;
    ASSERT_EQ(ode.jacobian(0.0, y.data(), J.data()), baselines::RhsStatus::Ok);
    typename PendulumPontryaginOde::Jacobian fd;
    for (int j = 0; j < n; ++j) {
      typename PendulumPontryaginOde::State yp = y, ym = y, fp, fm;
      const double a = kFdStep * std::max(1.0, std::abs(y(j)));
      yp(j) += a;
      ym(j) -= a;
      ode.rhs(0.0, yp.data(), fp.data());
      ode.rhs(0.0, ym.data(), fm.data());
      fd.col(j) = (fp - fm) / (2 * a);
    }
    EXPECT_LT((J - fd).norm(), kFdTolerance * fd.norm()) << "trial " << trial << "\nJ - fd =\n" << (J - fd);
  }
}

// The shooting Jacobian from CVODES sensitivities agrees with central differences of the
// residual (step cbrt(rtol): error ~ rtol^(2/3) times the global-error constant).
TEST(Pontryagin, ShootingJacobianSensitivitiesMatchDifferences) {
  const Pendulum3D p = Pendulum3D::paper();
  baselines::SensitivitySettings s;
  s.rtol = kSensRtol;
  const baselines::PendulumShootingFunction fn(p, TransferProblem::pendulum_paper(), {}, s);
  const Vec6 lambda = Vec6::Ones();
  const auto sens = fn.evaluate(lambda, true, baselines::ShootingJacobian::Sensitivities);
  const auto diff = fn.evaluate(lambda, true, baselines::ShootingJacobian::FiniteDifferences);
  ASSERT_TRUE(sens.ok && diff.ok) << sens.message << diff.message;
  const double err = (sens.jacobian - diff.jacobian).norm() / sens.jacobian.norm();
  std::cout << "[ measured ] |dr/dl (sensitivities) - dr/dl (differences)| / |dr/dl| = " << err << "\n";
  EXPECT_LT(err, kSensGlobalErrorPerRtol * std::pow(kSensRtol, 2.0 / 3.0));
  EXPECT_LT((sens.residual - diff.residual).norm(), kSensGlobalErrorPerRtol * kSensRtol);
}

// Converges on the paper's transfer from the discrete solution's costate and from the discrete
// solver's documented guess; the violation is below the tolerance the integration sets.
// Cost: the symmetric discrete cost is J_h = J + c h^2 + O(h^4); with J_h at h and h/2,
// e_h = 4/3 (J_h - J_{h/2}) estimates J_h - J, and the continuous optimum (integrated at
// rtol 1e-10: error ~1e-8, negligible) must lie within 2 |e_h| of J_h (the bound) and within
// 0.1 |e_h| of the Richardson value J_h - e_h (the O(h^2) law itself).
TEST(Pontryagin, ConvergesAndAgreesWithTheDiscreteOptimum) {
  const Pendulum3D p = Pendulum3D::paper();
  const double h = 0.004;
  const ocp::ShootingSummary d1 = discrete(h), d2 = discrete(h / 2);
  ASSERT_TRUE(d1.converged() && d2.converged()) << d1.brief() << "\n" << d2.brief();
  ContinuousShootingOptions o;
  o.integration.rtol = kSensRtol;
  o.initial_costate = baselines::continuous_costate_from_discrete(d2.multiplier);
  const auto r = baselines::solve_pontryagin(p, TransferProblem::pendulum_paper(), o);
  std::cout << "[ measured ] from the discrete costate: " << r.summary.brief() << " (tolerance " << r.tolerance
            << ", " << r.integrations << " integrations, " << r.integration_steps << " steps)\n";
  ASSERT_TRUE(r.summary.converged()) << r.summary.brief();
  EXPECT_LE(r.summary.violation, baselines::kViolationPerRtol * kSensRtol);
  EXPECT_LT(r.summary.cond_max, 1e5);
  const double e_h = 4.0 / 3.0 * (d1.cost - d2.cost);
  std::cout << "[ measured ] J_cont = " << r.summary.cost << ", J_h(" << h << ") = " << d1.cost << ", J_h/2 = " << d2.cost
            << ", Richardson " << d1.cost - e_h << ", |J_cont - Richardson| / |e_h| = "
            << std::abs(r.summary.cost - (d1.cost - e_h)) / std::abs(e_h) << "\n";
  EXPECT_LT(std::abs(r.summary.cost - d1.cost), 2.0 * std::abs(e_h));
  EXPECT_LT(std::abs(r.summary.cost - (d1.cost - e_h)), 0.1 * std::abs(e_h));
  // The discrete multipliers approximate the costate: lambda_0 -> lambda(0) as h -> 0 (the
  // component along the symmetry direction v_g is arbitrary in both and removed first).
  const Vec6 v_g = Pendulum3D::vertical_momentum_gradient(Mat3::Identity(), Vec3::Zero()).normalized();
  auto shape = [&](const Vec6& l) { return Vec6(l - v_g * v_g.dot(l)); };
  const double dl1 = (shape(d1.multiplier) - shape(r.summary.multiplier)).norm();
  const double dl2 = (shape(d2.multiplier) - shape(r.summary.multiplier)).norm();
  std::cout << "[ measured ] |lambda_0 - lambda(0)|: h = " << h << ": " << dl1 << ", h/2: " << dl2 << " (ratio " << dl1 / dl2
            << ")\n";
  EXPECT_LT(dl2, dl1);

  ContinuousShootingOptions g = o;
  g.initial_costate = Eigen::VectorXd::Ones(6);
  const auto r1 = baselines::solve_pontryagin(p, TransferProblem::pendulum_paper(), g);
  std::cout << "[ measured ] from (1, ..., 1): " << r1.summary.brief() << "\n";
  ASSERT_TRUE(r1.summary.converged()) << r1.summary.brief();
  EXPECT_NEAR(r1.summary.cost, r.summary.cost, 1e3 * kSensRtol * r.summary.cost);
}

// The violation reached follows the integration tolerance (default tolerance kViolationPerRtol
// rtol), and the cost converges as rtol falls.
TEST(Pontryagin, ViolationFollowsTheIntegrationTolerance) {
  double reference = 0.0;
  for (const double rtol : {1e-12, 1e-10, 1e-8, 1e-6}) {
    ContinuousShootingOptions o;
    o.integration.rtol = rtol;
    o.initial_costate = Eigen::VectorXd::Ones(6);
    const auto r = baselines::solve_pontryagin(Pendulum3D::paper(), TransferProblem::pendulum_paper(), o);
    std::printf("[ measured ] rtol %.0e: %s, J = %.10f, %zu integrations, %zu steps, %zu RHS\n", rtol,
                r.summary.brief().c_str(), r.summary.cost, r.integrations, r.integration_steps, r.rhs_evaluations);
    ASSERT_TRUE(r.summary.converged()) << r.summary.brief();
    EXPECT_LE(r.summary.violation, baselines::kViolationPerRtol * rtol);
    if (rtol == 1e-12) reference = r.summary.cost;
    EXPECT_NEAR(r.summary.cost, reference, kSensGlobalErrorPerRtol * rtol * reference);
  }
}

// The continuous conditions are the limit of the discrete ones: from the same lambda(0), the
// symmetric discrete sweep's terminal residual and Psi12 = d[eta; dPi]_N / dlambda_0
// (lgvi/ocp/indirect.hpp) approach the continuous r and Psi at second order in h.
TEST(Pontryagin, DiscreteSweepConvergesToTheContinuousOneAtSecondOrder) {
  const Pendulum3D p = Pendulum3D::paper();
  const TransferProblem problem = TransferProblem::pendulum_paper();
  baselines::SensitivitySettings s;
  s.rtol = 1e-12;
  const baselines::PendulumShootingFunction fn(p, problem, {}, s);
  const Vec6 lambda = Vec6::Ones();
  const auto c = fn.evaluate(lambda, true);
  ASSERT_TRUE(c.ok) << c.message;
  std::vector<double> e_psi, e_r;
  for (const double h : {0.01, 0.005, 0.0025}) {
    const ocp::StateMultiplierFlow<ocp::PendulumModel> flow(p, problem, LgviForm::Symmetric, h, {});
    ocp::StateMultiplierFlow<ocp::PendulumModel>::Sweep sweep;
    ASSERT_TRUE(flow.run(lambda, true, sweep));
    e_psi.push_back((sweep.Psi12 - c.Psi).norm() / c.Psi.norm());
    e_r.push_back((sweep.residual - c.residual).norm() / c.residual.norm());
    std::cout << "[ measured ] h = " << h << ": |Psi12 - Psi| / |Psi| = " << e_psi.back()
              << ", |r_h - r| / |r| = " << e_r.back() << ", cost " << sweep.cost << " vs " << c.cost << "\n";
  }
  for (std::size_t i = 0; i + 1 < e_psi.size(); ++i) {
    EXPECT_NEAR(std::log2(e_psi[i] / e_psi[i + 1]), 2.0, kSensOrderTolerance);
    EXPECT_NEAR(std::log2(e_r[i] / e_r[i + 1]), 2.0, kSensOrderTolerance);
  }
}

// The differences Jacobian reaches the same optimum.
TEST(Pontryagin, FiniteDifferenceJacobianConverges) {
  ContinuousShootingOptions o;
  o.integration.rtol = kSensRtol;
  o.jacobian = baselines::ShootingJacobian::FiniteDifferences;
  o.initial_costate = Eigen::VectorXd::Ones(6);
  const auto r = baselines::solve_pontryagin(Pendulum3D::paper(), TransferProblem::pendulum_paper(), o);
  std::cout << "[ measured ] differences: " << r.summary.brief() << " (" << r.integrations << " integrations)\n";
  ASSERT_TRUE(r.summary.converged()) << r.summary.brief();
  expect_no_nan(r.summary);
}

// Without the decomposition the full Jacobian is singular up to the integration error (rank 5:
// the vertical momentum): its condition number is ~1/rtol or worse.
TEST(Pontryagin, FullJacobianIsRankDeficient) {
  ContinuousShootingOptions o;
  o.integration.rtol = kSensRtol;
  o.initial_costate = Eigen::VectorXd::Ones(6);
  o.decomposition = false;
  o.max_iterations = 2;
  o.max_backtracks = 8;
  const auto r = baselines::solve_pontryagin(Pendulum3D::paper(), TransferProblem::pendulum_paper(), o);
  std::cout << "[ measured ] no decomposition: " << r.summary.brief() << "\n";
  expect_no_nan(r.summary);
  ASSERT_FALSE(r.summary.history.empty());
  EXPECT_GT(r.summary.history.front().cond_sensitivity, 0.01 / kSensRtol);
}

TEST(Pontryagin, FailuresAreNamedStatuses) {
  const Pendulum3D p = Pendulum3D::paper();
  const TransferProblem problem = TransferProblem::pendulum_paper();
  {  // a tolerance the integration cannot support
    ContinuousShootingOptions o;
    o.integration.rtol = 1e-5;
    o.tolerance = 1e-13;
    o.initial_costate = Eigen::VectorXd::Ones(6);
    o.max_iterations = 40;
    const auto r = baselines::solve_pontryagin(p, problem, o);
    std::cout << "[ measured ] rtol 1e-5, tolerance 1e-13: " << r.summary.brief() << "\n";
    EXPECT_FALSE(r.summary.converged());
    EXPECT_TRUE(r.summary.status == ShootingStatus::Stalled || r.summary.status == ShootingStatus::LineSearchFailed ||
                r.summary.status == ShootingStatus::MaxIterations);
    expect_no_nan(r.summary);
  }
  {  // zero costate: u = 0 keeps the pendulum at rest; the linearization cannot turn it
    ContinuousShootingOptions o;
    o.integration.rtol = kSensRtol;
    const auto r = baselines::solve_pontryagin(p, problem, o);
    std::cout << "[ measured ] zero guess: " << r.summary.brief() << "\n";
    EXPECT_FALSE(r.summary.converged());
    expect_no_nan(r.summary);
  }
  {  // a huge guess: the controls overwhelm the integrator's step budget
    ContinuousShootingOptions o;
    o.integration.rtol = kSensRtol;
    o.integration.max_steps = 2000;
    o.initial_costate = 1e6 * Eigen::VectorXd::Ones(6);
    const auto r = baselines::solve_pontryagin(p, problem, o);
    std::cout << "[ measured ] guess 1e6: " << r.summary.brief() << "\n";
    EXPECT_FALSE(r.summary.converged());
    expect_no_nan(r.summary);
  }
  {  // bad input
    ContinuousShootingOptions o;
    o.initial_costate = Eigen::VectorXd::Ones(5);
    EXPECT_EQ(baselines::solve_pontryagin(p, problem, o).summary.status, ShootingStatus::InvalidInput);
    o.initial_costate = Eigen::VectorXd::Ones(6);
    o.W = -Eigen::MatrixXd::Identity(3, 3);
    EXPECT_EQ(baselines::solve_pontryagin(p, problem, o).summary.status, ShootingStatus::InvalidInput);
    o.W.resize(0, 0);
    o.integration.rtol = 0.0;
    const auto r = baselines::solve_pontryagin(p, problem, o);
    EXPECT_EQ(r.summary.status, ShootingStatus::InvalidInput);
    EXPECT_NE(r.summary.message.find("rtol"), std::string::npos) << r.summary.message;
    o.integration.rtol = 1e-10;
    o.integration.max_steps = 0;
    EXPECT_EQ(baselines::solve_pontryagin(p, problem, o).summary.status, ShootingStatus::InvalidInput);
  }
}


// --- the dumbbell -------------------------------------------------------------------------------

using baselines::DumbbellPontryaginOde;
using baselines::Vec12;

Vec12 random12(std::mt19937_64& rng, double scale) {
  Vec12 v;
  v << random6(rng, scale), random6(rng, scale);
  return v;
}

baselines::Mat6 random_spd6(std::mt19937_64& rng) {
  Eigen::Matrix<double, 6, 6> A;
  for (int i = 0; i < 6; ++i) A.col(i) = random6(rng, 0.5);
  return A * A.transpose() + baselines::Mat6::Identity();
}

/// A configuration near the reference orbit (|x| ~ 1, the spheres well away from the centre).
Vec3 orbit_position(std::mt19937_64& rng) {
  const Vec3 d = random6(rng, 0.1).head<3>();
  return Vec3(0.8, 0.5, 0.3) + d;
}

// The canonical equations against central differences of H (step kFdStep, tolerance kFdTolerance
// relative, test_support.hpp): lambda_R' = lambda_R x Omega - dH/deta, lambda_x' = -dH/dx,
// lambda_Pi' = -dH/dPi, lambda_p' = -dH/dp; the state equations [Omega; p/m; Pi'; p'] = dH/dlambda
// (as the ODE evaluates them) and dH/du = 0 at the optimal control.
TEST(DumbbellPontryagin, CostateEquationsMatchHamiltonianDerivatives) {
  auto rng = make_rng(41);
  const DumbbellSpacecraft d = DumbbellSpacecraft::paper();
  const DumbbellPontryaginOde ode(d, random_spd6(rng));
  for (int trial = 0; trial < 10; ++trial) {
    const Mat3 R = so3::random_rotation(rng);
    const Vec3 x = orbit_position(rng);
    const Vec3 Pi = random6(rng, 0.05).head<3>();
    const Vec3 p = random6(rng, 1.0).head<3>();
    const Vec12 lambda = random12(rng, 1.0);
    const Vec6 u = ode.control(lambda);
    const double a = kFdStep;
    Vec12 dH_w;  // [dH/deta; dH/dx; dH/dPi; dH/dp]
    Vec12 dH_lambda;
    Vec6 dH_u;
    for (int i = 0; i < 3; ++i) {
      const Vec3 e = a * Vec3::Unit(i);
      dH_w(i) = (ode.hamiltonian(R * so3::exp(e), x, Pi, p, lambda, u) -
                 ode.hamiltonian(R * so3::exp(-e), x, Pi, p, lambda, u)) / (2 * a);
      dH_w(3 + i) = (ode.hamiltonian(R, x + e, Pi, p, lambda, u) - ode.hamiltonian(R, x - e, Pi, p, lambda, u)) / (2 * a);
      dH_w(6 + i) = (ode.hamiltonian(R, x, Pi + e, p, lambda, u) - ode.hamiltonian(R, x, Pi - e, p, lambda, u)) / (2 * a);
      dH_w(9 + i) = (ode.hamiltonian(R, x, Pi, p + e, lambda, u) - ode.hamiltonian(R, x, Pi, p - e, lambda, u)) / (2 * a);
    }
    for (int i = 0; i < 6; ++i) {
      const Vec6 e = a * Vec6::Unit(i);
      dH_u(i) = (ode.hamiltonian(R, x, Pi, p, lambda, u + e) - ode.hamiltonian(R, x, Pi, p, lambda, u - e)) / (2 * a);
    }
    for (int i = 0; i < 12; ++i) {
      const Vec12 e = a * Vec12::Unit(i);
      dH_lambda(i) = (ode.hamiltonian(R, x, Pi, p, lambda + e, u) - ode.hamiltonian(R, x, Pi, p, lambda - e, u)) / (2 * a);
    }
    const Vec3 Omega = d.inertia.J_inverse * Pi;
    const Vec12 rate = ode.costate_rate(R, x, Pi, lambda);
    Vec12 expected = -dH_w;
    expected.head<3>() += lambda.head<3>().cross(Omega);
    EXPECT_LT((rate - expected).norm(), kFdTolerance * (1.0 + expected.norm())) << "trial " << trial;
    typename DumbbellPontryaginOde::State y;
    y << baselines::QuaternionChart::from_rotation(R), x, Pi, p, lambda, 0.0;
    typename DumbbellPontryaginOde::State ydot;
    ode.rhs(0.0, y.data(), ydot.data());
    Vec12 state_rate;
    state_rate << Omega, ydot.segment<9>(DumbbellPontryaginOde::kX);
    EXPECT_LT((dH_lambda - state_rate).norm(), kFdTolerance * (1.0 + state_rate.norm())) << "trial " << trial;
    EXPECT_LT(dH_u.norm(), kFdTolerance * (1.0 + u.norm() + lambda.norm())) << "dH/du = 0 at the optimal control";
    EXPECT_LT((ydot.segment<12>(DumbbellPontryaginOde::kLambda) - rate).norm(), roundoff(1.0 + rate.norm(), 64));
  }
}

TEST(DumbbellPontryagin, OdeJacobianMatchesFiniteDifferences) {
  auto rng = make_rng(42);
  const DumbbellSpacecraft d = DumbbellSpacecraft::paper();
  const DumbbellPontryaginOde ode(d, random_spd6(rng));
  constexpr int n = DumbbellPontryaginOde::kDim;
  for (int trial = 0; trial < 5; ++trial) {
    typename DumbbellPontryaginOde::State y;
    y << baselines::QuaternionChart::from_rotation(so3::random_rotation(rng)), orbit_position(rng),
        random6(rng, 0.05).head<3>(), random6(rng, 1.0).head<3>(), random12(rng, 1.0), 0.3;
    y.head<4>() *= 1.01;  // off the unit sphere, where the integrator's quaternion drifts
    typename DumbbellPontryaginOde::Jacobian J;
    ASSERT_EQ(ode.jacobian(0.0, y.data(), J.data()), baselines::RhsStatus::Ok);
    typename DumbbellPontryaginOde::Jacobian fd;
    for (int j = 0; j < n; ++j) {
      typename DumbbellPontryaginOde::State yp = y, ym = y, fp, fm;
      const double a = kFdStep * std::max(1.0, std::abs(y(j)));
      yp(j) += a;
      ym(j) -= a;
      ode.rhs(0.0, yp.data(), fp.data());
      ode.rhs(0.0, ym.data(), fm.data());
      fd.col(j) = (fp - fm) / (2 * a);
    }
    EXPECT_LT((J - fd).norm(), kFdTolerance * fd.norm()) << "trial " << trial << "\nJ - fd =\n" << (J - fd);
  }
}

// Where the dumbbell's continuous shooting stops (lgvi/ocp/README.md: violation 9.2e-9 at rtol
// 1e-12, above the tolerance 1e2 rtol): at the computed residual's noise. From the discrete
// symmetric N = 1000 solution (homotopy), the continuous shooting's end point lambda*; then r at
// lambda* (1 + k 1e-15 d), k = -5..5, d a unit direction: perturbations of ~10 ulps, for which the
// linearization r + J dlambda is exact to far below the noise (|dlambda| ~ 1e-15 |lambda|, the
// second-order term ~|J'| |dlambda|^2). The scatter about that line is the computed residual's
// noise (the integration's round-off and stopping tests amplified by the stiff rod axis, Psi ~
// 1e6); Newton cannot resolve r below it, so the end point's violation must be of its size:
// scatter >= violation / 10 (a Newton failure above the noise would leave the violation far
// larger than the scatter).
TEST(DumbbellPontryagin, ShootingStopsAtTheResidualsNoiseFloor) {
  const DumbbellSpacecraft d = DumbbellSpacecraft::paper();
  const TransferProblem problem = TransferProblem::dumbbell_paper();
  ocp::ShootingOptions discrete;
  discrete.h = problem.t_final / 1000;
  discrete.globalization = ocp::Globalization::Homotopy;
  discrete.max_iterations = 300;
  const auto start = ocp::solve_indirect(d, problem, discrete);
  ASSERT_EQ(start.summary.status, ShootingStatus::Converged) << start.summary.brief();
  ContinuousShootingOptions o;
  o.integration.rtol = 1e-12;
  o.max_iterations = 300;
  o.initial_costate = start.summary.multiplier;
  const auto end = baselines::solve_pontryagin(d, problem, o);
  ASSERT_TRUE(std::isfinite(end.summary.violation)) << end.summary.brief();
  const baselines::DumbbellShootingFunction fn(d, problem, {}, o.integration);
  const baselines::Vec12 lambda = end.summary.multiplier;
  const auto at = fn.evaluate(lambda, true);
  ASSERT_TRUE(at.ok) << at.message;
  const baselines::Vec12 direction = baselines::Vec12::Ones().normalized();
  double scatter = 0.0;
  for (int k = -5; k <= 5; ++k) {
    const baselines::Vec12 dlambda = (k * 1e-15 * lambda.norm()) * direction;
    const auto e = fn.evaluate(lambda + dlambda, true);  // as the shooting evaluates
    ASSERT_TRUE(e.ok) << e.message;
    scatter = std::max(scatter, (e.residual - at.residual - at.jacobian * dlambda).norm());
  }
  // The same residual without the sensitivities in CVODES's error test (another step sequence):
  // the integration error of r itself, reported beside the noise.
  const auto values_only = fn.evaluate(lambda, false);
  std::cout << "[ measured ] violation " << end.summary.violation << ", scatter of r under 1e-15 relative "
            << "perturbations " << scatter << ", |r| without sensitivities " << values_only.residual.norm() << "\n";
  EXPECT_GE(scatter, 0.1 * end.summary.violation);
}

// The continuous conditions are the limit of the discrete ones: from the same lambda(0), the
// symmetric discrete sweep (lgvi/ocp/indirect.hpp, a second-order LGVI with trapezoidal node
// controls) has terminal residual and Psi12 = dw_N/dlambda_0 within O(h^2) of the continuous r and
// Psi: the error ratio per halving of h is 4, i.e. log2 = 2 +- kSensOrderTolerance. The continuous
// reference at rtol 1e-12 (global error ~1e-9, test_support.hpp) is far below the discrete errors
// (~1e-3..1e-4 relative at these h).
TEST(DumbbellPontryagin, DiscreteSweepConvergesToTheContinuousOneAtSecondOrder) {
  const DumbbellSpacecraft d = DumbbellSpacecraft::paper();
  const TransferProblem problem = TransferProblem::dumbbell_paper();
  baselines::SensitivitySettings s;
  s.rtol = 1e-12;
  const baselines::DumbbellShootingFunction fn(d, problem, {}, s);
  // The shooting's guess, the uncontrolled motion (lambda = 0): r is O(1) and Psi the full stiff
  // linearization (the rod-axis inertia 0.001 makes it grow like T^2 / J_11^2 ~ 1e6). A controlled
  // lambda of the optimum's size (lambda_P ~ 0.05) spins the rod so fast that N = 50 is out of the
  // asymptotic range and the CVODES reference takes seconds.
  const Vec12 lambda = Vec12::Zero();
  const auto c = fn.evaluate(lambda, true);
  ASSERT_TRUE(c.ok) << c.message;
  std::vector<double> e_psi, e_r;
  for (const int steps : {100, 200, 400}) {
    const ocp::StateMultiplierFlow<ocp::DumbbellModel> flow(d, problem, LgviForm::Symmetric,
                                                           problem.t_final / steps, {});
    ocp::StateMultiplierFlow<ocp::DumbbellModel>::Sweep sweep;
    ASSERT_TRUE(flow.run(lambda, true, sweep));
    e_psi.push_back((sweep.Psi12 - c.Psi).norm() / c.Psi.norm());
    e_r.push_back((sweep.residual - c.residual).norm() / c.residual.norm());
    std::cout << "[ measured ] N = " << steps << ": |Psi12 - Psi| / |Psi| = " << e_psi.back()
              << ", |r_h - r| / |r| = " << e_r.back() << ", cost " << sweep.cost << " vs " << c.cost << "\n";
  }
  for (std::size_t i = 0; i + 1 < e_psi.size(); ++i) {
    EXPECT_NEAR(std::log2(e_psi[i] / e_psi[i + 1]), 2.0, kSensOrderTolerance);
    EXPECT_NEAR(std::log2(e_r[i] / e_r[i + 1]), 2.0, kSensOrderTolerance);
  }
}

}  // namespace
}  // namespace lgvi::test
