// Forward sensitivities of a continuous-time model with SUNDIALS CVODES: y(t1) and
// S(t1) = d y(t1) / d p for initial sensitivities S(t0) = S0 (S0 = I: the state-transition
// matrix d y(t1) / d y(t0); S0 = selected columns of I: the derivative with respect to those
// initial values, e.g. the initial costate of baselines/pontryagin.hpp), and the conversion of a
// single-attitude model's transition matrix to the tangent coordinates z = [eta; dOmega]
// (dR = R hat(eta)) of the LGVI's linearization (lgvi/ocp/linearization.hpp, eq. 16).
//
// The sensitivity equations S' = (df/dy) S (no parameters enter f) use the model's own Jacobian
// (Ode::jacobian, baselines/model.hpp) by default: one Jacobian evaluation per call for all
// columns, exact up to the model's Jacobian (analytic kinematics and velocity terms; central
// differences of the potential's and control's moments in R, ~eps^(2/3) relative, exact for the
// pendulum's moment, which is linear in R). CVODES's own directional difference quotients
// (centered, CV_CENTERED) are the alternative, at ~2 right-hand sides per column per call and
// ~eps^(2/3)-limited accuracy: measured at rtol 1e-10, their noise fails the sensitivities' error
// test and the run takes ~100x the steps (baselines/README.md).
//
// Corrector: simultaneous (CV_SIMULTANEOUS: state and sensitivities in one Newton system with
// the state's Jacobian, one error test) by default; staggered (CV_STAGGERED: sensitivities
// corrected after the state converged) as an option. The sensitivities take part in the local
// error test (CVodeSetSensErrCon) with the state's tolerances, so their accuracy follows rtol as
// the state's does.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include <Eigen/Dense>

#include "baselines/coordinates.hpp"
#include "baselines/model.hpp"
#include "baselines/ode.hpp"
#include "lgvi/integrate.hpp"

namespace lgvi::baselines {

enum class SensitivityCorrector { Simultaneous, Staggered };
enum class SensitivityRhs {
  Analytic,            ///< S' = (df/dy) S with the model's Jacobian
  DifferenceQuotient,  ///< CVODES's centered directional differences of f
};
enum class MultistepMethod { Adams, Bdf };

const char* to_string(SensitivityCorrector c);
const char* to_string(SensitivityRhs r);

struct SensitivitySettings {
  double rtol = 1e-10;
  std::optional<double> atol;  ///< default rtol (the states are O(1), as in solver.hpp)
  MultistepMethod method = MultistepMethod::Adams;  ///< non-stiff rigid bodies: Adams, orders up to 12
  SensitivityCorrector corrector = SensitivityCorrector::Simultaneous;
  SensitivityRhs rhs = SensitivityRhs::Analytic;
  bool sensitivity_error_control = true;  ///< include S in the local error test
  std::size_t max_steps = 1'000'000;
};

struct SensitivityResult {
  Eigen::VectorXd y;  ///< y(t1) (at the failure: the last state CVODES reached)
  Eigen::MatrixXd S;  ///< d y(t1) / d p, dimension x S0.cols()
  /// steps, rhs_evaluations (every call of f, difference quotients included),
  /// jacobian_evaluations (every Ode::jacobian call: Newton matrices and sensitivity right-hand
  /// sides), nonlinear_iterations, rejected_steps, wall time, status (SolverFailed with the
  /// CVODES flag name and message, failed_time).
  Stats stats;
  std::size_t sensitivity_rhs_evaluations = 0;  ///< calls of the sensitivity right-hand side
  bool ok() const { return stats.ok(); }
};

/// Integrates y' = f(t, y) from (t0, y0) to t1 > t0 with the forward sensitivities S(t0) = S0
/// (n x n_s; n_s = 0: the state alone, without CVodeSensInit). Never prints; every CVODES flag is checked and a failure is returned
/// in stats (a right-hand side on the model's singular set or with non-finite values stops the
/// run). Throws InvalidInput for bad arguments ("y0", "S0", "t1", "rtol", "atol").
SensitivityResult integrate_sensitivities(const Ode& ode, const Eigen::VectorXd& y0, const Eigen::MatrixXd& S0,
                                          double t0, double t1, const SensitivitySettings& settings = {});

// --- tangent coordinates ----------------------------------------------------------------------

/// eta of a chart tangent dc at c: dR = (d R / dc) dc, eta = vee(skew(R^T dR)) / s with
/// s = tr(R^T R) / 3 (1 on SO(3); |q|^4 for the quaternion chart, whose R(q) = |q|^2 R(q/|q|):
/// exact for it off the unit sphere too, and first order in the drift for the matrix chart).
template <class Chart>
Vec3 chart_tangent_to_eta(const typename Chart::Coords& c, const typename Chart::Coords& dc) {
  const Mat3 R = Chart::rotation(c);
  const Eigen::Matrix<double, 9, 1> dvec = Chart::rotation_jacobian(c) * dc;
  Mat3 dR;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) dR(i, j) = dvec(3 * i + j);
  }
  const Mat3 M = R.transpose() * dR;
  const double s = (R.transpose() * R).trace() / 3.0;
  return so3::vee(0.5 * (M - M.transpose())) / s;
}

/// The 3 x Chart::size matrix of chart_tangent_to_eta (linear in dc).
template <class Chart>
Eigen::Matrix<double, 3, Chart::size> eta_per_chart(const typename Chart::Coords& c) {
  Eigen::Matrix<double, 3, Chart::size> E;
  for (int k = 0; k < Chart::size; ++k) {
    E.col(k) = chart_tangent_to_eta<Chart>(c, Chart::Coords::Unit(k));
  }
  return E;
}

/// Transition matrix of a single-attitude model (y = [c; Omega], AttitudeMechanics) in tangent
/// coordinates: Phi_z = d z(t1) / d z(t0) = T_out S T_in, z = [eta; dOmega], with
/// T_in = blockdiag(dc/d eta = Chart::rate_omega_jacobian(c0), I) (dc of R -> R exp(eta) is the
/// chart's kinematics for Omega = eta) and T_out = blockdiag(eta_per_chart(c1), I).
/// S is the n x n transition matrix d y(t1) / d y(t0); y0, y1 the states at t0, t1.
template <class Chart, class M>
Eigen::Matrix<double, 6, 6> tangent_transition(const CoordinateOde<Chart, M>& /*ode*/, const Eigen::VectorXd& y0,
                                               const Eigen::VectorXd& y1, const Eigen::MatrixXd& S) {
  using Ode = CoordinateOde<Chart, M>;
  static_assert(Ode::N == 1 && Ode::NX == 0 && Ode::NW == 3, "single attitude with w = Omega");
  constexpr int n = Ode::kDim;
  constexpr int C = Chart::size;
  if (y0.size() != n || y1.size() != n || S.rows() != n || S.cols() != n) {
    throw InvalidInput("S", "tangent_transition needs the full transition matrix of the model");
  }
  Eigen::Matrix<double, n, 6> T_in = Eigen::Matrix<double, n, 6>::Zero();
  T_in.template topLeftCorner<C, 3>() = Chart::rate_omega_jacobian(y0.template head<C>());
  T_in.template bottomRightCorner<3, 3>().setIdentity();
  Eigen::Matrix<double, 6, n> T_out = Eigen::Matrix<double, 6, n>::Zero();
  T_out.template topLeftCorner<3, C>() = eta_per_chart<Chart>(y1.template head<C>());
  T_out.template bottomRightCorner<3, 3>().setIdentity();
  const Eigen::Matrix<double, n, n> Sf = S;
  return T_out * Sf * T_in;
}

}  // namespace lgvi::baselines
