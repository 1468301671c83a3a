// The discrete necessary conditions (eqs. 17-19, 27, 28) and their exact sensitivities
// z_N = Psi12 dlambda_0: against central differences, on short horizons.
#include <gtest/gtest.h>

#include <iostream>
#include <vector>

#include "ocp_cases.hpp"

namespace lgvi::test {
namespace {

using ocp::DumbbellModel;
using ocp::PendulumModel;
using ocp::StateMultiplierFlow;
using ocp::TransferProblem;

/// Short-horizon versions of the paper's problems (the tests only need generic trajectories).
TransferProblem short_pendulum() {
  TransferProblem p = TransferProblem::pendulum_paper();
  p.Omega0 = Vec3(0.5, -1.0, 0.8);  // away from rest: all terms of the linearization active
  p.t_final = 0.2;
  return p;
}
/// A dumbbell multiplier with moderate controls. lambda_Pi is the moment control (eq. 18) and
/// lambda_R feeds it at the rate lambda_R / J per unit time (the drift's multiplier map, (**)
/// in linearization.hpp); the rod-axis inertia is 0.001, so lambda_R ~ 1e-4 and lambda_Pi ~ 1e-2
/// keep the rod's spin within what one step of 0.01-0.02 resolves.
Eigen::Matrix<double, 12, 1> dumbbell_multiplier(std::mt19937_64& rng) {
  Eigen::Matrix<double, 12, 1> l = random_vector<12>(rng, 1.0);
  l.head<3>() *= 1e-4;
  l.segment<3>(6) *= 1e-2;
  return l;
}
TransferProblem short_dumbbell() {
  TransferProblem p = TransferProblem::dumbbell_paper();
  p.Omega0 = Vec3(0.3, -0.2, 0.9835);
  p.t_final = 0.2;
  return p;
}

template <class Model>
void check_sensitivities(const typename Model::System& system, const TransferProblem& problem, LgviForm form,
                         double h, const typename Model::VecS& lambda0, const char* label) {
  using Flow = StateMultiplierFlow<Model>;
  using VecS = typename Model::VecS;
  constexpr int ns = Flow::ns;
  const Flow flow(system, problem, form, h, Eigen::MatrixXd());
  typename Flow::Sweep nominal, trial;
  ASSERT_TRUE(flow.run(lambda0, true, nominal)) << flow.failure_message(nominal);
  // Five-point differences (error O(a^4)): the dumbbell's multiplier map is so strongly curved
  // (the rod-axis inertia 0.001 enters it as 1/J) that the O(a^2) error of central differences
  // reaches 1e-6 of Psi22 at a = 1e-6 for some multipliers.
  typename Model::MatS Psi12_fd, Psi22_fd, jac_fd;
  const double a = kOcpFdStep * std::max(1.0, lambda0.norm());
  const auto& sN = nominal.states.back();
  for (int i = 0; i < ns; ++i) {
    VecS dw = VecS::Zero(), dl = VecS::Zero(), dr = VecS::Zero();
    for (const auto& [k, weight] : {std::pair{-2.0, 1.0}, std::pair{-1.0, -8.0}, std::pair{1.0, 8.0},
                                    std::pair{2.0, -1.0}}) {
      ASSERT_TRUE(flow.run(lambda0 + k * a * VecS::Unit(i), false, trial));
      dw += weight * momentum_difference(flow.model(), sN, trial.states.back());
      dl += weight * trial.multipliers.back();
      dr += weight * trial.residual;
    }
    Psi12_fd.col(i) = dw / (12.0 * a);
    Psi22_fd.col(i) = dl / (12.0 * a);
    jac_fd.col(i) = dr / (12.0 * a);
  }
  const double e12 = relative_error(nominal.Psi12, Psi12_fd);
  const double e22 = relative_error(nominal.Psi22, Psi22_fd);
  const double ej = relative_error(nominal.jacobian, jac_fd);
  std::cout << "[ measured ] " << label << " (" << to_string(form) << ", " << flow.steps()
            << " steps): Psi12 " << e12 << ", Psi22 " << e22 << ", dr/dlambda0 " << ej << "\n";
  EXPECT_LT(e12, kOcpFdTolerance) << label;
  EXPECT_LT(e22, kOcpFdTolerance) << label;
  EXPECT_LT(ej, kOcpFdTolerance) << label;
}

TEST(Sensitivities, PendulumPsiMatchesFiniteDifferences) {
  const Pendulum3D pendulum = Pendulum3D::paper();
  auto rng = make_rng(511);
  for (const LgviForm form : {LgviForm::Symmetric, LgviForm::Printed}) {
    check_sensitivities<PendulumModel>(pendulum, short_pendulum(), form, 0.01, random_vector<6>(rng, 2.0),
                                       "pendulum h = 0.01");
  }
  // The paper's step over the paper's horizon (1000 steps) with a generic multiplier.
  TransferProblem full = TransferProblem::pendulum_paper();
  check_sensitivities<PendulumModel>(pendulum, full, LgviForm::Symmetric, 0.001, random_vector<6>(rng, 1.0),
                                     "pendulum, paper horizon");
}

TEST(Sensitivities, DumbbellPsiMatchesFiniteDifferences) {
  const DumbbellSpacecraft dumbbell = DumbbellSpacecraft::paper();
  auto rng = make_rng(512);
  for (const LgviForm form : {LgviForm::Symmetric, LgviForm::Printed}) {
    check_sensitivities<DumbbellModel>(dumbbell, short_dumbbell(), form, 0.01, dumbbell_multiplier(rng),
                                       "dumbbell h = 0.01");
  }
}

// Backward recursion lambda_k = A_k^T lambda_{k+1} (eqs. 19, 28) with the analytic A_k, B_k of
// linearize_step gives the gradient of Phi(u) = J(u) + g . w(s_N(u)) for ANY controls u; compared
// with central differences of Phi.
template <class Model>
void check_adjoint_gradient(const typename Model::System& system, const TransferProblem& problem,
                            LgviForm form, double h, std::mt19937_64& rng, double u_scale, const char* label) {
  using Flow = StateMultiplierFlow<Model>;
  using VecU = typename Model::VecU;
  using VecS = typename Model::VecS;
  constexpr int nu = Model::nu;
  const Flow flow(system, problem, form, h, Eigen::MatrixXd());
  const std::size_t N = flow.steps();
  std::vector<VecU> u(N + 1);
  for (auto& uj : u) uj = random_vector<nu>(rng, u_scale);
  if (form == LgviForm::Printed) u[0].setZero();
  typename Flow::Sweep nominal, trial;
  ASSERT_TRUE(flow.simulate(u, nominal));
  const VecS g = random_vector<2 * Model::nq>(rng, 1.0);
  const auto& sN = nominal.states.back();
  auto Phi = [&](const std::vector<VecU>& controls) {
    EXPECT_TRUE(flow.simulate(controls, trial));
    return trial.cost + g.dot(momentum_difference(flow.model(), sN, trial.states.back()));
  };
  // Adjoint.
  std::vector<ocp::StepJacobians<Model>> jac(N);
  for (std::size_t k = 0; k < N; ++k) {
    ASSERT_TRUE(ocp::linearize_step(flow.model(), flow.lgvi(), nominal.states[k], h, u[k], u[k + 1], jac[k]).converged());
  }
  std::vector<VecS> lambda(N + 1);
  lambda[N] = g;
  for (std::size_t k = N; k-- > 0;) lambda[k] = jac[k].A.transpose() * lambda[k + 1];
  std::vector<VecU> grad(N + 1);
  for (std::size_t j = 0; j <= N; ++j) {
    grad[j] = flow.cost_weight(j) * (flow.W() * u[j]);
    if (j < N) grad[j] += jac[j].B_k.transpose() * lambda[j + 1];
    if (j >= 1) grad[j] += jac[j - 1].B_k1.transpose() * lambda[j];
  }
  // Central differences with the balanced step.
  double err2 = 0.0, norm2 = 0.0;
  for (std::size_t j = 0; j <= N; ++j) {
    for (int i = 0; i < nu; ++i) {
      std::vector<VecU> p = u, m = u;
      p[j](i) += kFdStep;
      m[j](i) -= kFdStep;
      const double fd = (Phi(p) - Phi(m)) / (2.0 * kFdStep);
      err2 += (fd - grad[j](i)) * (fd - grad[j](i));
      norm2 += grad[j](i) * grad[j](i);
    }
  }
  const double rel = std::sqrt(err2 / norm2);
  std::cout << "[ measured ] " << label << " (" << to_string(form) << ", " << N
            << " steps): |adjoint gradient - central differences| / |gradient| = " << rel << "\n";
  EXPECT_LT(rel, kFdTolerance) << label;
}

TEST(MultiplierRecursion, AdjointGradientMatchesFiniteDifferences) {
  auto rng = make_rng(513);
  const Pendulum3D pendulum = Pendulum3D::paper();
  const DumbbellSpacecraft dumbbell = DumbbellSpacecraft::paper();
  for (const LgviForm form : {LgviForm::Symmetric, LgviForm::Printed}) {
    check_adjoint_gradient<PendulumModel>(pendulum, short_pendulum(), form, 0.02, rng, 2.0, "pendulum");
    check_adjoint_gradient<DumbbellModel>(dumbbell, short_dumbbell(), form, 0.02, rng, 0.01, "dumbbell");
  }
}

// The forward sweep from any lambda_0 satisfies the necessary conditions: its multipliers obey
// lambda_k = A_k^T lambda_{k+1} with the independently computed A_k, and its controls are
// stationary for Phi(u) = J(u) + lambda_N . w(s_N(u)) (the discrete Pontryagin conditions of
// the problem whose terminal cost is linear with gradient lambda_N).
template <class Model>
void check_forward_conditions(const typename Model::System& system, const TransferProblem& problem,
                              LgviForm form, double h, const typename Model::VecS& lambda0, const char* label) {
  using Flow = StateMultiplierFlow<Model>;
  using VecU = typename Model::VecU;
  constexpr int nu = Model::nu;
  const Flow flow(system, problem, form, h, Eigen::MatrixXd());
  const std::size_t N = flow.steps();
  typename Flow::Sweep sweep, trial;
  ASSERT_TRUE(flow.run(lambda0, false, sweep)) << flow.failure_message(sweep);
  double recursion = 0.0;
  for (std::size_t k = 0; k < N; ++k) {
    ocp::StepJacobians<Model> jac;
    ASSERT_TRUE(ocp::linearize_step(flow.model(), flow.lgvi(), sweep.states[k], h, sweep.controls[k],
                                    sweep.controls[k + 1], jac).converged());
    const auto back = (jac.A.transpose() * sweep.multipliers[k + 1]).eval();
    recursion = std::max(recursion, (back - sweep.multipliers[k]).norm() / sweep.multipliers[k].norm());
  }
  const auto& sN = sweep.states.back();
  const auto& lN = sweep.multipliers.back();
  auto terms = [&](const std::vector<VecU>& controls, double& cost, double& terminal) {
    EXPECT_TRUE(flow.simulate(controls, trial));
    cost = trial.cost;
    terminal = lN.dot(momentum_difference(flow.model(), sN, trial.states.back()));
  };
  double stationarity2 = 0.0, cost_gradient2 = 0.0;
  const std::size_t first = form == LgviForm::Printed ? 1 : 0;  // u_0 does not act in the printed form
  for (std::size_t j = first; j <= N; ++j) {
    for (int i = 0; i < nu; ++i) {
      std::vector<VecU> p = sweep.controls, m = sweep.controls;
      p[j](i) += kFdStep;
      m[j](i) -= kFdStep;
      double cp, tp, cm, tm;
      terms(p, cp, tp);
      terms(m, cm, tm);
      const double dcost = (cp - cm) / (2.0 * kFdStep);
      const double dterm = (tp - tm) / (2.0 * kFdStep);
      stationarity2 += (dcost + dterm) * (dcost + dterm);
      cost_gradient2 += dcost * dcost;
    }
  }
  const double stationarity = std::sqrt(stationarity2 / cost_gradient2);
  std::cout << "[ measured ] " << label << " (" << to_string(form) << "): multiplier recursion "
            << recursion << ", |grad Phi| / |grad J| = " << stationarity << "\n";
  EXPECT_LT(recursion, roundoff(1.0, 100.0 * static_cast<double>(N)));
  EXPECT_LT(stationarity, kFdTolerance);
}

TEST(NecessaryConditions, ForwardSweepIsStationary) {
  auto rng = make_rng(514);
  const Pendulum3D pendulum = Pendulum3D::paper();
  const DumbbellSpacecraft dumbbell = DumbbellSpacecraft::paper();
  for (const LgviForm form : {LgviForm::Symmetric, LgviForm::Printed}) {
    check_forward_conditions<PendulumModel>(pendulum, short_pendulum(), form, 0.02, random_vector<6>(rng, 2.0),
                                            "pendulum");
    check_forward_conditions<DumbbellModel>(dumbbell, short_dumbbell(), form, 0.02, dumbbell_multiplier(rng),
                                            "dumbbell");
  }
}

// The pendulum's symmetry (section 3.2): the conserved vertical momentum's gradient dC(s_N) is a
// left null vector of Psi12 and dC(s_0) a right null vector (adding it to lambda_0 changes no
// control), to round-off.
TEST(Symmetry, PendulumSensitivityIsRankDeficient) {
  const Pendulum3D pendulum = Pendulum3D::paper();
  auto rng = make_rng(515);
  for (const LgviForm form : {LgviForm::Symmetric, LgviForm::Printed}) {
    const StateMultiplierFlow<PendulumModel> flow(pendulum, TransferProblem::pendulum_paper(), form, 0.001,
                                                  Eigen::MatrixXd());
    StateMultiplierFlow<PendulumModel>::Sweep sweep;
    ASSERT_TRUE(flow.run(random_vector<6>(rng, 1.0), true, sweep));
    const Vec6 left = PendulumModel::conserved_gradient(sweep.states.back());
    const Vec6 right = PendulumModel::conserved_gradient(flow.initial_state());
    const double scale = sweep.Psi12.norm();
    const double l = (left.transpose() * sweep.Psi12).norm() / (left.norm() * scale);
    const double r = (sweep.Psi12 * right).norm() / (right.norm() * scale);
    const Eigen::JacobiSVD<Mat6> svd(sweep.jacobian);
    std::cout << "[ measured ] " << to_string(form) << ": |dC^T Psi12| " << l << ", |Psi12 dC0| " << r
              << ", singular values of dr/dlambda0 " << svd.singularValues().transpose() << "\n";
    EXPECT_LT(l, roundoff(1.0, 100.0));
    EXPECT_LT(r, roundoff(1.0, 100.0));
    // The other five directions are well determined (the shape block is invertible).
    EXPECT_GT(svd.singularValues()(4), 1e-6 * svd.singularValues()(0));
  }
}

}  // namespace
}  // namespace lgvi::test

namespace lgvi::test {
namespace {

// The free body with a body-frame control moment (ocp::FreeBodyModel: phi = 0, B = I): its
// sensitivities and necessary conditions by the same finite-difference checks as the paper's
// systems (the tolerances of ocp_cases.hpp), on a tumbling state so that the drift's
// linearization is fully active.
ocp::TransferProblem short_free_body() {
  ocp::TransferProblem p;
  p.Omega0 = Vec3(0.5, -1.0, 0.8);
  p.Rf = Vec3(-1.0, -1.0, 1.0).asDiagonal();
  p.t_final = 0.2;
  return p;
}

TEST(Sensitivities, FreeBodyPsiMatchesFiniteDifferences) {
  const FreeRigidBody body(Vec3(0.13, 0.28, 0.17).asDiagonal());
  auto rng = make_rng(515);
  for (const LgviForm form : {LgviForm::Symmetric, LgviForm::Printed}) {
    check_sensitivities<ocp::FreeBodyModel>(body, short_free_body(), form, 0.01, random_vector<6>(rng, 2.0),
                                            "free body h = 0.01");
  }
}

TEST(NecessaryConditions, FreeBodyForwardSweepIsStationary) {
  auto rng = make_rng(516);
  const FreeRigidBody body(Vec3(0.13, 0.28, 0.17).asDiagonal());
  for (const LgviForm form : {LgviForm::Symmetric, LgviForm::Printed}) {
    check_forward_conditions<ocp::FreeBodyModel>(body, short_free_body(), form, 0.02, random_vector<6>(rng, 2.0),
                                                  "free body");
  }
}

}  // namespace
}  // namespace lgvi::test
