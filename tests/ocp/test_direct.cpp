// Direct method (sections 4.1, 4.2): spline maps, linearized multibody steps, exact gradients
// against central differences, the redundant constraint's rank deficiency, and a problem with a
// closed-form optimum.
#include <gsl/gsl_errno.h>
#include <gsl/gsl_interp.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/SVD>

#include "lgvi/multibody_step_equations.hpp"
#include "lgvi/ocp/direct.hpp"
#include "lgvi/ocp/newton_armijo.hpp"
#include "lgvi/ocp/spline.hpp"
#include "lgvi/so3.hpp"
#include "test_support.hpp"

namespace lgvi::test {
namespace {

using ocp::SplineEnd;

// --- splines -------------------------------------------------------------------------------------

// Spline values at the nodes: S c against an independent evaluation.
Eigen::VectorXd sample(const Eigen::VectorXd& c, double T, long steps, SplineEnd end) {
  return ocp::spline_sampling_matrix(static_cast<int>(c.size()), T, steps, end) * c;
}

TEST(Spline, NaturalMatchesGslCspline) {
  auto rng = make_rng(61);
  std::normal_distribution<double> normal;
  for (int n : {3, 4, 7, 12}) {
    const double T = 2.0;
    const long steps = 200;
    Eigen::VectorXd c(n), t(n);
    for (int i = 0; i < n; ++i) {
      c(i) = normal(rng);
      t(i) = T * i / (n - 1);
    }
    gsl_interp* interp = gsl_interp_alloc(gsl_interp_cspline, n);
    gsl_interp_accel* acc = gsl_interp_accel_alloc();
    ASSERT_EQ(gsl_interp_init(interp, t.data(), c.data(), n), GSL_SUCCESS);
    const Eigen::VectorXd s = sample(c, T, steps, SplineEnd::Natural);
    double worst = 0.0;
    for (long j = 0; j <= steps; ++j) {
      const double tj = std::min(T * j / steps, T);
      worst = std::max(worst, std::abs(s(j) - gsl_interp_eval(interp, t.data(), c.data(), tj, acc)));
    }
    gsl_interp_accel_free(acc);
    gsl_interp_free(interp);
    // Two O(n)-operation evaluations of values of size |c|: round-off only.
    EXPECT_LE(worst, roundoff(c.cwiseAbs().maxCoeff(), 4.0 * n)) << "n = " << n;
  }
}

TEST(Spline, NotAKnotReproducesCubicsNaturalReproducesLines) {
  const double T = 4.0;
  const long steps = 400;
  const auto cubic = [](double t) { return 0.3 - 1.2 * t + 0.7 * t * t - 0.25 * t * t * t; };
  const auto line = [](double t) { return 0.3 - 1.2 * t; };
  for (int n : {4, 5, 7, 10}) {
    Eigen::VectorXd c3(n), c1(n);
    for (int i = 0; i < n; ++i) {
      c3(i) = cubic(T * i / (n - 1));
      c1(i) = line(T * i / (n - 1));
    }
    const Eigen::VectorXd s3 = sample(c3, T, steps, SplineEnd::NotAKnot);
    const Eigen::VectorXd s1 = sample(c1, T, steps, SplineEnd::Natural);
    const Eigen::VectorXd s3n = sample(c3, T, steps, SplineEnd::Natural);
    double e3 = 0.0, e1 = 0.0, e3n = 0.0;
    for (long j = 0; j <= steps; ++j) {
      const double t = T * j / steps;
      e3 = std::max(e3, std::abs(s3(j) - cubic(t)));
      e1 = std::max(e1, std::abs(s1(j) - line(t)));
      e3n = std::max(e3n, std::abs(s3n(j) - cubic(t)));
    }
    const double scale = 10.0;  // |cubic| on [0, 4]
    EXPECT_LE(e3, roundoff(scale, 8.0 * n)) << "not-a-knot, n = " << n;
    EXPECT_LE(e1, roundoff(scale, 8.0 * n)) << "natural, linear data, n = " << n;
    // The test can fail: the natural spline does not reproduce the cubic (its s'' = 0 at the ends).
    EXPECT_GT(e3n, 1e-3) << "natural, cubic data, n = " << n;
  }
  // n = 3, not-a-knot: the parabola through three points.
  const auto parabola = [](double t) { return 1.0 + 2.0 * t - 0.5 * t * t; };
  Eigen::VectorXd c(3);
  for (int i = 0; i < 3; ++i) c(i) = parabola(T * i / 2.0);
  const Eigen::VectorXd s = sample(c, T, steps, SplineEnd::NotAKnot);
  for (long j = 0; j <= steps; ++j) EXPECT_NEAR(s(j), parabola(T * j / steps), roundoff(10.0, 24.0));
}

TEST(Spline, BadInputIsRejected) {
  EXPECT_THROW(ocp::spline_sampling_matrix(2, 1.0, 10, SplineEnd::Natural), InvalidInput);
  EXPECT_THROW(ocp::spline_sampling_matrix(5, 0.0, 10, SplineEnd::Natural), InvalidInput);
  EXPECT_THROW(ocp::parse_spline_end("clamped"), InvalidInput);
}

// --- linearized steps ------------------------------------------------------------------------------

template <int N>
Eigen::Matrix<double, N, 1> random_vector(std::mt19937_64& rng, double scale) {
  std::normal_distribution<double> normal;
  Eigen::Matrix<double, N, 1> v;
  for (int i = 0; i < N; ++i) v(i) = scale * normal(rng);
  return v;
}

CartPendulumState perturbed(const CartPendulumLgvi& l, const CartPendulumState& s,
                            const Eigen::Matrix<double, 10, 1>& w) {
  return ocp::perturb(s, l.system(), w);
}
ConnectedBodiesState perturbed(const ConnectedBodiesLgvi&, const ConnectedBodiesState& s,
                               const Eigen::Matrix<double, 12, 1>& w) {
  return ocp::perturb(s, w);
}

/// J_G_xi of the step from s to out (the matrix the linearization solves with).
Eigen::MatrixXd implicit_function_matrix(const CartPendulumLgvi& l, const CartPendulumState& s,
                                         const CartPendulumState& out, double h, const Vec2& u0) {
  const CartPendulumStepEquation equation(l.system(), s, h, impulse_weights(l.form(), h).start, u0);
  return equation.J_G_xi(s.R.transpose() * out.R);
}
Eigen::MatrixXd implicit_function_matrix(const ConnectedBodiesLgvi& l, const ConnectedBodiesState& s,
                                         const ConnectedBodiesState& out, double h, const Vec3& u0) {
  const ConnectedBodiesStepEquation equation(l.system(), s, h, impulse_weights(l.form(), h).start, u0);
  return equation.J_G_xi(s.R1.transpose() * out.R1, s.R2.transpose() * out.R2);
}

// The flow's linearization (Lgvi::linearize, lgvi/multibody_lgvi.*) against central differences
// of its step(), column by column, with the balanced step kFdStep = eps^(1/3) on these O(1)
// variables and the bound kFdTolerance = 1e3 eps^(2/3) relative to the Jacobians' norm
// (test_support.hpp): truncation and the step's round-off / kFdStep are both ~eps^(2/3).
// Then the closed-form solve of the implicit-function system (LinearizationSolve::ClosedForm)
// against the pivoted LU's: the LU is backward stable and the block elimination is for the
// well-conditioned diagonal blocks these steps have (locked inertias), so each X =
// -J_G_xi^{-1} J_G_in is within ~n kappa(J_G_xi) eps |X| of the exact one, and the Jacobians
// (formed from X by the same code) within that bound relative to their norm: roundoff(kappa |J|, n).
template <class Lgvi, class Model>
void check_step_jacobians(const Lgvi& lgvi, const typename Lgvi::State& s, double h,
                          const typename Lgvi::Control& u0, const typename Lgvi::Control& u1, double& worst) {
  using StateJacobian = typename Lgvi::StateJacobian;
  using ControlJacobian = typename Lgvi::ControlJacobian;
  constexpr int nw = StateJacobian::RowsAtCompileTime, nu = ControlJacobian::ColsAtCompileTime;
  using W = Eigen::Matrix<double, nw, 1>;
  typename Lgvi::State out, plus, minus;
  ASSERT_TRUE(lgvi.step(s, h, u0, u1, out).converged());
  StateJacobian A, A_fd;
  ControlJacobian B0, B1, B0_fd, B1_fd;
  lgvi.linearize(s, out, h, u0, u1, A, B0, B1);
  const double a = kFdStep;
  const auto difference = [&](const typename Lgvi::State& x) { return Model::difference(out, x); };
  for (int i = 0; i < nw; ++i) {
    W w = W::Zero();
    w(i) = a;
    ASSERT_TRUE(lgvi.step(perturbed(lgvi, s, w), h, u0, u1, plus).converged());
    ASSERT_TRUE(lgvi.step(perturbed(lgvi, s, -w), h, u0, u1, minus).converged());
    A_fd.col(i) = (difference(plus) - difference(minus)) / (2.0 * a);
  }
  for (int i = 0; i < nu; ++i) {
    typename Lgvi::Control du = Lgvi::Control::Zero();
    du(i) = a;
    ASSERT_TRUE(lgvi.step(s, h, u0 + du, u1, plus).converged());
    ASSERT_TRUE(lgvi.step(s, h, u0 - du, u1, minus).converged());
    B0_fd.col(i) = (difference(plus) - difference(minus)) / (2.0 * a);
    ASSERT_TRUE(lgvi.step(s, h, u0, u1 + du, plus).converged());
    ASSERT_TRUE(lgvi.step(s, h, u0, u1 - du, minus).converged());
    B1_fd.col(i) = (difference(plus) - difference(minus)) / (2.0 * a);
  }
  const double scale = A.norm() + B0.norm() + B1.norm();
  const double error = std::max({(A - A_fd).norm(), (B0 - B0_fd).norm(), (B1 - B1_fd).norm()}) / scale;
  worst = std::max(worst, error);
  EXPECT_LE(error, kFdTolerance) << "A\n" << A << "\nfd\n" << A_fd << "\nB0\n" << B0 << "\nfd\n"
                                              << B0_fd << "\nB1\n" << B1 << "\nfd\n" << B1_fd;
  const double kappa = ocp::condition_number(implicit_function_matrix(lgvi, s, out, h, u0));
  StateJacobian A_cf;
  ControlJacobian B0_cf, B1_cf;
  lgvi.linearize(s, out, h, u0, u1, A_cf, B0_cf, B1_cf, LinearizationSolve::ClosedForm);
  const double closed_form_difference = std::max({(A_cf - A).norm(), (B0_cf - B0).norm(), (B1_cf - B1).norm()});
  EXPECT_LE(closed_form_difference, roundoff(kappa * scale, ControlJacobian::ColsAtCompileTime == 2 ? 3 : 6))
      << "kappa(J_G_xi) = " << kappa;
}


TEST(DirectLinearization, CartPendulumStepMatchesDifferences) {
  double worst = 0.0;
  auto rng = make_rng(62);
  const CartPendulum system = CartPendulum::paper();
  for (LgviForm form : {LgviForm::Printed, LgviForm::Symmetric}) {
    const CartPendulumLgvi lgvi(system, form);
    for (int trial = 0; trial < 5; ++trial) {
      const CartPendulumState s = lgvi.make_state(so3::random_rotation(rng), random_vector<2>(rng, 1.0),
                                                  random_vector<3>(rng, 1.0), random_vector<2>(rng, 1.0));
      SCOPED_TRACE(std::string(to_string(form)) + " trial " + std::to_string(trial));
      check_step_jacobians<CartPendulumLgvi, ocp::CartPendulumDirectModel>(
          lgvi, s, 0.05, random_vector<2>(rng, 5.0), random_vector<2>(rng, 5.0), worst);
    }
  }
  std::cout << "[ measured ] worst |J - J_fd| / |J| = " << worst << " (bound " << kFdTolerance << ")\n";
}

TEST(DirectLinearization, ConnectedBodiesStepMatchesDifferences) {
  double worst = 0.0;
  auto rng = make_rng(63);
  const ConnectedBodies system = ConnectedBodies::paper();
  for (LgviForm form : {LgviForm::Printed, LgviForm::Symmetric}) {
    const ConnectedBodiesLgvi lgvi(system, form);
    for (int trial = 0; trial < 5; ++trial) {
      const ConnectedBodiesState s = lgvi.make_state(so3::random_rotation(rng), so3::random_rotation(rng),
                                                     random_vector<3>(rng, 1.0), random_vector<3>(rng, 1.0));
      SCOPED_TRACE(std::string(to_string(form)) + " trial " + std::to_string(trial));
      check_step_jacobians<ConnectedBodiesLgvi, ocp::ConnectedBodiesDirectModel>(
          lgvi, s, 0.05, random_vector<3>(rng, 1.0), random_vector<3>(rng, 1.0), worst);
    }
  }
  std::cout << "[ measured ] worst |J - J_fd| / |J| = " << worst << " (bound " << kFdTolerance << ")\n";
}

// The terminal residual's Jacobian D = dr/dw_N against central differences.
template <class Model>
void check_residual_jacobian(const typename Model::Lgvi& lgvi, const typename Model::Transfer& p,
                             const typename Model::State& s) {
  constexpr int nw = Model::nw;
  const typename Model::MatRW D = Model::residual_jacobian(lgvi, p, s);
  typename Model::MatRW D_fd;
  for (int i = 0; i < nw; ++i) {
    Eigen::Matrix<double, nw, 1> w = Eigen::Matrix<double, nw, 1>::Zero();
    w(i) = kOcpFdStep;
    D_fd.col(i) = (Model::residual(lgvi, p, perturbed(lgvi, s, w)) - Model::residual(lgvi, p, perturbed(lgvi, s, -w))) /
                  (2.0 * kOcpFdStep);
  }
  EXPECT_LE((D - D_fd).norm(), kOcpFdTolerance * D.norm()) << "D\n" << D << "\nfd\n" << D_fd;
}

TEST(DirectLinearization, TerminalResidualJacobians) {
  auto rng = make_rng(64);
  const CartPendulum cp = CartPendulum::paper();
  const CartPendulumLgvi lc(cp);
  const ConnectedBodies cb = ConnectedBodies::paper();
  const ConnectedBodiesLgvi lb(cb);
  for (int trial = 0; trial < 5; ++trial) {
    check_residual_jacobian<ocp::CartPendulumDirectModel>(
        lc, ocp::CartPendulumTransfer::paper(),
        lc.make_state(so3::random_rotation(rng), random_vector<2>(rng, 1.0), random_vector<3>(rng, 1.0),
                      random_vector<2>(rng, 1.0)));
    check_residual_jacobian<ocp::ConnectedBodiesDirectModel>(
        lb, ocp::ConnectedBodiesTransfer::paper(),
        lb.make_state(so3::random_rotation(rng), so3::random_rotation(rng), random_vector<3>(rng, 1.0),
                      random_vector<3>(rng, 1.0)));
  }
}

// --- exact gradients of the transcription ------------------------------------------------------------

// Cost and constraint gradients with respect to the knot values against central differences of
// the whole transcription (the issue: relative <= 1e-6).
template <class Model>
void check_gradients(const ocp::DirectTranscription<Model>& tr, const Eigen::VectorXd& c) {
  typename ocp::DirectTranscription<Model>::Evaluation e, plus, minus;
  ASSERT_TRUE(tr.evaluate(c, true, e));
  const int n = tr.parameters();
  Eigen::VectorXd g_fd(n);
  Eigen::MatrixXd J_fd(tr.constraints(), n);
  for (int i = 0; i < n; ++i) {
    const double a = kOcpFdStep * (1.0 + std::abs(c(i)));
    Eigen::VectorXd x = c;
    x(i) += a;
    ASSERT_TRUE(tr.evaluate(x, false, plus));
    x(i) = c(i) - a;
    ASSERT_TRUE(tr.evaluate(x, false, minus));
    g_fd(i) = (plus.cost - minus.cost) / (2.0 * a);
    J_fd.col(i) = (plus.constraints - minus.constraints) / (2.0 * a);
  }
  EXPECT_LE((e.cost_gradient - g_fd).norm(), kOcpFdTolerance * e.cost_gradient.norm());
  EXPECT_LE((e.constraint_jacobian - J_fd).norm(), kOcpFdTolerance * e.constraint_jacobian.norm())
      << "exact\n" << e.constraint_jacobian << "\nfd\n" << J_fd;
}

TEST(DirectGradients, CartPendulumMatchesCentralDifferences) {
  const CartPendulum system = CartPendulum::paper();
  for (LgviForm form : {LgviForm::Printed, LgviForm::Symmetric}) {
    for (SplineEnd end : {SplineEnd::NotAKnot, SplineEnd::Natural}) {
      ocp::DirectOptions o;
      o.form = form;
      o.spline = end;
      o.h = 0.02;
      ocp::CartPendulumTransfer p = ocp::CartPendulumTransfer::paper();
      p.t_final = 1.0;  // short horizon: fast, and far from the optimum (generic point)
      const ocp::DirectTranscription<ocp::CartPendulumDirectModel> tr(system, p, o);
      SCOPED_TRACE(std::string(to_string(form)) + ", " + ocp::to_string(end));
      check_gradients(tr, ocp::default_initial_knots(system, o.knots));
    }
  }
}

TEST(DirectGradients, ConnectedBodiesMatchesCentralDifferences) {
  const ConnectedBodies system = ConnectedBodies::paper();
  auto rng = make_rng(65);
  for (LgviForm form : {LgviForm::Printed, LgviForm::Symmetric}) {
    ocp::DirectOptions o;
    o.form = form;
    o.h = 0.04;
    o.keep_redundant_constraint = true;  // all 12 rows
    ocp::ConnectedBodiesTransfer p = ocp::ConnectedBodiesTransfer::paper();
    p.t_final = 2.0;
    const ocp::DirectTranscription<ocp::ConnectedBodiesDirectModel> tr(system, p, o);
    SCOPED_TRACE(to_string(form));
    Eigen::VectorXd c = ocp::default_initial_knots(system, o.knots);
    std::normal_distribution<double> normal;
    for (Eigen::Index i = 0; i < c.size(); ++i) c(i) += 0.1 * normal(rng);
    check_gradients(tr, c);
  }
}

// Keeping the terminal Omega2 (section 4.2): the total angular momentum R1 Pi1 + R2 Pi2 = 0 is
// conserved for every control, so the 12 terminal rows depend on the 21 knots through a 9-dimensional
// set: three singular values of the constraint Jacobian vanish (to round-off). Without the Omega2
// rows the 9 x 21 Jacobian has full rank.
TEST(DirectGradients, RedundantTerminalVelocityMakesTheJacobianRankDeficient) {
  const ConnectedBodies system = ConnectedBodies::paper();
  ocp::DirectOptions o;
  o.h = 0.02;
  ocp::ConnectedBodiesTransfer p = ocp::ConnectedBodiesTransfer::paper();
  p.t_final = 2.0;
  const Eigen::VectorXd c = ocp::default_initial_knots(system, o.knots);
  for (bool keep : {true, false}) {
    o.keep_redundant_constraint = keep;
    const ocp::DirectTranscription<ocp::ConnectedBodiesDirectModel> tr(system, p, o);
    ocp::DirectTranscription<ocp::ConnectedBodiesDirectModel>::Evaluation e;
    ASSERT_TRUE(tr.evaluate(c, true, e));
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(e.constraint_jacobian);
    const Eigen::VectorXd sv = svd.singularValues();
    const double floor = roundoff(sv(0), static_cast<double>(tr.steps()) * 100.0);
    std::cout << "[ keep " << keep << " ] singular values: " << sv.transpose() << "\n";
    if (keep) {
      ASSERT_EQ(sv.size(), 12);
      EXPECT_GT(sv(8), 1e3 * floor);
      for (int i = 9; i < 12; ++i) EXPECT_LE(sv(i), floor) << "singular value " << i;
    } else {
      ASSERT_EQ(sv.size(), 9);
      EXPECT_GT(sv(8), 1e3 * floor);
    }
  }
}

}  // namespace
}  // namespace lgvi::test

namespace lgvi::test {
namespace {

// --- SLSQP ---------------------------------------------------------------------------------------------

// A problem with a closed-form optimum: the pendulum's mass at the pivot (d = 0) decouples it from
// the cart and from gravity, and the cart is a double integrator. In the printed form
// p_{k+1} = p_k + h u_{k+1}, (M + m)(q_{k+1} - q_k) = h p_k, so per axis, rest to rest from 0 to
// x_f, the constraints on u_1..u_N are G u = b with G = [h 1^T; h^2/(M+m) (N - j)_j], b = (0, x_f),
// and the least-cost control is u = G^T (G G^T)^{-1} b with cost J = h/2 b^T (G G^T)^{-1} b. It is
// affine in j, which both spline end conditions reproduce exactly (tested above), so the spline
// parameterization attains the discrete optimum.
TEST(DirectSolve, DoubleIntegratorReachesItsClosedFormCost) {
  const double M = 1.0, m = 1.0;
  const CartPendulum system(M, m, Vec3(1.03, 1.04, 0.03).asDiagonal(), Vec3::Zero(), 9.81);
  ocp::CartPendulumTransfer p;
  p.t_final = 0.5;
  p.qf = Vec2(0.1, -0.05);
  ocp::DirectOptions o;
  o.h = 0.01;
  o.knots = 4;
  o.initial_knots = Eigen::VectorXd::Constant(2 * o.knots, 0.1);
  // The pendulum's rows (attitude, angular velocity) do not depend on the control at all: left
  // out (with their zero Jacobian rows SLSQP does not converge, see the next test).
  o.constraint_rows = {3, 4, 8, 9};
  const long N = std::lround(p.t_final / o.h);
  Eigen::MatrixXd G(2, N);
  for (long j = 1; j <= N; ++j) {
    G(0, j - 1) = o.h;
    G(1, j - 1) = o.h * o.h / (M + m) * static_cast<double>(N - j);
  }
  const Eigen::Matrix2d GG = G * G.transpose();
  double expected = 0.0;
  for (int axis = 0; axis < 2; ++axis) {
    const Eigen::Vector2d b(0.0, p.qf(axis));
    expected += 0.5 * o.h * b.dot(GG.ldlt().solve(b));
  }
  for (SplineEnd end : {SplineEnd::NotAKnot, SplineEnd::Natural}) {
    o.spline = end;
    const auto result = ocp::solve_direct(system, p, o);
    const ocp::DirectSummary& S = result.summary;
    SCOPED_TRACE(ocp::to_string(end));
    EXPECT_EQ(S.status, ocp::DirectStatus::Converged) << S.brief();
    EXPECT_LE(S.violation, o.tolerance);
    // The cost is quadratic and the constraints linear in the knots: SLSQP's relative cost
    // tolerance (1e-14) and the violation (<= 1e-10 against |b| = 0.1) bound the error far below 1e-8.
    EXPECT_NEAR(S.cost, expected, 1e-8 * expected) << S.brief();
  }
}

// The trap of the issue: zero (rank-deficient) constraint rows stop SLSQP, and the status says so.
TEST(DirectSolve, RankDeficientConstraintsAreReportedNotConverged) {
  const CartPendulum system(1.0, 1.0, Vec3(1.03, 1.04, 0.03).asDiagonal(), Vec3::Zero(), 9.81);
  ocp::CartPendulumTransfer p;
  p.t_final = 0.5;
  p.qf = Vec2(0.1, -0.05);
  ocp::DirectOptions o;
  o.knots = 4;
  o.initial_knots = Eigen::VectorXd::Constant(2 * o.knots, 0.1);
  const auto result = ocp::solve_direct(system, p, o);  // all 10 rows, 6 of them identically zero
  std::cout << "[ result   ] " << result.summary.brief() << "\n";
  EXPECT_NE(result.summary.status, ocp::DirectStatus::Converged) << result.summary.brief();
}

// The full section 4.1 example (about 0.2 s): the acceptance bounds of the issue.
TEST(DirectSolve, CartPendulumPaperExample) {
  const CartPendulum system = CartPendulum::paper();
  const ocp::DirectOptions o;  // h = 0.01, 7 knots, not-a-knot, printed form, exact gradients
  const auto result = ocp::solve_direct(system, ocp::CartPendulumTransfer::paper(), o);
  const ocp::DirectSummary& S = result.summary;
  std::cout << "[ result   ] " << S.brief() << "\n";
  EXPECT_EQ(S.status, ocp::DirectStatus::Converged) << S.brief();
  EXPECT_LE(S.violation, 1e-8);
  EXPECT_LE(S.cost, 1.01 * 297.43);
  ASSERT_EQ(result.states.size(), S.steps + 1);
  EXPECT_LE((result.states.back().R - Mat3(Vec3(-1.0, -1.0, 1.0).asDiagonal())).norm(), 1e-8);
}

// The full section 4.2 example from one start (about 2 s): random start 6 of the CLI's default
// multistart (seed 1), the one that reaches the lowest cost there (README). The bounds,
// with the full terminal condition (Omega2 included, though not a constraint).
TEST(DirectSolve, ConnectedBodiesPaperExampleFromOneStart) {
  const ConnectedBodies system = ConnectedBodies::paper();
  ocp::DirectOptions o;
  o.initial_knots = ocp::start_knots(system, o, 6);
  const auto result = ocp::solve_direct(system, ocp::ConnectedBodiesTransfer::paper(), o);
  const ocp::DirectSummary& S = result.summary;
  std::cout << "[ result   ] " << S.brief() << "\n";
  EXPECT_EQ(S.status, ocp::DirectStatus::Converged) << S.brief();
  EXPECT_LE(S.violation, 1e-8);
  EXPECT_LE(S.cost, 1.01 * 0.574);
  ASSERT_EQ(S.residual.size(), 12);
  EXPECT_LE(S.residual.tail<3>().norm(), 1e-8);  // Omega2_N, implied by the other nine
}

// Finite-difference gradients reach the same optimum of a short problem, with more simulations.
TEST(DirectSolve, FiniteDifferenceGradientsAgreeOnAShortHorizon) {
  const CartPendulum system = CartPendulum::paper();
  ocp::CartPendulumTransfer p = ocp::CartPendulumTransfer::paper();
  ocp::DirectOptions o;
  o.h = 0.02;
  const auto exact = ocp::solve_direct(system, p, o);
  o.gradients = ocp::GradientMethod::FiniteDifference;
  const auto fd = ocp::solve_direct(system, p, o);
  ASSERT_EQ(exact.summary.status, ocp::DirectStatus::Converged) << exact.summary.brief();
  ASSERT_EQ(fd.summary.status, ocp::DirectStatus::Converged) << fd.summary.brief();
  std::cout << "[ exact    ] " << exact.summary.brief() << "\n[ fd       ] " << fd.summary.brief() << "\n";
  EXPECT_NEAR(fd.summary.cost, exact.summary.cost, 1e-6 * exact.summary.cost);
  EXPECT_GT(fd.summary.simulations, exact.summary.simulations);
}

TEST(DirectSolve, BadInputIsAStatusNamingTheField) {
  const CartPendulum system = CartPendulum::paper();
  ocp::DirectOptions o;
  o.knots = 2;
  EXPECT_EQ(ocp::solve_direct(system, ocp::CartPendulumTransfer::paper(), o).summary.status,
            ocp::DirectStatus::InvalidInput);
  o = {};
  o.h = 0.003;
  const auto r = ocp::solve_direct(system, ocp::CartPendulumTransfer::paper(), o);
  EXPECT_EQ(r.summary.status, ocp::DirectStatus::InvalidInput);
  EXPECT_NE(r.summary.message.find("h:"), std::string::npos) << r.summary.message;
  o = {};
  o.initial_knots = Eigen::VectorXd::Ones(3);
  EXPECT_NE(ocp::solve_direct(system, ocp::CartPendulumTransfer::paper(), o).summary.message.find("initial_knots"),
            std::string::npos);
}

}  // namespace
}  // namespace lgvi::test
