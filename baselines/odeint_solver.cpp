// Boost.Odeint (1.74): classic RK4 (fixed step), Dormand-Prince 5(4) with dense output,
// Runge-Kutta-Fehlberg 7(8) with error control (odeint has no dense output for it: it steps
// freely and the output times are read off the Hermite interpolant of solver_detail.hpp),
// Bulirsch-Stoer with dense output. The adaptive ones step over the whole horizon whatever the
// output times, from an output-independent first step (Run::initial_step). State type
// std::vector<double> (allocated once by the steppers' resizers). A right-hand-side failure is
// thrown out of the system functor and turned into the status here; odeint's own exceptions
// (step size adjustment failing 500 times in a row) become SolverFailed.
#include <boost/numeric/odeint.hpp>

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "baselines/solver_detail.hpp"

namespace lgvi::baselines::detail {

namespace {

namespace odeint = boost::numeric::odeint;
using State = std::vector<double>;

struct RhsFailure {};

struct System {
  Run* run;
  void operator()(const State& y, State& dydt, double t) const {
    if (!run->rhs(t, y.data(), dydt.data())) throw RhsFailure{};
  }
};

/// odeint's default error checker, counting the steps it rejects (scaled error > 1, the test of
/// controlled_runge_kutta): odeint's dense-output driver retries inside do_step and reports no
/// count.
template <class Stepper>
class CountingErrorChecker
    : public odeint::default_error_checker<typename Stepper::value_type, typename Stepper::algebra_type,
                                           typename Stepper::operations_type> {
 public:
  using Base = odeint::default_error_checker<typename Stepper::value_type, typename Stepper::algebra_type,
                                             typename Stepper::operations_type>;
  CountingErrorChecker(double atol, double rtol, std::size_t* rejected) : Base(atol, rtol), rejected_(rejected) {}

  template <class StateIn, class Deriv, class Err, class Time>
  double error(typename Stepper::algebra_type& algebra, const StateIn& x_old, const Deriv& dxdt_old, Err& x_err,
               Time dt) const {
    const double e = Base::error(algebra, x_old, dxdt_old, x_err, dt);
    if (e > 1.0) ++*rejected_;
    return e;
  }

 private:
  std::size_t* rejected_;
};

/// Dense-output steppers (dopri5, Bulirsch-Stoer): step freely, interpolate the requested times,
/// watch the event, renormalize by re-initializing (see solver.hpp for the cost). `order`: for
/// the first step's estimate.
template <class Stepper>
void dense_loop(Run& run, State& y, Stepper& stepper, int order) {
  const System system{&run};
  const double t_end = run.times.back();
  stepper.initialize(y, run.times[0], run.initial_step(order, y.data()));
  State x(run.n);
  while (!run.done() && !run.stopped()) {
    if (run.stats.steps >= run.settings.max_steps) {
      run.stop_failed(stepper.current_time(),
                      "step budget of " + std::to_string(run.settings.max_steps) + " steps exhausted");
      return;
    }
    const auto [t0, t1] = stepper.do_step(system);
    ++run.stats.steps;
    if (t1 - t0 < run.min_step() && t1 < t_end) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "step size underflow (dt = %.3g, minimum %.3g)", t1 - t0, run.min_step());
      run.stop_failed(t0, buf);
      return;
    }
    const State& y1 = stepper.current_state();
    if (!run.check_finite(t1, y1.data())) return;
    double t_stop = t1;
    bool singular = false;
    if (run.singular_at(y1.data())) {
      // Locate the root on the stepper's own dense output (bisection).
      double lo = t0, hi = t1;
      for (int k = 0; k < 200 && hi - lo > 4e-16 * std::max(std::abs(lo), std::abs(hi)); ++k) {
        const double mid = 0.5 * (lo + hi);
        stepper.calc_state(mid, x);
        (run.ode.singularity_function(x.data()) > 0.0 ? lo : hi) = mid;
      }
      t_stop = hi;
      singular = true;
    }
    while (!run.done() && run.times[run.next_output()] <= std::min(t_stop, t_end)) {
      const std::size_t i = run.next_output();
      if (singular && run.times[i] >= t_stop) break;
      if (run.times[i] == t1) {
        x = y1;
      } else {
        stepper.calc_state(run.times[i], x);
      }
      if (!run.emit(i, x.data())) return;
    }
    if (singular) {
      stepper.calc_state(t_stop, x);
      run.stop_singular(t_stop, x.data());
      return;
    }
    if (run.ode.renormalizes() && !run.done()) {
      x = y1;
      run.ode.renormalize(x.data());
      stepper.initialize(x, t1, stepper.current_time_step());
    }
  }
}

/// Error-controlled stepper without dense output (rkf78): a try_step loop over the whole
/// horizon (only the last step is shortened, to end on it), the output times read off the
/// Hermite interpolant of each accepted step and of its midpoint (HermiteOutput).
template <class Stepper>
void controlled_loop(Run& run, State& y, Stepper& stepper, int order) {
  const System system{&run};
  const double t_end = run.times.back();
  double t = run.times[0];
  double dt_free = run.initial_step(order, y.data());
  // The Hermite output's midpoint: a step of the same method on a stepper of its own.
  typename Stepper::stepper_type side;
  State side_in(run.n), side_dxdt(run.n), side_out(run.n);
  const HermiteOutput::MidpointStep midpoint = [&](double t0, const double* y0, const double* f0, double hm,
                                                   double* y_out) {
    side_in.assign(y0, y0 + run.n);
    side_dxdt.assign(f0, f0 + run.n);
    try {
      side.do_step(system, side_in, side_dxdt, t0, side_out, hm);
    } catch (const RhsFailure&) {
      return false;
    }
    std::copy(side_out.begin(), side_out.end(), y_out);
    return true;
  };
  HermiteOutput output(run, run.settings.hermite_midpoint ? midpoint : HermiteOutput::MidpointStep{});
  output.start(t, y.data());
  State y_old(run.n);
  while (!run.done() && !run.stopped()) {
    if (run.stats.steps >= run.settings.max_steps) {
      run.stop_failed(t, "step budget of " + std::to_string(run.settings.max_steps) + " steps exhausted");
      return;
    }
    const bool clipped = t + dt_free >= t_end;
    double dt = clipped ? t_end - t : dt_free;
    const double t_old = t;
    y_old = y;
    std::size_t fails = 0;
    while (stepper.try_step(system, y, t, dt) == odeint::fail) {
      ++run.stats.rejected_steps;
      if (++fails >= 500 || dt < run.min_step()) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "step size underflow (dt = %.3g, minimum %.3g, %zu rejected attempts)", dt,
                      run.min_step(), fails);
        run.stop_failed(t, buf);
        return;
      }
    }
    ++run.stats.steps;
    if (clipped && t_end - t < 1e-14 * std::max(1.0, std::abs(t_end))) t = t_end;
    // The step the controller suggests; the last, shortened step's suggestion is kept only if
    // larger.
    if (!clipped || dt > dt_free) dt_free = dt;
    if (!run.check_finite(t, y.data())) return;
    if (run.singular_at(y.data())) {
      run.stop_at_event(t_old, y_old.data(), t, y.data());
      return;
    }
    if (run.ode.renormalizes()) run.ode.renormalize(y.data());
    if (!output.step(t, y.data())) return;
  }
}

void rk4(Run& run, State& y) {
  odeint::runge_kutta4<State> stepper;
  const System system{&run};
  fixed_step_loop(run, y, [&](double t, double h, State& state) {
    stepper.do_step(system, state, t, h);
    return true;
  });
}

void dopri5(Run& run, State& y) {
  // What make_dense_output(atol, rtol, dopri5) builds, with the error checker counting rejections.
  using Dopri = odeint::runge_kutta_dopri5<State>;
  using Controlled = odeint::controlled_runge_kutta<Dopri, CountingErrorChecker<Dopri>>;
  odeint::dense_output_runge_kutta<Controlled> stepper(
      Controlled(CountingErrorChecker<Dopri>(*run.settings.atol, *run.settings.rtol, &run.stats.rejected_steps)));
  dense_loop(run, y, stepper, 5);
}

void rkf78(Run& run, State& y) {
  auto stepper = odeint::make_controlled(*run.settings.atol, *run.settings.rtol, odeint::runge_kutta_fehlberg78<State>());
  controlled_loop(run, y, stepper, 7);
}

void bulirsch_stoer(Run& run, State& y) {
  // Error factors as odeint's defaults (|y| and dt |y'|); the interpolation error is
  // controlled too, since the requested times are interpolated. Its rejected steps are not
  // reported (odeint retries inside do_step). First step estimated for order 8 (odeint starts
  // the extrapolation at k = 4 columns, order 2k).
  odeint::bulirsch_stoer_dense_out<State> stepper(*run.settings.atol, *run.settings.rtol, 1.0, 1.0, 0.0, true);
  dense_loop(run, y, stepper, 8);
}

/// One of the loops above, its odeint failures turned into the run's stop.
Stats run_guarded(Run& run, std::vector<double>& y, void (*loop)(Run&, State&)) {
  if (run.done()) return run.stats;
  try {
    loop(run, y);
  } catch (const RhsFailure&) {
    run.stop_on_rhs_failure();
  } catch (const odeint::step_adjustment_error& e) {
    run.stop_failed(run.times[run.next_output() - 1], std::string("odeint: ") + e.what());
  } catch (const odeint::no_progress_error& e) {
    run.stop_failed(run.times[run.next_output() - 1], std::string("odeint: ") + e.what());
  }
  return run.stats;
}

}  // namespace

Stats run_odeint_rk4(Run& run, std::vector<double>& y) { return run_guarded(run, y, rk4); }
Stats run_odeint_dopri5(Run& run, std::vector<double>& y) { return run_guarded(run, y, dopri5); }
Stats run_odeint_rkf78(Run& run, std::vector<double>& y) { return run_guarded(run, y, rkf78); }
Stats run_odeint_bs(Run& run, std::vector<double>& y) { return run_guarded(run, y, bulirsch_stoer); }

}  // namespace lgvi::baselines::detail
