// SUNDIALS ARKODE (ARKODE 5.4, the SUNDIALS 6 API): two adaptive Runge-Kutta baselines.
//
//   arkode-erk    ERKStep, fully explicit, with Verner's 8-stage pair of order 6 and embedded
//                 order 5 (ARKODE_VERNER_8_5_6; J. H. Verner, "Explicit Runge-Kutta methods with
//                 estimates of the local truncation error", SIAM J. Numer. Anal. 15 (1978)
//                 772-790). Order 6 puts it between odeint-dopri5 (5) and odeint-rkf78 and
//                 gsl-rk8pd (7-8) instead of duplicating Fehlberg 7(8) (ARKODE_FEHLBERG_13_7_8,
//                 odeint-rkf78's pair). Passed with a ninth, unused stage that works around
//                 ERKStep 6.4.1 taking the table for first-same-as-last (verner_6_5_without_fsal).
//   arkode-dirk   ARKStep, implicit only (no explicit part), with the ESDIRK half of Kennedy and
//                 Carpenter's ARK5(4)8L[2]SA (ARKODE_ARK548L2SA_DIRK_8_4_5; C. A. Kennedy,
//                 M. H. Carpenter, "Additive Runge-Kutta schemes for convection-diffusion-reaction
//                 equations", Appl. Numer. Math. 44 (2003) 139-181): order 5, embedded order 4,
//                 8 stages of which the first is explicit (7 implicit solves per step), L-stable
//                 and stiffly accurate. Newton iteration on each stage with a dense direct
//                 linear solver (SUNDenseMatrix + SUNLinSol_Dense) and the model's Jacobian, as
//                 for CVODE. Why this table: the rigid-body models are not stiff (the
//                 Jacobian's eigenvalues are ~i |Omega|), so the baseline measures what an
//                 implicit one-step method costs at a given accuracy; it is ARKODE's
//                 highest-order adaptive DIRK family (with the 7-stage ESDIRK547L2SA and
//                 Kvaerno 7(4)5), so at the tight tolerances of the comparisons its step count
//                 is closest to the explicit pairs'. SDIRK 5(3)4 (Hairer and Wanner's order-4
//                 SDIRK) has fewer stages but order 4: more steps at rtol 1e-10
//                 (baselines/README.md gives the measured counts). L-stability damps the
//                 rotations' oscillatory modes slightly (numerical dissipation, within rtol per
//                 step): energy and momentum drift like the other non-symplectic baselines'.
//
// Both: scalar tolerances rtol/atol, the Euler model's singular set as a root function
// (ARKODE's root finder, direction decreasing), every return flag checked, ARKODE's error handler
// redirected into the status (the last message, appended to the failure).
//
// Output: as for CVODE (cvode_solver.cpp), ARKODE steps one step per call (ARK_ONE_STEP) towards
// the end of the horizon (its stop time: nothing else shortens a step; ARKODE estimates its first
// step from the horizon, not from an output interval), and the output times each step passed
// are read off ARKODE's own dense output (ERKStepGetDky / ARKStepGetDky) of the last step. The
// interpolation module is set explicitly: Hermite (ARK_INTERP_HERMITE), degree 5
// (ARK_INTERP_MAX_DEGREE), which ARKODE builds from y and f at the step's two ends plus f
// evaluated inside the step on each GetDky call (measured: 4 RHS per output time for arkode-erk,
// 1 for arkode-dirk; counted in output_rhs_evaluations). At rtol 1e-6 the steps are long
// (h |Omega| ~ 0.3-1), where a cubic (degree 3, no extra RHS) would be off by ~(h w)^4 / 384,
// above rtol. The Lagrange module (recommended by ARKODE for stiff problems) fits
// the last few step ends instead, a polynomial through long steps that is no better here. The
// steps do not depend on the output times.
//
// Renormalization (quaternion-renormalized): not offered (post_step_hook = false). ARKODE 5.4 has
// a post-processing hook (ERKStepSetPostprocessStepFn, ARKStepSetPostprocessStepFn) but no
// projection: the state would be changed after the error test, unseen by the error estimate and
// the step-size controller, and the dense output would interpolate between states the steps did
// not produce. Use cvode-bdf (projection) or an odeint/GSL one-step method for that model.
//
// ARKODE and CVODES are separate libraries; the symbols they share are SUNDIALS's common objects
// (vectors, dense matrices and linear solvers, the context) from the same 6.4.1 release.
#include <arkode/arkode_arkstep.h>
#include <arkode/arkode_butcher_erk.h>
#include <arkode/arkode_erkstep.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "baselines/solver_detail.hpp"

namespace lgvi::baselines::detail {

namespace {

/// ARKODE's name of a return flag (e.g. "ARK_ERR_FAILURE"), or "flag N".
std::string arkode_flag_name(int flag) {
  char* name = ARKStepGetReturnFlagName(flag);
  std::string s = name ? name : ("flag " + std::to_string(flag));
  std::free(name);
  return s;
}

/// The time-stepping module: explicit (ERKStep) or diagonally implicit (ARKStep, implicit only).
enum class ArkodeModule { Erk, Dirk };

/// ARKODE's Verner 6(5) table with a ninth stage appended: c = 0, a zero row, zero weights.
/// ERKStep of SUNDIALS 6.4.1 takes any table whose last node is c_s = 1 for first-same-as-last
/// and reuses its last stage's f as f(t_n+1, y_n+1), the next step's first stage and the
/// interpolant's end slope. Verner's last row is not b (c_8 = 1 all the same), so that f is
/// wrong and the method drops to order 3: measured with fixed steps on Euler's equations of the
/// free body, |y_h - y_2h| falls by 8.0 per halving (Dormand-Prince, a true FSAL pair, by 32);
/// the same table stepped outside ARKODE shows order 6 (b) and 5 (d). (SUNDIALS issue 311, fixed
/// after 6.4.1.) With the appended stage the last node is 0, ERKStep evaluates f at the step's
/// end, and the pair is Verner's: 8 + 1 RHS per step, the ninth (f(t_n, y_n) again, unused)
/// being the price of the workaround. The caller frees the table (ERKStepSetTable copies it).
ARKodeButcherTable verner_6_5_without_fsal() {
  const ARKodeButcherTable verner = ARKodeButcherTable_LoadERK(ARKODE_VERNER_8_5_6);
  if (verner == nullptr) return nullptr;
  const int s = verner->stages;
  const ARKodeButcherTable table = ARKodeButcherTable_Alloc(s + 1, SUNTRUE);
  if (table != nullptr) {
    table->q = verner->q;
    table->p = verner->p;
    for (int i = 0; i <= s; ++i) {
      for (int j = 0; j <= s; ++j) table->A[i][j] = i < s && j < s ? verner->A[i][j] : 0.0;
      table->c[i] = i < s ? verner->c[i] : 0.0;
      table->b[i] = i < s ? verner->b[i] : 0.0;
      table->d[i] = i < s ? verner->d[i] : 0.0;
    }
  }
  ARKodeButcherTable_Free(verner);
  return table;
}

// The interpolation module of the dense output (see the top of this file).
constexpr int kInterpolantType = ARK_INTERP_HERMITE;
constexpr int kInterpolantDegree = ARK_INTERP_MAX_DEGREE;  // 5

struct ArkodeUser {
  Run* run;
  std::vector<double> J;  ///< row-major Jacobian buffer
};

int ark_rhs(realtype t, N_Vector y, N_Vector ydot, void* user) {
  auto* u = static_cast<ArkodeUser*>(user);
  // Unrecoverable (-1): on the singular set or with a non-finite value nothing sensible can be
  // retried; the run reports the remembered failure.
  return u->run->rhs(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot)) ? 0 : -1;
}

int ark_jac(realtype t, N_Vector y, N_Vector /*fy*/, SUNMatrix Jm, void* user, N_Vector, N_Vector, N_Vector) {
  auto* u = static_cast<ArkodeUser*>(user);
  const std::size_t n = u->run->n;
  if (!u->run->jacobian(t, N_VGetArrayPointer(y), u->J.data())) return -1;
  for (std::size_t j = 0; j < n; ++j) {
    realtype* col = SUNDenseMatrix_Column(Jm, static_cast<sunindextype>(j));
    for (std::size_t i = 0; i < n; ++i) col[i] = u->J[i * n + j];
  }
  return 0;
}

int ark_root(realtype /*t*/, N_Vector y, realtype* g, void* user) {
  auto* u = static_cast<ArkodeUser*>(user);
  g[0] = u->run->ode.singularity_function(N_VGetArrayPointer(y));
  return 0;
}

void ark_error_handler(int /*code*/, const char* module, const char* function, char* msg, void* message) {
  *static_cast<std::string*>(message) =
      std::string(module ? module : "") + "/" + (function ? function : "") + ": " + (msg ? msg : "");
}

/// Owns the ARKODE objects of one integration; frees them in reverse order whatever happens, and
/// calls the ERKStep or ARKStep function of each operation.
struct ArkodeObjects {
  explicit ArkodeObjects(ArkodeModule module) : module(module) {}
  ArkodeObjects(const ArkodeObjects&) = delete;
  ArkodeObjects& operator=(const ArkodeObjects&) = delete;
  ~ArkodeObjects() {
    if (mem) (erk() ? ERKStepFree : ARKStepFree)(&mem);
    if (table) ARKodeButcherTable_Free(table);
    if (LS) SUNLinSolFree(LS);
    if (A) SUNMatDestroy(A);
    if (y) N_VDestroy(y);
    if (ctx) SUNContext_Free(&ctx);
  }

  const ArkodeModule module;
  SUNContext ctx = nullptr;
  N_Vector y = nullptr;
  SUNMatrix A = nullptr;
  SUNLinearSolver LS = nullptr;
  ARKodeButcherTable table = nullptr;  ///< arkode-erk's table (verner_6_5_without_fsal)
  void* mem = nullptr;
  std::string last_message;  ///< "MODULE/FUNCTION: message" of ARKODE's last error; empty if none

  bool erk() const { return module == ArkodeModule::Erk; }

  std::string setup_failure(int flag, const char* call) const {
    return std::string(call) + " returned " + arkode_flag_name(flag) +
           (last_message.empty() ? "" : " (" + last_message + ")");
  }

  int evolve(double tout, double* t) {
    return erk() ? ERKStepEvolve(mem, tout, y, t, ARK_ONE_STEP) : ARKStepEvolve(mem, tout, y, t, ARK_ONE_STEP);
  }
  int dky(double t, N_Vector out) { return erk() ? ERKStepGetDky(mem, t, 0, out) : ARKStepGetDky(mem, t, 0, out); }
  double current_time(double fallback) const {
    realtype t = fallback;
    if ((erk() ? ERKStepGetCurrentTime(mem, &t) : ARKStepGetCurrentTime(mem, &t)) < 0) return fallback;
    return t;
  }

  /// Copies ARKODE's counters into stats: accepted steps, rejected attempts (error-test and, for
  /// the DIRK, nonlinear-solver convergence failures: attempts - accepted), Newton iterations.
  void collect(Stats& stats) const {
    long steps = 0, attempts = 0, nni = 0;
    const bool have = erk() ? ERKStepGetNumSteps(mem, &steps) >= 0 && ERKStepGetNumStepAttempts(mem, &attempts) >= 0
                            : ARKStepGetNumSteps(mem, &steps) >= 0 && ARKStepGetNumStepAttempts(mem, &attempts) >= 0;
    if (have) {
      stats.steps = static_cast<std::size_t>(steps);
      stats.rejected_steps = static_cast<std::size_t>(attempts - steps);
    }
    if (!erk() && ARKStepGetNumNonlinSolvIters(mem, &nni) >= 0) {
      stats.nonlinear_iterations = static_cast<std::size_t>(nni);
    }
  }
};

Stats run_arkode(Run& run, std::vector<double>& y, ArkodeModule module) {
  ArkodeUser user{&run, std::vector<double>(run.n * run.n)};
  ArkodeObjects ark(module);
  const auto n = static_cast<sunindextype>(run.n);
  const double t0 = run.times[0];
  const double t_end = run.times.back();
  if (run.done()) return run.stats;

  // A setup flag is a programming or memory error, reported as such with the call's name.
  auto setup = [&](int flag, const char* call) {
    if (flag < 0 && !run.stopped()) run.stop_failed(t0, ark.setup_failure(flag, call));
    return flag >= 0;
  };
  if (SUNContext_Create(nullptr, &ark.ctx) != 0 || ark.ctx == nullptr) {
    run.stop_failed(t0, "SUNContext_Create failed");
    return run.stats;
  }
  ark.y = N_VNew_Serial(n, ark.ctx);
  if (ark.y == nullptr) {
    run.stop_failed(t0, "N_VNew_Serial failed");
    return run.stats;
  }
  std::copy(y.begin(), y.end(), N_VGetArrayPointer(ark.y));
  bool ok = true;
  if (ark.erk()) {
    ark.mem = ERKStepCreate(ark_rhs, t0, ark.y, ark.ctx);
    ark.table = verner_6_5_without_fsal();
    if (ark.mem == nullptr || ark.table == nullptr) {
      run.stop_failed(t0, "ERKStepCreate or the Butcher table failed");
      return run.stats;
    }
    ok = setup(ERKStepSetErrHandlerFn(ark.mem, ark_error_handler, &ark.last_message), "ERKStepSetErrHandlerFn") &&
         setup(ERKStepSetUserData(ark.mem, &user), "ERKStepSetUserData") &&
         setup(ERKStepSStolerances(ark.mem, *run.settings.rtol, *run.settings.atol), "ERKStepSStolerances") &&
         setup(ERKStepSetTable(ark.mem, ark.table), "ERKStepSetTable") &&
         setup(ERKStepSetInterpolantType(ark.mem, kInterpolantType), "ERKStepSetInterpolantType") &&
         setup(ERKStepSetInterpolantDegree(ark.mem, kInterpolantDegree), "ERKStepSetInterpolantDegree") &&
         setup(ERKStepSetStopTime(ark.mem, t_end), "ERKStepSetStopTime");
  } else {
    ark.mem = ARKStepCreate(nullptr, ark_rhs, t0, ark.y, ark.ctx);  // no explicit part: implicit only
    ark.A = SUNDenseMatrix(n, n, ark.ctx);
    if (ark.mem == nullptr || ark.A == nullptr) {
      run.stop_failed(t0, "ARKODE allocation failed");
      return run.stats;
    }
    ark.LS = SUNLinSol_Dense(ark.y, ark.A, ark.ctx);
    if (ark.LS == nullptr) {
      run.stop_failed(t0, "SUNLinSol_Dense failed");
      return run.stats;
    }
    ok = setup(ARKStepSetErrHandlerFn(ark.mem, ark_error_handler, &ark.last_message), "ARKStepSetErrHandlerFn") &&
         setup(ARKStepSetUserData(ark.mem, &user), "ARKStepSetUserData") &&
         setup(ARKStepSStolerances(ark.mem, *run.settings.rtol, *run.settings.atol), "ARKStepSStolerances") &&
         setup(ARKStepSetTableNum(ark.mem, ARKODE_ARK548L2SA_DIRK_8_4_5, ARKODE_ERK_NONE), "ARKStepSetTableNum") &&
         setup(ARKStepSetLinearSolver(ark.mem, ark.LS, ark.A), "ARKStepSetLinearSolver") &&
         setup(ARKStepSetJacFn(ark.mem, ark_jac), "ARKStepSetJacFn") &&
         setup(ARKStepSetInterpolantType(ark.mem, kInterpolantType), "ARKStepSetInterpolantType") &&
         setup(ARKStepSetInterpolantDegree(ark.mem, kInterpolantDegree), "ARKStepSetInterpolantDegree") &&
         setup(ARKStepSetStopTime(ark.mem, t_end), "ARKStepSetStopTime");
  }
  if (ok && run.settings.fixed_step_probe) {  // order measurements: no error control
    // At a fixed step a stage whose Newton iteration fails its convergence test cannot be retried
    // with a shorter step: the run stops (ARK_CONV_FAILURE). The probe therefore gives the
    // implicit stages a fresh Jacobian on every step and up to kProbeNewtonIterations iterations
    // (ARKODE's defaults, a Jacobian kept for 20 steps and 3 iterations, suit the adaptive runs,
    // which shrink the step instead: with them the first step of h = 0.1 on the free body fails).
    // The stages then converge to the nonlinear tolerance set by rtol, as in an adaptive run.
    constexpr int kProbeNewtonIterations = 10;
    ok = ark.erk() ? setup(ERKStepSetFixedStep(ark.mem, *run.settings.fixed_step_probe), "ERKStepSetFixedStep")
                   : setup(ARKStepSetFixedStep(ark.mem, *run.settings.fixed_step_probe), "ARKStepSetFixedStep") &&
                         setup(ARKStepSetLSetupFrequency(ark.mem, 1), "ARKStepSetLSetupFrequency") &&
                         setup(ARKStepSetMaxNonlinIters(ark.mem, kProbeNewtonIterations), "ARKStepSetMaxNonlinIters");
  }
  if (ok && run.ode.has_singular_set()) {
    int direction = -1;  // g decreases through 0 when |cos theta| falls to the threshold
    ok = ark.erk() ? setup(ERKStepRootInit(ark.mem, 1, ark_root), "ERKStepRootInit") &&
                         setup(ERKStepSetRootDirection(ark.mem, &direction), "ERKStepSetRootDirection")
                   : setup(ARKStepRootInit(ark.mem, 1, ark_root), "ARKStepRootInit") &&
                         setup(ARKStepSetRootDirection(ark.mem, &direction), "ARKStepSetRootDirection");
  }
  if (!ok) return run.stats;

  N_Vector dky = N_VClone(ark.y);  // interpolated outputs
  if (dky == nullptr) {
    run.stop_failed(t0, "N_VClone failed");
    return run.stats;
  }
  while (!run.done() && !run.stopped()) {
    ark.collect(run.stats);
    if (run.stats.steps >= run.settings.max_steps) {
      run.stop_failed(ark.current_time(t0),
                      "step budget of " + std::to_string(run.settings.max_steps) + " steps exhausted");
      break;
    }
    realtype t = 0.0;
    const int flag = ark.evolve(t_end, &t);
    ark.collect(run.stats);
    if (flag < 0) {
      if (!run.stop_on_rhs_failure()) {
        run.stop_failed(ark.current_time(t),
                        arkode_flag_name(flag) + (ark.last_message.empty() ? "" : ": " + ark.last_message));
      }
      break;
    }
    // ARK_SUCCESS, ARK_TSTOP_RETURN (t = t_end) or ARK_ROOT_RETURN (t the root, y(t)
    // interpolated): deliver the output times the step passed (before a root only).
    const bool root = flag == ARK_ROOT_RETURN;
    while (!run.done() && (root ? run.times[run.next_output()] < t : run.times[run.next_output()] <= t)) {
      const std::size_t i = run.next_output();
      if (run.times[i] == t) {
        if (!run.emit(i, N_VGetArrayPointer(ark.y))) break;
        continue;
      }
      // The degree-5 Hermite interpolant evaluates f inside the step: output evaluations.
      run.set_output_evaluations(true);
      const int dky_flag = ark.dky(run.times[i], dky);
      run.set_output_evaluations(false);
      if (dky_flag < 0) {
        run.stop_failed(run.times[i], (ark.erk() ? "ERKStepGetDky returned " : "ARKStepGetDky returned ") +
                                          arkode_flag_name(dky_flag) +
                                          (ark.last_message.empty() ? "" : " (" + ark.last_message + ")"));
        break;
      }
      if (!run.emit(i, N_VGetArrayPointer(dky))) break;
    }
    if (root && !run.stopped()) run.stop_singular(t, N_VGetArrayPointer(ark.y));
  }
  N_VDestroy(dky);
  ark.collect(run.stats);
  std::copy(N_VGetArrayPointer(ark.y), N_VGetArrayPointer(ark.y) + run.n, y.begin());
  return run.stats;
}

}  // namespace

Stats run_arkode_erk(Run& run, std::vector<double>& y) { return run_arkode(run, y, ArkodeModule::Erk); }
Stats run_arkode_dirk(Run& run, std::vector<double>& y) { return run_arkode(run, y, ArkodeModule::Dirk); }

}  // namespace lgvi::baselines::detail
