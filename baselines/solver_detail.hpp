// Shared machinery of the solver adapters (not part of the public interface): the run context
// that counts evaluations, records why a right-hand side failed and delivers samples; the
// fixed-step loop; event location on a step's Hermite interpolant.
#pragma once

#include <cmath>
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "baselines/solver.hpp"

namespace lgvi::baselines::detail {

/// One integration: the model, the resolved settings, the output times, the observer, and the
/// Stats being filled. Solver callbacks go through rhs()/jacobian() so that every evaluation is
/// counted the same way for every library.
class Run {
 public:
  Run(const std::string& method, const Ode& ode, std::span<const double> times, const SolverSettings& settings,
      const SampleObserver& observer)
      : method(method), ode(ode), times(times), settings(settings),
        n(static_cast<std::size_t>(ode.dimension())), observer_(observer) {}

  const std::string& method;
  const Ode& ode;
  std::span<const double> times;
  const SolverSettings& settings;
  Stats stats;
  std::size_t n;

  /// f(t, y). False when the model is singular there or f is not finite; the first such
  /// failure is remembered (time, state) for the status.
  bool rhs(double t, const double* y, double* f);
  /// df/dy row-major; false as rhs().
  bool jacobian(double t, const double* y, double* J);
  /// df/dt by central differences in t (zero for autonomous models); false as rhs().
  bool time_derivative(double t, const double* y, double* dfdt);

  /// Delivers the sample of times[index]; false (and status ObserverStopped) if the observer
  /// stops the run.
  bool emit(std::size_t index, const double* y);
  /// Next index to deliver.
  std::size_t next_output() const { return next_; }
  bool done() const { return next_ >= times.size(); }

  /// Stops the run: the model's singular set was reached at t with state y.
  void stop_singular(double t, const double* y);
  /// Stops the run: the solver failed at t.
  void stop_failed(double t, const std::string& detail);
  /// Turns the remembered right-hand-side failure into the status (singular or non-finite).
  /// Returns false if there was none.
  bool stop_on_rhs_failure();
  bool stopped() const { return !stats.ok(); }

  /// True if the state has a non-finite entry (then stops the run with SolverFailed at t).
  bool check_finite(double t, const double* y);
  /// True when the model's event function says y is singular.
  bool singular_at(const double* y) const { return ode.has_singular_set() && !(ode.singularity_function(y) > 0.0); }

  /// After an accepted step (t0, y0) -> (t1, y1) whose end is singular: finds the event's root on
  /// the cubic Hermite interpolant (derivatives f(y0), f(y1) evaluated here; linear in the event
  /// function if f(y1) cannot be evaluated) and stops the run there.
  void stop_at_event(double t0, const double* y0, double t1, const double* y1);

  /// Initial step guess for the adaptive methods that need one.
  double initial_step() const;
  /// Smallest step an adaptive method may take before the run is reported as failed (step size
  /// underflow): 16 eps times the larger of |t_end| and the horizon. Below it the steps no longer
  /// resolve time; GSL would otherwise go on while t changes by an ulp, which near t = 0 is
  /// ~1e-300.
  double min_step() const;

 private:
  const SampleObserver& observer_;
  std::size_t next_ = 0;
  // The first right-hand-side failure.
  enum class Failure { None, Singular, NonFinite } failure_ = Failure::None;
  double failure_time_ = 0.0;
  std::vector<double> failure_state_;
};

/// Fixed-step driver for odeint-rk4 and gsl-rk4imp. step(t, h, y) advances y in place and
/// returns false on failure (after recording it in run, or leaving it to the right-hand-side
/// failure). Checks the event function before the first step and after each step, renormalizes
/// after each step when the model asks for it, and delivers every requested time.
template <class Step>
void fixed_step_loop(Run& run, std::vector<double>& y, Step&& step) {
  const double h = *run.settings.h;
  double t = run.times[0];
  std::vector<double> y_old(run.n);
  while (!run.done() && !run.stopped()) {
    const std::size_t i = run.next_output();
    const double t_target = run.times[i];
    const double span = t_target - t;
    const auto m = static_cast<std::size_t>(std::max(1.0, std::round(span / h)));
    const double hs = span / static_cast<double>(m);
    for (std::size_t s = 0; s < m && !run.stopped(); ++s) {
      if (run.stats.steps >= run.settings.max_steps) {
        run.stop_failed(t, "step budget of " + std::to_string(run.settings.max_steps) + " steps exhausted");
        return;
      }
      y_old = y;
      const double t_old = t;
      if (!step(t, hs, y)) {
        if (!run.stop_on_rhs_failure() && !run.stopped()) run.stop_failed(t_old, run.method + ": step failed");
        return;
      }
      t = (s + 1 == m) ? t_target : t_old + hs;
      ++run.stats.steps;
      if (!run.check_finite(t, y.data())) return;
      if (run.singular_at(y.data())) {
        run.stop_at_event(t_old, y_old.data(), t, y.data());
        return;
      }
      if (run.ode.renormalizes()) run.ode.renormalize(y.data());
    }
    if (!run.stopped()) run.emit(i, y.data());
  }
}

Stats run_cvode(Run& run, std::vector<double>& y, bool bdf);
Stats run_odeint(Run& run, std::vector<double>& y);
Stats run_gsl(Run& run, std::vector<double>& y);

}  // namespace lgvi::baselines::detail
