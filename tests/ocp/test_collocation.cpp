// Hermite-Simpson collocation of the attitude transfers (lgvi/ocp/collocation.hpp): the RHS and
// its Jacobian against the baselines' quaternion model and central differences, the pendulum's
// reorientation solved with its defects within the tolerance, the cost approached by the discrete
// solutions as h -> 0, the replayed answer, bad options.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

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
