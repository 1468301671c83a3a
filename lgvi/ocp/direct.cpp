// Direct discrete optimal control: linearized multibody steps, forward sensitivities, SLSQP.
// The derivations of every block below are in lgvi/ocp/README.md ("Direct method").
#include "lgvi/ocp/direct.hpp"
#include "lgvi/ocp/direct_ipopt.hpp"

#include <nlopt.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <random>
#include <sstream>
#include <type_traits>

#include <Eigen/Eigenvalues>

namespace lgvi::ocp {

void DirectOptions::validate() const {
  kKnots.require(knots, "knots");
  kShootingInterval.require(shooting_interval, "shooting_interval");
  kMaxEvaluations.require(max_evaluations, "max_evaluations");
  kTolerance.require(tolerance, "tolerance");
  Range::open(0, 1).require(ftol_rel, "ftol_rel");
  Range::numbers(0, kMaxMagnitude).require(objective_scale, "objective_scale");
  Range::numbers(0, kMaxMagnitude).require(guess_scale, "guess_scale");
  kStarts.require(starts, "starts");
  kFirstStart.require(first_start, "first_start");
  for (Eigen::Index i = 0; i < initial_knots.size(); ++i) {
    require_admissible(initial_knots(i), "initial_knots[" + std::to_string(i) + "]");
  }
}

using so3::hat;

// --- problems ----------------------------------------------------------------------------------

CartPendulumTransfer CartPendulumTransfer::paper() {
  CartPendulumTransfer p;
  p.Rf = Vec3(-1.0, -1.0, 1.0).asDiagonal();
  p.t_final = 2.0;
  return p;
}

ConnectedBodiesTransfer ConnectedBodiesTransfer::paper() {
  ConnectedBodiesTransfer p;
  p.R1_f = Vec3(1.0, -1.0, -1.0).asDiagonal();
  p.R2_f = p.R1_f;
  p.t_final = 4.0;
  return p;
}

// --- cart-pendulum -----------------------------------------------------------------------------

CartPendulumDirectModel::VecR CartPendulumDirectModel::residual(const Lgvi& lgvi, const Transfer& p,
                                                                const State& sN) {
  Vec3 Omega;
  Vec2 q_dot;
  lgvi.velocities(sN, Omega, q_dot);
  VecR r;
  r << so3::log(sN.R.transpose() * p.Rf), sN.q - p.qf, Omega - p.Omegaf, q_dot - p.q_dotf;
  return r;
}

CartPendulumDirectModel::MatRW CartPendulumDirectModel::residual_jacobian(const Lgvi& lgvi, const Transfer& p,
                                                                          const State& sN) {
  const CartPendulum& S = lgvi.system();
  Vec3 Omega;
  Vec2 q_dot;
  lgvi.velocities(sN, Omega, q_dot);
  const Vec3 phi = so3::log(sN.R.transpose() * p.Rf);
  MatRW D = MatRW::Zero();
  D.block<3, 3>(0, 0) = -so3::left_jacobian_inverse(phi);
  D.block<2, 2>(3, 3) = Eigen::Matrix2d::Identity();
  // [Omega; q'] = M(R)^{-1} [Pi; p] (eq. 37): d = M^{-1} ([dPi; dp] - dM(R)[eta] [Omega; q']).
  const Eigen::Matrix<double, 3, 2> RtE = sN.R.transpose().leftCols<2>();
  const Mat3 Dd = hat(S.d);
  Eigen::Matrix<double, 5, 10> rhs = Eigen::Matrix<double, 5, 10>::Zero();
  rhs.block<3, 3>(0, 0) = -S.mass * Dd * hat(RtE * q_dot);
  rhs.block<2, 3>(3, 0) = -S.mass * RtE.transpose() * hat(Dd * Omega);
  rhs.block<5, 5>(0, 5) = Mat5::Identity();
  D.block<5, 10>(5, 0) = Eigen::LLT<Mat5>(S.mass_matrix(sN.R)).solve(rhs);
  return D;
}

CartPendulumState perturb(const CartPendulumState& s, const CartPendulum& system,
                          const Eigen::Matrix<double, 10, 1>& w) {
  CartPendulumState t = s;
  t.R = s.R * so3::exp(w.head<3>());
  t.q += w.segment<2>(3);
  t.Pi += w.segment<3>(5);
  t.p += w.segment<2>(8);
  t.M = system.moment(t.R);
  t.R_compensation.setZero();
  return t;
}

CartPendulumState CartPendulumDirectModel::retract(const Lgvi& lgvi, const State& a, const VecW& w) {
  return perturb(a, lgvi.system(), w);
}

CartPendulumDirectModel::VecW CartPendulumDirectModel::difference(const State& a, const State& b) {
  VecW w;
  w << so3::log(a.R.transpose() * b.R), b.q - a.q, b.Pi - a.Pi, b.p - a.p;
  return w;
}

// --- connected bodies --------------------------------------------------------------------------

ConnectedBodiesDirectModel::VecR ConnectedBodiesDirectModel::residual(const Lgvi& lgvi, const Transfer& p,
                                                                      const State& sN) {
  Vec3 Omega1, Omega2;
  lgvi.velocities(sN, Omega1, Omega2);
  VecR r;
  r << so3::log(sN.R1.transpose() * p.R1_f), so3::log(sN.R2.transpose() * p.R2_f), Omega1 - p.Omega1_f,
      Omega2 - p.Omega2_f;
  return r;
}

ConnectedBodiesDirectModel::MatRW ConnectedBodiesDirectModel::residual_jacobian(const Lgvi& lgvi,
                                                                                const Transfer& p,
                                                                                const State& sN) {
  const ConnectedBodies& S = lgvi.system();
  Vec3 Omega1, Omega2;
  lgvi.velocities(sN, Omega1, Omega2);
  MatRW D = MatRW::Zero();
  D.block<3, 3>(0, 0) = -so3::left_jacobian_inverse(so3::log(sN.R1.transpose() * p.R1_f));
  D.block<3, 3>(3, 3) = -so3::left_jacobian_inverse(so3::log(sN.R2.transpose() * p.R2_f));
  // Omega = M^{-1} Pi (eq. 47): dOmega = M^{-1} (dPi - dM[eta] Omega).
  const Mat3 D1 = hat(S.d1), D2 = hat(S.d2);
  const Mat3 R12 = sN.R1.transpose() * sN.R2;
  const Vec3 v2 = D2 * Omega2, v1 = D1 * Omega1;
  Eigen::Matrix<double, 6, 12> rhs = Eigen::Matrix<double, 6, 12>::Zero();
  rhs.block<3, 3>(0, 0) = -S.mu * D1 * hat(R12 * v2);
  rhs.block<3, 3>(0, 3) = S.mu * D1 * R12 * hat(v2);
  rhs.block<3, 3>(3, 3) = -S.mu * D2 * hat(R12.transpose() * v1);
  rhs.block<3, 3>(3, 0) = S.mu * D2 * R12.transpose() * hat(v1);
  rhs.block<6, 6>(0, 6) = Mat6x6::Identity();
  D.block<6, 12>(6, 0) = Eigen::LLT<Mat6x6>(S.mass_matrix(sN.R1, sN.R2)).solve(rhs);
  return D;
}

ConnectedBodiesState perturb(const ConnectedBodiesState& s, const Eigen::Matrix<double, 12, 1>& w) {
  ConnectedBodiesState t = s;
  t.R1 = s.R1 * so3::exp(w.segment<3>(0));
  t.R2 = s.R2 * so3::exp(w.segment<3>(3));
  t.Pi1 += w.segment<3>(6);
  t.Pi2 += w.segment<3>(9);
  return t;
}

ConnectedBodiesState ConnectedBodiesDirectModel::retract(const Lgvi&, const State& a, const VecW& w) {
  return perturb(a, w);
}

ConnectedBodiesDirectModel::VecW ConnectedBodiesDirectModel::difference(const State& a, const State& b) {
  VecW w;
  w << so3::log(a.R1.transpose() * b.R1), so3::log(a.R2.transpose() * b.R2), b.Pi1 - a.Pi1, b.Pi2 - a.Pi2;
  return w;
}

ConnectedBodiesDirectModel::VecW ConnectedBodiesDirectModel::geodesic_difference(const Lgvi& /*lgvi*/, const State& a,
                                                                                 const State& b) {
  VecW d = difference(a, b);
  const Vec3 phi1 = d.segment<3>(0), phi2 = d.segment<3>(3);
  // At a half turn both directions are minimal geodesics; body 2 turns against body 1 (chosen by
  // measurement, README "Multiple shooting with IPOPT").
  if (phi2.norm() > M_PI - 1e-9 && phi1.dot(phi2) > 0.0) d.segment<3>(3) = -phi2;
  return d;
}

// --- names -------------------------------------------------------------------------------------

const char* to_string(GradientMethod g) { return g == GradientMethod::Exact ? "exact" : "finite-difference"; }

GradientMethod parse_gradient_method(const std::string& name) {
  if (name == "exact") return GradientMethod::Exact;
  if (name == "finite-difference") return GradientMethod::FiniteDifference;
  throw InvalidInput("gradients", "must be 'exact' or 'finite-difference' (got '" + name + "')");
}

const char* to_string(DirectSolver s) { return s == DirectSolver::Slsqp ? "slsqp" : "ipopt"; }

DirectSolver parse_direct_solver(const std::string& name) {
  if (name == "slsqp") return DirectSolver::Slsqp;
  if (name == "ipopt") return DirectSolver::IpoptMultipleShooting;
  throw InvalidInput("solver", "must be 'slsqp' or 'ipopt' (got '" + name + "')");
}

const char* to_string(ShootingStateGuess g) { return g == ShootingStateGuess::Simulated ? "simulated" : "geodesic"; }

ShootingStateGuess parse_shooting_state_guess(const std::string& name) {
  if (name == "simulated") return ShootingStateGuess::Simulated;
  if (name == "geodesic") return ShootingStateGuess::Geodesic;
  throw InvalidInput("state_guess", "must be 'simulated' or 'geodesic' (got '" + name + "')");
}

const char* to_string(IpoptHessian h) {
  switch (h) {
    case IpoptHessian::LimitedMemory: return "limited-memory";
    case IpoptHessian::CostOnly: return "cost";
    case IpoptHessian::Exact: return "exact";
  }
  return "unknown";
}

IpoptHessian parse_ipopt_hessian(const std::string& name) {
  if (name == "limited-memory") return IpoptHessian::LimitedMemory;
  if (name == "cost") return IpoptHessian::CostOnly;
  if (name == "exact") return IpoptHessian::Exact;
  throw InvalidInput("hessian", "must be 'limited-memory', 'cost' or 'exact' (got '" + name + "')");
}

const char* to_string(DirectStatus s) {
  switch (s) {
    case DirectStatus::Converged: return "converged";
    case DirectStatus::Infeasible: return "success reported but constraints violated";
    case DirectStatus::RoundoffLimited: return "round-off limited";
    case DirectStatus::MaxEvaluations: return "evaluation limit";
    case DirectStatus::SimulationFailed: return "simulation failed";
    case DirectStatus::SolverFailure: return "solver failure";
    case DirectStatus::InvalidInput: return "invalid input";
    case DirectStatus::NonFiniteValue: return "non-finite value";
  }
  return "unknown";
}

std::string DirectSummary::brief() const {
  char buf[512];
  if (status == DirectStatus::InvalidInput) {
    std::snprintf(buf, sizeof buf, "%s: %s", to_string(status), message.c_str());
    return buf;
  }
  std::snprintf(buf, sizeof buf,
                "%s (%s) after %d iterations (%d evaluations, %ld simulations): cost %.8g, violation %.3g, "
                "%.3g s%s%s",
                to_string(status), nlopt_result.c_str(), iterations, evaluations, simulations, cost,
                violation, wall_seconds, message.empty() ? "" : "; ", message.c_str());
  return buf;
}

// --- transcription -----------------------------------------------------------------------------

namespace {

template <int N>
Eigen::Matrix<double, N, N> validated_weight(const Eigen::MatrixXd& W) {
  if (W.size() == 0) return Eigen::Matrix<double, N, N>::Identity();
  if (W.rows() != N || W.cols() != N) {
    throw InvalidInput("W", "must be " + std::to_string(N) + "x" + std::to_string(N));
  }
  require_finite(W, "W");
  if ((W - W.transpose()).cwiseAbs().maxCoeff() > 1e-12 * W.cwiseAbs().maxCoeff()) {
    throw InvalidInput("W", "is not symmetric (must be symmetric positive definite)");
  }
  const Eigen::Matrix<double, N, N> Ws = 0.5 * (W + W.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> eig(Ws, Eigen::EigenvaluesOnly);
  if (!(eig.eigenvalues()(0) > 1e-14 * eig.eigenvalues()(N - 1))) {
    throw InvalidInput("W", "is not positive definite");
  }
  return Ws;
}

void require_rotation(const Mat3& R, const std::string& field) {
  require_finite(R, field);
  if (!so3::is_rotation(R, 1e-10)) throw InvalidInput(field, "is not a rotation matrix (R^T R != I or det R != 1)");
}

void validate(const CartPendulumTransfer& p) {
  require_rotation(p.Rf, "Rf");
  require_finite(p.qf, "qf");
  require_finite(p.Omegaf, "Omegaf");
  require_finite(p.q_dotf, "q_dotf");
}
void validate(const ConnectedBodiesTransfer& p) {
  require_rotation(p.R1_f, "R1_f");
  require_rotation(p.R2_f, "R2_f");
  require_finite(p.Omega1_f, "Omega1_f");
  require_finite(p.Omega2_f, "Omega2_f");
}

std::size_t whole_steps(double t_final, double h) {
  require_positive(h, "h");
  require_positive(t_final, "t_final");
  const double n = t_final / h;
  if (!(n >= 0.5) || n > kMaxOcpSteps + 0.5 || std::abs(n - std::round(n)) > 1e-9 * n) {
    std::ostringstream s;
    s.precision(17);
    s << "the horizon t_final = " << t_final << " is not a whole number of steps h = " << h << " (t_final / h = " << n
      << "; need an integer between 1 and " << Range::text(kMaxOcpSteps) << ", lgvi/range.hpp)";
    throw InvalidInput("h", s.str());
  }
  return static_cast<std::size_t>(std::llround(n));
}

}  // namespace

template <class Model>
DirectTranscription<Model>::DirectTranscription(const System& system, const Transfer& problem,
                                                const DirectOptions& options)
    : lgvi_(system, options.form, options.newton), problem_(problem) {
  h_ = options.h;
  steps_ = whole_steps(problem.t_final, options.h);
  if (options.knots < 3) throw InvalidInput("knots", "needs at least 3 knots per component");
  if (static_cast<std::size_t>(options.knots) > steps_ + 1) {
    throw InvalidInput("knots", "more knots than grid nodes");
  }
  knots_ = options.knots;
  if (!options.constraint_rows.empty()) {
    for (int r : options.constraint_rows) {
      if (r < 0 || r >= Model::nr_full) throw InvalidInput("constraint_rows", "row out of range");
    }
    rows_ = options.constraint_rows;
  } else {
    for (int r = 0; r < (options.keep_redundant_constraint ? Model::nr_full : Model::nr); ++r) rows_.push_back(r);
  }
  W_ = validated_weight<nu>(options.W);
  validate(problem);
  S_ = spline_sampling_matrix(knots_, problem.t_final, static_cast<long>(steps_), options.spline);
  const auto [c0, c1] = impulse_weights(options.form, h_);
  node_weights_ = Eigen::VectorXd::Constant(steps_ + 1, c0 + c1);
  node_weights_(0) = c0;
  node_weights_(steps_) = c1;
  initial_ = Model::initial_state(lgvi_, problem);
}

template <class Model>
typename DirectTranscription<Model>::NodeControls DirectTranscription<Model>::node_controls(
    const Eigen::VectorXd& c) const {
  NodeControls U(nu, S_.rows());
  for (int a = 0; a < nu; ++a) U.row(a) = (S_ * c.segment(a * knots_, knots_)).transpose();
  return U;
}

template <class Model>
template <class E>
void DirectTranscription<Model>::sample_controls_and_cost(const Eigen::VectorXd& c, bool gradients, E& e) const {
  const std::size_t N = steps_;
  e.controls.resize(nu, static_cast<Eigen::Index>(N + 1));
  for (int a = 0; a < nu; ++a) e.controls.row(a).noalias() = (S_ * c.segment(a * knots_, knots_)).transpose();
  // Cost and its gradient (exact: quadratic in c).
  e.cost = 0.0;
  for (std::size_t j = 0; j <= N; ++j) {
    const VecU u = e.controls.col(static_cast<Eigen::Index>(j));
    const VecU Wu = W_ * u;
    e.cost += 0.5 * node_weights_(j) * u.dot(Wu);
    if (gradients) {
      for (int a = 0; a < nu; ++a) {
        e.cost_gradient.segment(a * knots_, knots_) += (node_weights_(j) * Wu(a)) * S_.row(j).transpose();
      }
    }
  }
}

template <class Model>
template <class E>
bool DirectTranscription<Model>::advance(State& s, std::size_t k_begin, std::size_t k_end, bool gradients,
                                         E& e, State* trajectory) const {
  State next;
  if (trajectory != nullptr) trajectory[0] = s;
  for (std::size_t k = k_begin; k < k_end; ++k) {
    const VecU u0 = e.controls.col(static_cast<Eigen::Index>(k));
    const VecU u1 = e.controls.col(static_cast<Eigen::Index>(k + 1));
    const RotationUpdateSummary r = lgvi_.step(s, h_, u0, u1, next);
    const char* non_finite = r.converged() ? non_finite_part(next) : nullptr;
    if (!r.converged() || non_finite != nullptr) {
      e.failed_step = k;
      e.failure = r;
      e.non_finite = non_finite;
      return false;
    }
    if constexpr (std::is_same_v<E, Evaluation>) {
      if (gradients) propagate_sensitivity(s, next, k, e);
    }
    s = next;
    if (trajectory != nullptr) trajectory[k + 1 - k_begin] = s;
  }
  return true;
}

template <class Model>
void DirectTranscription<Model>::propagate_sensitivity(const State& s, const State& next, std::size_t k,
                                                       Evaluation& e) const {
  // Phi_{k+1} = A_k Phi_k + B0_k du_k/dc + B1_k du_{k+1}/dc (knot columns first).
  typename Model::MatW A;
  typename Model::MatWU B0, B1;
  const VecU u0 = e.controls.col(static_cast<Eigen::Index>(k));
  const VecU u1 = e.controls.col(static_cast<Eigen::Index>(k + 1));
  lgvi_.linearize(s, next, h_, u0, u1, A, B0, B1);
  // Coefficient-based products (lazyProduct): for nw rows Eigen's blocked GEMM spends more on
  // packing than on arithmetic, and a sum of two outer products would be evaluated into heap
  // temporaries; the sums are the same, term by term in the same order, so the result is too.
  e.Phi_next.noalias() = A.lazyProduct(e.Phi);
  const auto s0 = S_.row(static_cast<Eigen::Index>(k)), s1 = S_.row(static_cast<Eigen::Index>(k + 1));
  for (int a = 0; a < nu; ++a) {
    e.Phi_next.middleCols(a * knots_, knots_).noalias() += B0.col(a).lazyProduct(s0) + B1.col(a).lazyProduct(s1);
  }
  e.Phi.swap(e.Phi_next);
}

template <class Model>
bool DirectTranscription<Model>::evaluate(const Eigen::VectorXd& c, bool gradients, Evaluation& e) const {
  const int np = parameters();
  e.cost_gradient.setZero(np);
  sample_controls_and_cost(c, gradients, e);
  if (gradients) {
    e.Phi.setZero(nw, np);
    e.Phi_next.resize(nw, np);
  }
  State s = initial_;
  e.ok = false;
  e.non_finite = nullptr;
  if (!advance(s, 0, steps_, gradients, e)) return false;
  e.ok = true;
  e.residual = Model::residual(lgvi_, problem_, s);
  const int m = constraints();
  e.constraints.resize(m);
  for (int i = 0; i < m; ++i) e.constraints(i) = e.residual(rows_[i]);
  if (gradients) {
    const typename Model::MatRW D = Model::residual_jacobian(lgvi_, problem_, s);
    e.constraint_jacobian.resize(m, np);
    for (int i = 0; i < m; ++i) e.constraint_jacobian.row(i).noalias() = D.row(rows_[i]) * e.Phi;
  }
  return true;
}

template <class Model>
bool DirectTranscription<Model>::evaluate_finite_difference(const Eigen::VectorXd& c, Evaluation& e) const {
  if (!evaluate(c, false, e)) return false;
  const int np = parameters();
  const double a = std::cbrt(std::numeric_limits<double>::epsilon());
  e.cost_gradient.resize(np);
  e.constraint_jacobian.resize(constraints(), np);
  Evaluation plus, minus;
  Eigen::VectorXd x = c;
  for (int i = 0; i < np; ++i) {
    const double step = a * (1.0 + std::abs(c(i)));
    x(i) = c(i) + step;
    const bool ok_plus = evaluate(x, false, plus);
    x(i) = c(i) - step;
    const bool ok_minus = evaluate(x, false, minus);
    x(i) = c(i);
    if (!ok_plus || !ok_minus) {
      e = ok_plus ? minus : plus;
      return false;
    }
    e.cost_gradient(i) = (plus.cost - minus.cost) / (2.0 * step);
    e.constraint_jacobian.col(i) = (plus.constraints - minus.constraints) / (2.0 * step);
  }
  return true;
}

template <class Model>
std::vector<typename Model::State> DirectTranscription<Model>::trajectory(const Eigen::VectorXd& c) const {
  const auto U = node_controls(c);
  std::vector<State> states{initial_};
  states.reserve(steps_ + 1);
  State next;
  for (std::size_t k = 0; k < steps_; ++k) {
    const VecU u0 = U.col(static_cast<Eigen::Index>(k)), u1 = U.col(static_cast<Eigen::Index>(k + 1));
    if (!lgvi_.step(states.back(), h_, u0, u1, next).converged()) return {};
    states.push_back(next);
  }
  return states;
}

template <class Model>
std::string DirectTranscription<Model>::failure_message(const Evaluation& e) const {
  return step_failure_message(e.failed_step, static_cast<double>(e.failed_step) * h_, e.failure, e.non_finite, 6);
}

// --- multiple shooting -------------------------------------------------------------------------

template <class Model>
bool DirectTranscription<Model>::shooting_nodes(const Eigen::VectorXd& c, int interval, ShootingStateGuess guess,
                                                ShootingNodes& n, Evaluation& e) const {
  if (interval < 1) throw InvalidInput("shooting_interval", "must be >= 1");
  n.nodes.clear();
  n.reference.clear();
  for (std::size_t k = 0; k < steps_; k += static_cast<std::size_t>(interval)) n.nodes.push_back(k);
  n.nodes.push_back(steps_);
  if (guess == ShootingStateGuess::Geodesic) {
    const State final_state = Model::final_state(lgvi_, problem_);
    const typename Model::VecW d = Model::geodesic_difference(lgvi_, initial_, final_state);
    for (std::size_t j = 1; j + 1 < n.nodes.size(); ++j) {
      const double tau = static_cast<double>(n.nodes[j]) / static_cast<double>(steps_);
      n.reference.push_back(Model::retract(lgvi_, initial_, typename Model::VecW(tau * d)));
    }
    e.ok = true;
    return true;
  }
  const NodeControls U = node_controls(c);
  State s = initial_, next;
  std::size_t j = 1;
  for (std::size_t k = 0; k < steps_; ++k) {
    const RotationUpdateSummary r =
        lgvi_.step(s, h_, U.col(static_cast<Eigen::Index>(k)), U.col(static_cast<Eigen::Index>(k + 1)), next);
    const char* non_finite = r.converged() ? non_finite_part(next) : nullptr;
    if (!r.converged() || non_finite != nullptr) {
      e.failed_step = k;
      e.failure = r;
      e.non_finite = non_finite;
      e.ok = false;
      return false;
    }
    s = next;
    if (j + 1 < n.nodes.size() && k + 1 == n.nodes[j]) {
      n.reference.push_back(s);
      ++j;
    }
  }
  return true;
}

template <class Model>
void DirectTranscription<Model>::shooting_structure(const ShootingNodes& n, std::vector<int>& rows,
                                                    std::vector<int>& cols) const {
  const int np = parameters(), K = n.segments();
  const auto block = [&](int r0, int c0, int nr, int nc) {
    for (int r = 0; r < nr; ++r) {
      for (int q = 0; q < nc; ++q) {
        rows.push_back(r0 + r);
        cols.push_back(c0 + q);
      }
    }
  };
  for (int j = 0; j < K; ++j) {
    const int r0 = j * nw, nr = j + 1 < K ? nw : constraints();
    block(r0, 0, nr, np);
    if (j >= 1) block(r0, np + (j - 1) * nw, nr, nw);
    if (j + 1 < K) block(r0, np + j * nw, nw, nw);
  }
}

namespace {

// The chart Jacobians of multiple shooting (tangent layout of Model::retract). Rotation blocks:
// retract: exp(z + dz) = exp(z) exp(Jr(z) dz), so the state moves by eta = Jr(z) dz;
// difference(a, b) = log(R_a^T R_b) = phi: d phi = Jr^{-1}(phi) eta_b - Jl^{-1}(phi) eta_a.
// The other coordinates enter with the identity.
template <class Model>
typename Model::MatW retract_jacobian(const typename Model::VecW& z) {
  typename Model::MatW J = Model::MatW::Identity();
  for (int i = 0; i < Model::rotations; ++i) J.template block<3, 3>(3 * i, 3 * i) = so3::right_jacobian(z.template segment<3>(3 * i));
  return J;
}
template <class Model>
void difference_jacobians(const typename Model::VecW& d, typename Model::MatW& J_d_a, typename Model::MatW& J_d_b) {
  J_d_a = -Model::MatW::Identity();
  J_d_b = Model::MatW::Identity();
  for (int i = 0; i < Model::rotations; ++i) {
    const Vec3 phi = d.template segment<3>(3 * i);
    J_d_a.template block<3, 3>(3 * i, 3 * i) = -so3::left_jacobian_inverse(phi);
    J_d_b.template block<3, 3>(3 * i, 3 * i) = so3::right_jacobian_inverse(phi);
  }
}

}  // namespace

template <class Model>
bool DirectTranscription<Model>::evaluate_shooting(const ShootingNodes& n, const Eigen::VectorXd& x, bool gradients,
                                                   ShootingEvaluation& e) const {
  using VecW = typename Model::VecW;
  const int np = parameters(), K = n.segments(), m = constraints();
  e.cost_gradient.setZero(x.size());
  sample_controls_and_cost(x.head(np), false, e);
  e.constraints.resize(shooting_constraints(n));
  e.states.resize(steps_ + static_cast<std::size_t>(K));
  e.ok = false;
  e.non_finite = nullptr;
  for (int j = 0; j < K; ++j) {
    // Segment j starts at s_j (s_0 the fixed initial state).
    const std::size_t k_begin = n.nodes[static_cast<std::size_t>(j)], k_end = n.nodes[static_cast<std::size_t>(j + 1)];
    State s = j == 0 ? initial_
                     : Model::retract(lgvi_, n.reference[static_cast<std::size_t>(j - 1)], x.segment(np + (j - 1) * nw, nw));
    if (!advance(s, k_begin, k_end, false, e, &e.states[k_begin + static_cast<std::size_t>(j)])) return false;
    if (j + 1 < K) {
      const State& target = Model::retract(lgvi_, n.reference[static_cast<std::size_t>(j)], x.segment(np + j * nw, nw));
      e.constraints.segment(j * nw, nw) = VecW(Model::difference(target, s));
    } else {
      const typename Model::VecR residual = Model::residual(lgvi_, problem_, s);
      for (int i = 0; i < m; ++i) e.constraints(j * nw + i) = residual(rows_[static_cast<std::size_t>(i)]);
    }
  }
  e.ok = true;
  if (gradients) shooting_gradients(n, x, e);
  return true;
}

template <class Model>
void DirectTranscription<Model>::shooting_gradients(const ShootingNodes& n, const Eigen::VectorXd& x,
                                                    ShootingEvaluation& e) const {
  using MatW = typename Model::MatW;
  using MatWU = typename Model::MatWU;
  using VecW = typename Model::VecW;
  const int np = parameters(), K = n.segments(), m = constraints();
  e.cost_gradient.setZero(x.size());
  sample_controls_and_cost(x.head(np), true, e);
  e.jacobian_values.clear();
  e.knot_rows.resize(nw, np);
  MatW J_d_a, J_d_b, L, L_next, A;
  MatWU B0, B1;
  const auto push = [&](const auto& block) {  // row-major, as shooting_structure lists it
    for (Eigen::Index r = 0; r < block.rows(); ++r) {
      for (Eigen::Index q = 0; q < block.cols(); ++q) e.jacobian_values.push_back(block(r, q));
    }
  };
  for (int j = 0; j < K; ++j) {
    // Reverse (adjoint) sweep along the stored states: the segment's output rows y = D s_end
    // (D = the defect's d/d(end state) J_d_b, or the terminal rows' residual Jacobian, padded to
    // nw rows with zeros) carried back as L_k = D A_{end-1} ... A_k, the knot rows accumulating
    // L_{k+1} (B0_k S_k + B1_k S_{k+1}) per control component; L at the segment's start is
    // dy/d eta_j. nw rows instead of the forward sweep's n_u knots + nw columns.
    const std::size_t k_begin = n.nodes[static_cast<std::size_t>(j)], k_end = n.nodes[static_cast<std::size_t>(j + 1)];
    const State* states = &e.states[k_begin + static_cast<std::size_t>(j)];
    const bool defect = j + 1 < K;
    if (defect) {
      difference_jacobians<Model>(e.constraints.segment(j * nw, nw), J_d_a, J_d_b);
      L = J_d_b;
    } else {
      const typename Model::MatRW D = Model::residual_jacobian(lgvi_, problem_, states[k_end - k_begin]);
      L.setZero();
      for (int i = 0; i < m; ++i) L.row(i) = D.row(rows_[static_cast<std::size_t>(i)]);
    }
    e.knot_rows.setZero();
    for (std::size_t k = k_end; k-- > k_begin;) {
      const VecU u0 = e.controls.col(static_cast<Eigen::Index>(k));
      const VecU u1 = e.controls.col(static_cast<Eigen::Index>(k + 1));
      lgvi_.linearize(states[k - k_begin], states[k + 1 - k_begin], h_, u0, u1, A, B0, B1,
                      LinearizationSolve::ClosedForm);
      const MatWU LB0 = L.lazyProduct(B0), LB1 = L.lazyProduct(B1);
      const auto s0 = S_.row(static_cast<Eigen::Index>(k)), s1 = S_.row(static_cast<Eigen::Index>(k + 1));
      for (int a = 0; a < nu; ++a) {
        e.knot_rows.middleCols(a * knots_, knots_).noalias() += LB0.col(a).lazyProduct(s0) + LB1.col(a).lazyProduct(s1);
      }
      L_next = L.lazyProduct(A);  // coefficient-based: into another matrix (L aliases)
      L = L_next;
    }
    const int rows = defect ? nw : m;
    push(e.knot_rows.topRows(rows));
    if (j >= 1) push(MatW(L * retract_jacobian<Model>(VecW(x.segment(np + (j - 1) * nw, nw)))).topRows(rows));
    if (defect) push(MatW(J_d_a * retract_jacobian<Model>(x.segment(np + j * nw, nw))));
  }
}

template class DirectTranscription<CartPendulumDirectModel>;
template class DirectTranscription<ConnectedBodiesDirectModel>;

// --- SLSQP -------------------------------------------------------------------------------------

Eigen::VectorXd default_initial_knots(const CartPendulum&, int knots) {
  // One period of a circular force, u = 10 (cos 2 pi t/T, sin 2 pi t/T) N at the knots: it
  // drives the cart round a loop, which swings the pendulum and turns it about the vertical.
  Eigen::VectorXd c(2 * knots);
  for (int i = 0; i < knots; ++i) {
    const double phase = 2.0 * M_PI * i / (knots - 1);
    c(i) = 10.0 * std::cos(phase);
    c(knots + i) = 10.0 * std::sin(phase);
  }
  return c;
}

double default_guess_scale(const CartPendulum&) { return 10.0; }
double default_guess_scale(const ConnectedBodies&) { return 0.3; }

Eigen::VectorXd default_initial_knots(const ConnectedBodies&, int knots) {
  // A cyclic shape change (the falling cat's): the joint moment about y and z in quadrature,
  // 0.2 (0, sin 2 pi t/T, cos 2 pi t/T) N m, which rotates the system about x by geometric phase.
  Eigen::VectorXd c = Eigen::VectorXd::Zero(3 * knots);
  for (int i = 0; i < knots; ++i) {
    const double phase = 2.0 * M_PI * i / (knots - 1);
    c(knots + i) = 0.2 * std::sin(phase);
    c(2 * knots + i) = 0.2 * std::cos(phase);
  }
  return c;
}

template <class System>
Eigen::VectorXd random_start_knots(const System& system, const DirectOptions& options, int start) {
  const int n = System::Control::RowsAtCompileTime * options.knots;
  const double sigma = options.guess_scale > 0.0 ? options.guess_scale : default_guess_scale(system);
  std::mt19937_64 rng(options.seed);
  std::normal_distribution<double> normal(0.0, sigma);
  Eigen::VectorXd x(n);
  for (int k = 1; k <= start; ++k) {
    for (int i = 0; i < n; ++i) x(i) = normal(rng);
  }
  return x;
}

Eigen::VectorXd start_knots(const CartPendulum& system, const DirectOptions& options, int start) {
  return random_start_knots(system, options, start);
}
Eigen::VectorXd start_knots(const ConnectedBodies& system, const DirectOptions& options, int start) {
  return random_start_knots(system, options, start);
}

namespace {

std::string nlopt_name(nlopt_result r) {
  switch (r) {
    case NLOPT_SUCCESS: return "NLOPT_SUCCESS";
    case NLOPT_STOPVAL_REACHED: return "NLOPT_STOPVAL_REACHED";
    case NLOPT_FTOL_REACHED: return "NLOPT_FTOL_REACHED";
    case NLOPT_XTOL_REACHED: return "NLOPT_XTOL_REACHED";
    case NLOPT_MAXEVAL_REACHED: return "NLOPT_MAXEVAL_REACHED";
    case NLOPT_MAXTIME_REACHED: return "NLOPT_MAXTIME_REACHED";
    case NLOPT_FAILURE: return "NLOPT_FAILURE";
    case NLOPT_INVALID_ARGS: return "NLOPT_INVALID_ARGS";
    case NLOPT_OUT_OF_MEMORY: return "NLOPT_OUT_OF_MEMORY";
    case NLOPT_ROUNDOFF_LIMITED: return "NLOPT_ROUNDOFF_LIMITED";
    case NLOPT_FORCED_STOP: return "NLOPT_FORCED_STOP";
    default: return "NLOPT_RESULT_" + std::to_string(static_cast<int>(r));
  }
}

// The state shared with NLopt's callbacks. SLSQP asks for the objective and then the
// constraints at the same point: one evaluation serves both (cached by the point).
template <class Model>
struct Callback {
  const DirectTranscription<Model>* problem;
  const DirectOptions* options;
  double cost_scale = 1.0;  ///< the objective handed to SLSQP is J / cost_scale
  typename DirectTranscription<Model>::Evaluation e;
  Eigen::VectorXd x;
  bool have = false;
  bool have_gradients = false;
  std::string failure;
  int start_index = 0;
  DirectSummary* summary;
  std::chrono::steady_clock::time_point start;

  bool ensure(const double* xp, bool gradients) {
    const int n = problem->parameters();
    const Eigen::Map<const Eigen::VectorXd> xm(xp, n);
    const bool same = have && x == xm;
    if (same && (have_gradients || !gradients)) return e.ok;
    x = xm;
    bool ok;
    if (gradients && options->gradients == GradientMethod::FiniteDifference) {
      ok = problem->evaluate_finite_difference(x, e);
      summary->simulations += 1 + 2 * n;
    } else {
      ok = problem->evaluate(x, gradients, e);
      summary->simulations += 1;
    }
    have = true;
    have_gradients = gradients;
    if (gradients) ++summary->gradient_evaluations;
    if (!ok) {
      // A trial point whose simulation fails (a rotation update that does not converge, e.g. at
      // a huge trial step) is reported to SLSQP as an infinite cost: its line search then
      // shortens the step. The last such failure is kept for the summary.
      ++summary->failed_simulations;
      failure = problem->failure_message(e);
      return false;
    }
    if (same && !summary->history.empty()) {
      summary->history.back().gradient = true;  // the same point, now with gradients
      return true;
    }
    DirectIteration it;
    it.evaluation = static_cast<int>(summary->history.size()) + 1;
    it.start = start_index;
    it.gradient = gradients;
    it.cost = e.cost;
    it.violation = e.constraints.norm();
    it.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    summary->history.push_back(it);
    return true;
  }

  static double objective(unsigned n, const double* xp, double* grad, void* data) {
    auto* self = static_cast<Callback*>(data);
    if (!self->ensure(xp, grad != nullptr)) return HUGE_VAL;
    if (grad != nullptr) {
      Eigen::Map<Eigen::VectorXd>(grad, n) = self->e.cost_gradient / self->cost_scale;
    }
    return self->e.cost / self->cost_scale;
  }

  static void constraints(unsigned m, double* result, unsigned n, const double* xp, double* grad, void* data) {
    auto* self = static_cast<Callback*>(data);
    if (!self->ensure(xp, grad != nullptr)) {
      for (unsigned i = 0; i < m; ++i) result[i] = HUGE_VAL;
      return;
    }
    Eigen::Map<Eigen::VectorXd>(result, m) = self->e.constraints;
    if (grad != nullptr) {
      // NLopt: grad[i * n + j] = d c_i / d x_j (row major).
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(grad, m, n) =
          self->e.constraint_jacobian;
    }
  }
};

// Scaling. The cost is quadratic in the knots, J = c^T H c / 2, H = W (x) S^T diag(w) S; SLSQP
// (and IPOPT's limited-memory Hessian) start their quasi-Newton matrix at a multiple of the
// identity, so the objective is J / mean(diag H): its Hessian then has unit mean diagonal. The
// constraints are O(1) in their units (rad, m, rad/s, m/s) and enter unscaled.
template <class Model>
double objective_scale(const DirectTranscription<Model>& tr, const DirectOptions& options) {
  double diag = 0.0;
  const Eigen::MatrixXd& Sm = tr.sampling();
  for (Eigen::Index j = 0; j < Sm.rows(); ++j) diag += tr.node_weight(j) * Sm.row(j).squaredNorm();
  return options.objective_scale > 0.0 ? options.objective_scale
                                       : diag / static_cast<double>(Sm.cols()) * tr.weight().trace() / Model::nu;
}

// Feasibility polish after multiple shooting: IPOPT meets the defects to its tolerance, but the
// reported violation is that of the knots re-simulated in one sweep, where the chaotic flow
// amplifies the defects. Minimum-norm Gauss-Newton steps on the constraints handed to the solver,
// c <- c - J^T (J J^T)^{-1} g(c), restore it (quadratic convergence from a point that is
// feasible up to amplified round-off; the cost moves by O(|g|), i.e. below the tolerance).
// Returns the number of steps taken (at most max_steps); counts into S.
template <class Model>
int polish_feasibility(const DirectTranscription<Model>& tr, const DirectOptions& options, Eigen::VectorXd& c,
                       DirectSummary& S, int max_steps) {
  typename DirectTranscription<Model>::Evaluation e;
  int steps = 0;
  for (; steps < max_steps; ++steps) {
    if (!tr.evaluate(c, true, e)) break;
    ++S.simulations;
    ++S.gradient_evaluations;
    if (e.residual.norm() <= 0.1 * options.tolerance) break;
    const Eigen::MatrixXd& J = e.constraint_jacobian;
    const Eigen::VectorXd step = J.transpose() * (J * J.transpose()).ldlt().solve(e.constraints);
    if (!step.allFinite()) break;
    c -= step;
  }
  return steps;
}

// One SLSQP run from x (updated to the returned point). Appends to S.history, counts into S.
template <class Model>
nlopt_result run_slsqp(const DirectTranscription<Model>& tr, const DirectOptions& options, int start_index,
                       Eigen::VectorXd& x, DirectSummary& S, std::chrono::steady_clock::time_point start) {
  const int n = tr.parameters();
  const int m = tr.constraints();
  Callback<Model> cb;
  cb.problem = &tr;
  cb.options = &options;
  cb.summary = &S;
  cb.start = start;
  cb.start_index = start_index;
  cb.cost_scale = objective_scale(tr, options);
  nlopt_opt opt = nlopt_create(NLOPT_LD_SLSQP, static_cast<unsigned>(n));
  nlopt_set_min_objective(opt, &Callback<Model>::objective, &cb);
  // The constraint tolerance SLSQP uses for its own feasibility test (it returns the best point
  // it deems feasible); the returned point is checked against options.tolerance regardless.
  const std::vector<double> ctol(m, 0.1 * options.tolerance / std::sqrt(double(m)));
  nlopt_add_equality_mconstraint(opt, static_cast<unsigned>(m), &Callback<Model>::constraints, &cb, ctol.data());
  nlopt_set_ftol_rel(opt, options.ftol_rel);
  nlopt_set_maxeval(opt, options.max_evaluations);
  double f = 0.0;
  const nlopt_result code = nlopt_optimize(opt, x.data(), &f);
  nlopt_destroy(opt);
  if (!cb.failure.empty()) S.last_failure = cb.failure;
  return code;
}

DirectStatus true_status(nlopt_result code, bool feasible) {
  switch (code) {
    case NLOPT_SUCCESS:
    case NLOPT_STOPVAL_REACHED:
    case NLOPT_FTOL_REACHED:
    case NLOPT_XTOL_REACHED: return feasible ? DirectStatus::Converged : DirectStatus::Infeasible;
    case NLOPT_ROUNDOFF_LIMITED: return DirectStatus::RoundoffLimited;
    case NLOPT_MAXEVAL_REACHED:
    case NLOPT_MAXTIME_REACHED: return DirectStatus::MaxEvaluations;
    default: return DirectStatus::SolverFailure;
  }
}

template <class Model>
DirectResult<Model> solve(const typename Model::System& system, const typename Model::Transfer& problem,
                          const DirectOptions& options, const char* name) {
  DirectResult<Model> result;
  DirectSummary& S = result.summary;
  S.system = name;
  S.form = options.form;
  S.spline = options.spline;
  S.gradients = options.gradients;
  S.solver = options.solver;
  S.h = options.h;
  S.knots = options.knots;
  const auto start = std::chrono::steady_clock::now();
  std::unique_ptr<DirectTranscription<Model>> tr;
  try {
    options.validate();
    tr = std::make_unique<DirectTranscription<Model>>(system, problem, options);
    S.initial_knots = options.initial_knots.size() > 0 ? options.initial_knots
                                                       : default_initial_knots(system, options.knots);
    if (S.initial_knots.size() != tr->parameters()) {
      throw InvalidInput("initial_knots", "needs " + std::to_string(tr->parameters()) + " values (got " +
                                              std::to_string(S.initial_knots.size()) + ")");
    }
    require_finite(S.initial_knots, "initial_knots");
  } catch (const InvalidInput& e) {
    S.status = DirectStatus::InvalidInput;
    S.message = e.what();
    return result;
  }
  S.steps = tr->steps();
  S.constraints = tr->constraints();

  // Start 0 from the given (or default) guess; starts 1.. from seeded N(0, sigma^2) knot values.
  // The result is the feasible start of lowest cost (else the least infeasible).
  int best = -1;
  std::string non_finite;  // the first start with a non-finite value, and where
  Eigen::VectorXd best_x;
  typename DirectTranscription<Model>::Evaluation best_e;
  for (int i = 0; i < options.starts; ++i) {
    const int k = options.first_start + i;
    DirectStart st;
    st.index = k;
    Eigen::VectorXd x = k == 0 ? S.initial_knots : start_knots(system, options, k);
    st.initial_knots = x;
    const auto t0 = std::chrono::steady_clock::now();
    const int gradients_before = S.gradient_evaluations;
    const std::size_t history_before = S.history.size();
    DirectStatus solver_status;  // from the solver's code, before our own check of the point
    if (options.solver == DirectSolver::Slsqp) {
      const nlopt_result code = run_slsqp(*tr, options, k, x, S, start);
      st.nlopt_result = nlopt_name(code);
      solver_status = true_status(code, true);
      st.evaluations = static_cast<int>(S.history.size() - history_before);
      st.iterations = 0;
      for (std::size_t i = history_before; i < S.history.size(); ++i) st.iterations += S.history[i].gradient ? 1 : 0;
    } else {
      const long simulations_before = S.simulations;
      const detail::IpoptOutcome o = detail::run_ipopt(*tr, options, k, objective_scale(*tr, options), x, S, start);
      st.nlopt_result = o.code;
      solver_status = o.success           ? DirectStatus::Converged
                      : o.iteration_limit ? DirectStatus::MaxEvaluations
                                          : DirectStatus::SolverFailure;
      if (o.success) polish_feasibility(*tr, options, x, S, 8);
      st.iterations = o.iterations;
      st.evaluations = static_cast<int>(S.simulations - simulations_before);
    }
    st.gradient_evaluations = S.gradient_evaluations - gradients_before;
    // The true status, from our own evaluation of the returned point.
    typename DirectTranscription<Model>::Evaluation e;
    const bool ok = tr->evaluate(x, false, e);
    S.simulations += 1;
    st.knot_values = x;
    if (!ok) {
      st.status = DirectStatus::SimulationFailed;
    } else {
      st.cost = e.cost;
      st.violation = e.residual.norm();
      st.status = solver_status != DirectStatus::Converged    ? solver_status
                  : st.violation <= options.tolerance ? DirectStatus::Converged
                                                      : DirectStatus::Infeasible;
    }
    st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    // A non-finite value in the start's history or result makes it a failure of its own.
    bool finite = true;
    if (ok) {
      std::string where;
      for (std::size_t h = history_before; h < S.history.size() && where.empty(); ++h) {
        const DirectIteration& it = S.history[h];
        if (!std::isfinite(it.cost)) where = "cost = " + std::to_string(it.cost);
        if (!std::isfinite(it.violation)) where = "violation = " + std::to_string(it.violation);
        if (!where.empty()) where += " at evaluation " + std::to_string(it.evaluation);
      }
      if (where.empty() && !std::isfinite(st.cost)) where = "cost = " + std::to_string(st.cost);
      if (where.empty() && !std::isfinite(st.violation)) where = "violation = " + std::to_string(st.violation);
      if (where.empty() && !x.allFinite()) where = "a knot value is not finite";
      if (!where.empty()) {
        finite = false;
        st.status = DirectStatus::NonFiniteValue;
        if (non_finite.empty()) non_finite = "start " + std::to_string(k) + ": " + where;
      }
    }
    const auto better = [&](const DirectStart& a, const DirectStart& b) {
      const bool fa = a.violation <= options.tolerance, fb = b.violation <= options.tolerance;
      if (fa != fb) return fa;
      return fa ? a.cost < b.cost : a.violation < b.violation;
    };
    if (ok && finite && (best < 0 || better(st, S.starts[best]))) {
      best = i;
      best_x = x;
      best_e = e;
    }
    S.starts.push_back(st);
  }
  S.best_start = best;
  for (const DirectStart& st : S.starts) {
    S.iterations += st.iterations;
    S.evaluations += st.evaluations;
  }
  if (best < 0 && !non_finite.empty()) {
    S.status = DirectStatus::NonFiniteValue;
    S.message = non_finite;
    S.knot_values = S.starts.back().knot_values;
  } else if (best < 0) {
    S.status = DirectStatus::SimulationFailed;
    S.message = S.last_failure.empty() ? "every start's returned point failed to simulate" : S.last_failure;
    S.knot_values = S.starts.back().knot_values;
  } else {
    const DirectStart& b = S.starts[best];
    S.status = b.status;
    S.nlopt_result = b.nlopt_result;
    S.knot_values = best_x;
    S.cost = best_e.cost;
    S.residual = best_e.residual;
    S.violation = best_e.residual.norm();
    S.constraint_violation = best_e.constraints.norm();
    if (S.status != DirectStatus::Converged) {
      S.message = S.violation <= options.tolerance ? "the returned point is feasible (violation within the tolerance)"
                                                   : "the returned point violates the terminal conditions";
    }
    result.states = tr->trajectory(best_x);
    result.controls = tr->node_controls(best_x);
  }
  S.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace

DirectResult<CartPendulumDirectModel> solve_direct(const CartPendulum& system, const CartPendulumTransfer& problem,
                                                    const DirectOptions& options) {
  return solve<CartPendulumDirectModel>(system, problem, options, "cart-pendulum");
}

DirectResult<ConnectedBodiesDirectModel> solve_direct(const ConnectedBodies& system,
                                                       const ConnectedBodiesTransfer& problem,
                                                       const DirectOptions& options) {
  return solve<ConnectedBodiesDirectModel>(system, problem, options, "connected-bodies");
}

}  // namespace lgvi::ocp
