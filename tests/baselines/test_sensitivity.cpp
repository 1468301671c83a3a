// CVODES forward sensitivities (baselines/sensitivity.hpp): the transition matrix against central
// differences of the baseline flow, the correctors and sensitivity right-hand sides against each
// other, the tangent-coordinate conversion across charts, and the LGVI's discrete linearization
// (symmetric form) converging to it at second order in h.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <vector>

#include "baselines/mechanics.hpp"
#include "baselines/model.hpp"
#include "baselines/sensitivity.hpp"
#include "baselines/solver.hpp"
#include "lgvi/lgvi.hpp"
#include "lgvi/ocp/linearization.hpp"
#include "lgvi/ocp/models.hpp"
#include "lgvi/systems/free_rigid_body.hpp"
#include "lgvi/systems/pendulum.hpp"
#include "test_support.hpp"

namespace lgvi::test {
namespace {

using baselines::AttitudeMechanics;
using baselines::CoordinateOde;
using baselines::MatrixChart;
using baselines::QuaternionChart;
using baselines::SensitivitySettings;

using PendulumQuaternion = CoordinateOde<QuaternionChart, AttitudeMechanics<Pendulum3D>>;
using PendulumMatrix = CoordinateOde<MatrixChart, AttitudeMechanics<Pendulum3D>>;
using FreeBodyQuaternion = CoordinateOde<QuaternionChart, AttitudeMechanics<FreeRigidBody>>;

const Mat3 kR0 = so3::exp(Vec3(0.4, -0.7, 0.9));
const Vec3 kOmega0(1.1, -0.6, 0.8);

template <class Ode>
Eigen::VectorXd initial(const Ode& ode) {
  return ode.initial_state({kR0}, {kOmega0});
}

/// y(t1) of the baseline flow (cvode-adams, the solver adapters' path) at tolerance rtol.
Eigen::VectorXd flow(const baselines::Ode& ode, const Eigen::VectorXd& y0, double t1, double rtol) {
  std::vector<double> y(y0.data(), y0.data() + y0.size());
  Eigen::VectorXd out = y0;
  const std::vector<double> times{0.0, t1};
  baselines::SolverSettings s;
  s.rtol = rtol;
  s.atol = rtol;
  const Stats st = baselines::integrate("cvode-adams", ode, y, times, s, [&](std::size_t, double, const double* v) {
    out = Eigen::Map<const Eigen::VectorXd>(v, y0.size());
    return true;
  });
  EXPECT_TRUE(st.ok()) << st.brief();
  return out;
}

/// Central differences of the flow in every initial value. Error: truncation a^2 |y'''| / 6 plus
/// the integration error's non-smooth part (step selection changes with y0), ~2 e / (2 a) with
/// e ~ kSensFdGlobalErrorPerRtol rtol the global error; with rtol = 1e-13 and a = 1e-4 both are
/// ~1e-8..1e-7 relative.
Eigen::MatrixXd fd_transition(const baselines::Ode& ode, const Eigen::VectorXd& y0, double t1) {
  const int n = ode.dimension();
  Eigen::MatrixXd S(n, n);
  for (int j = 0; j < n; ++j) {
    Eigen::VectorXd p = y0, m = y0;
    p(j) += kSensFdStep;
    m(j) -= kSensFdStep;
    S.col(j) = (flow(ode, p, t1, kSensFdRtol) - flow(ode, m, t1, kSensFdRtol)) / (2.0 * kSensFdStep);
  }
  return S;
}

template <class Ode>
void check_against_fd(const Ode& ode, const char* label) {
  const Eigen::VectorXd y0 = initial(ode);
  const double T = 1.0;
  SensitivitySettings s;
  s.rtol = kSensRtol;
  const auto r = baselines::integrate_sensitivities(ode, y0, Eigen::MatrixXd::Identity(y0.size(), y0.size()), 0.0, T, s);
  ASSERT_TRUE(r.ok()) << r.stats.brief();
  const Eigen::MatrixXd fd = fd_transition(ode, y0, T);
  const double err = (r.S - fd).norm() / fd.norm();
  std::cout << "[ measured ] " << label << ": |S_cvodes - S_fd| / |S_fd| = " << err << " (" << r.stats.steps
            << " steps, " << r.stats.rhs_evaluations << " RHS, " << r.stats.jacobian_evaluations << " Jacobians)\n";
  EXPECT_LT(err, kSensFdTolerance);
  EXPECT_LT((r.y - flow(ode, y0, T, kSensFdRtol)).norm(), 1e3 * kSensRtol) << "the state itself";
}

TEST(Sensitivity, PendulumQuaternionMatchesFiniteDifferences) {
  const Pendulum3D p = Pendulum3D::paper();
  check_against_fd(PendulumQuaternion(AttitudeMechanics<Pendulum3D>(p)), "pendulum, quaternion");
}

TEST(Sensitivity, PendulumMatrixMatchesFiniteDifferences) {
  const Pendulum3D p = Pendulum3D::paper();
  check_against_fd(PendulumMatrix(AttitudeMechanics<Pendulum3D>(p)), "pendulum, matrix");
}

TEST(Sensitivity, FreeBodyQuaternionMatchesFiniteDifferences) {
  const FreeRigidBody b(Vec3(0.13, 0.28, 0.17).asDiagonal());
  check_against_fd(FreeBodyQuaternion(AttitudeMechanics<FreeRigidBody>(b)), "free body, quaternion");
}

// The two correctors and the two sensitivity right-hand sides solve the same equations: they
// agree to the integration error (a modest multiple of rtol), and the analytic right-hand side
// needs no extra f evaluations.
TEST(Sensitivity, CorrectorsAndRightHandSidesAgree) {
  const Pendulum3D p = Pendulum3D::paper();
  const PendulumQuaternion ode{AttitudeMechanics<Pendulum3D>(p)};
  const Eigen::VectorXd y0 = initial(ode);
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(7, 7);
  SensitivitySettings s;
  s.rtol = kSensRtol;
  const auto ref = baselines::integrate_sensitivities(ode, y0, I, 0.0, 1.0, s);
  ASSERT_TRUE(ref.ok());
  for (const auto corrector : {baselines::SensitivityCorrector::Simultaneous, baselines::SensitivityCorrector::Staggered}) {
    for (const auto rhs : {baselines::SensitivityRhs::Analytic, baselines::SensitivityRhs::DifferenceQuotient}) {
      for (const auto method : {baselines::MultistepMethod::Adams, baselines::MultistepMethod::Bdf}) {
        s.corrector = corrector;
        s.rhs = rhs;
        s.method = method;
        const auto r = baselines::integrate_sensitivities(ode, y0, I, 0.0, 1.0, s);
        ASSERT_TRUE(r.ok()) << r.stats.brief();
        const double err = (r.S - ref.S).norm() / ref.S.norm();
        std::cout << "[ measured ] " << to_string(corrector) << ", " << to_string(rhs) << ", "
                  << (method == baselines::MultistepMethod::Adams ? "adams" : "bdf") << ": " << r.stats.steps
                  << " steps, " << r.stats.rhs_evaluations << " RHS, " << r.stats.jacobian_evaluations
                  << " Jacobians, difference from the reference " << err << "\n";
        EXPECT_LT(err, kSensGlobalErrorPerRtol * kSensRtol);
      }
    }
  }
}

// Phi_z does not depend on the chart: the quaternion and the matrix model give the same tangent
// transition matrix (to the integration error), and it preserves the vertical momentum's
// gradient structure: e3^T R Pi conserved => dC(s_1)^T T Phi_z = dC(s_0)^T T, T = blockdiag(I, J).
TEST(Sensitivity, TangentTransitionIsChartIndependent) {
  const Pendulum3D p = Pendulum3D::paper();
  const PendulumQuaternion q{AttitudeMechanics<Pendulum3D>(p)};
  const PendulumMatrix m{AttitudeMechanics<Pendulum3D>(p)};
  SensitivitySettings s;
  s.rtol = kSensRtol;
  const Eigen::VectorXd yq = initial(q), ym = initial(m);
  const auto rq = baselines::integrate_sensitivities(q, yq, Eigen::MatrixXd::Identity(7, 7), 0.0, 1.0, s);
  const auto rm = baselines::integrate_sensitivities(m, ym, Eigen::MatrixXd::Identity(12, 12), 0.0, 1.0, s);
  ASSERT_TRUE(rq.ok() && rm.ok());
  const Eigen::Matrix<double, 6, 6> Pq = baselines::tangent_transition(q, yq, rq.y, rq.S);
  const Eigen::Matrix<double, 6, 6> Pm = baselines::tangent_transition(m, ym, rm.y, rm.S);
  const double err = (Pq - Pm).norm() / Pm.norm();
  std::cout << "[ measured ] |Phi_z(quaternion) - Phi_z(matrix)| / |Phi_z| = " << err << "\n";
  EXPECT_LT(err, kSensGlobalErrorPerRtol * kSensRtol);

  auto gradient = [&](const Mat3& R, const Vec3& Omega) {
    const Vec3 a = R.row(2).transpose();
    const Vec3 Pi = p.inertia.J * Omega;
    Eigen::Matrix<double, 6, 1> g;
    g << Pi.cross(a), a;  // on [eta; dPi]
    return g;
  };
  Eigen::Matrix<double, 6, 6> T = Eigen::Matrix<double, 6, 6>::Identity();
  T.bottomRightCorner<3, 3>() = p.inertia.J;
  const Mat3 R1 = QuaternionChart::rotation(rq.y.head<4>().normalized());
  const Eigen::Matrix<double, 1, 6> lhs = gradient(R1, rq.y.tail<3>()).transpose() * T * Pq;
  const Eigen::Matrix<double, 1, 6> rhs = gradient(kR0, kOmega0).transpose() * T;
  EXPECT_LT((lhs - rhs).norm() / rhs.norm(), kSensGlobalErrorPerRtol * kSensRtol);
}

// The symmetric LGVI is a second-order flow map, so its linearization (the product of the
// A_k of lgvi/ocp/linearization.hpp in z = [eta; dOmega]) differs from the exact transition
// matrix by C h^2 over a fixed horizon: halving h divides the difference by ~4.
TEST(Sensitivity, LgviLinearizationConvergesAtSecondOrder) {
  const Pendulum3D p = Pendulum3D::paper();
  const PendulumQuaternion ode{AttitudeMechanics<Pendulum3D>(p)};
  const double T = 0.5;
  SensitivitySettings s;
  s.rtol = kSensRtol;
  const Eigen::VectorXd y0 = initial(ode);
  const auto r = baselines::integrate_sensitivities(ode, y0, Eigen::MatrixXd::Identity(7, 7), 0.0, T, s);
  ASSERT_TRUE(r.ok());
  const Eigen::Matrix<double, 6, 6> Phi = baselines::tangent_transition(ode, y0, r.y, r.S);

  const AttitudeLgvi<Pendulum3D> lgvi(p, LgviForm::Symmetric);
  const ocp::PendulumModel model(p);
  std::vector<double> hs, errors;
  for (const int steps : {10, 20, 40, 80}) {
    const double h = T / steps;
    AttitudeState st = lgvi.make_state(kR0, kOmega0);
    Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Identity();
    for (int k = 0; k < steps; ++k) {
      ocp::StepJacobians<ocp::PendulumModel> jac;
      AttitudeState next;
      const Vec3 zero = Vec3::Zero();
      ASSERT_TRUE(ocp::linearize_step(model, lgvi, st, h, zero, zero, jac, &next).converged());
      A = ocp::to_velocity_coordinates(model, jac).A * A;
      st = next;
    }
    const double e = (A - Phi).norm() / Phi.norm();
    std::cout << "[ measured ] h = " << h << ": |Phi_lgvi - Phi_cvodes| / |Phi| = " << e << "\n";
    hs.push_back(h);
    errors.push_back(e);
    EXPECT_GT(e, 1e3 * kSensGlobalErrorPerRtol * kSensRtol) << "the difference must be the LGVI's, not CVODES's";
  }
  for (std::size_t i = 0; i + 1 < errors.size(); ++i) {
    const double order = std::log2(errors[i] / errors[i + 1]);
    std::cout << "[ measured ] observed order " << order << "\n";
    EXPECT_NEAR(order, 2.0, kSensOrderTolerance);
  }
}

TEST(Sensitivity, BadInputThrowsAndFailuresAreReported) {
  const Pendulum3D p = Pendulum3D::paper();
  const PendulumQuaternion ode{AttitudeMechanics<Pendulum3D>(p)};
  const Eigen::VectorXd y0 = initial(ode);
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(7, 7);
  SensitivitySettings s;
  EXPECT_THROW(baselines::integrate_sensitivities(ode, y0.head(5), I, 0.0, 1.0, s), InvalidInput);
  EXPECT_THROW(baselines::integrate_sensitivities(ode, y0, I.topRows(6), 0.0, 1.0, s), InvalidInput);
  // No columns: the state alone, as with sensitivities.
  s.rtol = kSensRtol;
  const auto plain = baselines::integrate_sensitivities(ode, y0, I.leftCols(0), 0.0, 1.0, s);
  const auto with = baselines::integrate_sensitivities(ode, y0, I, 0.0, 1.0, s);
  ASSERT_TRUE(plain.ok() && with.ok());
  EXPECT_EQ(plain.S.cols(), 0);
  EXPECT_LT((plain.y - with.y).norm(), kSensGlobalErrorPerRtol * kSensRtol);
  EXPECT_THROW(baselines::integrate_sensitivities(ode, y0, I, 0.0, 0.0, s), InvalidInput);
  s.rtol = -1.0;
  EXPECT_THROW(baselines::integrate_sensitivities(ode, y0, I, 0.0, 1.0, s), InvalidInput);
  // A step budget too small to reach t1: a named CVODES failure, finite numbers.
  s.rtol = 1e-10;
  s.max_steps = 5;
  const auto r = baselines::integrate_sensitivities(ode, y0, I, 0.0, 1.0, s);
  EXPECT_EQ(r.stats.status, IntegrationStatus::SolverFailed);
  std::cout << "[ measured ] " << r.stats.failure_detail << "\n";
  EXPECT_NE(r.stats.failure_detail.find("CV_TOO_MUCH_WORK"), std::string::npos) << r.stats.failure_detail;
  EXPECT_TRUE(r.y.allFinite());
}

}  // namespace
}  // namespace lgvi::test
