#include "baselines/pontryagin.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>

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
  const Vec3 a = R.row(2).transpose();
  const Vec3 Omega = system_.inertia.J_inverse * Pi;
  const Vec3 lR = lambda.head<3>(), lP = lambda.tail<3>();
  const Vec3 w = system_.mass * system_.gravity * system_.rho - control(R, lambda);
  Vec6 rate;
  rate.head<3>() = lR.cross(Omega) - a.cross(w.cross(lP));
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
  D.block<3, 3>(kLambdaR, kLambdaPi) = -hat(a) * hat(w) - hat(a) * hat(lP) * du_dlP;
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

Vec6 PendulumShootingFunction::conserved_gradient(const Mat3& R, const Vec3& Pi) {
  const Vec3 a = R.row(2).transpose();
  Vec6 g;
  g << Pi.cross(a), a;
  return g;
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
    // Central differences: error a^2 |r'''| + (global error) / a, balanced at a = cbrt(rtol).
    for (int i = 0; i < 6; ++i) {
      const double a = std::cbrt(integration_.rtol) * std::max(1.0, std::abs(lambda0(i)));
      Vec6 plus = lambda0, minus = lambda0;
      plus(i) += a;
      minus(i) -= a;
      const PontryaginEvaluation ep = evaluate(plus, false), em = evaluate(minus, false);
      e.stats.steps += ep.stats.steps + em.stats.steps;
      e.stats.rhs_evaluations += ep.stats.rhs_evaluations + em.stats.rhs_evaluations;
      if (!ep.ok || !em.ok) {
        e.ok = false;
        e.message = "finite-difference column " + std::to_string(i) + ": " + (ep.ok ? em.message : ep.message);
        return e;
      }
      e.jacobian.col(i) = (ep.residual - em.residual) / (2.0 * a);
    }
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

// --- Newton-Armijo shooting ------------------------------------------------------------------

ContinuousShootingResult solve_pontryagin(const Pendulum3D& system, const ocp::TransferProblem& problem,
                                          const ContinuousShootingOptions& o) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto seconds = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
  ContinuousShootingResult result;
  ocp::ShootingSummary& S = result.summary;
  S.system = "pendulum (continuous)";
  S.h = 0.0;
  S.decomposition = o.decomposition;
  result.rtol = o.integration.rtol;
  result.jacobian = o.jacobian;
  const double tolerance = o.tolerance > 0.0 ? o.tolerance : kViolationPerRtol * o.integration.rtol;
  result.tolerance = tolerance;

  std::unique_ptr<PendulumShootingFunction> fn;
  Vec6 lambda = Vec6::Zero();
  try {
    fn = std::make_unique<PendulumShootingFunction>(system, problem, o.W, o.integration);
    if (o.initial_costate.size() != 0) {
      if (o.initial_costate.size() != 6) throw InvalidInput("initial_costate", "must have 6 entries");
      require_finite(o.initial_costate, "initial_costate");
      lambda = o.initial_costate;
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
  } catch (const InvalidInput& e) {
    S.status = ocp::ShootingStatus::InvalidInput;
    S.message = e.what();
    S.wall_seconds = seconds();
    return result;
  }
  S.multiplier_guess = lambda;
  S.multiplier = lambda;

  // One shot is one integration of the state-costate ODE (13 with finite-difference Jacobians).
  struct Integrations {
    const Pendulum3D& system;
    const PendulumShootingFunction& fn;
    const ContinuousShootingOptions& o;
    ContinuousShootingResult& result;
    std::string failure;  // why the last failed evaluation failed

    PontryaginEvaluation evaluate(const Vec6& l, bool jac) {
      PontryaginEvaluation e = fn.evaluate(l, jac, o.jacobian);
      result.integrations += (jac && o.jacobian == ShootingJacobian::FiniteDifferences) ? 13 : 1;
      result.integration_steps += e.stats.steps;
      result.rhs_evaluations += e.stats.rhs_evaluations;
      return e;
    }
    // A failed evaluation leaves `out` alone: after a failed re-run the result reports the last
    // successful one.
    bool evaluate(const Vec6& l, bool jac, PontryaginEvaluation& out) {
      PontryaginEvaluation e = evaluate(l, jac);
      if (!e.ok) {
        failure = e.message;
        return false;
      }
      out = std::move(e);
      return true;
    }
    std::pair<Mat6, Vec6> terminal_symmetry(const PontryaginEvaluation& current) const {
      const Vec3 PiT = system.inertia.J * current.Omega_final;
      return {fn.residual_jacobian(current.residual),
              PendulumShootingFunction::conserved_gradient(current.R_final, PiT)};
    }
    // The integration's noise floor: r carries a global error of ~kViolationPerRtol rtol that
    // changes non-smoothly with lambda (step selection); no Newton step resolves r below it.
    double round_off_floor(const PontryaginEvaluation&, const Vec6&) const {
      return kViolationPerRtol * o.integration.rtol;
    }
    std::string stall_message(double violation, int it, double floor, double) const {
      char buf[400];
      std::snprintf(buf, sizeof buf,
                    "no decrease below violation %.3g at outer iteration %d: that is the integration's noise floor "
                    "(~%.2g at rtol %.3g), above the tolerance %.3g; tighten rtol or loosen the tolerance",
                    violation, it, floor, o.integration.rtol, result.tolerance);
      return buf;
    }
    std::string rerun_failure(const PontryaginEvaluation&) const {
      return "re-running the accepted step with its Jacobian: " + failure;
    }
  } integrations{system, *fn, o, result, {}};

  PontryaginEvaluation current = integrations.evaluate(lambda, true);
  S.sweeps = 1;
  if (!current.ok) {
    S.status = ocp::ShootingStatus::SweepFailed;
    S.message = "the initial costate guess: " + current.message;
    S.wall_seconds = seconds();
    result.final = current;
    return result;
  }
  ocp::NewtonArmijoOptions<6> newton;
  newton.max_iterations = o.max_iterations;
  newton.max_backtracks = o.max_backtracks;
  newton.armijo = o.armijo;
  newton.tolerance = tolerance;
  newton.polish_iterations = o.polish_iterations;
  newton.start = start;
  if (o.decomposition) {
    const Vec3 Pi0 = system.inertia.J * problem.Omega0;
    newton.initial_conserved_gradient = PendulumShootingFunction::conserved_gradient(problem.R0, Pi0);
  }
  ocp::newton_armijo_shooting(integrations, newton, lambda, current, S);
  S.steps = current.stats.steps;
  result.final = current;
  return result;
}

}  // namespace lgvi::baselines
