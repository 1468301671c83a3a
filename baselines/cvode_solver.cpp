// SUNDIALS CVODE (v6 API): Adams or BDF, Newton iteration with a dense direct linear solver and
// the model's Jacobian (or CVODE's difference quotient), scalar tolerances, the Euler model's
// singular set as a root function, CVODE's projection interface for the renormalized quaternion
// and for cvode-bdf-projected's manifold projection (BDF only). Every return flag is checked;
// CVODE's error handler is redirected into the status.
//
// cvode-bdf-projected: the same BDF settings as cvode-bdf, and CVodeSetProjFn with cv_project_
// manifold: after every step (CVODE's default projection frequency 1) the model projects the
// state onto its constraints and invariants (Ode::project; baselines/projection.hpp), the values
// to keep taken from the initial state once (Ode::projection_target). CVODE adds the correction
// to its Nordsieck history and uses the projected error estimate in its error test (CVODE user
// guide, "Projection"; projection is BDF-only in CVODE). A projection that does not converge
// returns 1, a recoverable failure: CVODE retries the step with a smaller h (at most 10 times,
// its default, then CV_PROJ_FAIL). The output times' states, read off CVODE's interpolant between
// two projected steps, are off the manifold by the interpolation error: they are projected too
// (without an error vector), so that every sample keeps the invariants to round-off.
//
// Output: CVODE steps one step at a time (CV_ONE_STEP) towards the end of the horizon (its stop
// time; nothing else limits a step), and the output times each step passed are read off its own
// interpolating polynomial (CVodeGetDky, the Nordsieck history: the method's order). So the steps
// do not depend on the output times. (CV_NORMAL, one call per output time, would step past each
// output time and interpolate too, but CVODE estimates its first step from the first call's
// output interval: the whole run would depend on the output grid.)
#include <cvodes/cvodes_proj.h>

#include <string>
#include <vector>

#include "baselines/cvode_detail.hpp"
#include "baselines/solver_detail.hpp"

namespace lgvi::baselines::detail {

namespace {

struct CvodeUser {
  Run* run;
  std::vector<double> J;  ///< row-major Jacobian buffer
  ProjectionTarget target = {};  ///< cvode-bdf-projected: the values the projection keeps
};

int cv_rhs(realtype t, N_Vector y, N_Vector ydot, void* user) {
  auto* u = static_cast<CvodeUser*>(user);
  // Unrecoverable (-1): on the singular set or with a non-finite value nothing sensible can be
  // retried; the run reports the remembered failure.
  return u->run->rhs(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot)) ? 0 : -1;
}

int cv_jac(realtype t, N_Vector y, N_Vector /*fy*/, SUNMatrix Jm, void* user, N_Vector, N_Vector, N_Vector) {
  auto* u = static_cast<CvodeUser*>(user);
  const std::size_t n = u->run->n;
  if (!u->run->jacobian(t, N_VGetArrayPointer(y), u->J.data())) return -1;
  for (std::size_t j = 0; j < n; ++j) {
    realtype* col = SUNDenseMatrix_Column(Jm, static_cast<sunindextype>(j));
    for (std::size_t i = 0; i < n; ++i) col[i] = u->J[i * n + j];
  }
  return 0;
}

int cv_root(realtype /*t*/, N_Vector y, realtype* g, void* user) {
  auto* u = static_cast<CvodeUser*>(user);
  g[0] = u->run->ode.singularity_function(N_VGetArrayPointer(y));
  return 0;
}

/// Renormalization: ycur <- ycur / |q| per quaternion, corr = projected - unprojected, the error
/// estimate projected on the tangent space (CVODE then uses it in its error test).
int cv_project(realtype /*t*/, N_Vector ycur, N_Vector corr, realtype /*eps*/, N_Vector err, void* user) {
  auto* u = static_cast<CvodeUser*>(user);
  const Ode& ode = u->run->ode;
  const std::size_t n = u->run->n;
  double* y = N_VGetArrayPointer(ycur);
  double* c = N_VGetArrayPointer(corr);
  for (std::size_t i = 0; i < n; ++i) c[i] = y[i];
  ode.renormalize(y);
  for (std::size_t i = 0; i < n; ++i) c[i] = y[i] - c[i];
  if (err != nullptr) ode.project_error(y, N_VGetArrayPointer(err));
  return 0;
}

/// cvode-bdf-projected: ycur onto the model's manifold (Ode::project), corr = projected -
/// unprojected, err onto the tangent space. Our own stopping rule (projection.hpp), tighter than
/// CVODE's epsProj (0.1 in the WRMS norm of the correction's error). Recoverable failure (1) when
/// the Newton iterations do not converge.
int cv_project_manifold(realtype /*t*/, N_Vector ycur, N_Vector corr, realtype /*eps*/, N_Vector err, void* user) {
  auto* u = static_cast<CvodeUser*>(user);
  const std::size_t n = u->run->n;
  double* y = N_VGetArrayPointer(ycur);
  double* c = N_VGetArrayPointer(corr);
  for (std::size_t i = 0; i < n; ++i) c[i] = y[i];
  const int iterations = u->run->ode.project(u->target, y, err != nullptr ? N_VGetArrayPointer(err) : nullptr);
  if (iterations < 0) {
    for (std::size_t i = 0; i < n; ++i) y[i] = c[i];  // CVODE retries from its own prediction
    return 1;
  }
  for (std::size_t i = 0; i < n; ++i) c[i] = y[i] - c[i];
  return 0;
}

enum class Kind { Adams, Bdf, BdfProjected };

}  // namespace

namespace {

Stats run_cvode(Run& run, std::vector<double>& y, Kind kind) {
  const bool bdf = kind != Kind::Adams;
  const bool projected = kind == Kind::BdfProjected;
  CvodeUser user{&run, std::vector<double>(run.n * run.n)};
  if (projected) user.target = run.ode.projection_target(y.data());
  CvodeObjects cv;
  const auto n = static_cast<sunindextype>(run.n);
  const double t0 = run.times[0];
  const double t_end = run.times.back();
  if (run.done()) return run.stats;

  // A setup flag is a programming or memory error, reported as such with the call's name.
  auto setup = [&](int flag, const char* call) {
    if (flag < 0 && !run.stopped()) run.stop_failed(t0, cv.setup_failure(flag, call));
    return flag >= 0;
  };
  if (const char* failed = cv.allocate(n, bdf, 0, "CVODE allocation failed", "SUNLinSol_Dense failed")) {
    run.stop_failed(t0, failed);
    return run.stats;
  }
  std::copy(y.begin(), y.end(), N_VGetArrayPointer(cv.y));
  bool ok = cv.setup(cv_rhs, run.settings.jacobian == JacobianSource::Analytic ? cv_jac : nullptr, &user, t0, t_end,
                     *run.settings.rtol, *run.settings.atol, setup);
  if (ok && run.ode.has_singular_set()) {
    int direction = -1;  // g decreases through 0 when |cos theta| falls to the threshold
    ok = setup(CVodeRootInit(cv.mem, 1, cv_root), "CVodeRootInit") &&
         setup(CVodeSetRootDirection(cv.mem, &direction), "CVodeSetRootDirection");
  }
  if (ok && run.ode.renormalizes()) ok = setup(CVodeSetProjFn(cv.mem, cv_project), "CVodeSetProjFn");
  // Nothing to project (Euler angles of a system without invariants here): plain cvode-bdf.
  const bool projecting = projected && user.target.count > 0;
  if (ok && projecting) ok = setup(CVodeSetProjFn(cv.mem, cv_project_manifold), "CVodeSetProjFn");
  if (!ok) return run.stats;

  auto collect = [&] {
    cv.collect(run.stats);
    // With CVODE's difference quotient the Jacobian evaluations are CVODE's count (its RHS calls
    // are already in rhs_evaluations, which counts every call).
    long nje = 0;
    if (run.settings.jacobian == JacobianSource::DifferenceQuotient && CVodeGetNumJacEvals(cv.mem, &nje) >= 0) {
      run.stats.jacobian_evaluations = static_cast<std::size_t>(nje);
    }
  };

  N_Vector dky = N_VClone(cv.y);  // interpolated outputs
  if (dky == nullptr) {
    run.stop_failed(t0, "N_VClone failed");
    return run.stats;
  }
  while (!run.done() && !run.stopped()) {
    collect();
    if (run.stats.steps >= run.settings.max_steps) {
      realtype t_reached = t0;
      CVodeGetCurrentTime(cv.mem, &t_reached);
      run.stop_failed(t_reached, "step budget of " + std::to_string(run.settings.max_steps) + " steps exhausted");
      break;
    }
    realtype t = 0.0;
    const int flag = CVode(cv.mem, t_end, cv.y, &t, CV_ONE_STEP);
    collect();
    if (flag < 0) {
      if (!run.stop_on_rhs_failure()) {
        realtype t_reached = t;
        CVodeGetCurrentTime(cv.mem, &t_reached);
        run.stop_failed(t_reached, cvode_flag_name(flag) + (cv.last_message.empty() ? "" : ": " + cv.last_message));
      }
      break;
    }
    // CV_SUCCESS, CV_TSTOP_RETURN (t = t_end) or CV_ROOT_RETURN (t the root, y(t) interpolated):
    // deliver the output times the step passed (before a root only).
    const bool root = flag == CV_ROOT_RETURN;
    while (!run.done() && (root ? run.times[run.next_output()] < t : run.times[run.next_output()] <= t)) {
      const std::size_t i = run.next_output();
      if (run.times[i] == t) {
        if (!run.emit(i, N_VGetArrayPointer(cv.y))) break;
        continue;
      }
      const int dky_flag = CVodeGetDky(cv.mem, run.times[i], 0, dky);
      if (dky_flag < 0) {
        run.stop_failed(run.times[i], "CVodeGetDky returned " + cvode_flag_name(dky_flag) +
                                          (cv.last_message.empty() ? "" : " (" + cv.last_message + ")"));
        break;
      }
      // Unconverged (never seen): the interpolated state as it is.
      if (projecting) run.ode.project(user.target, N_VGetArrayPointer(dky), nullptr);
      if (!run.emit(i, N_VGetArrayPointer(dky))) break;
    }
    if (root && !run.stopped()) run.stop_singular(t, N_VGetArrayPointer(cv.y));
  }
  N_VDestroy(dky);
  collect();
  std::copy(N_VGetArrayPointer(cv.y), N_VGetArrayPointer(cv.y) + run.n, y.begin());
  return run.stats;
}

}  // namespace

Stats run_cvode_adams(Run& run, std::vector<double>& y) { return run_cvode(run, y, Kind::Adams); }
Stats run_cvode_bdf(Run& run, std::vector<double>& y) { return run_cvode(run, y, Kind::Bdf); }
Stats run_cvode_bdf_projected(Run& run, std::vector<double>& y) { return run_cvode(run, y, Kind::BdfProjected); }

}  // namespace lgvi::baselines::detail
