// GSL odeiv2 (2.7): rk8pd (explicit, error control), rk4imp (implicit Gauss-Legendre, fixed
// step), msbdf (variable-order BDF). All three are driven through a gsl_odeiv2_driver, which
// msbdf and rk4imp require (they read the error levels of its control object); the stepping
// itself is a loop of gsl_odeiv2_evolve_apply calls so that every accepted step can be checked
// (event, finiteness) and, where allowed, renormalized. The adaptive methods step freely towards
// the end of the horizon (only the last step is shortened, to end on it), from an
// output-independent first step (Run::initial_step); GSL has no dense output, so the output times
// are read off the Hermite interpolant of each accepted step (HermiteOutput, solver_detail.hpp).
//
// GSL facts that shape this adapter (GSL 2.7 sources, ode-initval2/):
//  - evolve_apply lands exactly on its target time t1 (here the end of the horizon) and
//    recomputes dydt_in from y at every call, so a one-step method may have y modified between
//    calls (rk8pd: free renormalization); msbdf keeps a Nordsieck history and may not (rejected
//    in resolve_settings).
//  - evolve's `count` counts attempts (it is incremented before the error test), `failed_steps`
//    the rejected ones: the accepted steps are counted here, one per successful evolve_apply.
//  - rk4imp always takes one step of h and two of h/2 (its error estimate by step doubling)
//    and returns the two half steps: a "fixed step h" is two Gauss steps of h/2 at about three
//    times the cost of one. Its modified Newton iteration stops when the estimated error is
//    below the control's error level (we use newton_tolerance (1 + |y_i|)), within 7
//    iterations, and fails on any non-contracting iteration. Fixed steps go through
//    evolve_apply_fixed_step with no control object, i.e. without step rejection.
//  - A user function returning GSL_EBADFUNC makes evolve return at once (used for the singular
//    set and non-finite values); any other failure makes evolve halve the step and retry.
//  - GSL's default error handler aborts the process: it is switched off for the run (and the
//    previous handler restored afterwards).
#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "baselines/solver_detail.hpp"

namespace lgvi::baselines::detail {

namespace {

int gsl_rhs(double t, const double y[], double dydt[], void* params) {
  return static_cast<Run*>(params)->rhs(t, y, dydt) ? GSL_SUCCESS : GSL_EBADFUNC;
}

int gsl_jac(double t, const double y[], double* dfdy, double dfdt[], void* params) {
  Run* run = static_cast<Run*>(params);
  if (!run->jacobian(t, y, dfdy)) return GSL_EBADFUNC;
  return run->time_derivative(t, y, dfdt) ? GSL_SUCCESS : GSL_EBADFUNC;
}

struct HandlerGuard {
  gsl_error_handler_t* previous = gsl_set_error_handler_off();
  ~HandlerGuard() { gsl_set_error_handler(previous); }
};

struct DriverDeleter {
  void operator()(gsl_odeiv2_driver* d) const { gsl_odeiv2_driver_free(d); }
};

std::string gsl_status(int status) {
  return std::string(gsl_strerror(status)) + " (GSL status " + std::to_string(status) + ")";
}

}  // namespace

namespace {

/// The GSL stepper `type` on the run: fixed step (the implicit rk4imp, its Newton iteration to
/// newton_tolerance) or adaptive, the first step estimated for `initial_order` (8 for rk8pd, 1
/// for msbdf, which starts at order 1); `one_step` (rk8pd) keeps no state between steps, so the
/// Hermite output's midpoint may take a step of it.
Stats run_gsl(Run& run, std::vector<double>& y, const gsl_odeiv2_step_type* type, bool fixed, int initial_order,
              bool one_step) {
  if (run.done()) return run.stats;
  const HandlerGuard guard;
  gsl_odeiv2_system sys{gsl_rhs, gsl_jac, run.n, &run};
  const double tol_abs = fixed ? run.settings.newton_tolerance : *run.settings.atol;
  const double tol_rel = fixed ? run.settings.newton_tolerance : *run.settings.rtol;
  double h = fixed ? *run.settings.h : run.initial_step(initial_order, y.data());
  std::unique_ptr<gsl_odeiv2_driver, DriverDeleter> d(gsl_odeiv2_driver_alloc_y_new(&sys, type, h, tol_abs, tol_rel));
  if (!d) {
    run.stop_failed(run.times[0], "gsl_odeiv2_driver_alloc_y_new failed");
    return run.stats;
  }

  if (fixed) {
    fixed_step_loop(run, y, [&](double t, double hs, std::vector<double>& state) {
      const int status = gsl_odeiv2_evolve_apply_fixed_step(d->e, nullptr, d->s, &sys, &t, hs, state.data());
      if (status == GSL_SUCCESS) return true;
      if (status != GSL_EBADFUNC) {
        run.stop_failed(t, "step failed: " + gsl_status(status) +
                               (status == GSL_FAILURE ? ", the modified Newton iteration did not converge" : ""));
      }
      return false;
    });
    return run.stats;
  }

  const double t_end = run.times.back();
  double t = run.times[0];
  // The Hermite output's midpoint (rk8pd only): a step of rk8pd on GSL's stepper, which keeps no
  // state between steps (evolve recomputes everything from y and t at its next call); msbdf's
  // Nordsieck history must not be disturbed.
  std::vector<double> yerr(run.n);
  HermiteOutput::MidpointStep midpoint;
  if (one_step && run.settings.hermite_midpoint) {
    midpoint = [&](double t0, const double* y0, const double* f0, double hm, double* y_out) {
      std::copy(y0, y0 + run.n, y_out);
      return gsl_odeiv2_step_apply(d->s, t0, hm, y_out, yerr.data(), f0, nullptr, &sys) == GSL_SUCCESS;
    };
  }
  HermiteOutput output(run, midpoint);
  output.start(t, y.data());
  std::vector<double> y_old(run.n);
  while (!run.done() && !run.stopped()) {
    if (run.stats.steps >= run.settings.max_steps) {
      run.stop_failed(t, "step budget of " + std::to_string(run.settings.max_steps) + " steps exhausted");
      return run.stats;
    }
    const double t_old = t;
    y_old = y;
    const int status = gsl_odeiv2_evolve_apply(d->e, d->c, d->s, &sys, &t, t_end, &h, y.data());
    run.stats.rejected_steps = d->e->failed_steps;
    if (status == GSL_EBADFUNC) {
      if (!run.stop_on_rhs_failure()) run.stop_failed(t_old, "user function failed");
      return run.stats;
    }
    if (status != GSL_SUCCESS) {
      run.stop_failed(t_old, "evolve failed: " + gsl_status(status) +
                                 (status == GSL_FAILURE ? ", the step size fell below the resolution of t" : ""));
      return run.stats;
    }
    ++run.stats.steps;
    if (h < run.min_step() && t < t_end) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "step size underflow (h = %.3g, minimum %.3g)", h, run.min_step());
      run.stop_failed(t, buf);
      return run.stats;
    }
    if (!run.check_finite(t, y.data())) return run.stats;
    if (run.singular_at(y.data())) {
      run.stop_at_event(t_old, y_old.data(), t, y.data());
      return run.stats;
    }
    if (run.ode.renormalizes()) run.ode.renormalize(y.data());
    if (!output.step(t, y.data())) return run.stats;
  }
  return run.stats;
}

}  // namespace

Stats run_gsl_rk8pd(Run& run, std::vector<double>& y) { return run_gsl(run, y, gsl_odeiv2_step_rk8pd, false, 8, true); }
Stats run_gsl_rk4imp(Run& run, std::vector<double>& y) { return run_gsl(run, y, gsl_odeiv2_step_rk4imp, true, 1, false); }
Stats run_gsl_msbdf(Run& run, std::vector<double>& y) { return run_gsl(run, y, gsl_odeiv2_step_msbdf, false, 1, false); }

}  // namespace lgvi::baselines::detail
