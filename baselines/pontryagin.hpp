// Continuous necessary conditions (Pontryagin) of the 3D pendulum's fixed-time transfer
// (section 3.2), solved by shooting on the initial costate: the continuous-time baseline of the
// discrete indirect method (lgvi/ocp/indirect.hpp), for the same problem:
//   R' = R hat(Omega),  Pi' = Pi x Omega + M(R) + B(R) u,  Omega = J^{-1} Pi,
//   M = m g rho x a, B(R) u = a x u (eq. 23), a = R^T e3,
//   minimize J = int_0^T 1/2 u^T W u dt,  (R, Omega)(0), (R, Omega)(T) given.
//
// Costates in body coordinates: lambda = [lambda_R; lambda_Pi] is a covector on the
// left-trivialized tangent w = [eta; dPi] (dR = R hat(eta)), the coordinates of the discrete
// multipliers (lgvi/ocp/linearization.hpp). With the variational equations
//   eta' = -Omega x eta + J^{-1} dPi,
//   dPi' = (-hat(Omega) + hat(Pi) J^{-1}) dPi + G eta + B du,   G = hat(m g rho - u) hat(a)
// (models.hpp), the Hamiltonian H = 1/2 u^T W u + lambda^T [Omega; Pi'] gives (continuous
// counterparts of eqs. 17-19, 27, 28):
//   u         = -W^{-1} B^T lambda_Pi = -W^{-1} (lambda_Pi x a)                  (dH/du = 0)
//   lambda_R'  = lambda_R x Omega - a x ((m g rho - u) x lambda_Pi)
//   lambda_Pi' = -J^{-1} (lambda_R - Pi x lambda_Pi) - Omega x lambda_Pi
// i.e. lambda' = -A^T lambda with A the matrix of the variational equations; lambda_R' is
// -dH/deta plus the coadjoint term lambda_R x Omega of the left trivialization, lambda_Pi' =
// -dH/dPi (tests/baselines check both against finite differences of H).
//
// Integration: y = [q; Pi; lambda_R; lambda_Pi; c] (14 entries; q the attitude quaternion of
// baselines/coordinates.hpp, c the running cost, c' = 1/2 u^T W u) with CVODES (Adams, dense
// Newton with the analytic Jacobian below) at SensitivitySettings::rtol; the Jacobian of the
// terminal residual with respect to lambda(0) from CVODES forward sensitivities (S(0) = the
// lambda columns of I) or, as an option, central differences of the residual.
//
// Terminal residual, as the discrete solver's: r = [log(R_f^T R(T))^vee; Omega(T) - Omega_f]
// with R(T) of the normalized quaternion; violation |r|; dr/dlambda(0) = D [eta(T); dPi(T)] with
// D = blockdiag(Jr^{-1}(r_R), J^{-1}).
//
// Symmetry. The vertical momentum C = e3^T R Pi = a . Pi is conserved for every control (B^T a
// = 0), so dr/dlambda(0) has rank 5 exactly as the discrete sensitivity: adding
// alpha dC = alpha [Pi x a; a] to lambda(0) changes no control, and no lambda(0) changes C(T).
// The decomposition of the discrete solver (indirect.hpp) applies unchanged: v_g = dC(s_0),
// u_g = D^{-T} dC(s_T), Newton on the 5x5 shape block.
#pragma once

#include <cstddef>
#include <string>
#include <utility>

#include <Eigen/Dense>

#include "baselines/coordinates.hpp"
#include "baselines/mechanics.hpp"
#include "baselines/ode.hpp"
#include "baselines/sensitivity.hpp"
#include "lgvi/ocp/indirect.hpp"
#include "lgvi/systems/dumbbell.hpp"
#include "lgvi/systems/pendulum.hpp"

namespace lgvi::baselines {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

/// The state-costate ODE of the pendulum (header comment). Holds the system by reference.
class PendulumPontryaginOde final : public Ode {
 public:
  static constexpr int kDim = 14;
  static constexpr int kQ = 0, kPi = 4, kLambdaR = 7, kLambdaPi = 10, kCost = 13;  ///< offsets in y
  using State = Vector<kDim>;
  using Jacobian = Eigen::Matrix<double, kDim, kDim, Eigen::RowMajor>;

  /// W: 3x3 symmetric positive definite (empty: identity). Throws InvalidInput("W", ...).
  PendulumPontryaginOde(const Pendulum3D& system, const Eigen::MatrixXd& W);

  /// y(0) from the boundary values and the initial costate [lambda_R; lambda_Pi]; cost 0.
  /// Throws InvalidInput("R0" / "Omega0" / "costate", ...).
  State initial_state(const Mat3& R0, const Vec3& Omega0, const Vec6& lambda0) const;

  /// The optimal control u = -W^{-1} (lambda_Pi x a), a = R^T e3.
  Vec3 control(const Mat3& R, const Vec6& lambda) const;
  /// H = 1/2 u^T W u + lambda_R . Omega + lambda_Pi . (Pi x Omega + M(R) + a x u), any u.
  double hamiltonian(const Mat3& R, const Vec3& Pi, const Vec6& lambda, const Vec3& u) const;
  /// d[lambda_R; lambda_Pi]/dt at (R, Pi, lambda) with the optimal control (header comment).
  Vec6 costate_rate(const Mat3& R, const Vec3& Pi, const Vec6& lambda) const;

  int dimension() const override { return kDim; }
  std::string model_name() const override { return "pendulum-pontryagin-quaternion"; }
  bool time_dependent() const override { return false; }
  RhsStatus rhs(double t, const double* y, double* ydot) const override;
  /// Analytic (all blocks); tests/baselines checks it against central differences.
  RhsStatus jacobian(double t, const double* y, double* dfdy_row_major) const override;

  const Pendulum3D& system() const { return system_; }
  const Mat3& W() const { return W_; }

 private:
  const Pendulum3D& system_;
  Mat3 W_;
  Mat3 W_inverse_;
};

/// How the shooting obtains dr/dlambda(0).
enum class ShootingJacobian {
  Sensitivities,      ///< CVODES forward sensitivities (baselines/sensitivity.hpp)
  FiniteDifferences,  ///< central differences of r, step cbrt(rtol) max(1, |lambda_i|)
};
const char* to_string(ShootingJacobian j);

/// Default violation tolerance per unit of rtol: the computed residual carries the integration's
/// global error, a modest multiple of rtol (measured floors 4..17 rtol, baselines/README.md); Newton cannot
/// resolve r below its noise, so the tolerance is kViolationPerRtol * rtol.
inline constexpr double kViolationPerRtol = 100.0;

struct ContinuousShootingOptions {
  Eigen::MatrixXd W;                ///< 3x3 (dumbbell 6x6) symmetric positive definite; empty: identity
  Eigen::VectorXd initial_costate;  ///< [lambda_R; lambda_Pi](0) guess (6; dumbbell 12); empty: zero
  bool decomposition = true;        ///< Newton on the symmetry's 5x5 shape block
  ShootingJacobian jacobian = ShootingJacobian::Sensitivities;
  /// rtol (default 1e-10), method, corrector; step budget per integration 20000 (the paper's
  /// transfer needs ~700 steps at rtol 1e-10): a line-search trial whose huge costate makes the
  /// dynamics stiff fails fast and counts as no decrease.
  SensitivitySettings integration = [] {
    SensitivitySettings s;
    s.max_steps = 20'000;
    return s;
  }();
  int max_iterations = 100;
  int max_backtracks = 30;
  double armijo = 1e-4;
  double tolerance = 0.0;  ///< on the violation; 0: kViolationPerRtol * integration.rtol
  int polish_iterations = 3;
};

/// One integration of the necessary conditions from lambda(0).
struct PontryaginEvaluation {
  bool ok = false;
  std::string message;  ///< why not ok (the CVODES failure)
  Stats stats;          ///< of the integration
  Vec6 residual = Vec6::Zero();
  double cost = 0.0;
  Mat6 jacobian = Mat6::Zero();  ///< dr/dlambda(0) (when requested)
  Mat6 Psi = Mat6::Zero();       ///< d[eta; dPi](T) / dlambda(0), the continuous Psi12 (when requested)
  Mat3 R_final = Mat3::Identity();
  Vec3 Omega_final = Vec3::Zero();
  Vec6 costate_final = Vec6::Zero();
};

/// The shooting function of one problem: lambda(0) -> r, J, dr/dlambda(0). Immutable; holds the
/// system by reference.
class PendulumShootingFunction {
 public:
  /// Validates the problem (rotations orthonormal, t_final > 0, finite) and W; throws InvalidInput.
  PendulumShootingFunction(const Pendulum3D& system, const ocp::TransferProblem& problem, const Eigen::MatrixXd& W,
                           const SensitivitySettings& integration);
  /// Integrates from lambda0; with `jacobian` also dr/dlambda(0) by `method`.
  PontryaginEvaluation evaluate(const Vec6& lambda0, bool jacobian,
                                ShootingJacobian method = ShootingJacobian::Sensitivities) const;
  /// D = d r / d[eta; dPi](T) at the residual r.
  Mat6 residual_jacobian(const Vec6& r) const;
  /// D and dC(s_T), from which the decomposition's u_g = D^{-T} dC(s_T).
  std::pair<Mat6, Vec6> terminal_symmetry(const PontryaginEvaluation& at) const;

  const PendulumPontryaginOde& ode() const { return ode_; }
  const ocp::TransferProblem& problem() const { return problem_; }
  const SensitivitySettings& integration() const { return integration_; }

 private:
  PendulumPontryaginOde ode_;
  ocp::TransferProblem problem_;
  SensitivitySettings integration_;
};

template <class Evaluation>
struct ContinuousShootingResultOf {
  /// Same type and meaning as the discrete solver's (status, iterations, history with violation,
  /// step length and condition numbers, brief()); system "pendulum (continuous)", h = 0,
  /// steps = CVODES steps of the final integration, multiplier = lambda(0).
  ocp::ShootingSummary summary;
  double rtol = 0.0;
  double tolerance = 0.0;  ///< the violation tolerance used
  ShootingJacobian jacobian = ShootingJacobian::Sensitivities;
  std::size_t integrations = 0;       ///< every integration (sweeps, FD columns)
  std::size_t integration_steps = 0;  ///< summed CVODES steps
  std::size_t rhs_evaluations = 0;    ///< summed
  Evaluation final;                   ///< the last accepted point (with its Jacobian)
};
using ContinuousShootingResult = ContinuousShootingResultOf<PontryaginEvaluation>;

/// Newton-Armijo shooting on lambda(0) (the discrete solver's algorithm, Kelley 2003 sec. 1.10,
/// with the same symmetry decomposition and statuses; SweepFailed: an integration failed). Never
/// throws; bad input becomes status InvalidInput with a message naming the field.
ContinuousShootingResult solve_pontryagin(const Pendulum3D& system, const ocp::TransferProblem& problem,
                                          const ContinuousShootingOptions& options);

// --- the dumbbell (section 3.1) ----------------------------------------------------------------
//
// The continuous necessary conditions of the dumbbell's orbit transfer, the baseline of the discrete
// solver's dumbbell (lgvi/ocp/indirect.hpp, the same TransferProblem::dumbbell_paper()):
//   R' = R hat(Omega), x' = p / m, Pi' = Pi x Omega + M(R, x) + u_m, p' = f(R, x) + u_f,
//   Omega = J^{-1} Pi, phi = [M; f] the gravity force of eqs. 13, 20 (DumbbellSpacecraft::forces),
//   minimize J = int_0^T 1/2 u^T W u dt, u = [u_m (body); u_f (inertial)], both ends given.
// Costates on the tangent w = [eta; dx; dPi; dp] (dR = R hat(eta)), the discrete multipliers'
// coordinates; with G = dphi/d[eta; dx] (ocp::DumbbellModel::force_jacobian) and the Hamiltonian
// H = 1/2 u^T W u + lambda_R.Omega + lambda_x.p/m + lambda_Pi.(Pi x Omega + M + u_m) + lambda_p.(f + u_f):
//   u          = -W^{-1} lambda_P,  lambda_P = [lambda_Pi; lambda_p]            (dH/du = 0; B = I)
//   [lambda_R; lambda_x]' = [lambda_R x Omega; 0] - G^T lambda_P                 (-dH/d[eta; x], coadjoint term)
//   lambda_Pi' = -J^{-1} (lambda_R - Pi x lambda_Pi) - Omega x lambda_Pi          (-dH/dPi)
//   lambda_p'  = -lambda_x / m                                                    (-dH/dp)
// (continuous counterparts of eqs. 17-19; tests/baselines check them against finite differences of H).
// Integration: y = [q; x; Pi; p; lambda (12); c] (26 entries), the rotation from the normalized
// quaternion (so the analytic Jacobian's chain rule dR = R hat(eta_per_chart(q) dq) is exact off the
// unit sphere too); the Jacobian's second-derivative block d(G^T lambda_P)/d[eta; dx] is
// ocp::DumbbellModel::force_jacobian_transpose_derivative (the third derivative of the potential).
// Terminal residual as the discrete solver's r = [log(R_f^T R(T)); x(T) - x_f; Omega(T) - Omega_f;
// v(T) - v_f], dr/dlambda(0) = blockdiag(Jr^{-1}(r_R), I, J^{-1}, I/m) d w(T)/dlambda(0).
// No symmetry: Newton-Armijo on the full 12x12 system.

using Vec12 = Eigen::Matrix<double, 12, 1>;
using Mat12 = Eigen::Matrix<double, 12, 12>;

/// The state-costate ODE of the dumbbell (comment above). Holds the system by reference.
class DumbbellPontryaginOde final : public Ode {
 public:
  static constexpr int kDim = 26;
  static constexpr int kQ = 0, kX = 4, kPi = 7, kP = 10, kLambda = 13, kCost = 25;  ///< offsets in y
  using State = Vector<kDim>;
  using Jacobian = Eigen::Matrix<double, kDim, kDim, Eigen::RowMajor>;

  /// W: 6x6 symmetric positive definite (empty: identity). Throws InvalidInput("W", ...).
  DumbbellPontryaginOde(const DumbbellSpacecraft& system, const Eigen::MatrixXd& W);

  /// y(0) from the boundary values and the initial costate; cost 0. Throws InvalidInput.
  State initial_state(const ocp::TransferProblem& problem, const Vec12& lambda0) const;
  /// The optimal control u = -W^{-1} lambda_P = [u_m; u_f].
  Vec6 control(const Vec12& lambda) const;
  /// H (comment above) at (R, x, Pi, p, lambda) for any u.
  double hamiltonian(const Mat3& R, const Vec3& x, const Vec3& Pi, const Vec3& p, const Vec12& lambda,
                     const Vec6& u) const;
  /// d lambda / dt at (R, x, Pi, lambda) with the optimal control (comment above).
  Vec12 costate_rate(const Mat3& R, const Vec3& x, const Vec3& Pi, const Vec12& lambda) const;

  int dimension() const override { return kDim; }
  std::string model_name() const override { return "dumbbell-pontryagin-quaternion"; }
  bool time_dependent() const override { return false; }
  RhsStatus rhs(double t, const double* y, double* ydot) const override;
  /// Analytic (all blocks); tests/baselines checks it against central differences.
  RhsStatus jacobian(double t, const double* y, double* dfdy_row_major) const override;

  const DumbbellSpacecraft& system() const { return system_; }
  const Mat6& W() const { return W_; }

 private:
  const DumbbellSpacecraft& system_;
  Mat6 W_;
  Mat6 W_inverse_;
};

/// One integration of the dumbbell's necessary conditions from lambda(0).
struct DumbbellPontryaginEvaluation {
  bool ok = false;
  std::string message;
  Stats stats;
  Vec12 residual = Vec12::Zero();
  double cost = 0.0;
  Mat12 jacobian = Mat12::Zero();  ///< dr/dlambda(0) (when requested)
  Mat12 Psi = Mat12::Zero();       ///< d[eta; dx; dPi; dp](T) / dlambda(0), the continuous Psi12
  Mat3 R_final = Mat3::Identity();
  Vec3 x_final = Vec3::Zero();
  Vec3 Omega_final = Vec3::Zero();
  Vec3 v_final = Vec3::Zero();
  Vec12 costate_final = Vec12::Zero();
};

/// The dumbbell's shooting function lambda(0) -> r, J, dr/dlambda(0). Holds the system by reference.
class DumbbellShootingFunction {
 public:
  DumbbellShootingFunction(const DumbbellSpacecraft& system, const ocp::TransferProblem& problem,
                           const Eigen::MatrixXd& W, const SensitivitySettings& integration);
  DumbbellPontryaginEvaluation evaluate(const Vec12& lambda0, bool jacobian,
                                        ShootingJacobian method = ShootingJacobian::Sensitivities) const;
  /// D = d r / d[eta; dx; dPi; dp](T) at the residual r.
  Mat12 residual_jacobian(const Vec12& r) const;
  /// D and a zero conserved gradient (no symmetry; the decomposition is never used).
  std::pair<Mat12, Vec12> terminal_symmetry(const DumbbellPontryaginEvaluation& at) const {
    return {residual_jacobian(at.residual), Vec12::Zero()};
  }

  const DumbbellPontryaginOde& ode() const { return ode_; }
  const ocp::TransferProblem& problem() const { return problem_; }

 private:
  DumbbellPontryaginOde ode_;
  ocp::TransferProblem problem_;
  SensitivitySettings integration_;
};

using DumbbellContinuousShootingResult = ContinuousShootingResultOf<DumbbellPontryaginEvaluation>;

/// Newton-Armijo shooting on the dumbbell's lambda(0) (the discrete solver's algorithm without the
/// decomposition; options.decomposition is ignored; options.initial_costate has 12 entries, empty:
/// zero, the uncontrolled motion; W 6x6). Never throws.
DumbbellContinuousShootingResult solve_pontryagin(const DumbbellSpacecraft& system,
                                                  const ocp::TransferProblem& problem,
                                                  const ContinuousShootingOptions& options);

/// The continuous initial costate that corresponds to the discrete solver's initial multiplier
/// (ShootingSummary::multiplier of solve_indirect on the pendulum): the identity, checked for
/// size (6) and finiteness. Why the identity: the discrete lambda_0 is the multiplier of s_0 on the
/// same coordinates [eta; dPi], and the discrete constraint s_{k+1} - Phi(s_k, u) carries the
/// impulse h B u against the cost h/2 u^T W u, so u_k = -W^{-1} B^T lambda_{k,Pi} is the
/// continuous optimality condition sampled at t_k. Symmetric form: |lambda_0 - lambda(0)| (shape
/// part, the symmetry direction being arbitrary in both) falls 4.0x per halving of h (measured,
/// tests/baselines: 1.4e-3 at h = 0.004), i.e. O(h^2). Throws InvalidInput("multiplier", ...).
Vec6 continuous_costate_from_discrete(const Eigen::VectorXd& discrete_multiplier);

}  // namespace lgvi::baselines
