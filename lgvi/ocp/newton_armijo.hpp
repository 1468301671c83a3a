// Newton-Armijo shooting on the initial multiplier lambda_0, shared by the discrete necessary
// conditions (indirect.cpp, solve_indirect) and the continuous baseline (baselines/pontryagin.cpp,
// solve_pontryagin): the outer Newton iterations, the full or symmetry-decomposed Newton system,
// the Armijo line search and its polishing steps, the stall / line-search-failure diagnosis and the
// ShootingSummary bookkeeping. What is shot (a sweep of the discrete flow, a CVODES integration of
// the state-costate ODE) enters through the Problem; the method is the one documented at
// solve_indirect (indirect.hpp): Kelley 2003, sec. 1.10, and the decomposition
// U^T (dr/dlambda) V = [S 0; 0 0], d = -V_s S^{-1} U_s^T r.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SVD>

#include "lgvi/ocp/indirect.hpp"

namespace lgvi::ocp {

/// 2-norm condition number; +inf for a singular or non-finite matrix.
inline double condition_number(const Eigen::MatrixXd& M) {
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(M);
  const auto& s = svd.singularValues();
  if (s.size() == 0 || !s.allFinite()) return std::numeric_limits<double>::infinity();
  const double lo = s(s.size() - 1);
  return lo > 0.0 ? s(0) / lo : std::numeric_limits<double>::infinity();
}

/// Settings of newton_armijo_shooting (validated by the caller).
template <int N>
struct NewtonArmijoOptions {
  int max_iterations = 100;
  int max_backtracks = 30;
  double armijo = 1e-4;      ///< sufficient decrease merit(r(l + t d)) <= (1 - armijo t) merit(r(l))
  double tolerance = 1e-12;  ///< on the violation |r|
  int polish_iterations = 3;
  /// Levenberg-Marquardt steps on the weighted residual instead of Newton-Armijo (Globalization);
  /// max_backtracks then bounds the rejected steps per outer iteration.
  bool levenberg_marquardt = false;
  double lm_initial_damping = 1e-3;  ///< mu_0 of Levenberg-Marquardt (relative to diag(J^T J))
  /// Armijo test against the largest merit of this many last accepted points (1: monotone).
  int nonmonotone_memory = 1;
  /// Merit of the line search |weights r| and the weighting of the Newton system (jacobian,
  /// residual and D alike); none: |r| and the unweighted system. The convergence test is always
  /// on the violation |r|.
  std::optional<Eigen::Matrix<double, N, N>> merit_weights;
  /// The symmetry's multiplier direction v_g = dC(s_0) (used when summary.decomposition).
  Eigen::Matrix<double, N, 1> initial_conserved_gradient = Eigen::Matrix<double, N, 1>::Zero();
  /// Start of the solve: rec.seconds and summary.wall_seconds count from here.
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
};

/// The two evaluations the Newton iterations hold: the accepted point's and a trial's.
enum class Shot { Current, Trial };

/// What is shot, seen by the Newton iterations (the Problem below, behind one virtual boundary so
/// that the iterations compile once per N (newton_armijo.cpp: N = 6, 12) instead of once per
/// problem). ShotsOf adapts a Problem and its Evaluation type.
template <int N>
class Shots {
 public:
  using Vec = Eigen::Matrix<double, N, 1>;
  using Mat = Eigen::Matrix<double, N, N>;
  virtual ~Shots() = default;
  /// One shot into the slot (Problem::evaluate).
  virtual bool evaluate(const Vec& lambda, bool jacobian, Shot slot) = 0;
  /// The trial becomes the accepted point.
  virtual void keep_trial() = 0;
  virtual const Vec& residual(Shot slot) const = 0;
  virtual const Mat& jacobian(Shot slot) const = 0;
  virtual double cost(Shot slot) const = 0;
  /// Problem::terminal_symmetry, round_off_floor and rerun_failure of the accepted point;
  /// Problem::stall_message.
  virtual std::pair<Mat, Vec> terminal_symmetry() const = 0;
  virtual double round_off_floor(const Vec& lambda) const = 0;
  virtual std::string stall_message(double violation, int iteration, double floor, double cond) const = 0;
  virtual std::string rerun_failure() const = 0;
};

/// A Problem (see newton_armijo_shooting) and its accepted evaluation `current` as Shots; the
/// trial lives here.
template <class Problem, class Evaluation, int N>
class ShotsOf final : public Shots<N> {
 public:
  using typename Shots<N>::Vec;
  using typename Shots<N>::Mat;
  ShotsOf(Problem& problem, Evaluation& current) : problem_(problem), current_(current) {}
  bool evaluate(const Vec& lambda, bool jacobian, Shot slot) override {
    return problem_.evaluate(lambda, jacobian, at(slot));
  }
  void keep_trial() override { current_ = trial_; }
  const Vec& residual(Shot slot) const override { return at(slot).residual; }
  const Mat& jacobian(Shot slot) const override { return at(slot).jacobian; }
  double cost(Shot slot) const override { return at(slot).cost; }
  std::pair<Mat, Vec> terminal_symmetry() const override { return problem_.terminal_symmetry(current_); }
  double round_off_floor(const Vec& lambda) const override { return problem_.round_off_floor(current_, lambda); }
  std::string stall_message(double violation, int iteration, double floor, double cond) const override {
    return problem_.stall_message(violation, iteration, floor, cond);
  }
  std::string rerun_failure() const override { return problem_.rerun_failure(current_); }

 private:
  Evaluation& at(Shot slot) { return slot == Shot::Current ? current_ : trial_; }
  const Evaluation& at(Shot slot) const { return slot == Shot::Current ? current_ : trial_; }
  Problem& problem_;
  Evaluation& current_;
  Evaluation trial_;
};

/// Newton homotopy (predictor-corrector path following; Allgower & Georg 1990, ch. 2): follows the
/// zeros of H(lambda, tau) = r(lambda) - (1 - tau) r(lambda_start) from tau = 0 (lambda_start) to
/// tau = 1, the path the damped Newton iteration approximates (its tangent is the Newton direction
/// -J^{-1} r(lambda_start)), so it ends on Newton-Armijo's extremal but is not bound to Armijo's
/// monotone decrease along straight lines. Predictor: the tangent step lambda - dtau J^{-1} r_start;
/// corrector: full Newton steps on H (at most `max_corrector`, each must halve |H|; accepted when
/// |H| <= corrector_tolerance |r_start|); a failed corrector halves dtau, an easy one (<= 2 steps)
/// doubles it. Every Jacobian evaluation counts as an outer iteration, every rejected point as an
/// inner one. Returns whether tau = 1 was reached; `lambda`, `current` are the last point on the
/// path (the end game is Newton-Armijo from there).
template <int N>
bool follow_homotopy(Shots<N>& shots, const NewtonArmijoOptions<N>& o, Eigen::Matrix<double, N, 1>& lambda,
                     ShootingSummary& S, double initial_step, int max_corrector, double corrector_tolerance) {
  using Vec = Eigen::Matrix<double, N, 1>;
  using Clock = std::chrono::steady_clock;
  auto seconds = [&] { return std::chrono::duration<double>(Clock::now() - o.start).count(); };
  const Vec r_start = shots.residual(Shot::Current);
  double tau = 0.0, dtau = initial_step;
  while (tau < 1.0) {
    if (S.iterations >= o.max_iterations || dtau < 1e-6) return false;
    const double next = std::min(1.0, tau + dtau);
    IterationRecord rec;
    rec.iteration = S.iterations;
    rec.violation = shots.residual(Shot::Current).norm();
    rec.cost = shots.cost(Shot::Current);
    rec.cond_sensitivity = rec.cond_inverted = condition_number(shots.jacobian(Shot::Current));
    Vec candidate = lambda - (next - tau) * shots.jacobian(Shot::Current).partialPivLu().solve(r_start);
    rec.step_norm = (candidate - lambda).norm();
    bool ok = false;
    int corrector = 0;
    double previous = std::numeric_limits<double>::infinity();
    for (; corrector <= max_corrector; ++corrector) {
      ++S.sweeps;
      if (!candidate.allFinite() || !shots.evaluate(candidate, true, Shot::Trial)) break;
      ++S.iterations;
      const Vec H = shots.residual(Shot::Trial) - (1.0 - next) * r_start;
      const double h = H.norm();
      if (h <= corrector_tolerance * r_start.norm() || (next == 1.0 && h <= o.tolerance)) {
        ok = true;
        break;
      }
      if (!(h <= 0.5 * previous)) break;
      previous = h;
      candidate -= shots.jacobian(Shot::Trial).partialPivLu().solve(H);
    }
    rec.sweeps = S.sweeps;
    rec.seconds = seconds();
    if (ok) {
      lambda = candidate;
      shots.keep_trial();
      tau = next;
      rec.step_length = next;  // tau reached
      rec.backtracks = corrector;
      if (corrector <= 2) dtau *= 2.0;
    } else {
      ++S.inner_iterations;
      rec.step_length = 0.0;
      dtau *= 0.5;
    }
    S.history.push_back(rec);
  }
  return true;
}

/// Newton-homotopy continuation with few Jacobians (Allgower & Georg 1990, ch. 2, 6, 7): follows the
/// same path as newton_homotopy, the zeros of H(lambda, tau) = r(lambda) - (1 - tau) r(lambda_start)
/// (Newton-Armijo's path; its tangent dlambda/dtau = -J^{-1} r_start is the Newton direction), but
///  - predictor: cubic Hermite extrapolation through the last two path points and their tangents
///    (error O(dtau^4); the tangent step lambda + dtau t for the first step);
///  - corrector: Broyden's quasi-Newton steps from the path point's Jacobian (rank-one secant
///    updates, residual-only sweeps), at most `max_corrector`, each must shrink |H| by half;
///  - the exact Jacobian (a sweep with sensitivities) only at accepted path points, for the next
///    tangent;
///  - step control from the predictor's measured error: dtau_next = dtau (target / e)^{1/p},
///    e = |H(lambda_pred)| / |r_start|, clipped to [1/4, max_growth]; a failed corrector quarters
///    dtau at most and never below the formula's value.
/// Counting: every sweep with sensitivities (every Jacobian) is an outer iteration, every
/// residual-only sweep (predicted and corrected points) an inner one. Returns whether tau = 1 was
/// reached with |r| <= corrector_tolerance |r_start|; `lambda`, `current` are the last path point
/// (the end game is Newton-Armijo from there).
template <int N>
bool follow_continuation(Shots<N>& shots, const NewtonArmijoOptions<N>& o, Eigen::Matrix<double, N, 1>& lambda,
                         ShootingSummary& S, const ContinuationSettings& c) {
  using Vec = Eigen::Matrix<double, N, 1>;
  using Mat = Eigen::Matrix<double, N, N>;
  using Clock = std::chrono::steady_clock;
  auto seconds = [&] { return std::chrono::duration<double>(Clock::now() - o.start).count(); };
  const Vec r_start = shots.residual(Shot::Current);
  const double r_norm = r_start.norm();
  if (!(r_norm > 0.0)) return true;
  double tau = 0.0, dtau = c.initial_step;
  Vec tangent = -shots.jacobian(Shot::Current).partialPivLu().solve(r_start);
  // The previous path point (tau, lambda, tangent) for the Hermite predictor.
  bool have_previous = false;
  double tau_prev = 0.0;
  Vec lambda_prev = lambda, tangent_prev = tangent;
  while (tau < 1.0) {
    if (S.iterations >= o.max_iterations || dtau < 1e-6 || !tangent.allFinite()) return false;
    const double next = std::min(1.0, tau + dtau);
    const double step = next - tau;
    IterationRecord rec;
    rec.iteration = S.iterations;
    rec.violation = shots.residual(Shot::Current).norm();
    rec.cost = shots.cost(Shot::Current);
    rec.cond_sensitivity = rec.cond_inverted = condition_number(shots.jacobian(Shot::Current));
    Vec candidate;
    int order = 2;
    if (have_previous) {
      // Cubic Hermite through (tau_prev, lambda_prev, tangent_prev), (tau, lambda, tangent),
      // evaluated at s = (next - tau_prev) / H, H = tau - tau_prev (s > 1: extrapolation).
      const double H = tau - tau_prev, s = (next - tau_prev) / H;
      const double h00 = 2 * s * s * s - 3 * s * s + 1, h10 = s * s * s - 2 * s * s + s;
      const double h01 = -2 * s * s * s + 3 * s * s, h11 = s * s * s - s * s;
      candidate = h00 * lambda_prev + h10 * H * tangent_prev + h01 * lambda + h11 * H * tangent;
      order = 4;
    } else {
      candidate = lambda + step * tangent;
    }
    // Broyden corrector from the path point's Jacobian.
    Mat B = shots.jacobian(Shot::Current);
    bool ok = false;
    double predicted_error = std::numeric_limits<double>::infinity();
    double previous = std::numeric_limits<double>::infinity();
    Vec H_prev = Vec::Zero(), delta = Vec::Zero();
    int evaluations = 0;
    for (int i = 0; i <= c.max_corrector; ++i) {
      ++S.sweeps;
      ++S.inner_iterations;
      ++evaluations;
      if (!candidate.allFinite() || !shots.evaluate(candidate, false, Shot::Trial)) break;
      const Vec H = shots.residual(Shot::Trial) - (1.0 - next) * r_start;
      const double h = H.norm();
      if (i == 0) predicted_error = h / r_norm;
      if (h <= c.corrector_tolerance * r_norm) {
        ok = true;
        break;
      }
      if (!(h <= 0.5 * previous)) break;
      if (i > 0) B += (H - H_prev - B * delta) * delta.transpose() / delta.squaredNorm();
      previous = h;
      H_prev = H;
      delta = -B.partialPivLu().solve(H);
      candidate += delta;
    }
    rec.backtracks = evaluations;
    double factor = std::isfinite(predicted_error) && predicted_error > 0.0
                        ? std::pow(c.predictor_target / predicted_error, 1.0 / order)
                        : 0.25;
    if (ok) {
      ++S.sweeps;
      if (!shots.evaluate(candidate, true, Shot::Trial)) ok = false;
    }
    if (ok) {
      ++S.iterations;
      rec.step_norm = (candidate - lambda).norm();
      tau_prev = tau;
      lambda_prev = lambda;
      tangent_prev = tangent;
      have_previous = true;
      lambda = candidate;
      shots.keep_trial();
      tau = next;
      tangent = -shots.jacobian(Shot::Current).partialPivLu().solve(r_start);
      rec.step_length = next;  // tau reached
      dtau = step * std::clamp(factor, 0.25, c.max_growth);
    } else {
      rec.step_length = 0.0;
      dtau = step * std::clamp(factor, 0.0625, 0.25);
    }
    rec.sweeps = S.sweeps;
    rec.seconds = seconds();
    S.history.push_back(rec);
  }
  return true;
}

/// Newton-Armijo iterations from `lambda` whose evaluation (with Jacobian, ok) is `current`;
/// `summary.decomposition` selects the symmetry-decomposed Newton system. On return `lambda` is
/// the last accepted multiplier, `current` its evaluation (see Problem::evaluate), and summary's
/// status, message, iterations, sweeps, condition ranges, history, cost, violation, residual,
/// multiplier and wall_seconds are set. Problem (Evaluation has `residual`, `jacobian`, `cost`):
///   bool evaluate(const Vec& lambda, bool jacobian, Evaluation& out): one shot, with dr/dlambda_0
///     when `jacobian`; on failure `out` holds whatever the problem leaves there (read only by
///     rerun_failure).
///   std::pair<Mat, Vec> terminal_symmetry(const Evaluation&): D = dr/dw_N and dC(s_N), from
///     which u_g = D^{-T} dC(s_N) (decomposition only).
///   double round_off_floor(const Evaluation& current, const Vec& lambda): the violation below
///     which Newton cannot resolve r; a failed line search within 10x of it is Stalled.
///   std::string stall_message(double violation, int iteration, double floor, double cond).
///   std::string rerun_failure(const Evaluation& failed): the accepted point's re-run with its
///     Jacobian failed.
template <int N>
void newton_armijo_iterations(Shots<N>& shots, const NewtonArmijoOptions<N>& o, Eigen::Matrix<double, N, 1>& lambda,
                              ShootingSummary& S) {
  using Vec = Eigen::Matrix<double, N, 1>;
  using Mat = Eigen::Matrix<double, N, N>;
  using Clock = std::chrono::steady_clock;
  auto seconds = [&] { return std::chrono::duration<double>(Clock::now() - o.start).count(); };
  auto merit = [&](const Vec& r) { return o.merit_weights ? (*o.merit_weights * r).norm() : r.norm(); };
  auto weighted = [&]<class T>(const T& M) -> T {
    if (o.merit_weights) return T(*o.merit_weights * M);
    return M;
  };

  double violation = shots.residual(Shot::Current).norm();
  double merit_value = merit(shots.residual(Shot::Current));
  // Non-monotone reference (Grippo, Lampariello, Lucidi 1986): the largest merit of the last
  // nonmonotone_memory accepted points; memory 1 is the classical Armijo test.
  std::vector<double> recent_merits{merit_value};
  auto reference_merit = [&] { return *std::max_element(recent_merits.begin(), recent_merits.end()); };
  S.cost = shots.cost(Shot::Current);
  S.violation = violation;
  S.cond_min = S.cond_full_min = std::numeric_limits<double>::infinity();
  S.cond_max = S.cond_full_max = 0.0;

  // Symmetry bases: v_g from the initial state (fixed), u_g from the terminal state.
  Mat V = Mat::Identity();
  if (S.decomposition) {
    const Eigen::HouseholderQR<Vec> qr(o.initial_conserved_gradient);
    V = qr.householderQ();  // V.col(0) = +-v_g / |v_g|, the rest its orthogonal complement
  }

  int polish_left = -1;  // -1: not polishing yet
  // Levenberg-Marquardt damping mu (relative to diag(J^T J), Marquardt's scaling, so invariant
  // under rescaling lambda_0's entries: the dumbbell's rod-axis inertia makes them differ by
  // orders of magnitude) and its growth factor nu; mu_0 = lm_initial_damping (MNT's tau).
  double lm_mu = o.lm_initial_damping, lm_nu = 2.0;
  for (int it = 0;; ++it) {
    IterationRecord rec;
    rec.iteration = it;
    rec.violation = violation;
    rec.cost = shots.cost(Shot::Current);
    if (violation <= o.tolerance) {
      S.status = ShootingStatus::Converged;
      if (polish_left < 0) polish_left = o.polish_iterations;
      if (polish_left == 0) break;
    } else if (it >= o.max_iterations) {
      S.status = ShootingStatus::MaxIterations;
      char buf[160];
      std::snprintf(buf, sizeof buf, "violation %.3g > tolerance %.3g after the limit of %d outer iterations",
                    violation, o.tolerance, o.max_iterations);
      S.message = buf;
      break;
    }
    const Mat jac = weighted(shots.jacobian(Shot::Current));
    const Vec r = weighted(shots.residual(Shot::Current));
    rec.cond_sensitivity = condition_number(shots.jacobian(Shot::Current));
    Vec direction;
    if (S.decomposition) {
      const std::pair<Mat, Vec> terminal = shots.terminal_symmetry();
      const Mat D = weighted(terminal.first);
      const Vec u_g = D.transpose().partialPivLu().solve(terminal.second);
      const Eigen::HouseholderQR<Vec> qr(u_g);
      const Mat U = qr.householderQ();
      const Mat blocks = U.transpose() * jac * V;
      const Eigen::Matrix<double, N - 1, N - 1> shape = blocks.template bottomRightCorner<N - 1, N - 1>();
      const double scale = blocks.norm();
      rec.group_block = std::max(blocks.row(0).norm(), blocks.col(0).norm()) / (scale > 0.0 ? scale : 1.0);
      const Vec r_rot = U.transpose() * r;
      rec.group_residual = std::abs(r_rot(0));
      rec.cond_inverted = condition_number(shape);
      const Eigen::Matrix<double, N - 1, 1> sigma = -shape.partialPivLu().solve(r_rot.template tail<N - 1>());
      direction = V.template rightCols<N - 1>() * sigma;
    } else {
      rec.cond_inverted = rec.cond_sensitivity;
      direction = -jac.partialPivLu().solve(r);
    }
    rec.step_norm = direction.allFinite() ? direction.norm() : std::numeric_limits<double>::infinity();
    S.cond_min = std::min(S.cond_min, rec.cond_inverted);
    S.cond_max = std::max(S.cond_max, rec.cond_inverted);
    S.cond_full_min = std::min(S.cond_full_min, rec.cond_sensitivity);
    S.cond_full_max = std::max(S.cond_full_max, rec.cond_sensitivity);
    if (!direction.allFinite()) {
      S.status = ShootingStatus::SingularSensitivity;
      char buf[256];
      std::snprintf(buf, sizeof buf, "the Newton system at outer iteration %d has no finite solution (cond %.3g)",
                    it, rec.cond_inverted);
      S.message = buf;
      rec.sweeps = S.sweeps;
      rec.seconds = seconds();
      S.history.push_back(rec);
      break;
    }
    // Line search (a full step only when polishing: kept if it lowers the violation). A trial
    // whose evaluation fails counts as not decreasing.
    const bool polishing = polish_left > 0;
    double t = 1.0;
    bool accepted = false;
    const int max_trials = polishing ? 1 : o.max_backtracks + 1;
    if (o.levenberg_marquardt && !polishing) {
      // Trust region by damping: (A + mu Dg) d = -g, A = J^T J, g = J^T r, Dg = diag(A); accept
      // when the actual reduction of |r|^2/2 is a positive fraction of the model's
      // (pred = d^T (mu Dg d - g) / 2); mu shrinks by max(1/3, 1 - (2 rho - 1)^3) after a
      // success, grows by nu (doubling) after a failure.
      const Mat A = jac.transpose() * jac;
      const Vec g = jac.transpose() * r;
      const Vec Dg = A.diagonal().cwiseMax(1e-30 * A.diagonal().maxCoeff());
      for (int b = 0; b < max_trials; ++b) {
        Mat damped = A;
        damped.diagonal() += lm_mu * Dg;
        const Vec d = damped.ldlt().solve(-g);
        rec.step_norm = d.norm();
        const Vec candidate = lambda + d;
        ++S.sweeps;
        if (b > 0) ++S.inner_iterations;
        rec.backtracks = b;
        double rho = -1.0;
        if (d.allFinite() && shots.evaluate(candidate, false, Shot::Trial)) {
          const double predicted = 0.5 * d.dot(lm_mu * Dg.cwiseProduct(d) - g);
          const Vec rt = weighted(shots.residual(Shot::Trial));
          const double actual = 0.5 * (r.squaredNorm() - rt.squaredNorm());
          rho = predicted > 0.0 ? actual / predicted : -1.0;
        }
        if (rho > 1e-4) {
          lambda = candidate;
          accepted = true;
          lm_mu *= std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3));
          lm_nu = 2.0;
          break;
        }
        lm_mu *= lm_nu;
        lm_nu *= 2.0;
      }
    }
    for (int b = 0; b < (o.levenberg_marquardt && !polishing ? 0 : max_trials); ++b) {
      const Vec candidate = lambda + t * direction;
      ++S.sweeps;
      if (b > 0) ++S.inner_iterations;
      rec.backtracks = b;
      if (shots.evaluate(candidate, false, Shot::Trial)) {
        const Vec& rt = shots.residual(Shot::Trial);
        const bool decrease =
            polishing ? rt.norm() < violation : merit(rt) <= (1.0 - o.armijo * t) * reference_merit();
        if (decrease) {
          lambda = candidate;
          accepted = true;
          break;
        }
      }
      t *= 0.5;
    }
    rec.sweeps = S.sweeps;
    if (!accepted) {
      rec.step_length = 0.0;
      rec.seconds = seconds();
      S.history.push_back(rec);
      if (polishing) break;  // at the round-off floor: converged stays
      const double floor = shots.round_off_floor(lambda);
      if (violation <= 10.0 * floor) {
        S.status = ShootingStatus::Stalled;
        S.message = shots.stall_message(violation, it, floor, rec.cond_inverted);
      } else {
        S.status = ShootingStatus::LineSearchFailed;
        char buf[400];
        std::snprintf(buf, sizeof buf,
                      "no sufficient decrease of the violation %.3g at outer iteration %d after %d %s "
                      "(last t = %.3g)",
                      violation, it, o.max_backtracks,
                      o.levenberg_marquardt ? "rejected damped steps" : "step halvings", 2.0 * t);
        S.message = buf;
      }
      break;
    }
    rec.step_length = t;
    // Re-run the accepted point with its Jacobian for the next Newton step.
    ++S.sweeps;
    rec.sweeps = S.sweeps;
    if (!shots.evaluate(lambda, true, Shot::Current)) {
      S.status = ShootingStatus::SweepFailed;
      S.message = shots.rerun_failure();
      rec.seconds = seconds();
      S.history.push_back(rec);
      break;
    }
    violation = shots.residual(Shot::Current).norm();
    merit_value = merit(shots.residual(Shot::Current));
    recent_merits.push_back(merit_value);
    if (static_cast<int>(recent_merits.size()) > o.nonmonotone_memory) recent_merits.erase(recent_merits.begin());
    ++S.iterations;
    if (polishing) --polish_left;
    rec.seconds = seconds();
    S.history.push_back(rec);
  }
  S.cost = shots.cost(Shot::Current);
  S.violation = violation;
  S.residual = shots.residual(Shot::Current);
  S.multiplier = lambda;
  if (S.cond_min > S.cond_max) S.cond_min = S.cond_max = 0.0;
  if (S.cond_full_min > S.cond_full_max) S.cond_full_min = S.cond_full_max = 0.0;
  S.wall_seconds = seconds();
}

// The Problem-facing entry points: each adapts the Problem once and runs the iterations above.

template <class Problem, class Evaluation, int N>
bool newton_homotopy(Problem& problem, const NewtonArmijoOptions<N>& o, Eigen::Matrix<double, N, 1>& lambda,
                     Evaluation& current, ShootingSummary& S, double initial_step = 0.1, int max_corrector = 4,
                     double corrector_tolerance = 0.1) {
  ShotsOf<Problem, Evaluation, N> shots(problem, current);
  return follow_homotopy(shots, o, lambda, S, initial_step, max_corrector, corrector_tolerance);
}

template <class Problem, class Evaluation, int N>
bool newton_continuation(Problem& problem, const NewtonArmijoOptions<N>& o, Eigen::Matrix<double, N, 1>& lambda,
                         Evaluation& current, ShootingSummary& S, const ContinuationSettings& c = {}) {
  ShotsOf<Problem, Evaluation, N> shots(problem, current);
  return follow_continuation(shots, o, lambda, S, c);
}

template <class Problem, class Evaluation, int N>
void newton_armijo_shooting(Problem& problem, const NewtonArmijoOptions<N>& o, Eigen::Matrix<double, N, 1>& lambda,
                            Evaluation& current, ShootingSummary& S) {
  ShotsOf<Problem, Evaluation, N> shots(problem, current);
  newton_armijo_iterations(shots, o, lambda, S);
}

// Compiled once in newton_armijo.cpp for the multiplier sizes of the library's problems (6: the
// free body and the pendulum, discrete and continuous; 12: the dumbbell).
#define LGVI_NEWTON_ITERATIONS(KEYWORD, N)                                                                      \
  KEYWORD template bool follow_homotopy<N>(Shots<N>&, const NewtonArmijoOptions<N>&, Eigen::Matrix<double, N, 1>&, \
                                           ShootingSummary&, double, int, double);                             \
  KEYWORD template bool follow_continuation<N>(Shots<N>&, const NewtonArmijoOptions<N>&,                        \
                                               Eigen::Matrix<double, N, 1>&, ShootingSummary&,                  \
                                               const ContinuationSettings&);                                    \
  KEYWORD template void newton_armijo_iterations<N>(Shots<N>&, const NewtonArmijoOptions<N>&,                   \
                                                    Eigen::Matrix<double, N, 1>&, ShootingSummary&);
LGVI_NEWTON_ITERATIONS(extern, 6)
LGVI_NEWTON_ITERATIONS(extern, 12)

}  // namespace lgvi::ocp
