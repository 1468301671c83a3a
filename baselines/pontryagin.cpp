#include "baselines/pontryagin.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>

#include "lgvi/ocp/models.hpp"
#include "lgvi/ocp/newton_armijo.hpp"
#include "lgvi/so3.hpp"

namespace lgvi::baselines {

namespace {

using so3::hat;

Mat3 validated_weight(const Eigen::MatrixXd& W) {
  if (W.size() == 0) return Mat3::Identity();
  if (W.rows() != 3 || W.cols() != 3) throw InvalidInput("W", "must be 3x3");
  require_finite(W, "W");
  const double scale = W.cwiseAbs().maxCoeff();
  if (scale == 0.0 || (W - W.transpose()).cwiseAbs().maxCoeff() > 1e-12 * scale) {
    throw InvalidInput("W", "must be symmetric positive definite");
  }
  const Mat3 W3 = W;
  const Eigen::LLT<Mat3> llt(W3);
  if (llt.info() != Eigen::Success) throw InvalidInput("W", "is not positive definite");
  return W;
}

/// Central-difference shooting Jacobian dr/dlambda(0), column by column, into e.jacobian;
/// e.stats gains the evaluations' work. Error a^2 |r'''| + (global error) / a, balanced at
/// a = cbrt(rtol) (scaled by |lambda_i| >= 1). Returns false (e.ok false, e.message naming the
/// column) when an evaluation fails. `evaluate(lambda, false)` is the shooting function.
template <class Evaluation, class Vec, class Evaluate>
bool central_difference_jacobian(const Vec& lambda0, double rtol, const Evaluate& evaluate, Evaluation& e) {
  for (int i = 0; i < lambda0.size(); ++i) {
    const double a = std::cbrt(rtol) * std::max(1.0, std::abs(lambda0(i)));
    Vec plus = lambda0, minus = lambda0;
    plus(i) += a;
    minus(i) -= a;
    const Evaluation ep = evaluate(plus, false), em = evaluate(minus, false);
    e.stats.steps += ep.stats.steps + em.stats.steps;
    e.stats.rhs_evaluations += ep.stats.rhs_evaluations + em.stats.rhs_evaluations;
    if (!ep.ok || !em.ok) {
      e.ok = false;
      e.message = "finite-difference column " + std::to_string(i) + ": " + (ep.ok ? em.message : ep.message);
      return false;
    }
    e.jacobian.col(i) = (ep.residual - em.residual) / (2.0 * a);
  }
  return true;
}

}  // namespace

// --- the state-costate ODE -------------------------------------------------------------------

PendulumPontryaginOde::PendulumPontryaginOde(const Pendulum3D& system, const Eigen::MatrixXd& W)
    : system_(system), W_(validated_weight(W)), W_inverse_(W_.inverse()) {}

PendulumPontryaginOde::State PendulumPontryaginOde::initial_state(const Mat3& R0, const Vec3& Omega0,
                                                                  const Vec6& lambda0) const {
  require_finite(R0, "R0");
  if (!so3::is_rotation(R0, 1e-10)) throw InvalidInput("R0", "is not a rotation matrix (R^T R != I or det R != 1)");
  require_finite(Omega0, "Omega0");
  require_finite(lambda0, "costate");
  State y;
  y.segment<4>(kQ) = QuaternionChart::from_rotation(R0);
  y.segment<3>(kPi) = system_.inertia.J * Omega0;
  y.segment<6>(kLambdaR) = lambda0;
  y(kCost) = 0.0;
  return y;
}

Vec3 PendulumPontryaginOde::control(const Mat3& R, const Vec6& lambda) const {
  const Vec3 a = R.row(2).transpose();
  return -W_inverse_ * lambda.tail<3>().cross(a);
}

double PendulumPontryaginOde::hamiltonian(const Mat3& R, const Vec3& Pi, const Vec6& lambda, const Vec3& u) const {
  const Vec3 Omega = system_.inertia.J_inverse * Pi;
  const Vec3 Pi_dot = Pi.cross(Omega) + system_.moment(R) + system_.control_moment(R, u);
  return 0.5 * u.dot(W_ * u) + lambda.head<3>().dot(Omega) + lambda.tail<3>().dot(Pi_dot);
}

Vec6 PendulumPontryaginOde::costate_rate(const Mat3& R, const Vec3& Pi, const Vec6& lambda) const {
  const Vec3 Omega = system_.inertia.J_inverse * Pi;
  const Vec3 lR = lambda.head<3>(), lP = lambda.tail<3>();
  Vec6 rate;
  // lambda_R' = lambda_R x Omega - (dM/deta)^T lambda_Pi, M the applied moment (gravity and control).
  rate.head<3>() = lR.cross(Omega) - system_.J_moment_eta(R, control(R, lambda)).transpose() * lP;
  rate.tail<3>() = -system_.inertia.J_inverse * (lR - Pi.cross(lP)) - Omega.cross(lP);
  return rate;
}

RhsStatus PendulumPontryaginOde::rhs(double /*t*/, const double* y_ptr, double* ydot_ptr) const {
  const Eigen::Map<const State> y(y_ptr);
  Eigen::Map<State> ydot(ydot_ptr);
  const QuaternionChart::Coords q = y.segment<4>(kQ);
  const Mat3 R = QuaternionChart::rotation(q);
  const Vec3 a = R.row(2).transpose();
  const Vec3 Pi = y.segment<3>(kPi);
  const Vec6 lambda = y.segment<6>(kLambdaR);
  const Vec3 Omega = system_.inertia.J_inverse * Pi;
  const Vec3 u = control(R, lambda);
  const Vec3 w = system_.mass * system_.gravity * system_.rho - u;
  ydot.segment<4>(kQ) = QuaternionChart::rate(q, Omega);
  ydot.segment<3>(kPi) = Pi.cross(Omega) + w.cross(a);
  ydot.segment<6>(kLambdaR) = costate_rate(R, Pi, lambda);
  ydot(kCost) = 0.5 * u.dot(W_ * u);
  return RhsStatus::Ok;
}

RhsStatus PendulumPontryaginOde::jacobian(double /*t*/, const double* y_ptr, double* J_ptr) const {
  const Eigen::Map<const State> y(y_ptr);
  Eigen::Map<Jacobian> D(J_ptr);
  D.setZero();
  const QuaternionChart::Coords q = y.segment<4>(kQ);
  const Mat3 R = QuaternionChart::rotation(q);
  const Vec3 a = R.row(2).transpose();
  // da/dq: the rows of vec_rows(R) that hold R31, R32, R33.
  const Eigen::Matrix<double, 3, 4> Da = QuaternionChart::rotation_jacobian(q).bottomRows<3>();
  const Mat3& Jinv = system_.inertia.J_inverse;
  const Vec3 Pi = y.segment<3>(kPi);
  const Vec3 lR = y.segment<3>(kLambdaR), lP = y.segment<3>(kLambdaPi);
  const Vec3 Omega = Jinv * Pi;
  const Vec3 u = -W_inverse_ * lP.cross(a);
  const Vec3 w = system_.mass * system_.gravity * system_.rho - u;
  // du = -W^{-1} (dlP x a + lP x da), dw = -du.
  const Eigen::Matrix<double, 3, 4> du_dq = -W_inverse_ * hat(lP) * Da;
  const Mat3 du_dlP = W_inverse_ * hat(a);

  D.block<4, 4>(kQ, kQ) = QuaternionChart::rate_jacobian(q, Omega);
  D.block<4, 3>(kQ, kPi) = QuaternionChart::rate_omega_jacobian(q) * Jinv;
  // Pi' = Pi x Omega + w x a.
  D.block<3, 4>(kPi, kQ) = hat(a) * du_dq + hat(w) * Da;
  D.block<3, 3>(kPi, kPi) = -hat(Omega) + hat(Pi) * Jinv;
  D.block<3, 3>(kPi, kLambdaPi) = hat(a) * du_dlP;
  // lambda_R' = lambda_R x Omega - a x (w x lambda_Pi).
  D.block<3, 4>(kLambdaR, kQ) = hat(w.cross(lP)) * Da - hat(a) * hat(lP) * du_dq;
  D.block<3, 3>(kLambdaR, kPi) = hat(lR) * Jinv;
  D.block<3, 3>(kLambdaR, kLambdaR) = -hat(Omega);
  D.block<3, 3>(kLambdaR, kLambdaPi) = -system_.J_moment_eta(R, u).transpose() - hat(a) * hat(lP) * du_dlP;
  // lambda_Pi' = -J^{-1} (lambda_R - Pi x lambda_Pi) - Omega x lambda_Pi.
  D.block<3, 3>(kLambdaPi, kPi) = -Jinv * hat(lP) + hat(lP) * Jinv;
  D.block<3, 3>(kLambdaPi, kLambdaR) = -Jinv;
  D.block<3, 3>(kLambdaPi, kLambdaPi) = Jinv * hat(Pi) - hat(Omega);
  // c' = 1/2 u^T W u.
  const Eigen::Matrix<double, 1, 3> Wu = (W_ * u).transpose();
  D.block<1, 4>(kCost, kQ) = Wu * du_dq;
  D.block<1, 3>(kCost, kLambdaPi) = Wu * du_dlP;
  return RhsStatus::Ok;
}

// --- the shooting function -----------------------------------------------------------------

const char* to_string(ShootingJacobian j) {
  return j == ShootingJacobian::Sensitivities ? "sensitivities" : "finite-differences";
}

PendulumShootingFunction::PendulumShootingFunction(const Pendulum3D& system, const ocp::TransferProblem& problem,
                                                   const Eigen::MatrixXd& W, const SensitivitySettings& integration)
    : ode_(system, W), problem_(problem), integration_(integration) {
  require_finite(problem.R0, "R0");
  require_finite(problem.Rf, "Rf");
  if (!so3::is_rotation(problem.R0, 1e-10)) throw InvalidInput("R0", "is not a rotation matrix");
  if (!so3::is_rotation(problem.Rf, 1e-10)) throw InvalidInput("Rf", "is not a rotation matrix");
  require_finite(problem.Omega0, "Omega0");
  require_finite(problem.Omegaf, "Omegaf");
  if (!(problem.t_final > 0.0) || !std::isfinite(problem.t_final)) throw InvalidInput("t_final", "must be finite and > 0");
  if (!(integration.rtol > 0.0) || !std::isfinite(integration.rtol)) throw InvalidInput("rtol", "must be finite and > 0");
}

Mat6 PendulumShootingFunction::residual_jacobian(const Vec6& r) const {
  Mat6 D = Mat6::Zero();
  D.topLeftCorner<3, 3>() = so3::right_jacobian_inverse(r.head<3>());
  D.bottomRightCorner<3, 3>() = ode_.system().inertia.J_inverse;
  return D;
}

PontryaginEvaluation PendulumShootingFunction::evaluate(const Vec6& lambda0, bool jacobian,
                                                        ShootingJacobian method) const {
  using Ode = PendulumPontryaginOde;
  PontryaginEvaluation e;
  if (!lambda0.allFinite()) {
    e.message = "non-finite costate";
    return e;
  }
  const Ode::State y0 = ode_.initial_state(problem_.R0, problem_.Omega0, lambda0);
  const bool sens = jacobian && method == ShootingJacobian::Sensitivities;
  Eigen::MatrixXd S0 = Eigen::MatrixXd::Zero(Ode::kDim, sens ? 6 : 0);
  if (sens) S0.middleRows<6>(Ode::kLambdaR).setIdentity();
  SensitivityResult run;
  try {
    run = integrate_sensitivities(ode_, y0, S0, 0.0, problem_.t_final, integration_);
  } catch (const InvalidInput& error) {  // settings the constructor does not check (atol, max_steps)
    e.message = error.what();
    return e;
  }
  e.stats = run.stats;
  if (!run.ok()) {
    e.message = run.stats.brief();
    return e;
  }
  const QuaternionChart::Coords q = run.y.segment<4>(Ode::kQ);
  const Mat3 R = QuaternionChart::rotation(q.normalized());
  const Vec3 Pi = run.y.segment<3>(Ode::kPi);
  e.R_final = R;
  e.Omega_final = ode_.system().inertia.J_inverse * Pi;
  e.costate_final = run.y.segment<6>(Ode::kLambdaR);
  e.cost = run.y(Ode::kCost);
  e.residual.head<3>() = so3::log(problem_.Rf.transpose() * R);
  e.residual.tail<3>() = e.Omega_final - problem_.Omegaf;
  if (!e.residual.allFinite() || !std::isfinite(e.cost)) {
    e.message = "non-finite terminal residual or cost";
    return e;
  }
  e.ok = true;
  if (!jacobian) return e;
  if (sens) {
    // [eta; dPi](T) per column: eta = eta_per_chart(q) dq (exact off the unit sphere too).
    Eigen::Matrix<double, 6, Ode::kDim> T = Eigen::Matrix<double, 6, Ode::kDim>::Zero();
    T.topLeftCorner<3, 4>() = eta_per_chart<QuaternionChart>(q);
    T.block<3, 3>(3, Ode::kPi).setIdentity();
    e.Psi = T * run.S;
    e.jacobian = residual_jacobian(e.residual) * e.Psi;
  } else {
    const auto shoot = [this](const Vec6& l, bool j) { return evaluate(l, j); };
    if (!central_difference_jacobian(lambda0, integration_.rtol, shoot, e)) return e;
    e.Psi = residual_jacobian(e.residual).inverse() * e.jacobian;
  }
  if (!e.jacobian.allFinite()) {
    e.ok = false;
    e.message = "non-finite shooting Jacobian";
  }
  return e;
}

std::pair<Mat6, Vec6> PendulumShootingFunction::terminal_symmetry(const PontryaginEvaluation& at) const {
  const Vec3 PiT = ode_.system().inertia.J * at.Omega_final;
  return {residual_jacobian(at.residual), Pendulum3D::vertical_momentum_gradient(at.R_final, PiT)};
}

// --- the dumbbell ------------------------------------------------------------------------------

namespace {

Mat6 validated_weight6(const Eigen::MatrixXd& W) {
  if (W.size() == 0) return Mat6::Identity();
  if (W.rows() != 6 || W.cols() != 6) throw InvalidInput("W", "must be 6x6");
  require_finite(W, "W");
  const double scale = W.cwiseAbs().maxCoeff();
  if (scale == 0.0 || (W - W.transpose()).cwiseAbs().maxCoeff() > 1e-12 * scale) {
    throw InvalidInput("W", "must be symmetric positive definite");
  }
  const Mat6 W6 = W;
  if (Eigen::LLT<Mat6>(W6).info() != Eigen::Success) throw InvalidInput("W", "is not positive definite");
  return W6;
}

}  // namespace

DumbbellPontryaginOde::DumbbellPontryaginOde(const DumbbellSpacecraft& system, const Eigen::MatrixXd& W)
    : system_(system), W_(validated_weight6(W)), W_inverse_(W_.inverse()) {}

DumbbellPontryaginOde::State DumbbellPontryaginOde::initial_state(const ocp::TransferProblem& problem,
                                                                  const Vec12& lambda0) const {
  require_finite(problem.R0, "R0");
  if (!so3::is_rotation(problem.R0, 1e-10)) throw InvalidInput("R0", "is not a rotation matrix");
  require_finite(problem.x0, "x0");
  require_finite(problem.Omega0, "Omega0");
  require_finite(problem.v0, "v0");
  require_finite(lambda0, "costate");
  State y;
  y.segment<4>(kQ) = QuaternionChart::from_rotation(problem.R0);
  y.segment<3>(kX) = problem.x0;
  y.segment<3>(kPi) = system_.inertia.J * problem.Omega0;
  y.segment<3>(kP) = system_.mass * problem.v0;
  y.segment<12>(kLambda) = lambda0;
  y(kCost) = 0.0;
  return y;
}

Vec6 DumbbellPontryaginOde::control(const Vec12& lambda) const { return -W_inverse_ * lambda.tail<6>(); }

double DumbbellPontryaginOde::hamiltonian(const Mat3& R, const Vec3& x, const Vec3& Pi, const Vec3& p,
                                          const Vec12& lambda, const Vec6& u) const {
  const Vec3 Omega = system_.inertia.J_inverse * Pi;
  const DumbbellSpacecraft::Forces phi = system_.forces(R, x);
  return 0.5 * u.dot(W_ * u) + lambda.segment<3>(0).dot(Omega) + lambda.segment<3>(3).dot(p / system_.mass) +
         lambda.segment<3>(6).dot(Pi.cross(Omega) + phi.moment + u.head<3>()) +
         lambda.segment<3>(9).dot(phi.force + u.tail<3>());
}

Vec12 DumbbellPontryaginOde::costate_rate(const Mat3& R, const Vec3& x, const Vec3& Pi, const Vec12& lambda) const {
  const ocp::DumbbellModel model(system_);
  const Vec3 Omega = system_.inertia.J_inverse * Pi;
  const Vec3 lR = lambda.segment<3>(0), lx = lambda.segment<3>(3), lPi = lambda.segment<3>(6);
  const Vec6 GtlP = model.force_jacobian(R, x, Vec6::Zero()).transpose() * lambda.tail<6>();
  Vec12 rate;
  rate.segment<3>(0) = lR.cross(Omega) - GtlP.head<3>();
  rate.segment<3>(3) = -GtlP.tail<3>();
  rate.segment<3>(6) = -system_.inertia.J_inverse * (lR - Pi.cross(lPi)) - Omega.cross(lPi);
  rate.segment<3>(9) = -lx / system_.mass;
  return rate;
}

RhsStatus DumbbellPontryaginOde::rhs(double /*t*/, const double* y_ptr, double* ydot_ptr) const {
  const Eigen::Map<const State> y(y_ptr);
  Eigen::Map<State> ydot(ydot_ptr);
  const QuaternionChart::Coords q = y.segment<4>(kQ);
  const Mat3 R = QuaternionChart::rotation(q.normalized());
  const Vec3 x = y.segment<3>(kX), Pi = y.segment<3>(kPi), p = y.segment<3>(kP);
  const Vec12 lambda = y.segment<12>(kLambda);
  const Vec3 Omega = system_.inertia.J_inverse * Pi;
  const Vec6 u = control(lambda);
  const DumbbellSpacecraft::Forces phi = system_.forces(R, x);
  ydot.segment<4>(kQ) = QuaternionChart::rate(q, Omega);
  ydot.segment<3>(kX) = p / system_.mass;
  ydot.segment<3>(kPi) = Pi.cross(Omega) + phi.moment + u.head<3>();
  ydot.segment<3>(kP) = phi.force + u.tail<3>();
  ydot.segment<12>(kLambda) = costate_rate(R, x, Pi, lambda);
  ydot(kCost) = 0.5 * u.dot(W_ * u);
  return RhsStatus::Ok;
}

RhsStatus DumbbellPontryaginOde::jacobian(double /*t*/, const double* y_ptr, double* J_ptr) const {
  const Eigen::Map<const State> y(y_ptr);
  Eigen::Map<Jacobian> D(J_ptr);
  D.setZero();
  const ocp::DumbbellModel model(system_);
  const QuaternionChart::Coords q = y.segment<4>(kQ);
  const Mat3 R = QuaternionChart::rotation(q.normalized());
  // dR = R hat(E dq) for R = rotation(q / |q|) (the radial direction of q drops out).
  const Eigen::Matrix<double, 3, 4> E = eta_per_chart<QuaternionChart>(q);
  const Vec3 x = y.segment<3>(kX), Pi = y.segment<3>(kPi);
  const Vec12 lambda = y.segment<12>(kLambda);
  const Vec6 lP = lambda.tail<6>();
  const Mat3& Jinv = system_.inertia.J_inverse;
  const Vec3 Omega = Jinv * Pi;
  const Vec3 lR = lambda.segment<3>(0), lPi = lambda.segment<3>(6);
  const Vec6 u = control(lambda);
  const Mat6 G = model.force_jacobian(R, x, u);                                // d phi / d[eta; dx]
  const Mat6 H = model.force_jacobian_transpose_derivative(R, x, u, lP);      // d (G^T lP) / d[eta; dx]
  const double m = system_.mass;
  constexpr int kLq = kLambda, kLPi = kLambda + 6, kLx = kLambda + 3;
  // q' = rate(q, Omega).
  D.block<4, 4>(kQ, kQ) = QuaternionChart::rate_jacobian(q, Omega);
  D.block<4, 3>(kQ, kPi) = QuaternionChart::rate_omega_jacobian(q) * Jinv;
  // x' = p / m.
  D.block<3, 3>(kX, kP) = Mat3::Identity() / m;
  // [Pi; p]' = [Pi x Omega; 0] + phi + u, u = -W^{-1} lP.
  D.block<6, 4>(kPi, kQ) = G.leftCols<3>() * E;
  D.block<6, 3>(kPi, kX) = G.rightCols<3>();
  D.block<3, 3>(kPi, kPi) = -so3::hat(Omega) + so3::hat(Pi) * Jinv;
  D.block<6, 6>(kPi, kLPi) = -W_inverse_;
  // [lambda_R; lambda_x]' = [lambda_R x Omega; 0] - G^T lP.
  D.block<6, 4>(kLq, kQ) = -H.leftCols<3>() * E;
  D.block<6, 3>(kLq, kX) = -H.rightCols<3>();
  D.block<3, 3>(kLq, kPi) = so3::hat(lR) * Jinv;
  D.block<3, 3>(kLq, kLq) = -so3::hat(Omega);
  D.block<6, 6>(kLq, kLPi) = -G.transpose();
  // lambda_Pi' = -J^{-1} (lambda_R - Pi x lambda_Pi) - Omega x lambda_Pi.
  D.block<3, 3>(kLPi, kPi) = -Jinv * so3::hat(lPi) + so3::hat(lPi) * Jinv;
  D.block<3, 3>(kLPi, kLq) = -Jinv;
  D.block<3, 3>(kLPi, kLPi) = Jinv * so3::hat(Pi) - so3::hat(Omega);
  // lambda_p' = -lambda_x / m.
  D.block<3, 3>(kLPi + 3, kLx) = -Mat3::Identity() / m;
  // c' = 1/2 u^T W u: d/dlP = -u^T.
  D.block<1, 6>(kCost, kLPi) = -u.transpose();
  return RhsStatus::Ok;
}

DumbbellShootingFunction::DumbbellShootingFunction(const DumbbellSpacecraft& system,
                                                   const ocp::TransferProblem& problem, const Eigen::MatrixXd& W,
                                                   const SensitivitySettings& integration)
    : ode_(system, W), problem_(problem), integration_(integration) {
  require_finite(problem.Rf, "Rf");
  if (!so3::is_rotation(problem.Rf, 1e-10)) throw InvalidInput("Rf", "is not a rotation matrix");
  require_finite(problem.xf, "xf");
  require_finite(problem.Omegaf, "Omegaf");
  require_finite(problem.vf, "vf");
  (void)ode_.initial_state(problem, Vec12::Zero());  // validates R0, x0, Omega0, v0
  if (!(problem.t_final > 0.0) || !std::isfinite(problem.t_final)) throw InvalidInput("t_final", "must be finite and > 0");
  if (!(integration.rtol > 0.0) || !std::isfinite(integration.rtol)) throw InvalidInput("rtol", "must be finite and > 0");
}

Mat12 DumbbellShootingFunction::residual_jacobian(const Vec12& r) const {
  Mat12 D = Mat12::Identity();
  D.topLeftCorner<3, 3>() = so3::right_jacobian_inverse(r.head<3>());
  D.block<3, 3>(6, 6) = ode_.system().inertia.J_inverse;
  D.block<3, 3>(9, 9) = Mat3::Identity() / ode_.system().mass;
  return D;
}

DumbbellPontryaginEvaluation DumbbellShootingFunction::evaluate(const Vec12& lambda0, bool jacobian,
                                                                ShootingJacobian method) const {
  using Ode = DumbbellPontryaginOde;
  DumbbellPontryaginEvaluation e;
  if (!lambda0.allFinite()) {
    e.message = "non-finite costate";
    return e;
  }
  const Ode::State y0 = ode_.initial_state(problem_, lambda0);
  const bool sens = jacobian && method == ShootingJacobian::Sensitivities;
  Eigen::MatrixXd S0 = Eigen::MatrixXd::Zero(Ode::kDim, sens ? 12 : 0);
  if (sens) S0.middleRows<12>(Ode::kLambda).setIdentity();
  SensitivityResult run;
  try {
    run = integrate_sensitivities(ode_, y0, S0, 0.0, problem_.t_final, integration_);
  } catch (const InvalidInput& error) {
    e.message = error.what();
    return e;
  }
  e.stats = run.stats;
  if (!run.ok()) {
    e.message = run.stats.brief();
    return e;
  }
  const DumbbellSpacecraft& d = ode_.system();
  const QuaternionChart::Coords q = run.y.segment<4>(Ode::kQ);
  e.R_final = QuaternionChart::rotation(q.normalized());
  e.x_final = run.y.segment<3>(Ode::kX);
  e.Omega_final = d.inertia.J_inverse * run.y.segment<3>(Ode::kPi);
  e.v_final = run.y.segment<3>(Ode::kP) / d.mass;
  e.costate_final = run.y.segment<12>(Ode::kLambda);
  e.cost = run.y(Ode::kCost);
  e.residual << so3::log(problem_.Rf.transpose() * e.R_final), e.x_final - problem_.xf,
      e.Omega_final - problem_.Omegaf, e.v_final - problem_.vf;
  if (!e.residual.allFinite() || !std::isfinite(e.cost)) {
    e.message = "non-finite terminal residual or cost";
    return e;
  }
  e.ok = true;
  if (!jacobian) return e;
  if (sens) {
    Eigen::Matrix<double, 12, Ode::kDim> T = Eigen::Matrix<double, 12, Ode::kDim>::Zero();
    T.topLeftCorner<3, 4>() = eta_per_chart<QuaternionChart>(q);
    T.block<9, 9>(3, Ode::kX).setIdentity();
    e.Psi = T * run.S;
    e.jacobian = residual_jacobian(e.residual) * e.Psi;
  } else {
    const auto shoot = [this](const Vec12& l, bool j) { return evaluate(l, j); };
    if (!central_difference_jacobian(lambda0, integration_.rtol, shoot, e)) return e;
    e.Psi = residual_jacobian(e.residual).inverse() * e.jacobian;
  }
  if (!e.jacobian.allFinite()) {
    e.ok = false;
    e.message = "non-finite shooting Jacobian";
  }
  return e;
}

Vec6 continuous_costate_from_discrete(const Eigen::VectorXd& discrete_multiplier) {
  if (discrete_multiplier.size() != 6) throw InvalidInput("multiplier", "must have 6 entries [lambda_R; lambda_Pi]");
  require_finite(discrete_multiplier, "multiplier");
  return discrete_multiplier;
}


namespace {

/// The Problem of ocp::newton_armijo_shooting for a continuous shooting function: one shot is one
/// integration of the state-costate ODE (2 n + 1 with finite-difference Jacobians).
template <class Fn, class Result, class Vec, class Mat>
struct Integrations {
  using Evaluation = decltype(Result::final);
  const Fn& fn;
  const ContinuousShootingOptions& o;
  Result& result;
  std::string failure;  // why the last failed evaluation failed

  Evaluation evaluate(const Vec& l, bool jac) {
    Evaluation e = fn.evaluate(l, jac, o.jacobian);
    result.integrations += (jac && o.jacobian == ShootingJacobian::FiniteDifferences) ? 2 * Vec::RowsAtCompileTime + 1 : 1;
    result.integration_steps += e.stats.steps;
    result.rhs_evaluations += e.stats.rhs_evaluations;
    return e;
  }
  // A failed evaluation leaves `out` alone: after a failed re-run the result reports the last
  // successful one.
  bool evaluate(const Vec& l, bool jac, Evaluation& out) {
    Evaluation e = evaluate(l, jac);
    if (!e.ok) {
      failure = e.message;
      return false;
    }
    out = std::move(e);
    return true;
  }
  std::pair<Mat, Vec> terminal_symmetry(const Evaluation& current) const { return fn.terminal_symmetry(current); }
  // The integration's noise floor: r carries a global error of ~kViolationPerRtol rtol that
  // changes non-smoothly with lambda (step selection); no Newton step resolves r below it.
  double round_off_floor(const Evaluation&, const Vec&) const { return kViolationPerRtol * o.integration.rtol; }
  std::string stall_message(double violation, int it, double floor, double) const {
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "no decrease below violation %.3g at outer iteration %d: that is the integration's noise floor "
                  "(~%.2g at rtol %.3g), above the tolerance %.3g; tighten rtol or loosen the tolerance",
                  violation, it, floor, o.integration.rtol, result.tolerance);
    return buf;
  }
  std::string rerun_failure(const Evaluation&) const {
    return "re-running the accepted step with its Jacobian: " + failure;
  }
};

/// Validation of the options common to both systems; throws InvalidInput naming the field.
void check_options(const ContinuousShootingOptions& o, int n) {
  if (o.initial_costate.size() != 0) {
    if (o.initial_costate.size() != n) {
      throw InvalidInput("initial_costate", "must have " + std::to_string(n) + " entries");
    }
    require_finite(o.initial_costate, "initial_costate");
  }
  if (o.max_iterations < 0) throw InvalidInput("max_iterations", "must be >= 0");
  if (o.max_backtracks < 0) throw InvalidInput("max_backtracks", "must be >= 0");
  if (!(o.armijo > 0.0 && o.armijo < 1.0)) throw InvalidInput("armijo", "must lie in (0, 1)");
  if (!(o.tolerance >= 0.0) || !std::isfinite(o.tolerance)) throw InvalidInput("tolerance", "must be finite and >= 0");
  if (o.polish_iterations < 0) throw InvalidInput("polish_iterations", "must be >= 0");
  if (o.integration.atol && !(*o.integration.atol > 0.0 && std::isfinite(*o.integration.atol))) {
    throw InvalidInput("atol", "must be finite and > 0");
  }
  if (o.integration.max_steps == 0) throw InvalidInput("max_steps", "must be > 0");
}

}  // namespace

// --- Newton-Armijo shooting ------------------------------------------------------------------

namespace {

/// The continuous shooting of either system: summary fields, the violation tolerance (default
/// kViolationPerRtol rtol), the shooting function's construction and the options' validation
/// (InvalidInput becomes the status), the initial costate (zero unless given), the first
/// integration with its Jacobian, then Newton-Armijo. `configure` adds the system's Newton
/// settings (the pendulum's symmetry direction).
template <class Fn, class Result, int N, class System, class Configure>
Result continuous_shooting(const System& system, const ocp::TransferProblem& problem, const ContinuousShootingOptions& o,
                           const char* name, bool decomposition, Configure configure) {
  using Vec = Eigen::Matrix<double, N, 1>;
  using Mat = Eigen::Matrix<double, N, N>;
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto seconds = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
  Result result;
  ocp::ShootingSummary& S = result.summary;
  S.system = name;
  S.h = 0.0;
  S.decomposition = decomposition;
  result.rtol = o.integration.rtol;
  result.jacobian = o.jacobian;
  const double tolerance = o.tolerance > 0.0 ? o.tolerance : kViolationPerRtol * o.integration.rtol;
  result.tolerance = tolerance;

  std::unique_ptr<Fn> fn;
  Vec lambda = Vec::Zero();
  try {
    fn = std::make_unique<Fn>(system, problem, o.W, o.integration);
    check_options(o, N);
    if (o.initial_costate.size() != 0) lambda = o.initial_costate;
  } catch (const InvalidInput& e) {
    S.status = ocp::ShootingStatus::InvalidInput;
    S.message = e.what();
    S.wall_seconds = seconds();
    return result;
  }
  S.multiplier_guess = lambda;
  S.multiplier = lambda;

  Integrations<Fn, Result, Vec, Mat> integrations{*fn, o, result, {}};
  auto current = integrations.evaluate(lambda, true);
  S.sweeps = 1;
  if (!current.ok) {
    S.status = ocp::ShootingStatus::SweepFailed;
    S.message = "the initial costate guess: " + current.message;
    S.wall_seconds = seconds();
    result.final = current;
    return result;
  }
  ocp::NewtonArmijoOptions<N> newton;
  newton.max_iterations = o.max_iterations;
  newton.max_backtracks = o.max_backtracks;
  newton.armijo = o.armijo;
  newton.tolerance = tolerance;
  newton.polish_iterations = o.polish_iterations;
  newton.start = start;
  configure(newton);
  ocp::newton_armijo_shooting(integrations, newton, lambda, current, S);
  S.steps = current.stats.steps;
  result.final = current;
  return result;
}

}  // namespace

ContinuousShootingResult solve_pontryagin(const Pendulum3D& system, const ocp::TransferProblem& problem,
                                          const ContinuousShootingOptions& o) {
  return continuous_shooting<PendulumShootingFunction, ContinuousShootingResult, 6>(
      system, problem, o, "pendulum (continuous)", o.decomposition, [&](ocp::NewtonArmijoOptions<6>& newton) {
        if (!o.decomposition) return;
        const Vec3 Pi0 = system.inertia.J * problem.Omega0;
        newton.initial_conserved_gradient = Pendulum3D::vertical_momentum_gradient(problem.R0, Pi0);
      });
}

DumbbellContinuousShootingResult solve_pontryagin(const DumbbellSpacecraft& system,
                                                  const ocp::TransferProblem& problem,
                                                  const ContinuousShootingOptions& o) {
  return continuous_shooting<DumbbellShootingFunction, DumbbellContinuousShootingResult, 12>(
      system, problem, o, "dumbbell (continuous)", false, [](ocp::NewtonArmijoOptions<12>&) {});
}

}  // namespace lgvi::baselines
