// Fixed-step driver for any LGVI flow map: steps, controls sampled at the grid, an observer for
// output, and a Stats summary. The driver never prints; observers do the output.
#pragma once

#include <chrono>
#include <cmath>
#include <cstddef>
#include <string>
#include <utility>
#include <algorithm>

#include "lgvi/flow_map.hpp"
#include "lgvi/rotation_update.hpp"

namespace lgvi {

/// Why an integration stopped. SolverFailed and CoordinateSingularity come from the
/// continuous-time baselines (baselines/): a solver's failure flag, or a coordinate model's
/// singular set (Euler angles at gimbal lock); failure_detail says which.
enum class IntegrationStatus {
  Completed,
  RotationUpdateFailed,
  ObserverStopped,
  SolverFailed,
  CoordinateSingularity,
  NonFiniteState,  ///< a step produced a non-finite state (overflow); failure_detail names the part
  StepFailed       ///< a one-step method's own solve failed (StepSummary::failure in failure_detail)
};
const char* to_string(IntegrationStatus s);

/// Summary of an integration run (the project's common Stats, like Ceres' Solver::Summary).
/// Every method returns this one type, the continuous-time baselines too (their statuses
/// SolverFailed and CoordinateSingularity and their counts below), so that the recorder, the
/// suites' summary columns and the CSV metadata read any run the same way; the core never sets
/// the baselines' fields, and lgvi::lgvi depends on nothing of baselines/ for them.
struct Stats {
  IntegrationStatus status = IntegrationStatus::Completed;
  std::size_t steps = 0;                  ///< steps completed
  std::size_t potential_evaluations = 0;  ///< the LGVI's "right-hand side" count
  std::size_t newton_iterations = 0;      ///< rotation-update Newton iterations, total
  int max_newton_iterations = 0;          ///< worst single step
  std::size_t fallbacks = 0;              ///< steps that needed the fallback parametrization
  double max_rotation_residual = 0.0;     ///< worst relative residual of the rotation update
  double wall_seconds = 0.0;
  // Failure location (status == RotationUpdateFailed, NonFiniteState): the step k -> k+1 that
  // failed, from t_k = failed_time.
  // Baselines (SolverFailed, CoordinateSingularity): failed_time is the time reached (the root
  // of the singular set's event function), failed_step the solver steps completed.
  std::size_t failed_step = 0;
  double failed_time = 0.0;
  double step_size = 0.0;  ///< the LGVI's h (for the admissible step of a failed rotation update)
  RotationUpdateSummary failure;
  // Continuous-time baselines; zero for the LGVI.
  std::size_t rhs_evaluations = 0;       ///< every right-hand-side call (difference-quotient Jacobians too)
  std::size_t output_rhs_evaluations = 0;  ///< of rhs_evaluations, those spent interpolating output times
  std::size_t jacobian_evaluations = 0;  ///< Jacobian evaluations requested by the solver
  std::size_t nonlinear_iterations = 0;  ///< implicit solvers' Newton iterations, where reported (CVODE)
  std::size_t rejected_steps = 0;        ///< error-test and convergence failures, where reported
  std::string failure_detail;            ///< SolverFailed / CoordinateSingularity / NonFiniteState: what and why, one line

  bool ok() const { return status == IntegrationStatus::Completed; }
  /// One line, e.g. "completed 1000 steps, 3012 Newton iterations (max 4), 0.01 s" or
  /// "rotation update failed at step 12 (t = 0.12): outside the rotation update's domain ...".
  std::string brief() const;
};

/// Integrates `steps` steps of size h from `state` (updated in place) with controls
/// u(t) sampled at the grid t_k = t0 + k h (each sample evaluated once). The observer is called
/// as observer(k, t_k, state, summary) for k = 0 (summary of a default, converged solve) and
/// after every step; returning false stops the run (status ObserverStopped).
/// Stops at the first failed rotation update, or at the first step whose result has a
/// non-finite entry (status NonFiniteState, failure_detail naming the part: the state's
/// non_finite_part(), found by argument-dependent lookup), leaving `state` at the last good step.
/// With `t_end` non-null (t0 + steps h < *t_end < t0 + (steps + 1) h), one more, shorter step of
/// h_last = *t_end - (t0 + steps h) follows, ending exactly at *t_end (observer index steps + 1).
/// The flow maps step in position-momentum form (R_k, Pi_k) -> (R_{k+1}, Pi_{k+1}) with h an
/// argument of each step, so a step of another size is the variational step of the discrete
/// Lagrangian L_d(R_k, F_k) with h_last in place of h (eqs. 7-9): the discrete Legendre
/// transforms of consecutive steps match whatever their sizes.
template <FlowMap Integrator, class ControlFn, class Observer>
Stats integrate(const Integrator& lgvi, typename Integrator::State& state, double t0, double h,
                std::size_t steps, ControlFn&& control, Observer&& observer,
                const double* t_end = nullptr) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  Stats stats;
  stats.step_size = h;
  using Summary = decltype(lgvi.step(state, h, control(t0), control(t0), state));
  Summary initial{};  // the summary of the initial state: converged, no iterations
  if constexpr (std::same_as<Summary, RotationUpdateSummary>) initial.status = RotationUpdateStatus::Converged;
  if (!observer(std::size_t{0}, t0, std::as_const(state), initial)) {
    stats.status = IntegrationStatus::ObserverStopped;
  }
  // Flow maps that sample the control inside the step (composition) take the control function.
  constexpr bool samples_control = requires { lgvi.step_at(state, t0, h, control, state); };
  typename Integrator::Control u_k = control(t0);
  const bool shorter_last = t_end != nullptr;
  const double t_last = shorter_last ? *t_end : 0.0;
  const std::size_t total_steps = steps + (shorter_last ? 1 : 0);
  for (std::size_t k = 0; k < total_steps && stats.ok(); ++k) {
    const bool last_shorter = k == steps;  // only with t_end
    const double t_k = t0 + static_cast<double>(k) * h;
    const double t1 = last_shorter ? t_last : t0 + static_cast<double>(k + 1) * h;
    const double h_k = last_shorter ? t1 - t_k : h;
    // Kept to restore on a non-finite result: the step writes `state` in place (a few dozen
    // doubles copied per step, small beside the rotation update's solve).
    const typename Integrator::State last_good = state;
    Summary s;
    typename Integrator::Control u_k1 = u_k;
    if constexpr (samples_control) {
      s = lgvi.step_at(state, t_k, h_k, control, state);
    } else {
      u_k1 = control(t1);
      s = lgvi.step(state, h_k, u_k, u_k1, state);
    }
    stats.newton_iterations += static_cast<std::size_t>(s.iterations);
    if (!s.converged()) {
      stats.failed_step = k;
      stats.failed_time = t_k;
      if constexpr (std::same_as<decltype(s), RotationUpdateSummary>) {
        stats.status = IntegrationStatus::RotationUpdateFailed;
        stats.failure = s;
      } else {
        stats.status = IntegrationStatus::StepFailed;
        stats.failure_detail = s.failure != nullptr ? s.failure : "the step's solve failed";
      }
      break;
    }
    if (const char* part = non_finite_part(std::as_const(state))) [[unlikely]] {
      state = last_good;
      stats.status = IntegrationStatus::NonFiniteState;
      stats.failed_step = k;
      stats.failed_time = t_k;
      stats.failure_detail = std::string(part) + " is not finite after the step (overflow: the state left the "
                                                  "range of double)";
      break;
    }
    ++stats.steps;
    if constexpr (requires { lgvi.potential_evaluations(); }) {
      stats.potential_evaluations += static_cast<std::size_t>(lgvi.potential_evaluations());
    } else {
      stats.potential_evaluations += Integrator::potential_evaluations_per_step;
    }
    stats.max_newton_iterations = std::max(stats.max_newton_iterations, s.iterations);
    stats.fallbacks += s.used_fallback ? 1 : 0;
    stats.max_rotation_residual = std::max(stats.max_rotation_residual, s.residual());
    if (!observer(k + 1, t1, std::as_const(state), s)) stats.status = IntegrationStatus::ObserverStopped;
    u_k = u_k1;
  }
  stats.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return stats;
}

/// Control function returning zero for every t (Control::Zero() for Eigen vectors, whose
/// default constructor leaves the entries uninitialized; a value-initialized struct otherwise).
template <class Control>
auto zero_control() {
  return [](double) {
    if constexpr (requires { Control::Zero(); }) {
      return Control(Control::Zero());
    } else {
      return Control{};
    }
  };
}
/// Observer that records nothing.
inline auto null_observer() {
  return [](std::size_t, double, const auto&, const RotationUpdateSummary&) { return true; };
}

}  // namespace lgvi
