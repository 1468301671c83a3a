// CVODES forward sensitivities (SUNDIALS 6 API): CVodeInit + dense Newton with the model's
// Jacobian, CVodeSensInit with the analytic sensitivity right-hand side or CVODES's difference
// quotients, CV_NORMAL to the stop time, CVodeGetSens. Every flag is checked.
#include "baselines/sensitivity.hpp"

#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "baselines/cvode_detail.hpp"

namespace lgvi::baselines {

const char* to_string(SensitivityCorrector c) {
  return c == SensitivityCorrector::Simultaneous ? "simultaneous" : "staggered";
}
const char* to_string(SensitivityRhs r) {
  return r == SensitivityRhs::Analytic ? "analytic" : "difference-quotient";
}

namespace {

using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct User {
  const Ode* ode;
  int n;
  std::vector<double> J;  ///< row-major Jacobian buffer (allocated once)
  std::size_t rhs_calls = 0;
  std::size_t jacobian_calls = 0;
  std::size_t sens_calls = 0;
  std::string failure;  ///< first callback failure
  double failure_time = 0.0;

  bool fail(double t, const std::string& what) {
    if (failure.empty()) {
      failure = what;
      failure_time = t;
    }
    return false;
  }
  bool rhs(double t, const double* y, double* f) {
    ++rhs_calls;
    if (ode->rhs(t, y, f) != RhsStatus::Ok) return fail(t, "right-hand side on the model's singular set: " + ode->describe_singularity(y));
    for (int i = 0; i < n; ++i) {
      if (!std::isfinite(f[i])) return fail(t, "non-finite right-hand side");
    }
    return true;
  }
  bool jacobian(double t, const double* y) {
    ++jacobian_calls;
    if (ode->jacobian(t, y, J.data()) != RhsStatus::Ok) return fail(t, "Jacobian on the model's singular set");
    for (const double v : J) {
      if (!std::isfinite(v)) return fail(t, "non-finite Jacobian");
    }
    return true;
  }
};

// Callback failures are unrecoverable (-1): a singular or non-finite model cannot be retried
// with a smaller step to any purpose.
int f_rhs(realtype t, N_Vector y, N_Vector ydot, void* data) {
  auto* u = static_cast<User*>(data);
  return u->rhs(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot)) ? 0 : -1;
}

int f_jac(realtype t, N_Vector y, N_Vector, SUNMatrix Jm, void* data, N_Vector, N_Vector, N_Vector) {
  auto* u = static_cast<User*>(data);
  if (!u->jacobian(t, N_VGetArrayPointer(y))) return -1;
  const int n = u->n;
  for (int j = 0; j < n; ++j) {
    realtype* col = SUNDenseMatrix_Column(Jm, j);
    for (int i = 0; i < n; ++i) col[i] = u->J[static_cast<std::size_t>(i * n + j)];
  }
  return 0;
}

/// S_i' = (df/dy) S_i for all columns from one Jacobian evaluation.
int f_sens(int Ns, realtype t, N_Vector y, N_Vector, N_Vector* yS, N_Vector* ySdot, void* data, N_Vector, N_Vector) {
  auto* u = static_cast<User*>(data);
  ++u->sens_calls;
  if (!u->jacobian(t, N_VGetArrayPointer(y))) return -1;
  const Eigen::Map<const RowMajor> J(u->J.data(), u->n, u->n);
  for (int i = 0; i < Ns; ++i) {
    Eigen::Map<Eigen::VectorXd> out(N_VGetArrayPointer(ySdot[i]), u->n);
    out.noalias() = J * Eigen::Map<const Eigen::VectorXd>(N_VGetArrayPointer(yS[i]), u->n);
  }
  return 0;
}

}  // namespace

SensitivityResult integrate_sensitivities(const Ode& ode, const Eigen::VectorXd& y0, const Eigen::MatrixXd& S0,
                                          double t0, double t1, const SensitivitySettings& settings) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const int n = ode.dimension();
  if (y0.size() != n) throw InvalidInput("y0", "must have the model's dimension " + std::to_string(n));
  require_finite(y0, "y0");
  if (S0.rows() != n) throw InvalidInput("S0", "must have " + std::to_string(n) + " rows");
  require_finite(S0, "S0");
  if (!std::isfinite(t0) || !std::isfinite(t1) || !(t1 > t0)) throw InvalidInput("t1", "must be finite and > t0");
  if (!(settings.rtol > 0.0) || !std::isfinite(settings.rtol)) throw InvalidInput("rtol", "must be finite and > 0");
  const double atol = settings.atol.value_or(settings.rtol);
  if (!(atol > 0.0) || !std::isfinite(atol)) throw InvalidInput("atol", "must be finite and > 0");
  if (settings.max_steps == 0) throw InvalidInput("max_steps", "must be > 0");

  SensitivityResult result;
  result.y = y0;
  result.S = S0;
  Stats& stats = result.stats;
  User user{&ode, n, std::vector<double>(static_cast<std::size_t>(n) * n), 0, 0, 0, {}, 0.0};
  detail::CvodeObjects cv;
  const int Ns = static_cast<int>(S0.cols());
  auto finish = [&] {
    stats.rhs_evaluations = user.rhs_calls;
    stats.jacobian_evaluations = user.jacobian_calls;
    result.sensitivity_rhs_evaluations = user.sens_calls;
    stats.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return result;
  };
  auto fail = [&](double t, const std::string& detail) {
    stats.status = IntegrationStatus::SolverFailed;
    stats.failed_time = t;
    stats.failure_detail = detail;
    stats.failed_step = stats.steps;
  };
  auto check = [&](int flag, const char* call) {
    if (flag < 0 && stats.ok()) fail(t0, cv.setup_failure(flag, call));
    return flag >= 0;
  };

  if (const char* failed = cv.allocate(n, settings.method == MultistepMethod::Bdf, Ns, "CVODES allocation failed",
                                       "CVODES allocation failed (sensitivity vectors or linear solver)")) {
    fail(t0, failed);
    return finish();
  }
  Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(cv.y), n) = y0;
  for (int i = 0; i < Ns; ++i) Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(cv.yS[i]), n) = S0.col(i);
  std::vector<realtype> atolS(static_cast<std::size_t>(Ns), atol);
  // CVODES's difference quotients need a parameter array even for initial-value sensitivities:
  // dummy parameters f does not read (their directional difference is zero), scale 1.
  std::vector<realtype> p_dummy(static_cast<std::size_t>(Ns), 0.0), pbar(static_cast<std::size_t>(Ns), 1.0);
  std::vector<int> plist(static_cast<std::size_t>(Ns));
  for (int i = 0; i < Ns; ++i) plist[static_cast<std::size_t>(i)] = i;
  const int ism = settings.corrector == SensitivityCorrector::Simultaneous ? CV_SIMULTANEOUS : CV_STAGGERED;
  bool ok = cv.setup(f_rhs, f_jac, &user, t0, t1, settings.rtol, atol, check) &&
            check(CVodeSetMaxNumSteps(cv.mem, static_cast<long>(settings.max_steps)), "CVodeSetMaxNumSteps");
  // No columns: the state alone (plain CVODE), e.g. the line-search trials of the shooting.
  ok = ok && (Ns == 0 ||
      (check(CVodeSensInit(cv.mem, Ns, ism, settings.rhs == SensitivityRhs::Analytic ? f_sens : nullptr, cv.yS),
            "CVodeSensInit") &&
      check(CVodeSensSStolerances(cv.mem, settings.rtol, atolS.data()), "CVodeSensSStolerances") &&
      check(CVodeSetSensErrCon(cv.mem, settings.sensitivity_error_control ? SUNTRUE : SUNFALSE),
            "CVodeSetSensErrCon") &&
      // Centered differences (rho = 0: CVODES's default increment); only used by DifferenceQuotient.
      check(CVodeSetSensDQMethod(cv.mem, CV_CENTERED, 0.0), "CVodeSetSensDQMethod") &&
      (settings.rhs == SensitivityRhs::Analytic ||
       check(CVodeSetSensParams(cv.mem, p_dummy.data(), pbar.data(), plist.data()), "CVodeSetSensParams"))));
  if (!ok) return finish();

  realtype t = t0;
  const int flag = CVode(cv.mem, t1, cv.y, &t, CV_NORMAL);
  cv.collect(stats);
  long netfS = 0, ncfnS = 0;
  if (Ns > 0 && CVodeGetSensNumErrTestFails(cv.mem, &netfS) >= 0 && CVodeGetSensNumNonlinSolvConvFails(cv.mem, &ncfnS) >= 0) {
    stats.rejected_steps += static_cast<std::size_t>(netfS + ncfnS);
  }
  result.y = Eigen::Map<const Eigen::VectorXd>(N_VGetArrayPointer(cv.y), n);
  if (flag < 0) {
    realtype t_reached = t;
    CVodeGetCurrentTime(cv.mem, &t_reached);
    if (!user.failure.empty()) {
      fail(user.failure_time, "CVode returned " + detail::cvode_flag_name(flag) + ": " + user.failure);
    } else {
      fail(t_reached, "CVode returned " + detail::cvode_flag_name(flag) + (cv.last_message.empty() ? "" : ": " + cv.last_message));
    }
    return finish();
  }
  realtype tS = t;
  if (Ns > 0 && !check(CVodeGetSens(cv.mem, &tS, cv.yS), "CVodeGetSens")) return finish();
  for (int i = 0; i < Ns; ++i) result.S.col(i) = Eigen::Map<const Eigen::VectorXd>(N_VGetArrayPointer(cv.yS[i]), n);
  if (!result.y.allFinite() || !result.S.allFinite()) fail(t1, "non-finite state or sensitivities at the end");
  return finish();
}

}  // namespace lgvi::baselines
