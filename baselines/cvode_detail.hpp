// What the CVODE solver adapter (baselines/cvode_solver.cpp) and the CVODES sensitivity integrator
// (baselines/sensitivity.cpp) share (SUNDIALS 6 API): the objects of one integration and their
// allocation, CVODE's error handler, the checked setup calls both make, and the counters both
// read. Not part of the public interface.
#pragma once

#include <cvodes/cvodes.h>  // CVODES provides the CVODE API (CMakeLists.txt: one SUNDIALS integrator library)
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <cstdlib>
#include <string>

#include "baselines/solver.hpp"

namespace lgvi::baselines::detail {

/// CVODE's name of a return flag (e.g. "CV_TOO_MUCH_WORK"), or "flag N".
inline std::string cvode_flag_name(int flag) {
  char* name = CVodeGetReturnFlagName(flag);
  std::string s = name ? name : ("flag " + std::to_string(flag));
  std::free(name);
  return s;
}

/// Owns the CVODE(S) objects of one integration; frees them in reverse order whatever happens.
/// Keeps CVODE's last error message (setup() redirects CVODE's error handler here).
struct CvodeObjects {
  SUNContext ctx = nullptr;
  N_Vector y = nullptr;
  N_Vector* yS = nullptr;  ///< CVODES's Ns sensitivity vectors, if any
  int Ns = 0;
  SUNMatrix A = nullptr;
  SUNLinearSolver LS = nullptr;
  void* mem = nullptr;
  std::string last_message;  ///< "MODULE/FUNCTION: message" of CVODE's last error; empty if none

  CvodeObjects() = default;
  CvodeObjects(const CvodeObjects&) = delete;
  CvodeObjects& operator=(const CvodeObjects&) = delete;
  ~CvodeObjects() {
    if (mem) CVodeFree(&mem);  // frees the sensitivity memory too
    if (LS) SUNLinSolFree(LS);
    if (A) SUNMatDestroy(A);
    if (yS) N_VDestroyVectorArray(yS, Ns);
    if (y) N_VDestroy(y);
    if (ctx) SUNContext_Free(&ctx);
  }

  /// Creates the context, the state vector (length n), the memory of a BDF or Adams method, the
  /// dense n x n matrix, `sensitivities` > 0 sensitivity vectors (clones of y) and the dense linear
  /// solver. Returns nullptr, or why it failed: "SUNContext_Create failed"; else `failed` when the
  /// vector, the memory or the matrix could not be allocated; else `solver_failed` (sensitivity
  /// vectors or linear solver). The callers word the last two.
  const char* allocate(sunindextype n, bool bdf, int sensitivities, const char* failed, const char* solver_failed) {
    if (SUNContext_Create(nullptr, &ctx) != 0 || ctx == nullptr) return "SUNContext_Create failed";
    y = N_VNew_Serial(n, ctx);
    mem = CVodeCreate(bdf ? CV_BDF : CV_ADAMS, ctx);
    A = SUNDenseMatrix(n, n, ctx);
    if (!y || !mem || !A) return failed;
    if (sensitivities > 0) {
      yS = N_VCloneVectorArray(sensitivities, y);
      Ns = sensitivities;
    }
    LS = SUNLinSol_Dense(y, A, ctx);
    if ((sensitivities > 0 && !yS) || !LS) return solver_failed;
    return nullptr;
  }

  /// The failure of a setup call: "CALL returned FLAG_NAME (CVODE's last message)".
  std::string setup_failure(int flag, const char* call) const {
    return std::string(call) + " returned " + cvode_flag_name(flag) +
           (last_message.empty() ? "" : " (" + last_message + ")");
  }

  /// The setup both make, in this order: the error handler (into last_message), CVodeInit(f, t0, y),
  /// the user data, scalar tolerances, the dense linear solver, the Jacobian (nullptr: CVODE's
  /// difference quotient), the stop time. Every flag goes through check(flag, call name), which
  /// returns whether to go on; false at the first that fails. y must hold the initial state.
  template <class Check>
  bool setup(CVRhsFn f, CVLsJacFn jacobian, void* user, double t0, double t_stop, double rtol, double atol,
             Check&& check) {
    return check(CVodeSetErrHandlerFn(mem, error_handler, &last_message), "CVodeSetErrHandlerFn") &&
           check(CVodeInit(mem, f, t0, y), "CVodeInit") && check(CVodeSetUserData(mem, user), "CVodeSetUserData") &&
           check(CVodeSStolerances(mem, rtol, atol), "CVodeSStolerances") &&
           check(CVodeSetLinearSolver(mem, LS, A), "CVodeSetLinearSolver") &&
           check(CVodeSetJacFn(mem, jacobian), "CVodeSetJacFn") && check(CVodeSetStopTime(mem, t_stop), "CVodeSetStopTime");
  }

  /// Copies CVODE's counters into stats where it reports them: steps, rejected steps (the state's
  /// error-test and nonlinear-solver convergence failures), nonlinear iterations.
  void collect(Stats& stats) const {
    long steps = 0, netf = 0, ncfn = 0, nni = 0;
    if (CVodeGetNumSteps(mem, &steps) >= 0) stats.steps = static_cast<std::size_t>(steps);
    if (CVodeGetNumErrTestFails(mem, &netf) >= 0 && CVodeGetNumNonlinSolvConvFails(mem, &ncfn) >= 0) {
      stats.rejected_steps = static_cast<std::size_t>(netf + ncfn);
    }
    if (CVodeGetNumNonlinSolvIters(mem, &nni) >= 0) stats.nonlinear_iterations = static_cast<std::size_t>(nni);
  }

 private:
  static void error_handler(int /*code*/, const char* module, const char* function, char* msg, void* message) {
    *static_cast<std::string*>(message) =
        std::string(module ? module : "") + "/" + (function ? function : "") + ": " + (msg ? msg : "");
  }
};

}  // namespace lgvi::baselines::detail
