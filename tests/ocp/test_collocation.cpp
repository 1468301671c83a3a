// Hermite-Simpson collocation (lgvi/ocp/collocation.hpp): every system's RHS against the
// baselines' quaternion model, its Jacobian and the whole constraint Jacobian of a small mesh
// against central differences, the pendulum's reorientation solved with its defects within the
// tolerance, the cost approached by the discrete solutions as h -> 0, the replayed answers of the
// pendulum and of the paper's other examples (fourth order), bad options and infeasible targets.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <iostream>
#include <limits>
#include <numbers>

#include "baselines/model.hpp"
#include "baselines/ocp_replay.hpp"
#include "lgvi/ocp/collocation.hpp"
#include "lgvi/ocp/indirect.hpp"
#include "lgvi/so3.hpp"

namespace lgvi {
namespace {

using Vec7 = Eigen::Matrix<double, 7, 1>;

Vec7 generic_state(double scale) {
  Vec7 y;
  Eigen::Vector4d q(0.8, -0.3, 0.4, 0.25);
  y << scale * q.normalized(), 0.7, -1.1, 0.4;
  return y;
}

template <class S, class Mechanics>
void check_rhs(const S& system) {
  const Vec3 u(0.3, -0.8, 1.2);
  for (const double scale : {1.0, 1.01}) {  // on and (at midpoints) just off the unit sphere
    const Vec7 y = generic_state(scale);
    Vec7 f;
    Eigen::Matrix<double, 7, 11> J;
    ocp::collocation_detail::attitude_rhs(system, y, u, 0.0, f, &J);
    // The same model as the baselines' quaternion model (baselines/model.hpp) with mu = 0.
    const Mechanics mech(system, [&](double) { return u; });
    const baselines::CoordinateOde<baselines::QuaternionChart, Mechanics> ode(mech);
    Vec7 expected;
    ASSERT_EQ(ode.rhs(0.0, y.data(), expected.data()), baselines::RhsStatus::Ok);
    EXPECT_LT((f - expected).norm(), 1e-13 * (1.0 + expected.norm()));
    // Jacobian against central differences in (y, u, mu) at mu = 0.2.
    const double mu = 0.2;
    ocp::collocation_detail::attitude_rhs(system, y, u, mu, f, &J);
    Eigen::Matrix<double, 11, 1> x;
    x << y, u, mu;
    const auto F = [&](const Eigen::Matrix<double, 11, 1>& z) {
      Vec7 out;
      ocp::collocation_detail::attitude_rhs(system, z.head<7>(), z.segment<3>(7), z(10), out, nullptr);
      return out;
    };
    for (int j = 0; j < 11; ++j) {
      const double a = 1e-6;
      Eigen::Matrix<double, 11, 1> p = x, m = x;
      p(j) += a;
      m(j) -= a;
      const Vec7 fd = (F(p) - F(m)) / (2 * a);
      // central differences: truncation ~ a^2 |f'''|, round-off ~ eps |f| / a
      EXPECT_LT((J.col(j) - fd).norm(), 1e-7 * (1.0 + fd.norm())) << "column " << j;
    }
  }
}

TEST(Collocation, RhsIsTheQuaternionModelAndItsJacobianMatchesCentralDifferences) {
  check_rhs<Pendulum3D, baselines::AttitudeMechanics<Pendulum3D>>(Pendulum3D::paper());
  check_rhs<FreeRigidBody, baselines::AttitudeMechanics<FreeRigidBody>>(FreeRigidBody(Vec3(1.2, 0.9, 0.6).asDiagonal()));
}

ocp::CollocationResult pendulum(int K) {
  ocp::CollocationOptions o;
  o.intervals = K;
  const ocp::CollocationResult r =
      ocp::solve_collocation(Pendulum3D::paper(), ocp::TransferProblem::pendulum_paper(), o);
  std::cout << "[ colloc   ] " << r.summary.brief() << "\n";
  return r;
}

double discrete_cost(int N) {
  const ocp::TransferProblem problem = ocp::TransferProblem::pendulum_paper();
  ocp::ShootingOptions o;
  o.form = LgviForm::Symmetric;
  o.h = problem.t_final / N;
  o.initial_multiplier = Eigen::VectorXd::Ones(6);
  o.max_iterations = 300;
  const auto r = ocp::solve_indirect(Pendulum3D::paper(), problem, o);
  EXPECT_TRUE(r.summary.converged()) << r.summary.brief();
  return r.summary.cost;
}

TEST(Collocation, PendulumReorientationConvergesWithinTheToleranceAndTheDiscreteCostsApproachIt) {
  const ocp::CollocationResult r = pendulum(40);
  ASSERT_TRUE(r.summary.converged()) << r.summary.brief();
  const ocp::CollocationOptions defaults;
  EXPECT_LE(r.summary.max_defect, defaults.tolerance);
  // The terminal constraint vec(conj(q_f) q_K) = sin(angle / 2) axis within the tolerance: the
  // log's angle within about twice that.
  EXPECT_LT(r.summary.violation, 4 * defaults.tolerance);
  // nodes exact; the midpoints' norm off by the Hermite interpolant's O(h^4) error
  EXPECT_LT(r.summary.quaternion_drift, 100 * std::pow(r.h, 4));
  EXPECT_EQ(r.states.cols(), 41);
  EXPECT_EQ(r.controls.cols(), 81);
  // Its controls replayed (the quadratic through node, midpoint, node): a fourth-order method's
  // terminal state, off by O(h^4) (h = 1/40: ~1e-6 here), far below the discrete solutions'.
  baselines::ReplayControls c;
  c.u = r.controls;
  c.h = r.h;
  c.interpolation = baselines::ReplayInterpolation::PiecewiseQuadratic;
  const baselines::ReplayResult replayed =
      baselines::replay(Pendulum3D::paper(), ocp::TransferProblem::pendulum_paper(), c);
  ASSERT_TRUE(replayed.ok) << replayed.message;
  std::cout << "[ colloc   ] replayed violation " << replayed.violation << ", cost " << replayed.cost << "\n";
  EXPECT_LT(replayed.violation, 1e-4);
  EXPECT_LT(std::abs(replayed.cost - r.summary.cost), 1e-4 * r.summary.cost);
  // The discrete (symmetric, second order) solutions' costs approach the continuous one.
  const double cost = r.summary.cost;
  const double d1 = std::abs(discrete_cost(50) - cost), d2 = std::abs(discrete_cost(100) - cost);
  std::cout << "[ colloc   ] |discrete - collocation| cost: N = 50: " << d1 << ", N = 100: " << d2 << "\n";
  EXPECT_LT(d2, 0.5 * d1);
}

// --- the paper's other examples ---------------------------------------------------------------

/// A state in the layout [q_1 .. q_NQ | x | w] with quaternions of norm `scale`.
Eigen::VectorXd generic_state(int nq, int n, double scale) {
  Eigen::VectorXd y(n);
  for (int i = 0; i < n; ++i) y(i) = 0.3 * std::sin(1.7 * i + 0.4) + 0.1;
  for (int i = 0; i < nq; ++i) {
    Eigen::Vector4d q(0.8 - 0.2 * i, -0.3, 0.4 + 0.1 * i, 0.25);
    y.segment<4>(4 * i) = scale * q.normalized();
  }
  return y;
}

/// f against the baselines' quaternion model of the same mechanics (mu = 0, on the unit sphere:
/// off it the multibody systems' physics is evaluated at R(q / |q|), collocation.hpp), and the
/// Jacobian [df/dy, df/du, df/dmu] against central differences (mu = 0.2, on and off the sphere).
template <class S, class Mechanics, class Control>
void check_system_rhs(const S& system, int nq, int ny, const Eigen::VectorXd& u, const Eigen::VectorXd& shift,
                      const std::function<Control(const Eigen::VectorXd&)>& control) {
  const int nu = static_cast<int>(u.size());
  for (const double scale : {1.0, 1.01}) {
    Eigen::VectorXd y = generic_state(nq, ny, scale) + shift;
    Eigen::VectorXd f;
    Eigen::MatrixXd J;
    if (scale == 1.0) {
      ocp::collocation_detail::rhs(system, y, u, Eigen::VectorXd::Zero(nq), f, &J);
      const Mechanics mech(system, [&](double) { return control(u); });
      const baselines::CoordinateOde<baselines::QuaternionChart, Mechanics> ode(mech);
      Eigen::VectorXd expected(ny);
      ASSERT_EQ(ode.rhs(0.0, y.data(), expected.data()), baselines::RhsStatus::Ok);
      EXPECT_LT((f - expected).norm(), 1e-13 * (1.0 + expected.norm())) << "f\n" << f << "\nexpected\n" << expected;
    }
    const Eigen::VectorXd mu = Eigen::VectorXd::Constant(nq, 0.2);
    ocp::collocation_detail::rhs(system, y, u, mu, f, &J);
    ASSERT_EQ(J.rows(), ny);
    ASSERT_EQ(J.cols(), ny + nu + nq);
    Eigen::VectorXd x(ny + nu + nq);
    x << y, u, mu;
    const auto F = [&](const Eigen::VectorXd& z) {
      Eigen::VectorXd out;
      ocp::collocation_detail::rhs(system, z.head(ny), z.segment(ny, nu), z.tail(nq), out, nullptr);
      return out;
    };
    for (int j = 0; j < x.size(); ++j) {
      const double a = 1e-6;
      Eigen::VectorXd p = x, m = x;
      p(j) += a;
      m(j) -= a;
      const Eigen::VectorXd fd = (F(p) - F(m)) / (2 * a);
      // central differences: truncation ~ a^2 |f'''|, round-off ~ eps |f| / a
      EXPECT_LT((J.col(j) - fd).norm(), 1e-7 * (1.0 + fd.norm())) << "column " << j;
    }
  }
}

Eigen::VectorXd vector_of(std::initializer_list<double> v) {
  Eigen::VectorXd x(static_cast<Eigen::Index>(v.size()));
  Eigen::Index i = 0;
  for (const double e : v) x(i++) = e;
  return x;
}

TEST(Collocation, MultibodyAndDumbbellRhsAreTheQuaternionModelsAndTheirJacobiansMatchCentralDifferences) {
  check_system_rhs<CartPendulum, baselines::CartPendulumMechanics, Vec2>(
      CartPendulum::paper(), 1, 11, vector_of({0.7, -1.3}), Eigen::VectorXd::Zero(11),
      [](const Eigen::VectorXd& u) { return Vec2(u); });
  check_system_rhs<ConnectedBodies, baselines::ConnectedBodiesMechanics, Vec3>(
      ConnectedBodies::paper(), 2, 14, vector_of({0.4, -0.2, 0.9}), Eigen::VectorXd::Zero(14),
      [](const Eigen::VectorXd& u) { return Vec3(u); });
  // the dumbbell near its orbit: x at radius ~1 (entries 4..6)
  Eigen::VectorXd shift = Eigen::VectorXd::Zero(13);
  shift.segment<3>(4) = Vec3(0.9, 0.3, -0.2);
  check_system_rhs<DumbbellSpacecraft, baselines::DumbbellMechanics, Wrench>(
      DumbbellSpacecraft::paper(), 1, 13, vector_of({0.1, -0.2, 0.3, 0.05, 0.4, -0.1}), shift,
      [](const Eigen::VectorXd& u) {
        Wrench w;
        w.moment = u.head<3>();
        w.force = u.tail<3>();
        return w;
      });
}

/// The K-interval mesh's guess, perturbed (mu and the controls nonzero).
template <class S, class P>
Eigen::VectorXd perturbed_guess(const S& system, const P& problem, int K) {
  Eigen::VectorXd x = ocp::collocation_detail::probe(system, problem, K).x;
  for (Eigen::Index i = 0; i < x.size(); ++i) x(i) += 0.05 * std::sin(0.37 * static_cast<double>(i) + 1.0);
  return x;
}

/// check(system, problem, 3) for each of the four systems' paper problems.
template <class Check>
void for_every_system(const Check& check) {
  check(Pendulum3D::paper(), ocp::TransferProblem::pendulum_paper(), 3);
  check(CartPendulum::paper(), ocp::CartPendulumTransfer::paper(), 3);
  check(ConnectedBodies::paper(), ocp::ConnectedBodiesTransfer::paper(), 3);
  check(DumbbellSpacecraft::paper(), ocp::TransferProblem::dumbbell_paper(), 3);
}

/// The whole constraint Jacobian of a K-interval mesh at a perturbation of the guess against
/// central differences of the constraints, and the cost's gradient.
template <class S, class P>
void check_transcription(const S& system, const P& problem, int K) {
  const Eigen::VectorXd x = perturbed_guess(system, problem, K);
  const auto at = ocp::collocation_detail::probe(system, problem, K, x);
  ASSERT_EQ(at.jacobian.rows(), at.g.size());
  ASSERT_EQ(at.jacobian.cols(), x.size());
  double worst = 0.0;
  for (Eigen::Index j = 0; j < x.size(); ++j) {
    const double a = 1e-6;
    Eigen::VectorXd p = x, m = x;
    p(j) += a;
    m(j) -= a;
    const auto gp = ocp::collocation_detail::probe(system, problem, K, p);
    const auto gm = ocp::collocation_detail::probe(system, problem, K, m);
    const Eigen::VectorXd fd = (gp.g - gm.g) / (2 * a);
    // as the RHS's check: truncation ~ a^2, round-off ~ eps |g| / a
    const double err = (at.jacobian.col(j) - fd).norm() / (1.0 + fd.norm());
    worst = std::max(worst, err);
    EXPECT_LT(err, 1e-7) << "column " << j;
    EXPECT_NEAR(at.cost_gradient(j), (gp.cost - gm.cost) / (2 * a), 1e-7 * (1.0 + std::abs(at.cost_gradient(j))))
        << "cost, column " << j;
  }
  std::cout << "[ colloc   ] constraint Jacobian " << at.jacobian.rows() << " x " << at.jacobian.cols()
            << ": worst relative difference from central differences " << worst << "\n";
}

TEST(Collocation, ConstraintJacobiansOfEverySystemMatchCentralDifferences) {
  for_every_system([](const auto& system, const auto& problem, int K) { check_transcription(system, problem, K); });
}

/// The Hessian of the Lagrangian sigma J + lambda^T g of a K-interval mesh (the exact one and the
/// cost's alone) at a perturbation of the guess, with multipliers of both signs on every row,
/// against central differences of the Lagrangian's exact gradient sigma grad J + Jac^T lambda.
/// The two are independent routes: the transcription differences the rate's Jacobian point by
/// point, this test the assembled constraint Jacobian of the whole mesh. Tolerance: the
/// transcription's error ~eps^(2/3) ~ 4e-11 relative, this test's (a = 1e-5) truncation a^2 |d3L|
/// ~ 1e-10 plus round-off eps |grad L| / a ~ 2e-11, so 1e-7 relative as the Jacobians' checks;
/// an entry missing from the sparse structure shows as a whole missing term.
template <class S, class P>
void check_hessian(const S& system, const P& problem, int K) {
  const Eigen::VectorXd x = perturbed_guess(system, problem, K);
  ocp::collocation_detail::HessianProbe hp;
  hp.sigma = 0.7;
  hp.lambda.resize(ocp::collocation_detail::probe(system, problem, K, x).g.size());
  for (Eigen::Index i = 0; i < hp.lambda.size(); ++i) hp.lambda(i) = std::cos(1.3 * static_cast<double>(i) + 0.2);
  for (const ocp::IpoptHessian kind : {ocp::IpoptHessian::Exact, ocp::IpoptHessian::CostOnly}) {
    hp.hessian = kind;
    const auto at = ocp::collocation_detail::probe(system, problem, K, x, hp);
    ASSERT_EQ(at.hessian.rows(), x.size());
    ASSERT_EQ(at.hessian.cols(), x.size());
    const bool exact = kind == ocp::IpoptHessian::Exact;
    const auto gradient = [&](const Eigen::VectorXd& z) {
      const auto p = ocp::collocation_detail::probe(system, problem, K, z);
      Eigen::VectorXd g = hp.sigma * p.cost_gradient;
      if (exact) g += p.jacobian.transpose() * hp.lambda;
      return g;
    };
    double worst = 0.0;
    for (Eigen::Index j = 0; j < x.size(); ++j) {
      const double a = 1e-5;
      Eigen::VectorXd p = x, m = x;
      p(j) += a;
      m(j) -= a;
      const Eigen::VectorXd fd = (gradient(p) - gradient(m)) / (2 * a);
      const double err = (at.hessian.col(j) - fd).norm() / (1.0 + fd.norm());
      worst = std::max(worst, err);
      EXPECT_LT(err, 1e-7) << ocp::to_string(kind) << ", column " << j;
    }
    std::cout << "[ colloc   ] Hessian (" << ocp::to_string(kind) << ") " << x.size() << " x " << x.size()
              << ": worst relative difference from central differences " << worst << "\n";
  }
}

TEST(Collocation, LagrangianHessiansOfEverySystemMatchCentralDifferences) {
  for_every_system([](const auto& system, const auto& problem, int K) { check_hessian(system, problem, K); });
}

/// The exact Hessian and IPOPT's L-BFGS reach the same optimum of the pendulum's transcription
/// from the slew guess (as measured at K = 25 .. 200), the exact one in fewer iterations
/// (Newton's local quadratic rate against L-BFGS's superlinear one: 6 against 20-23 measured).
TEST(Collocation, ExactHessianAndLbfgsReachTheSameOptimum) {
  ocp::CollocationOptions o;
  o.intervals = 40;
  o.hessian = ocp::IpoptHessian::Exact;
  const auto exact = ocp::solve_collocation(Pendulum3D::paper(), ocp::TransferProblem::pendulum_paper(), o);
  o.hessian = ocp::IpoptHessian::LimitedMemory;
  const auto lbfgs = ocp::solve_collocation(Pendulum3D::paper(), ocp::TransferProblem::pendulum_paper(), o);
  ASSERT_TRUE(exact.summary.converged()) << exact.summary.brief();
  ASSERT_TRUE(lbfgs.summary.converged()) << lbfgs.summary.brief();
  std::cout << "[ colloc   ] exact: " << exact.summary.brief() << "\n[ colloc   ] L-BFGS: " << lbfgs.summary.brief()
            << "\n";
  // both stop at IPOPT's tol 1e-9 (scaled dual infeasibility): costs equal to ~1e-9 relative
  EXPECT_NEAR(exact.summary.cost, lbfgs.summary.cost, 1e-8 * lbfgs.summary.cost);
  EXPECT_GT(exact.summary.hessian_nonzeros, 0);
  EXPECT_EQ(lbfgs.summary.hessian_nonzeros, 0);
  EXPECT_LT(exact.summary.iterations, lbfgs.summary.iterations);
}

/// Solves with K and 2K intervals and replays both answers (the quadratic controls on the
/// quaternion model by gsl-rk8pd at 1e-13). Hermite-Simpson is fourth order: the replayed
/// terminal violation is e(K) ~ C h^4, plus the own violation (<= the tolerance 1e-10) and the
/// replay's error (~1e-12). The stated tolerance is the fourth-order prediction from the coarse
/// mesh with a factor 2 for the pre-asymptotic range, e(2K) <= 2 e(K) / 16 (observed order >= 3),
/// and the answer must be a real transfer: e(2K) below 1e-3 of the angle the attitudes travel.
/// (The connected bodies' and the dumbbell's K = 50 / 100 pairs, ~4 s each in a Release build,
/// are left to suite ocp-comparison's full form: lgvi/ocp/README.md, "Continuous collocation".)
template <class S, class P>
void check_replayed_order(const S& system, const P& problem, int K, double travel) {
  double e[2] = {0.0, 0.0}, drift[2] = {0.0, 0.0};
  for (int i = 0; i < 2; ++i) {
    ocp::CollocationOptions o;
    o.intervals = K << i;
    const ocp::CollocationResult r = ocp::solve_collocation(system, problem, o);
    std::cout << "[ colloc   ] " << r.summary.brief() << "\n";
    ASSERT_TRUE(r.summary.converged()) << r.summary.brief();
    EXPECT_LE(r.summary.max_defect, o.tolerance);
    drift[i] = r.summary.quaternion_drift;
    baselines::ReplayControls c;
    c.u = r.controls;
    c.h = r.h;
    c.interpolation = baselines::ReplayInterpolation::PiecewiseQuadratic;
    const baselines::ReplayResult replayed = baselines::replay(system, problem, c);
    ASSERT_TRUE(replayed.ok) << replayed.message;
    e[i] = replayed.violation;
    std::cout << "[ colloc   ] K = " << o.intervals << ": replayed violation " << replayed.violation << ", cost "
              << replayed.cost << " (own " << r.summary.cost << ")\n";
    // the replayed cost is the exact integral of the same quadratic controls whose Simpson sum is
    // the own cost: they differ by Simpson's O(h^4) quadrature error of a smooth integrand
    EXPECT_LT(std::abs(replayed.cost - r.summary.cost), 1e-3 * r.summary.cost);
  }
  std::cout << "[ colloc   ] observed order " << std::log2(e[0] / e[1]) << ", of the |q| drift "
            << std::log2(drift[0] / drift[1]) << "\n";
  EXPECT_LE(e[1], 2.0 * e[0] / 16.0);
  // the nodes' norms are imposed; the midpoints' are off by the Hermite interpolant's O(h^4)
  // error: the same rule
  EXPECT_LE(drift[1], 2.0 * drift[0] / 16.0);
  EXPECT_LT(e[1], 1e-3 * travel);
}

TEST(Collocation, CartPendulumReplaysToTheTargetAtFourthOrder) {
  // K = 50 and 100 reach the same local optimum from the slew guess (260.021 both, with the exact
  // Hessian; IPOPT's L-BFGS reached 601.09 and 601.11 there, and at K = 20 and 40 different ones,
  // 260.16 and 601.08: such a pair would not measure an order)
  check_replayed_order(CartPendulum::paper(), ocp::CartPendulumTransfer::paper(), 50, std::numbers::pi);
}

TEST(Collocation, InfeasibleTargetsAndBadWeightsAreNamedStatuses) {
  ocp::ConnectedBodiesTransfer p = ocp::ConnectedBodiesTransfer::paper();
  p.Omega2_f = Vec3(0.0, 0.0, 1.0);  // total angular momentum not conserved: unreachable
  auto r = ocp::solve_collocation(ConnectedBodies::paper(), p, {});
  EXPECT_EQ(r.summary.status, ocp::CollocationStatus::InvalidInput);
  EXPECT_EQ(r.summary.message.rfind("Omega2_f:", 0), 0u) << r.summary.message;
  ocp::TransferProblem d = ocp::TransferProblem::dumbbell_paper();
  d.xf = Vec3(0.1, 0.0, 0.0);  // a sphere inside the central body
  r = ocp::solve_collocation(DumbbellSpacecraft::paper(), d, {});
  EXPECT_EQ(r.summary.status, ocp::CollocationStatus::InvalidInput);
  EXPECT_EQ(r.summary.message.rfind("xf:", 0), 0u) << r.summary.message;
  ocp::CollocationOptions o;
  o.W = Eigen::MatrixXd::Identity(3, 3);  // the cart-pendulum has 2 controls
  r = ocp::solve_collocation(CartPendulum::paper(), ocp::CartPendulumTransfer::paper(), o);
  EXPECT_EQ(r.summary.status, ocp::CollocationStatus::InvalidInput);
  EXPECT_EQ(r.summary.message.rfind("W:", 0), 0u) << r.summary.message;
  ocp::CartPendulumTransfer c = ocp::CartPendulumTransfer::paper();
  c.q_dotf(0) = std::numeric_limits<double>::quiet_NaN();
  r = ocp::solve_collocation(CartPendulum::paper(), c, {});
  EXPECT_EQ(r.summary.status, ocp::CollocationStatus::InvalidInput);
  EXPECT_EQ(r.summary.message.rfind("q_dotf:", 0), 0u) << r.summary.message;
  // a start that cannot converge within its iterations: a named status, never a crash
  o = {};
  o.intervals = 10;
  o.max_iterations = 2;
  r = ocp::solve_collocation(ConnectedBodies::paper(), ocp::ConnectedBodiesTransfer::paper(), o);
  EXPECT_EQ(r.summary.status, ocp::CollocationStatus::IterationLimit) << r.summary.brief();
}

TEST(Collocation, BadOptionsAreNamedStatuses) {
  const auto status = [](ocp::CollocationOptions o, ocp::TransferProblem p = ocp::TransferProblem::pendulum_paper()) {
    const auto r = ocp::solve_collocation(Pendulum3D::paper(), p, o);
    EXPECT_EQ(r.summary.status, ocp::CollocationStatus::InvalidInput);
    EXPECT_TRUE(std::isfinite(r.summary.cost) || std::isinf(r.summary.cost));
    return r.summary.message;
  };
  ocp::CollocationOptions o;
  o.intervals = 1;
  EXPECT_EQ(status(o).rfind("intervals:", 0), 0u);
  o = {};
  o.tolerance = 0.0;
  EXPECT_EQ(status(o).rfind("tolerance:", 0), 0u);
  o = {};
  o.max_iterations = 0;
  EXPECT_EQ(status(o).rfind("max_iterations:", 0), 0u);
  o = {};
  o.W = Eigen::MatrixXd::Identity(2, 2);
  EXPECT_EQ(status(o).rfind("W:", 0), 0u);
  ocp::TransferProblem p = ocp::TransferProblem::pendulum_paper();
  p.Rf(0, 0) = 2.0;
  EXPECT_EQ(status({}, p).rfind("Rf:", 0), 0u);
  p = ocp::TransferProblem::pendulum_paper();
  p.t_final = -1.0;
  EXPECT_EQ(status({}, p).rfind("t_final:", 0), 0u);
}

}  // namespace
}  // namespace lgvi
