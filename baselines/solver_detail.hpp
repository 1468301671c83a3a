// Shared machinery of the solver adapters (not part of the public interface): the run context
// that counts evaluations, records why a right-hand side failed and delivers samples; the
// output-independent starting step; the fixed-step loop; the Hermite dense output of the methods
// that have none; event location on a step's Hermite interpolant.
#pragma once

#include <cmath>
#include <cstddef>
#include <functional>
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
  /// While set (by HermiteOutput), rhs() counts its calls in output_rhs_evaluations too, and a
  /// failure (singular set, non-finite) is not remembered as the run's: the interpolant does
  /// without that evaluation.
  void set_output_evaluations(bool on) { output_mode_ = on; }

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
  /// the step's interpolant, delivers the output times before the root from it, and stops the
  /// run there. The interpolant: cubic Hermite with f(y0), f(y1) (evaluated here, 2 RHS); the
  /// quadratic through y0, f(y0), y1 when f(y1) cannot be evaluated (the Euler model's rates are
  /// refused inside the band, where y1 is); linear when neither can.
  void stop_at_event(double t0, const double* y0, double t1, const double* y1);

  /// Initial step of the adaptive methods that need one (odeint, GSL), independent of the output
  /// times (so that the output grid cannot change the run): settings.initial_step if set, else
  /// the starting-step estimate of Hairer, Norsett and Wanner (Solving ODEs I, sec. II.4) for a
  /// method of order `order`, in the norm of the error control (scale atol + rtol |y0_i|): from
  /// the sizes of y0, f(y0) and of the change of f over an explicit Euler step (2 RHS, counted),
  /// h = min(100 h0, (0.01 / max(|f|, |f'|))^(1/(order+1))), h0 = 0.01 |y0| / |f|, and at most
  /// the horizon.
  double initial_step(int order, const double* y0);
  /// Smallest step an adaptive method may take before the run is reported as failed (step size
  /// underflow): 16 eps times the larger of |t_end| and the horizon. Below it the steps no longer
  /// resolve time; GSL would otherwise go on while t changes by an ulp, which near t = 0 is
  /// ~1e-300.
  double min_step() const;

 private:
  const SampleObserver& observer_;
  std::size_t next_ = 0;
  bool output_mode_ = false;
  // The first right-hand-side failure.
  enum class Failure { None, Singular, NonFinite } failure_ = Failure::None;
  double failure_time_ = 0.0;
  std::vector<double> failure_state_;
};

/// Dense output for the adaptive methods that have none (odeint-rkf78, gsl-rk8pd, gsl-msbdf):
/// they step freely over the whole horizon (no step is shortened to land on an output time), and
/// the output times inside an accepted step [t0, t1] (h = t1 - t0, s = (t - t0) / h) are read off
/// a Hermite interpolant of the step: the polynomial in s matching y, y' = f and y'' at the nodes
/// (Newton form on the confluent nodes, divided differences).
///  - With a midpoint step (rkf78, rk8pd: one step of the same method from t0 to t0 + h/2, kept
///    apart from the run): nodes s = 0, 1/2, 1, degree 8. Error y^(9)(xi) / 9! (s (s - 1/2)
///    (s - 1))^3 h^9 <= 3.1e-10 h^9 max|y^(9)|, order 9 locally like the steps' (rk8pd's local
///    error is O(h^9), rkf78's O(h^8)), plus the errors of y1 and y(t0 + h/2), each a local error
///    of the method. Without the midpoint (SolverSettings::hermite_midpoint) a quintic (nodes 0,
///    1) is off by up to h^6 max|y^(6)| / 46080, too much for the long steps of these methods at
///    loose tolerances: on the free-body scene at rtol 1e-6 (h w ~ 1.8 per step) its samples lie
///    6.8e-5 from the steps, the midpoint interpolant's 1.2e-7 (tests/baselines/
///    test_dense_output.cpp).
///  - Without (msbdf: a multistep method cannot step aside without disturbing its history; its
///    steps are short, order <= 5): nodes 0, 1, degree 5, error <= h^6 max|y^(6)| / 46080, order
///    6 locally.
/// y'' = (df/dy) f + df/dt is the derivative of f along the solution, by a central difference:
/// g = (f(t + e, y + e f) - f(t - e, y - e f)) / (2 e), e = cbrt(eps) / w with w the fastest
/// relative rate max_i |f_i| / (1 + |y_i|) (at most cbrt(eps) times the horizon): relative error
/// ~eps^(2/3), entering the interpolant multiplied by at most 0.018 h^2 (the sum of the maxima of
/// the g-basis functions on nodes 0, 1/2, 1; 0.017 on nodes 0, 1).
/// A node whose derivatives cannot be evaluated (the Euler model near its singular set) enters
/// with fewer conditions (lower degree). Every number is a function of the accepted steps alone,
/// so two output grids get the same sample at a time they share, bit for bit.
/// Cost: only steps with an output time strictly inside are interpolated. Per such step: the
/// midpoint step (12 RHS: rk8pd's and rkf78's stages after the first) and f, g there (3), and f,
/// g at each end (3; the end of a step is the start of the next, evaluated once): ~18 RHS per
/// interpolated step, all counted in rhs_evaluations and output_rhs_evaluations.
class HermiteOutput {
 public:
  /// One step of the method from (t0, y0) with f(t0, y0) = f0 over `h`, into y_out, without
  /// touching the run's stepper state. False if it failed (the interpolant then does without).
  using MidpointStep = std::function<bool(double t0, const double* y0, const double* f0, double h, double* y_out)>;

  explicit HermiteOutput(Run& run, MidpointStep midpoint = {});
  /// The state the first step starts from.
  void start(double t, const double* y);
  /// After an accepted step from the current start to (t1, y1), y1 being the state the next step
  /// starts from (renormalized where the model asks): delivers every output time in
  /// (t0, t1]. False if the observer stopped the run.
  bool step(double t1, const double* y1);

 private:
  struct Point {
    double t = 0.0;
    std::vector<double> y, f, g;
    bool evaluated = false;  ///< derivatives attempted
    int level = 0;           ///< derivatives valid: 0 none, 1 f, 2 f and g
  };
  /// Evaluates f and g at p (3 RHS, output evaluations).
  void evaluate(Point& p);
  /// The Newton coefficients of the step's interpolant (nodes_, coefficients_).
  void prepare();
  void interpolate(double t, double* y) const;

  Run& run_;
  MidpointStep midpoint_;
  Point a_, b_, m_;  ///< start, end and midpoint of the current step
  std::vector<double> plus_, minus_, x_;
  std::vector<double> nodes_;         ///< the confluent nodes in s, at most 9
  std::vector<double> coefficients_;  ///< Newton coefficients, nodes_.size() per component
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

// The adapters, one per solver (SolverInfo::adapter; solver_list() names each once).
Stats run_cvode_adams(Run& run, std::vector<double>& y);
Stats run_cvode_bdf(Run& run, std::vector<double>& y);
Stats run_cvode_bdf_projected(Run& run, std::vector<double>& y);
Stats run_odeint_rk4(Run& run, std::vector<double>& y);
Stats run_odeint_dopri5(Run& run, std::vector<double>& y);
Stats run_odeint_rkf78(Run& run, std::vector<double>& y);
Stats run_odeint_bs(Run& run, std::vector<double>& y);
Stats run_gsl_rk8pd(Run& run, std::vector<double>& y);
Stats run_gsl_rk4imp(Run& run, std::vector<double>& y);
Stats run_gsl_msbdf(Run& run, std::vector<double>& y);
Stats run_arkode_erk(Run& run, std::vector<double>& y);
Stats run_arkode_dirk(Run& run, std::vector<double>& y);

}  // namespace lgvi::baselines::detail
