// iLQR with an augmented Lagrangian on the discrete LGVI dynamics (ddp.hpp; derivation in
// lgvi/ocp/README.md "DDP").
#include "lgvi/ocp/ddp.hpp"

#include "lgvi/cpu_time.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <utility>

namespace lgvi::ocp {

void DdpOptions::validate() const {
  kKnots.require(knots, "knots");
  kStarts.require(starts, "starts");
  kFirstStart.require(first_start, "first_start");
  kMaxIterations.require(max_iterations, "max_iterations");
  kTolerance.require(tolerance, "tolerance");
  kGradientTolerance.require(gradient_tolerance, "gradient_tolerance");
  kGradientTolerance.require(inner_tolerance, "inner_tolerance");
  kPenalty.require(penalty, "penalty");
  kPenaltyFactor.require(penalty_factor, "penalty_factor");
  kViolationDecrease.require(violation_decrease, "violation_decrease");
  kPenalty.require(penalty_max, "penalty_max");
  kRegularization.require(regularization_min, "regularization_min");
  kRegularization.require(regularization_max, "regularization_max");
  if (!(regularization_max > regularization_min)) {
    throw InvalidInput("regularization_max", "must exceed regularization_min");
  }
  kOuterInnerIterations.require(outer_inner_iterations, "outer_inner_iterations");
  Range::numbers(0, kMaxMagnitude).require(guess_scale, "guess_scale");
  for (Eigen::Index i = 0; i < initial_knots.size(); ++i) {
    require_admissible(initial_knots(i), "initial_knots[" + std::to_string(i) + "]");
  }
}

DirectOptions DdpOptions::direct() const {
  DirectOptions d;
  d.form = form;
  d.h = h;
  d.knots = knots;
  d.spline = spline;
  d.W = W;
  d.initial_knots = initial_knots;
  d.starts = starts;
  d.first_start = first_start;
  d.seed = seed;
  d.guess_scale = guess_scale;
  d.keep_redundant_constraint = keep_redundant_constraint;
  d.tolerance = tolerance;
  d.newton = newton;
  return d;
}

const char* to_string(DdpStatus s) {
  switch (s) {
    case DdpStatus::Converged: return "converged";
    case DdpStatus::MaxIterations: return "max-iterations";
    case DdpStatus::StepFailure: return "step-failure";
    case DdpStatus::NonFinite: return "non-finite";
    case DdpStatus::LineSearchFailed: return "line-search-failed";
    case DdpStatus::InvalidInput: return "invalid-input";
  }
  return "unknown";
}

std::string DdpSummary::brief() const {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "%s after %d iterations (%d outer, %ld rollouts): cost %.10g, violation %.3e, %.3f s CPU%s%s",
                to_string(status), iterations, outer_iterations, rollouts, cost, violation, cpu_seconds,
                message.empty() ? "" : "; ", message.c_str());
  return buf;
}

// --- the iLQR machinery ------------------------------------------------------------------------

template <class Model>
Ddp<Model>::Ddp(const typename Model::System& system, const typename Model::Transfer& problem,
                const DdpOptions& options)
    : tr_(system, problem, options.direct()),
      imposed_rows_(options.keep_redundant_constraint ? Model::nr_full : Model::nr) {}

template <class Model>
typename Ddp<Model>::Trajectory Ddp<Model>::make_trajectory() const {
  Trajectory t;
  t.states.resize(tr_.steps() + 1);
  t.controls.setZero(nu, static_cast<Eigen::Index>(tr_.steps() + 1));
  return t;
}

template <class Model>
typename Ddp<Model>::Gains Ddp<Model>::make_gains() const {
  Gains g;
  const std::size_t N = tr_.steps();
  g.K.resize(N);
  g.k.setZero(nu, static_cast<Eigen::Index>(N + 1));
  g.gradient.setZero(nu, static_cast<Eigen::Index>(N + 1));
  g.A.resize(N);
  g.B0.resize(N);
  g.B1.resize(N);
  return g;
}

template <class Model>
typename Model::VecR Ddp<Model>::imposed(const VecR& r) const {
  VecR out = r;
  out.tail(Model::nr_full - imposed_rows_).setZero();
  return out;
}

template <class Model>
bool Ddp<Model>::step(Trajectory& t, std::size_t k) const {
  const auto kk = static_cast<Eigen::Index>(k);
  const VecU u0 = t.controls.col(kk), u1 = t.controls.col(kk + 1);
  const RotationUpdateSummary r = tr_.lgvi().step(t.states[k], tr_.h(), u0, u1, t.states[k + 1]);
  const char* non_finite = r.converged() ? non_finite_part(t.states[k + 1]) : nullptr;
  if (r.converged() && non_finite == nullptr) return true;
  t.failed_step = k;
  t.failure = step_failure_message(k, static_cast<double>(k) * tr_.h(), r, non_finite);
  return false;
}

template <class Model>
void Ddp<Model>::finish(Trajectory& t) const {
  const std::size_t N = tr_.steps();
  t.cost = 0.0;
  for (std::size_t j = 0; j <= N; ++j) {
    const VecU u = t.controls.col(static_cast<Eigen::Index>(j));
    t.cost += 0.5 * tr_.node_weight(static_cast<Eigen::Index>(j)) * u.dot(tr_.weight() * u);
  }
  t.residual = Model::residual(tr_.lgvi(), tr_.problem(), t.states[N]);
}

template <class Model>
bool Ddp<Model>::rollout(Trajectory& t) const {
  const std::size_t N = tr_.steps();
  t.states[0] = Model::initial_state(tr_.lgvi(), tr_.problem());
  t.failure.clear();
  for (std::size_t k = 0; k < N; ++k) {
    if (!step(t, k)) return false;
  }
  finish(t);
  return true;
}

template <class Model>
bool Ddp<Model>::forward(const Trajectory& nominal, const Gains& g, double alpha, Trajectory& trial) const {
  // u_0 <- u_0 + alpha k_u0; v_k = u_{k+1} + alpha k_k + K_k dx_k with dx_k = (difference(s_k,
  // s_k^new), u_k^new - u_k): the policy applied along the new trajectory, stepped by the LGVI.
  const std::size_t N = tr_.steps();
  trial.controls.col(0) = nominal.controls.col(0) + alpha * g.k.col(0);
  trial.states[0] = nominal.states[0];
  trial.failure.clear();
  VecX dx;
  for (std::size_t k = 0; k < N; ++k) {
    const auto kk = static_cast<Eigen::Index>(k);
    dx.template head<nw>() = Model::difference(nominal.states[k], trial.states[k]);
    dx.template tail<nu>() = trial.controls.col(kk) - nominal.controls.col(kk);
    trial.controls.col(kk + 1) = nominal.controls.col(kk + 1) + alpha * g.k.col(kk + 1) + g.K[k] * dx;
    if (!step(trial, k)) return false;
  }
  finish(trial);
  return true;
}

template <class Model>
double Ddp<Model>::objective(const Trajectory& t, const VecR& lambda, double mu) const {
  const VecR r = imposed(t.residual);
  return t.cost + imposed(lambda).dot(r) + 0.5 * mu * r.squaredNorm();
}

template <class Model>
bool Ddp<Model>::backward(const Trajectory& t, const VecR& lambda, double mu, double rho, Gains& g) const {
  const std::size_t N = tr_.steps();
  const double h = tr_.h();
  const MatU& W = tr_.weight();
  for (std::size_t k = 0; k < N; ++k) {
    const auto kk = static_cast<Eigen::Index>(k);
    const VecU u0 = t.controls.col(kk), u1 = t.controls.col(kk + 1);
    tr_.lgvi().linearize(t.states[k], t.states[k + 1], h, u0, u1, g.A[k], g.B0[k], g.B1[k]);
  }
  // Terminal: V_x = [D^T (lambda + mu r); w_N W u_N], V_xx = [mu D^T D, 0; 0, w_N W] (Gauss-Newton).
  typename Model::MatRW D = Model::residual_jacobian(tr_.lgvi(), tr_.problem(), t.states[N]);
  D.bottomRows(Model::nr_full - imposed_rows_).setZero();
  const VecR y = imposed(lambda) + mu * imposed(t.residual);
  const auto nn = static_cast<Eigen::Index>(N);
  const VecU uN = t.controls.col(nn);
  VecX p, adjoint;
  MatX P = MatX::Zero();
  p.template head<nw>() = D.transpose() * y;
  p.template tail<nu>() = tr_.node_weight(nn) * (W * uN);
  P.template topLeftCorner<nw, nw>() = mu * D.transpose() * D;
  P.template bottomRightCorner<nu, nu>() = tr_.node_weight(nn) * W;
  adjoint = p;
  g.expected_linear = g.expected_quadratic = 0.0;
  MatX Fx = MatX::Zero();
  Eigen::Matrix<double, nx, nu> Fv = Eigen::Matrix<double, nx, nu>::Zero();
  Fv.template bottomRows<nu>().setIdentity();
  for (std::size_t k = N; k-- > 0;) {
    const auto kk = static_cast<Eigen::Index>(k);
    Fx.template topLeftCorner<nw, nw>() = g.A[k];
    Fx.template topRightCorner<nw, nu>() = g.B0[k];
    Fv.template topRows<nw>() = g.B1[k];
    const double wk = tr_.node_weight(kk);
    const VecU uk = t.controls.col(kk);
    VecX lx = VecX::Zero();
    lx.template tail<nu>() = wk * (W * uk);
    // The exact gradient in u_{k+1} (adjoint, before the adjoint moves to step k).
    g.gradient.col(kk + 1) = Fv.transpose() * adjoint;
    adjoint = lx + Fx.transpose() * adjoint;
    const Eigen::Matrix<double, nx, nu> PFv = P * Fv;
    const MatX PFx = P * Fx;
    const VecX Qx = lx + Fx.transpose() * p;
    const VecU Qv = Fv.transpose() * p;
    MatX Qxx = Fx.transpose() * PFx;
    Qxx.template bottomRightCorner<nu, nu>() += wk * W;
    MatU Qvv = Fv.transpose() * PFv;
    Qvv.diagonal().array() += rho;
    const MatUX Qvx = Fv.transpose() * PFx;
    const Eigen::LLT<MatU> llt(Qvv);
    if (llt.info() != Eigen::Success) return false;
    const VecU kv = -llt.solve(Qv);
    g.K[k] = -llt.solve(Qvx);
    g.k.col(kk + 1) = kv;
    g.expected_linear += kv.dot(Qv);
    g.expected_quadratic += kv.dot(Qvv * kv);
    p = Qx + Qvx.transpose() * kv;
    P = Qxx + Qvx.transpose() * g.K[k];
    P = 0.5 * (P + P.transpose()).eval();
  }
  g.gradient.col(0) = adjoint.template tail<nu>();
  // Time 0: s_0 fixed, V_0 quadratic in du_0.
  MatU H0 = P.template bottomRightCorner<nu, nu>();
  H0.diagonal().array() += rho;
  const VecU g0 = p.template tail<nu>();
  VecU k0 = VecU::Zero();
  // Printed form: w_0 = c0 = 0 and u_0 enters no step (B0 = 0), so V_0 does not depend on u_0.
  if (!(H0.isZero(0.0) && g0.isZero(0.0))) {
    const Eigen::LLT<MatU> llt0(H0);
    if (llt0.info() != Eigen::Success) return false;
    k0 = -llt0.solve(g0);
  }
  g.k.col(0) = k0;
  g.expected_linear += k0.dot(g0);
  g.expected_quadratic += k0.dot(H0 * k0);
  return std::isfinite(g.expected_linear) && std::isfinite(g.expected_quadratic);
}

template class Ddp<CartPendulumDirectModel>;
template class Ddp<ConnectedBodiesDirectModel>;

// --- the solver --------------------------------------------------------------------------------

namespace {

// Regularization schedule of Tassa et al. 2012 (sec. II.F): rho is 0 or in [rho_min, rho_max];
// increase: delta <- max(delta0, delta delta0), rho <- max(rho_min, rho delta); decrease:
// delta <- min(1/delta0, delta/delta0), rho <- rho delta (0 below rho_min); delta0 = 1.6.
constexpr double kDelta0 = 1.6;
// Armijo-like acceptance on the expected change (Tassa 2012): (J_new - J) / dV(alpha) > kArmijo.
constexpr double kArmijo = 1e-4;
constexpr int kLineSearchSteps = 12;  // alpha = 1, 1/2, ..., 2^-11

template <class Model>
DdpStart run_start(const Ddp<Model>& ddp, const DdpOptions& o, int index, const Eigen::VectorXd& knots,
                   std::vector<DdpIteration>& history) {
  using D = Ddp<Model>;
  using VecR = typename Model::VecR;
  DdpStart st;
  st.index = index;
  st.initial_knots = knots;
  const double cpu0 = thread_cpu_seconds();
  typename D::Trajectory nominal = ddp.make_trajectory(), trial = ddp.make_trajectory();
  typename D::Gains gains = ddp.make_gains();
  nominal.controls = ddp.transcription().node_controls(knots);
  const auto finish = [&](DdpStatus status, std::string message) {
    st.status = status;
    st.message = std::move(message);
    st.cost = nominal.cost;
    st.violation = nominal.residual.norm();
    st.controls = nominal.controls;
    st.cpu_seconds = thread_cpu_seconds() - cpu0;
    if (status != DdpStatus::StepFailure && status != DdpStatus::NonFinite &&
        (!std::isfinite(st.cost) || !std::isfinite(st.violation) || !st.controls.allFinite())) {
      st.status = DdpStatus::NonFinite;
      st.message = "cost " + std::to_string(st.cost) + ", violation " + std::to_string(st.violation);
    }
    return st;
  };
  ++st.rollouts;
  if (!ddp.rollout(nominal)) {
    nominal.cost = std::numeric_limits<double>::infinity();
    nominal.residual.setConstant(std::numeric_limits<double>::infinity());
    return finish(DdpStatus::StepFailure, nominal.failure);
  }
  VecR lambda = VecR::Zero();
  double mu = o.penalty, rho = 0.0, delta = 1.0;
  double omega = std::max(o.inner_tolerance, o.gradient_tolerance);
  double previous_r = ddp.imposed(nominal.residual).norm();
  int inner = 0;
  while (st.iterations < o.max_iterations) {
    const double objective = ddp.objective(nominal, lambda, mu);
    if (!std::isfinite(objective)) return finish(DdpStatus::NonFinite, "objective " + std::to_string(objective));
    if (!ddp.backward(nominal, lambda, mu, rho, gains)) {
      delta = std::max(kDelta0, delta * kDelta0);
      rho = std::max(o.regularization_min, rho * delta);
      if (rho > o.regularization_max) return finish(DdpStatus::LineSearchFailed, "Q_vv not positive definite");
      continue;
    }
    ++st.iterations;
    const double gradient = gains.gradient.cwiseAbs().maxCoeff();
    const double scale = 1.0 + std::abs(objective);
    // Inner done: gradient small, or the expected decrease at round-off of the objective.
    const bool stationary = gradient <= o.gradient_tolerance * scale || -gains.expected_linear <= 1e-15 * scale;
    const bool inner_done = stationary || gradient <= omega * scale || inner >= o.outer_inner_iterations;
    if (inner_done) {
      const double violation = nominal.residual.norm();
      if (violation <= o.tolerance && stationary) return finish(DdpStatus::Converged, "");
      omega = std::max(0.1 * omega, o.gradient_tolerance);
      // Outer update: lambda += mu r; mu *= penalty_factor when |r| fell by less than violation_decrease.
      const VecR r = ddp.imposed(nominal.residual);
      lambda += mu * r;
      if (r.norm() > o.violation_decrease * previous_r) mu = std::min(o.penalty_max, mu * o.penalty_factor);
      previous_r = r.norm();
      ++st.outer_iterations;
      inner = 0;
      rho = 0.0;
      delta = 1.0;
      continue;
    }
    // Backtracking line search on the expected change.
    double alpha = 1.0, expected = 0.0, accepted_objective = objective;
    bool accepted = false;
    for (int i = 0; i < kLineSearchSteps; ++i, alpha *= 0.5) {
      ++st.rollouts;
      if (!ddp.forward(nominal, gains, alpha, trial)) continue;
      const double trial_objective = ddp.objective(trial, lambda, mu);
      expected = alpha * gains.expected_linear + 0.5 * alpha * alpha * gains.expected_quadratic;
      if (expected < 0.0 && std::isfinite(trial_objective) && (trial_objective - objective) / expected > kArmijo) {
        accepted = true;
        accepted_objective = trial_objective;
        break;
      }
    }
    if (accepted) {
      std::swap(nominal, trial);
      delta = std::min(1.0 / kDelta0, delta / kDelta0);
      rho = rho * delta >= o.regularization_min ? rho * delta : 0.0;
      ++inner;
    } else {
      delta = std::max(kDelta0, delta * kDelta0);
      rho = std::max(o.regularization_min, rho * delta);
      if (rho > o.regularization_max) return finish(DdpStatus::LineSearchFailed, "no step decreased the objective");
    }
    DdpIteration it;
    it.start = index;
    it.iteration = st.iterations;
    it.outer = st.outer_iterations;
    it.cost = nominal.cost;
    it.violation = nominal.residual.norm();
    it.objective = accepted_objective;
    it.gradient = gradient;
    it.expected = accepted ? expected : 0.0;
    it.alpha = accepted ? alpha : 0.0;
    it.regularization = rho;
    it.penalty = mu;
    it.seconds = thread_cpu_seconds() - cpu0;
    history.push_back(it);
  }
  return finish(DdpStatus::MaxIterations, "");
}

template <class Model>
DdpResult<Model> solve(const typename Model::System& system, const typename Model::Transfer& problem,
                       const DdpOptions& options, const char* name) {
  DdpResult<Model> result;
  DdpSummary& S = result.summary;
  S.system = name;
  S.form = options.form;
  S.h = options.h;
  const auto wall0 = std::chrono::steady_clock::now();
  const double cpu0 = thread_cpu_seconds();
  std::unique_ptr<Ddp<Model>> ddp;
  Eigen::VectorXd knots0;
  try {
    options.validate();
    ddp = std::make_unique<Ddp<Model>>(system, problem, options);
    knots0 = options.initial_knots.size() > 0 ? options.initial_knots : default_initial_knots(system, options.knots);
    const int np = ddp->transcription().parameters();
    if (knots0.size() != np) {
      throw InvalidInput("initial_knots",
                         "needs " + std::to_string(np) + " values (got " + std::to_string(knots0.size()) + ")");
    }
  } catch (const InvalidInput& e) {
    S.status = DdpStatus::InvalidInput;
    S.message = e.what();
    return result;
  }
  S.steps = ddp->transcription().steps();
  S.constraints = options.keep_redundant_constraint ? Model::nr_full : Model::nr;
  const DirectOptions direct = options.direct();
  int best = -1;
  for (int i = 0; i < options.starts; ++i) {
    const int k = options.first_start + i;
    const Eigen::VectorXd knots = k == 0 ? knots0 : start_knots(system, direct, k);
    DdpStart st = run_start(*ddp, options, k, knots, S.history);
    S.iterations += st.iterations;
    S.outer_iterations += st.outer_iterations;
    S.rollouts += st.rollouts;
    const bool usable = st.status != DdpStatus::StepFailure && st.status != DdpStatus::NonFinite;
    const auto better = [&](const DdpStart& a, const DdpStart& b) {
      const bool fa = a.violation <= options.tolerance, fb = b.violation <= options.tolerance;
      if (fa != fb) return fa;
      return fa ? a.cost < b.cost : a.violation < b.violation;
    };
    S.starts.push_back(std::move(st));
    if (usable && (best < 0 || better(S.starts.back(), S.starts[static_cast<std::size_t>(best)]))) {
      best = static_cast<int>(S.starts.size()) - 1;
    }
  }
  S.best_start = best;
  if (best < 0) {
    const DdpStart& last = S.starts.back();
    S.status = last.status;
    S.message = "no start gave a usable trajectory; start " + std::to_string(last.index) + ": " + last.message;
  } else {
    const DdpStart& b = S.starts[static_cast<std::size_t>(best)];
    S.status = b.status;
    S.message = b.message;
    typename Ddp<Model>::Trajectory t = ddp->make_trajectory();
    t.controls = b.controls;
    if (ddp->rollout(t)) {
      S.cost = t.cost;
      S.residual = t.residual;
      S.violation = t.residual.norm();
      result.states = t.states;
      result.controls = t.controls;
    }
  }
  S.cpu_seconds = thread_cpu_seconds() - cpu0;
  S.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return result;
}

}  // namespace

DdpResult<CartPendulumDirectModel> solve_ddp(const CartPendulum& system, const CartPendulumTransfer& problem,
                                             const DdpOptions& options) {
  return solve<CartPendulumDirectModel>(system, problem, options, "cart-pendulum");
}

DdpResult<ConnectedBodiesDirectModel> solve_ddp(const ConnectedBodies& system, const ConnectedBodiesTransfer& problem,
                                                const DdpOptions& options) {
  return solve<ConnectedBodiesDirectModel>(system, problem, options, "connected-bodies");
}

}  // namespace lgvi::ocp
