#include "lgvi/ocp/indirect.hpp"

#include "lgvi/ocp/newton_armijo.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

namespace lgvi::ocp {

void ShootingOptions::validate() const {
  if (initial_multiplier.size() != 0) {
    for (Eigen::Index i = 0; i < initial_multiplier.size(); ++i) {
      require_admissible(initial_multiplier(i), "initial_multiplier[" + std::to_string(i) + "]");
    }
  }
  kMaxIterations.require(max_iterations, "max_iterations");
  kMaxBacktracks.require(max_backtracks, "max_backtracks");
  Range::open(0, 1).require(armijo, "armijo");
  kTolerance.require(tolerance, "tolerance");
  kPolishIterations.require(polish_iterations, "polish_iterations");
  kLmInitialDamping.require(lm_initial_damping, "lm_initial_damping");
  kNonmonotoneMemory.require(nonmonotone_memory, "nonmonotone_memory");
  Range::above(0, 1).require(homotopy_initial_step, "homotopy_initial_step");
  const ContinuationSettings& c = continuation;
  Range::above(0, 1).require(c.initial_step, "continuation.initial_step");
  Range::open(0, 1).require(c.predictor_target, "continuation.predictor_target");
  Range::open(0, 1).require(c.corrector_tolerance, "continuation.corrector_tolerance");
  Range::integers(0, 1000).require(c.max_corrector, "continuation.max_corrector");
  Range::numbers(1, 1e6).require(c.max_growth, "continuation.max_growth");
}

// --- problems ----------------------------------------------------------------------------------

TransferProblem TransferProblem::pendulum_paper() {
  TransferProblem p;
  p.R0 = Mat3::Identity();
  p.Omega0 = Vec3::Zero();
  p.Rf = Vec3(-1.0, -1.0, 1.0).asDiagonal();
  p.Omegaf = Vec3::Zero();
  p.t_final = 1.0;
  return p;
}

TransferProblem TransferProblem::dumbbell_paper() {
  TransferProblem p;
  const double s2 = std::sqrt(2.0);
  const double s3 = std::sqrt(3.0);
  const double speed = 0.9835;  // printed (the dumbbell's circular speed, docs/lgvi.md "Parameters the paper leaves out")
  p.x0 = Vec3(1.0, 0.0, 0.0);
  p.v0 = Vec3(0.0, speed, 0.0);
  p.R0 << 0.0, -1.0, 0.0,  //
      1.0, 0.0, 0.0,       //
      0.0, 0.0, 1.0;
  p.Omega0 = Vec3(0.0, 0.0, speed);
  p.xf = Vec3(-s2 / 4.0, s2 / 4.0, s3 / 2.0);
  const Vec3 along = Vec3(-1.0, -1.0, 0.0) / s2;
  p.vf = speed * along;
  const Vec3 normal = p.xf.cross(along);  // unit: xf and along are orthonormal
  p.Rf.col(0) = along;
  p.Rf.col(1) = normal.cross(along);
  p.Rf.col(2) = normal;
  p.Omegaf = Vec3(0.0, 0.0, speed);
  p.t_final = 0.5 * M_PI;
  return p;
}

const char* to_string(Merit m) { return m == Merit::Velocity ? "velocity" : "momentum"; }

const char* to_string(Globalization g) {
  switch (g) {
    case Globalization::NewtonArmijo: return "newton-armijo";
    case Globalization::LevenbergMarquardt: return "levenberg-marquardt";
    case Globalization::Homotopy: return "homotopy";
    case Globalization::Continuation: return "continuation";
  }
  return "unknown";
}

Globalization parse_globalization(const std::string& name) {
  if (name == "newton-armijo") return Globalization::NewtonArmijo;
  if (name == "levenberg-marquardt") return Globalization::LevenbergMarquardt;
  if (name == "homotopy") return Globalization::Homotopy;
  if (name == "continuation") return Globalization::Continuation;
  throw InvalidInput("globalization", "must be 'newton-armijo', 'levenberg-marquardt', 'homotopy' or 'continuation' (got '" +
                                          name + "')");
}

Merit parse_merit(const std::string& name) {
  if (name == "velocity") return Merit::Velocity;
  if (name == "momentum") return Merit::Momentum;
  throw InvalidInput("merit", "must be 'velocity' or 'momentum' (got '" + name + "')");
}

const char* to_string(ShootingStatus s) {
  switch (s) {
    case ShootingStatus::Converged: return "converged";
    case ShootingStatus::MaxIterations: return "iteration limit";
    case ShootingStatus::LineSearchFailed: return "line search failed";
    case ShootingStatus::Stalled: return "stalled at the round-off floor";
    case ShootingStatus::SingularSensitivity: return "singular sensitivity";
    case ShootingStatus::SweepFailed: return "sweep failed";
    case ShootingStatus::InvalidInput: return "invalid input";
    case ShootingStatus::NonFiniteValue: return "non-finite value";
  }
  return "unknown";
}

std::string ShootingSummary::brief() const {
  char buf[512];
  if (status == ShootingStatus::InvalidInput || status == ShootingStatus::SweepFailed) {
    std::snprintf(buf, sizeof buf, "%s: %s", to_string(status), message.c_str());
    return buf;
  }
  std::snprintf(buf, sizeof buf,
                "%s after %d outer iterations (%d inner): violation %.3g, cost %.6g, cond %.3g..%.3g "
                "(full %.3g..%.3g), %.3g s%s%s",
                to_string(status), iterations, inner_iterations, violation, cost, cond_min, cond_max,
                cond_full_min, cond_full_max, wall_seconds, message.empty() ? "" : ": ", message.c_str());
  return buf;
}

namespace {

/// The first non-finite value of a finished run's history and result ("cond_sensitivity = inf
/// at outer iteration 3", "multiplier[2] = nan"), or "" when all are finite.
std::string first_non_finite(const ShootingSummary& S) {
  const auto text = [](const char* name, double v, const std::string& where) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s = %g%s", name, v, where.c_str());
    return std::string(buf);
  };
  for (const IterationRecord& r : S.history) {
    const std::string at = " at outer iteration " + std::to_string(r.iteration);
    const std::pair<const char*, double> values[] = {
        {"violation", r.violation},         {"cost", r.cost},           {"step_length", r.step_length},
        {"cond_sensitivity", r.cond_sensitivity}, {"cond_inverted", r.cond_inverted}, {"step_norm", r.step_norm},
        {"group_residual", r.group_residual}, {"group_block", r.group_block}, {"seconds", r.seconds}};
    for (const auto& [name, v] : values) {
      if (!std::isfinite(v)) return text(name, v, at);
    }
  }
  const std::pair<const char*, double> result[] = {{"cost", S.cost},         {"violation", S.violation},
                                                   {"cond_min", S.cond_min}, {"cond_max", S.cond_max},
                                                   {"cond_full_min", S.cond_full_min},
                                                   {"cond_full_max", S.cond_full_max}};
  for (const auto& [name, v] : result) {
    if (!std::isfinite(v)) return text(name, v, " in the result");
  }
  for (const auto& [name, v] : {std::pair{"residual", &S.residual}, std::pair{"multiplier", &S.multiplier}}) {
    for (Eigen::Index i = 0; i < v->size(); ++i) {
      if (!std::isfinite((*v)(i))) return text((std::string(name) + "[" + std::to_string(i) + "]").c_str(), (*v)(i), "");
    }
  }
  return "";
}

}  // namespace

// --- the state-multiplier flow -------------------------------------------------------------

namespace {

template <class Model>
typename Model::State make_initial(const typename Model::Lgvi& lgvi, const TransferProblem& p) {
  if constexpr (Model::has_translation) {
    return lgvi.make_state(p.R0, p.x0, p.Omega0, p.v0);
  } else {
    return lgvi.make_state(p.R0, p.Omega0);
  }
}

template <int N>
Eigen::Matrix<double, N, N> validated_weight(const Eigen::MatrixXd& W) {
  if (W.size() == 0) return Eigen::Matrix<double, N, N>::Identity();
  if (W.rows() != N || W.cols() != N) {
    throw InvalidInput("W", "must be " + std::to_string(N) + "x" + std::to_string(N) + " (got " +
                                std::to_string(W.rows()) + "x" + std::to_string(W.cols()) + ")");
  }
  require_finite(W, "W");
  const double scale = W.cwiseAbs().maxCoeff();
  if (scale == 0.0) throw InvalidInput("W", "is zero (must be symmetric positive definite)");
  if ((W - W.transpose()).cwiseAbs().maxCoeff() > 1e-12 * scale) {
    throw InvalidInput("W", "is not symmetric (must be symmetric positive definite)");
  }
  const Eigen::Matrix<double, N, N> Ws = 0.5 * (W + W.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> eig(Ws, Eigen::EigenvaluesOnly);
  const double lo = eig.eigenvalues()(0);
  if (!(lo > 1e-14 * eig.eigenvalues()(N - 1))) {
    std::ostringstream s;
    s << "is not positive definite (smallest eigenvalue " << lo << ")";
    throw InvalidInput("W", s.str());
  }
  return Ws;
}

}  // namespace

template <class Model>
StateMultiplierFlow<Model>::StateMultiplierFlow(const System& system, const TransferProblem& p,
                                                LgviForm form, double h, const Eigen::MatrixXd& W,
                                                RotationUpdateOptions rotation)
    : model_(system), lgvi_(system, form, rotation), problem_(p), h_(h), steps_(0) {
  require_positive(h, "h");
  require_positive(p.t_final, "t_final");
  const double n = p.t_final / h;
  if (!(n >= 0.5) || n > kMaxOcpSteps + 0.5 || std::abs(n - std::round(n)) > 1e-9 * n) {
    std::ostringstream s;
    s.precision(17);
    s << "the horizon t_final = " << p.t_final << " is not a whole number of steps h = " << h
      << " (t_final / h = " << n << "; need an integer between 1 and " << Range::text(kMaxOcpSteps)
      << ", lgvi/range.hpp)";
    throw InvalidInput("h", s.str());
  }
  steps_ = static_cast<std::size_t>(std::llround(n));
  W_ = validated_weight<nu>(W);
  W_inverse_ = W_.inverse();
  require_finite(p.Rf, "Rf");
  if (!so3::is_rotation(p.Rf, 1e-10)) throw InvalidInput("Rf", "is not a rotation matrix (R^T R != I or det R != 1)");
  require_finite(p.Omegaf, "Omegaf");
  require_finite(p.xf, "xf");
  require_finite(p.vf, "vf");
  initial_ = make_initial<Model>(lgvi_, p);
}

template <class Model>
std::string StateMultiplierFlow<Model>::failure_message(const Sweep& failed) const {
  if (failed.failed_step >= steps_) {
    return "non-finite terminal state or multiplier after " + std::to_string(steps_) + " steps";
  }
  return step_failure_message(failed.failed_step, static_cast<double>(failed.failed_step) * h_, failed.failure,
                              failed.non_finite);
}

template <class Model>
typename StateMultiplierFlow<Model>::VecU StateMultiplierFlow<Model>::control_from_multiplier(
    const State& s, const VecS& lambda) const {
  const typename Model::MatQU B = model_.control_matrix(s.R, Model::position(s));
  return -W_inverse_ * (B.transpose() * lambda.template tail<nq>());
}

template <class Model>
double StateMultiplierFlow<Model>::cost_weight(std::size_t node) const {
  const auto [c0, c1] = impulse_weights(lgvi_.form(), h_);
  if (node == 0) return c0;
  if (node == steps_) return c1;
  return c0 + c1;
}

template <class Model>
double StateMultiplierFlow<Model>::cost(const std::vector<VecU>& controls) const {
  double J = 0.0;
  for (std::size_t j = 0; j < controls.size() && j <= steps_; ++j) {
    J += 0.5 * cost_weight(j) * controls[j].dot(W_ * controls[j]);
  }
  return J;
}

template <class Model>
typename StateMultiplierFlow<Model>::VecS StateMultiplierFlow<Model>::residual(const State& sN) const {
  VecS r;
  r.template head<3>() = so3::log(problem_.Rf.transpose() * sN.R);
  const Vec3 dOmega = lgvi_.omega(sN) - problem_.Omegaf;
  if constexpr (Model::has_translation) {
    r.template segment<3>(3) = sN.x - problem_.xf;
    r.template segment<3>(6) = dOmega;
    r.template segment<3>(9) = sN.v - problem_.vf;
  } else {
    r.template tail<3>() = dOmega;
  }
  return r;
}

template <class Model>
typename StateMultiplierFlow<Model>::MatS StateMultiplierFlow<Model>::residual_jacobian(
    const State&, const VecS& r) const {
  MatS D = MatS::Identity();
  D.template topLeftCorner<3, 3>() = so3::right_jacobian_inverse(r.template head<3>());
  D.template bottomRightCorner<nq, nq>() = model_.momentum_per_velocity().inverse();
  return D;
}

namespace {

/// Tangents through a kick of weight c at configuration (R, x) whose control is the optimality
/// condition u = -W^{-1} B^T lambda_P: Z = [Z_q; Z_P] state tangents, Lam = [L_q; L_P] multiplier
/// tangents (one column per direction). The kick leaves Z_q and L_P unchanged.
template <class Model, class MatS, class MatU>
void kick_tangent(const Model& model, const MatU& W_inverse, const Mat3& R, const Vec3& x, double c,
                  const typename Model::VecU& u, const typename Model::VecQ& lP,
                  const typename Model::MatQ& G, MatS& Z, MatS& Lam) {
  constexpr int nq = Model::nq;
  const typename Model::MatQU B = model.control_matrix(R, x);
  const typename Model::MatUQ C = model.control_matrix_transpose_derivative(R, x, lP);
  const typename Model::MatQ H = model.force_jacobian_transpose_derivative(R, x, u, lP);
  const Eigen::Matrix<double, Model::nu, 2 * nq> dU =
      -W_inverse * (B.transpose() * Lam.template bottomRows<nq>() + C * Z.template topRows<nq>());
  Z.template bottomRows<nq>() += c * (G * Z.template topRows<nq>() + B * dU);
  Lam.template topRows<nq>() -=
      c * (G.transpose() * Lam.template bottomRows<nq>() + H * Z.template topRows<nq>() + C.transpose() * dU);
}

}  // namespace

template <class Model>
bool StateMultiplierFlow<Model>::run(const VecS& lambda0, bool sensitivities, Sweep& out) const {
  using VecQ = typename Model::VecQ;
  using MatQ = typename Model::MatQ;
  const std::size_t N = steps_;
  const auto [c0, c1] = impulse_weights(lgvi_.form(), h_);
  out.ok = false;
  out.non_finite = nullptr;
  out.states.assign(1, initial_);
  out.controls.clear();
  out.multipliers.assign(1, lambda0);
  out.states.reserve(N + 1);
  out.controls.reserve(N + 1);
  out.multipliers.reserve(N + 1);
  MatS Z = MatS::Zero();
  MatS Lam = MatS::Identity();
  State s = initial_;
  VecS lam = lambda0;
  VecU u = (c0 != 0.0) ? control_from_multiplier(s, lam) : VecU::Zero();
  out.controls.push_back(u);
  double J = 0.5 * c0 * u.dot(W_ * u);
  const Mat3& Jd = lgvi_.system().inertia.Jd;
  for (std::size_t k = 0; k < N; ++k) {
    VecQ lq = lam.template head<nq>();
    const VecQ lP = lam.template tail<nq>();
    const Vec3 x0 = Model::position(s);
    // Kick at node k (symmetric form only).
    const VecQ P_plus = model_.kicked_momenta(s, c0, u);
    if (c0 != 0.0) {
      const MatQ G0 = model_.force_jacobian(s.R, x0, u);
      if (sensitivities) kick_tangent(model_, W_inverse_, s.R, x0, c0, u, lP, G0, Z, Lam);
      lq -= c0 * G0.transpose() * lP;
    }
    // Drift: the rotation update, as step() will solve it.
    Mat3 F;
    const RotationUpdateSummary solved = lgvi_.solver().solve(h_ * P_plus.template head<3>(), F);
    if (!solved.converged() || !lam.allFinite()) {
      out.failed_step = k;
      out.failure = solved;
      out.cost = J;
      return false;
    }
    const RotationalDrift drift(Jd, h_, F, P_plus.template head<3>());
    const Mat3 R1 = s.R * F;
    Vec3 x1 = Vec3::Zero();
    VecQ lq_m, lP_m;
    Vec3 lR_out, lPi_out;
    drift.multiplier(lq.template head<3>(), lP.template head<3>(), lR_out, lPi_out);
    lq_m.template head<3>() = lR_out;
    lP_m.template head<3>() = lPi_out;
    if constexpr (Model::has_translation) {
      const double m = model_.system.mass;
      x1 = s.x + (h_ / m) * P_plus.template tail<3>();
      lq_m.template tail<3>() = lq.template tail<3>();
      lP_m.template tail<3>() = lP.template tail<3>() - (h_ / m) * lq.template tail<3>();
    }
    if (sensitivities) {
      for (int j = 0; j < ns; ++j) {
        Vec3 eta = Z.col(j).template segment<3>(0);
        Vec3 dPi = Z.col(j).template segment<3>(nq);
        Vec3 dlR = Lam.col(j).template segment<3>(0);
        Vec3 dlP = Lam.col(j).template segment<3>(nq);
        drift.tangent(eta, dPi, dlR, dlP, lP.template head<3>(), lR_out, lPi_out);
        Z.col(j).template segment<3>(0) = eta;
        Z.col(j).template segment<3>(nq) = dPi;
        Lam.col(j).template segment<3>(0) = dlR;
        Lam.col(j).template segment<3>(nq) = dlP;
      }
      if constexpr (Model::has_translation) {
        const double m = model_.system.mass;
        Z.template middleRows<3>(3) += (h_ / m) * Z.template middleRows<3>(nq + 3);
        Lam.template middleRows<3>(nq + 3) -= (h_ / m) * Lam.template middleRows<3>(3);
      }
    }
    // Control at node k+1 from the multiplier's momentum part (unchanged by the kick).
    const VecU u1 = -W_inverse_ * (model_.control_matrix(R1, x1).transpose() * lP_m);
    State s1;
    const RotationUpdateSummary stepped = lgvi_.step(s, h_, Model::control(u), Model::control(u1), s1);
    const char* non_finite = stepped.converged() ? non_finite_part(s1) : nullptr;
    if (!stepped.converged() || non_finite != nullptr) {
      out.failed_step = k;
      out.failure = stepped;
      out.non_finite = non_finite;
      out.cost = J;
      return false;
    }
    // Kick at node k+1.
    const MatQ G1 = model_.force_jacobian(R1, x1, u1);
    if (sensitivities) kick_tangent(model_, W_inverse_, R1, x1, c1, u1, lP_m, G1, Z, Lam);
    lq_m -= c1 * G1.transpose() * lP_m;
    lam << lq_m, lP_m;
    // The multiplier and the control overflow before the state does (a huge guess, a huge h).
    if (!lam.allFinite() || !u1.allFinite()) {
      out.failed_step = k;
      out.failure = stepped;
      out.non_finite = lam.allFinite() ? "u (control)" : "lambda (multiplier)";
      out.cost = J;
      return false;
    }
    s = s1;
    u = u1;
    J += 0.5 * cost_weight(k + 1) * u.dot(W_ * u);
    out.states.push_back(s);
    out.controls.push_back(u);
    out.multipliers.push_back(lam);
  }
  out.cost = J;
  out.residual = residual(s);
  if (sensitivities) {
    out.Psi12 = Z;
    out.Psi22 = Lam;
    out.jacobian = residual_jacobian(s, out.residual) * Z;
  }
  out.ok = out.residual.allFinite() && lam.allFinite() && std::isfinite(J) &&
           (!sensitivities || (Z.allFinite() && Lam.allFinite()));
  if (!out.ok) {
    out.failed_step = N;
    out.failure = RotationUpdateSummary{};
  }
  return out.ok;
}

template <class Model>
bool StateMultiplierFlow<Model>::simulate(const std::vector<VecU>& controls, Sweep& out) const {
  out.ok = false;
  out.non_finite = nullptr;
  out.states.assign(1, initial_);
  out.controls = controls;
  out.multipliers.clear();
  if (controls.size() != steps_ + 1) return false;
  State s = initial_;
  for (std::size_t k = 0; k < steps_; ++k) {
    State s1;
    const RotationUpdateSummary stepped =
        lgvi_.step(s, h_, Model::control(controls[k]), Model::control(controls[k + 1]), s1);
    const char* non_finite = stepped.converged() ? non_finite_part(s1) : nullptr;
    if (!stepped.converged() || non_finite != nullptr) {
      out.failed_step = k;
      out.failure = stepped;
      out.non_finite = non_finite;
      return false;
    }
    s = s1;
    out.states.push_back(s);
  }
  out.cost = cost(controls);
  out.residual = residual(s);
  out.ok = true;
  return true;
}

template class StateMultiplierFlow<PendulumModel>;
template class StateMultiplierFlow<DumbbellModel>;
template class StateMultiplierFlow<FreeBodyModel>;

// --- Newton-Armijo shooting ----------------------------------------------------------------

namespace {

template <class Model>
ShootingResult<Model> shoot(const typename Model::System& system, const TransferProblem& problem,
                            const ShootingOptions& o) {
  using Flow = StateMultiplierFlow<Model>;
  using VecS = typename Flow::VecS;
  using MatS = typename Flow::MatS;
  constexpr int ns = Flow::ns;
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto seconds = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };

  ShootingResult<Model> result;
  ShootingSummary& S = result.summary;
  S.system = Model::name();
  S.form = o.form;
  S.h = o.h;
  S.globalization = o.globalization;
  S.decomposition = o.decomposition && Model::has_symmetry && o.globalization == Globalization::NewtonArmijo;

  std::unique_ptr<Flow> flow;
  VecS lambda = VecS::Zero();
  try {
    flow = std::make_unique<Flow>(system, problem, o.form, o.h, o.W, o.rotation);
    if (o.initial_multiplier.size() != 0) {
      if (o.initial_multiplier.size() != ns) {
        throw InvalidInput("initial_multiplier", "must have " + std::to_string(ns) + " entries (got " +
                                                     std::to_string(o.initial_multiplier.size()) + ")");
      }
      lambda = o.initial_multiplier;
    }
    o.validate();
    if ((o.globalization == Globalization::Homotopy || o.globalization == Globalization::Continuation) &&
        Model::has_symmetry) {
      throw InvalidInput("globalization", std::string(to_string(o.globalization)) +
                                              " inverts the full sensitivity: not for a system with a symmetry "
                                              "(the pendulum's is singular)");
    }
  } catch (const InvalidInput& e) {
    S.status = ShootingStatus::InvalidInput;
    S.message = e.what();
    S.wall_seconds = seconds();
    return result;
  }
  S.steps = flow->steps();
  S.multiplier_guess = lambda;
  S.multiplier = lambda;

  typename Flow::Sweep& current = result.sweep;
  S.sweeps = 1;
  if (!flow->run(lambda, true, current)) {
    S.status = ShootingStatus::SweepFailed;
    S.message = "the initial multiplier guess: " + flow->failure_message(current) +
                " (the guess's controls are too large for the rotation update; try a smaller guess)";
    S.wall_seconds = seconds();
    return result;
  }

  NewtonArmijoOptions<ns> newton;
  newton.max_iterations = o.max_iterations;
  newton.max_backtracks = o.max_backtracks;
  newton.armijo = o.armijo;
  newton.tolerance = o.tolerance;
  newton.polish_iterations = o.polish_iterations;
  newton.levenberg_marquardt = o.globalization == Globalization::LevenbergMarquardt;
  newton.lm_initial_damping = o.lm_initial_damping;
  newton.nonmonotone_memory = o.nonmonotone_memory;
  newton.start = start;
  // Merit of the line search: |diag(weights) r|; the convergence test is always on the violation
  // |r| (velocity coordinates). Momentum weights measure the angular and linear velocity errors
  // as momenta (J dOmega, m dv), the LGVI's own variables: a Newton step that spins up a body
  // axis of small inertia is then not rejected for the large angular velocity it causes.
  MatS weights = MatS::Identity();
  if (o.merit == Merit::Momentum) {
    weights.template bottomRightCorner<Flow::nq, Flow::nq>() = flow->model().momentum_per_velocity();
  }
  newton.merit_weights = weights;
  if (S.decomposition) newton.initial_conserved_gradient = Model::conserved_gradient(flow->initial_state());

  // One shot is one sweep of the flow (with the exact sensitivities when a Jacobian is asked for).
  struct Sweeps {
    const Flow& flow;
    bool evaluate(const VecS& l, bool sensitivities, typename Flow::Sweep& out) const {
      return flow.run(l, sensitivities, out);
    }
    std::pair<MatS, VecS> terminal_symmetry(const typename Flow::Sweep& current) const {
      const typename Model::State& sN = current.states.back();
      return {flow.residual_jacobian(sN, current.residual), Model::conserved_gradient(sN)};
    }
    // Round-off floor of r near lambda: one unit in the last place of each lambda_0 entry
    // moves r by about |column| ulp; Newton cannot resolve r below that.
    double round_off_floor(const typename Flow::Sweep& current, const VecS& lambda) const {
      double floor = 0.0;
      for (int i = 0; i < ns; ++i) {
        floor += current.jacobian.col(i).norm() * std::numeric_limits<double>::epsilon() * std::abs(lambda(i));
      }
      return floor;
    }
    std::string stall_message(double violation, int it, double floor, double cond) const {
      char buf[400];
      std::snprintf(buf, sizeof buf,
                    "no decrease below violation %.3g at outer iteration %d: that is the round-off floor of "
                    "the terminal residual (one unit in the last place of lambda_0 moves it by ~%.2g; "
                    "condition number %.3g)",
                    violation, it, floor, cond);
      return buf;
    }
    // Cannot happen: the same sweep just succeeded without sensitivities.
    std::string rerun_failure(const typename Flow::Sweep& failed) const {
      return "re-running the accepted step: " + flow.failure_message(failed);
    }
  } sweeps{*flow};
  // Homotopy: follow the Newton path to tau = 1, then Newton-Armijo's end game from there (also
  // when the path following gives up: Newton-Armijo then continues from the last path point).
  if (o.globalization == Globalization::Homotopy) {
    newton_homotopy(sweeps, newton, lambda, current, S, o.homotopy_initial_step);
  } else if (o.globalization == Globalization::Continuation) {
    newton_continuation(sweeps, newton, lambda, current, S, o.continuation);
  }
  newton_armijo_shooting(sweeps, newton, lambda, current, S);
  // A non-finite value in the history or the result is a failure of its own (not for the
  // statuses that are about one already: a singular Newton system, a failed sweep).
  if (S.status != ShootingStatus::SingularSensitivity && S.status != ShootingStatus::SweepFailed) {
    const std::string where = first_non_finite(S);
    if (!where.empty()) {
      S.status = ShootingStatus::NonFiniteValue;
      S.message = where;
    }
  }
  return result;
}

}  // namespace

ShootingResult<PendulumModel> solve_indirect(const Pendulum3D& system, const TransferProblem& problem,
                                             const ShootingOptions& options) {
  return shoot<PendulumModel>(system, problem, options);
}

ShootingResult<FreeBodyModel> solve_indirect(const FreeRigidBody& system, const TransferProblem& problem,
                                             const ShootingOptions& options) {
  return shoot<FreeBodyModel>(system, problem, options);
}

ShootingResult<DumbbellModel> solve_indirect(const DumbbellSpacecraft& system,
                                             const TransferProblem& problem, const ShootingOptions& options) {
  return shoot<DumbbellModel>(system, problem, options);
}

}  // namespace lgvi::ocp
