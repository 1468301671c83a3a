// Indirect discrete optimal control (sections 3.1, 3.2): the discrete necessary conditions
// propagated forward from (x_0, lambda_0), their exact sensitivities, and Newton-Armijo shooting
// on lambda_0 with the pendulum's symmetry decomposition.
//
// The discrete problem. Controls sit at the grid nodes t_j = j h, j = 0..N; step k is the
// integrator's step(s_k, h, u_k, u_{k+1}) (lgvi.hpp), i.e. kick(c0, u_k), drift,
// kick(c1, u_{k+1}). The cost is the node-weighted sum
//     J = sum_j w_j / 2 u_j^T W u_j,   w_0 = c0, w_N = c1, w_j = c0 + c1 = h otherwise:
//   - printed form (c0 = 0, c1 = h): J = sum_{k=0}^{N-1} h/2 u_{k+1}^T W u_{k+1}, the paper's
//     eqs. 14, 24 exactly (u_0 does not enter and is reported as 0);
//   - symmetric form (c0 = c1 = h/2): the trapezoidal rule on the same grid; each control acts
//     at its node with the full impulse h u_j (half from each neighbouring step), h/2 at the
//     ends. Why not one control per step applied as both half impulses,
//     step(s_k, h, u_{k+1}, u_{k+1})? Then the kick at node k uses (u_k + u_{k+1}) / 2 and the
//     optimality condition of u_{k+1} couples the multipliers of nodes k and k+1: the
//     conditions are no longer explicit forward in k and shooting would need an implicit solve
//     per step. With node controls both forms have the same explicit structure.
// Necessary conditions (derivation in linearization.hpp): with lambda_k the multiplier of the
// state s_k (a covector on w = [eta; dx; dPi; dp]),
//     u_j = -W^{-1} B(q_j)^T lambda_{j,P}                     (eqs. 17, 18, 27)
//     lambda_k = A_k^T lambda_{k+1},   k = 0..N-1              (eqs. 19, 28)
// where lambda_{j,P} is the momentum part, equal on both sides of the kicks at node j. The
// paper indexes the multiplier of step k's constraint, lambda_k^{paper} = lambda_{k+1} here;
// the unknown of the shooting is lambda_0 here, the multiplier of the initial state
// (= A_0^T lambda_0^{paper}), because in the symmetric form u_0 depends on it.
// Sensitivities. The forward sweep (s_k, lambda_k) -> (s_{k+1}, lambda_{k+1}) is differentiated
// exactly (tangents through every kick and drift, including the derivatives of A_k, i.e. the
// second derivatives of the flow: models.hpp H, C; linearization.hpp RotationalDrift::tangent):
//     [w_N; dlambda_N] = [Psi11 Psi12; Psi21 Psi22] [w_0; dlambda_0],   w_0 = 0.
// Terminal violation. r = [log(R_f^T R_N)^vee; x_N - x_f; Omega_N - Omega_f; v_N - v_f]
// (the translational parts only for the dumbbell); the violation is its Euclidean 2-norm,
// sqrt(theta^2 + |dx|^2 + |dOmega|^2 + |dv|^2) with theta = |log(R_f^T R_N)| the rotation angle
// between R_N and R_f (units of the problem: rad, length, rad/time, length/time). Its Jacobian
// is dr/dlambda_0 = D Psi (w coordinates), D = blockdiag(Jr^{-1}(r_R), I, J^{-1}, I/m).
#pragma once

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "lgvi/lgvi.hpp"
#include "lgvi/range.hpp"
#include "lgvi/ocp/linearization.hpp"
#include "lgvi/ocp/models.hpp"
#include "lgvi/ocp/step_failure.hpp"

namespace lgvi::ocp {

/// Boundary conditions and horizon of a fixed-time transfer (x, v unused for the pendulum).
struct TransferProblem {
  Mat3 R0 = Mat3::Identity();
  Vec3 x0 = Vec3::Zero();
  Vec3 Omega0 = Vec3::Zero();
  Vec3 v0 = Vec3::Zero();
  Mat3 Rf = Mat3::Identity();
  Vec3 xf = Vec3::Zero();
  Vec3 Omegaf = Vec3::Zero();
  Vec3 vf = Vec3::Zero();
  double t_final = 1.0;

  /// Section 3.2: rest-to-rest 180 deg about the vertical, R0 = I, Rf = diag(-1, -1, 1), T = 1 s.
  static TransferProblem pendulum_paper();
  /// Section 3.1: +60 deg inclination over a quarter of the reference orbit (T = pi/2 with
  /// mu = 1, radius 1: period 2 pi). The printed 4-digit boundary values are the roundings of
  /// the exact geometry used here: x_f = (-sqrt2/4, sqrt2/4, sqrt3/2), v_f = 0.9835
  /// (-1/sqrt2, -1/sqrt2, 0), R_f = [v_f/|v_f|, n x v_f/|v_f|, n] with the orbit normal
  /// n = x_f x v_f/|v_f| (body e1 along-track, e3 along the normal, as R_0); speeds 0.9835 as
  /// printed. Every printed digit is reproduced (|difference| <= 5e-5).
  static TransferProblem dumbbell_paper();
};

enum class ShootingStatus {
  Converged,            ///< violation <= tolerance
  MaxIterations,        ///< outer iteration cap reached
  LineSearchFailed,     ///< Armijo condition not met within max_backtracks
  /// No decrease possible although above the tolerance: the violation is within 10x the residual's
  /// round-off floor (the change of r caused by one unit in the last place of lambda_0).
  Stalled,
  SingularSensitivity,  ///< the Newton system could not be solved (non-finite step)
  SweepFailed,          ///< the sweep from the initial guess failed (rotation update)
  InvalidInput,         ///< bad problem or options (message names the field)
  /// A value of the iteration history or of the result is not finite (the message names it and
  /// the iteration): never a success (or an iteration limit, a line search failure) with an inf
  /// or NaN in its files. SingularSensitivity and SweepFailed keep their own status.
  NonFiniteValue,
};
const char* to_string(ShootingStatus s);

/// Merit function of the line search (the violation reported and tested is always |r|).
enum class Merit {
  Velocity,  ///< |r|, r = [log(R_f^T R_N); dx; dOmega; dv]
  Momentum,  ///< |[log(R_f^T R_N); dx; J dOmega; m dv]|: errors weighted as the LGVI's momenta
};
const char* to_string(Merit m);
/// Parses "velocity" or "momentum"; throws InvalidInput("merit", ...).
Merit parse_merit(const std::string& name);

/// Globalization of the shooting's Newton iteration. NewtonArmijo: the paper's (Newton direction,
/// Armijo backtracking on the merit). LevenbergMarquardt: damped Gauss-Newton steps
/// (J^T J + mu diag(J^T J)) d = -J^T r on the merit's weighted residual, mu adapted from the ratio
/// of actual to predicted reduction (Madsen, Nielsen, Tingleff 2004, sec. 3.2); it uses the full
/// system (no symmetry decomposition: a rank-deficient J is regularized by the damping).
/// Homotopy: Newton homotopy path following (newton_armijo.hpp, newton_homotopy) from the guess to
/// tau = 1, then Newton-Armijo's end game; it follows the path the damped Newton iteration
/// approximates, so it reaches Newton-Armijo's extremal with fewer Jacobians (lgvi/ocp/README.md).
/// Continuation: the same path followed with a Hermite predictor, Broyden corrector and the exact
/// Jacobian only at accepted path points (newton_continuation), then Newton-Armijo's end game;
/// the same extremal in fewer Jacobians (lgvi/ocp/README.md).
enum class Globalization { NewtonArmijo, LevenbergMarquardt, Homotopy, Continuation };
const char* to_string(Globalization g);
/// Parses "newton-armijo", "levenberg-marquardt", "homotopy" or "continuation"; throws
/// InvalidInput("globalization", ...).
Globalization parse_globalization(const std::string& name);

/// Settings of newton_continuation (validated by the caller).
struct ContinuationSettings {
  double initial_step = 0.05;  ///< first step in tau (measured on the dumbbell: 0.02 / 0.05 / 0.1 / 0.3 gave
                               ///< 54 / 34 / 46 / 41 outer iterations; lgvi/ocp/README.md)
  /// Step control: the next step is chosen so that the predicted point's homotopy residual
  /// |H(lambda_pred, tau)| is about this fraction of |r_start| (a point the corrector reaches in
  /// 2-3 steps); the predictor's error is O(dtau^p), p = 2 (tangent) or 4 (Hermite).
  double predictor_target = 0.1;
  double corrector_tolerance = 1e-2;  ///< accept a path point at |H| <= this |r_start|
  int max_corrector = 6;              ///< quasi-Newton corrector steps per tau step
  double max_growth = 4.0;            ///< bound on dtau_next / dtau
};


struct ShootingOptions {
  LgviForm form = LgviForm::Symmetric;
  double h = 1e-3;                     ///< t_final / h must be an integer (to 1e-9 relative)
  Eigen::MatrixXd W;                   ///< n_u x n_u symmetric positive definite; empty: identity
  Eigen::VectorXd initial_multiplier;  ///< lambda_0 guess (2 n_q); empty: zero
  /// Symmetry decomposition (systems with a symmetry): invert the shape block only.
  bool decomposition = true;
  Merit merit = Merit::Velocity;
  Globalization globalization = Globalization::NewtonArmijo;
  int max_iterations = 100;
  int max_backtracks = 30;     ///< step halvings (Levenberg-Marquardt: rejected steps) per outer iteration
  /// Levenberg-Marquardt: the initial damping mu_0, relative to diag(J^T J) (> 0).
  double lm_initial_damping = 1e-3;
  /// Armijo test against the largest merit of the last this many accepted points (Grippo,
  /// Lampariello, Lucidi 1986); 1: the classical monotone test.
  int nonmonotone_memory = 1;
  /// Homotopy: the first step in tau (doubled after easy corrections, halved after failed ones).
  double homotopy_initial_step = 0.1;
  /// Continuation: predictor / corrector settings.
  ContinuationSettings continuation;
  double armijo = 1e-4;        ///< sufficient decrease |r(l + t d)| <= (1 - armijo t) |r(l)|
  double tolerance = 1e-12;    ///< on the violation
  /// After reaching the tolerance, up to this many more full Newton steps, kept while they lower
  /// the violation (reaches the round-off floor).
  int polish_iterations = 3;
  RotationUpdateOptions rotation;

  // The ranges of the settings (the [ocp.indirect] table, the ocp command's options and the
  // Python module state and check the same, through validate() or these Ranges).
  static constexpr Range kMaxIterations = Range::integers(1, 1e6);
  static constexpr Range kMaxBacktracks = Range::integers(0, 1000);  ///< 2^-1000 underflows a step
  /// Levenberg-Marquardt's damping is adapted by factors of 2-10 per iteration; a start above
  /// 1e10 diag(J^T J) takes steps of 1e-10 of a gradient step and spends the iteration cap first.
  static constexpr Range kLmInitialDamping = Range::above(0, 1e10);
  static constexpr Range kNonmonotoneMemory = Range::integers(1, 1000);
  /// On the violation |r| (rad, rad/s, ...): above 0.1 the terminal state is missed by more than
  /// the attitude of 6 deg, no solution of the transfer.
  static constexpr Range kTolerance = Range::above(0, 0.1);
  static constexpr Range kPolishIterations = Range::integers(0, 100);

  /// Throws InvalidInput naming the first setting outside its range (by its member's name:
  /// "max_iterations", "lm_initial_damping", "continuation.max_growth") with the range and the
  /// value, "must be an integer in [1, 1000000] (got 0)"; an initial_multiplier entry that is
  /// not finite or not admissible (range.hpp: 0 or of magnitude in [1e-100, 1e100]). Its size is
  /// the model's (solve_indirect checks it). h and W are the flow's (StateMultiplierFlow).
  void validate() const;
};

/// One outer Newton-Armijo iteration (the state at its start and the step it took).
struct IterationRecord {
  int iteration = 0;
  double violation = 0.0;       ///< at the start of the iteration
  double cost = 0.0;
  double step_length = 0.0;     ///< accepted t (0 when none)
  int backtracks = 0;           ///< inner iterations (step halvings)
  double cond_sensitivity = 0.0;  ///< 2-norm condition number of dr/dlambda_0 (full)
  double cond_inverted = 0.0;     ///< of the matrix actually inverted (shape block or full)
  double step_norm = 0.0;       ///< |d lambda_0| of the Newton direction
  double group_residual = 0.0;  ///< |component of r along the symmetry's range direction|
  double group_block = 0.0;     ///< max |off-diagonal/group block| of U^T (dr/dl) V, relative
  int sweeps = 0;               ///< cumulative sweeps (1 per outer + 1 per trial)
  double seconds = 0.0;         ///< cumulative wall time
};

struct ShootingSummary {
  ShootingStatus status = ShootingStatus::InvalidInput;
  std::string message;
  std::string system;
  LgviForm form = LgviForm::Symmetric;
  double h = 0.0;
  std::size_t steps = 0;
  bool decomposition = false;  ///< whether it was used
  Globalization globalization = Globalization::NewtonArmijo;
  int iterations = 0;          ///< outer (Newton) iterations
  int inner_iterations = 0;    ///< backtracking trials
  int sweeps = 0;
  double cost = std::numeric_limits<double>::infinity();       ///< inf until a sweep succeeded
  double violation = std::numeric_limits<double>::infinity();  ///< inf until a sweep succeeded
  Eigen::VectorXd residual;     ///< r at the end (see the header comment)
  double cond_min = 0.0;        ///< over iterations, of the matrix inverted
  double cond_max = 0.0;
  double cond_full_min = 0.0;   ///< of the full sensitivity dr/dlambda_0
  double cond_full_max = 0.0;
  double wall_seconds = 0.0;
  Eigen::VectorXd multiplier_guess;
  Eigen::VectorXd multiplier;   ///< lambda_0 at the end
  std::vector<IterationRecord> history;

  bool converged() const { return status == ShootingStatus::Converged; }
  /// One line, e.g. "converged in 23 iterations (41 backtracks): violation 3.1e-15, cost 7.29".
  std::string brief() const;
};

/// The state-multiplier flow of the necessary conditions for one model, its sensitivities and
/// the terminal residual. Immutable after construction; run() allocates only `out`'s vectors.
template <class Model>
class StateMultiplierFlow {
 public:
  static constexpr int nq = Model::nq;
  static constexpr int nu = Model::nu;
  static constexpr int ns = 2 * nq;
  using System = typename Model::System;
  using State = typename Model::State;
  using VecS = typename Model::VecS;
  using MatS = typename Model::MatS;
  using VecU = typename Model::VecU;
  using MatU = typename Model::MatU;

  /// Validates h > 0, t_final / h integral, W symmetric positive definite (n_u x n_u), the
  /// boundary rotations orthonormal, all values finite. Throws InvalidInput naming the field.
  StateMultiplierFlow(const System& system, const TransferProblem& problem, LgviForm form, double h,
                      const Eigen::MatrixXd& W, RotationUpdateOptions rotation = {});

  struct Sweep {
    std::vector<State> states;      ///< s_0..s_N (up to the failure)
    std::vector<VecU> controls;     ///< u_0..u_N
    std::vector<VecS> multipliers;  ///< lambda_0..lambda_N (costate of s_k)
    double cost = 0.0;
    bool ok = false;
    std::size_t failed_step = 0;    ///< the step k -> k+1 whose rotation update failed
    RotationUpdateSummary failure;
    const char* non_finite = nullptr;  ///< the part of s_{k+1} that overflowed (failure converged)
    VecS residual = VecS::Zero();
    MatS Psi12 = MatS::Zero();      ///< d w_N / d lambda_0 (w coordinates)
    MatS Psi22 = MatS::Zero();      ///< d lambda_N / d lambda_0
    MatS jacobian = MatS::Zero();   ///< d r / d lambda_0 = D Psi12
  };

  /// Sweeps forward from (s_0, lambda0); with `sensitivities` also the exact tangents.
  /// Returns out.ok; on failure out says at which step and why.
  bool run(const VecS& lambda0, bool sensitivities, Sweep& out) const;
  /// Sweeps with given controls u_0..u_N (not from multipliers): for gradient tests.
  bool simulate(const std::vector<VecU>& controls, Sweep& out) const;
  /// "rotation update failed at step k (t = ...): ..." for a failed sweep.
  std::string failure_message(const Sweep& failed) const;

  /// Terminal residual r(s_N) and D = d r / d w_N.
  VecS residual(const State& sN) const;
  MatS residual_jacobian(const State& sN, const VecS& r) const;
  /// The optimality condition u = -W^{-1} B(q)^T lambda_P at a node.
  VecU control_from_multiplier(const State& s, const VecS& lambda) const;
  double cost_weight(std::size_t node) const;
  double cost(const std::vector<VecU>& controls) const;

  const Model& model() const { return model_; }
  const typename Model::Lgvi& lgvi() const { return lgvi_; }
  const State& initial_state() const { return initial_; }
  const TransferProblem& problem() const { return problem_; }
  std::size_t steps() const { return steps_; }
  double h() const { return h_; }
  const MatU& W() const { return W_; }

 private:
  Model model_;
  typename Model::Lgvi lgvi_;
  TransferProblem problem_;
  double h_;
  std::size_t steps_;
  MatU W_;
  MatU W_inverse_;
  State initial_;
};

/// The trajectory of a shooting result, for output.
template <class Model>
struct ShootingResult {
  ShootingSummary summary;
  typename StateMultiplierFlow<Model>::Sweep sweep;  ///< the final sweep (states, controls, multipliers)
};

/// Newton-Armijo shooting on lambda_0 (Kelley, "Solving nonlinear equations with Newton's
/// method", 2003, sec. 1.10: direction d = -(dr/dlambda)^{-1} r, step t = 1, 1/2, 1/4, ...
/// until |r(lambda + t d)| <= (1 - armijo t) |r(lambda)|; a trial whose sweep fails counts as
/// not decreasing). With the symmetry decomposition (systems with has_symmetry), the
/// sensitivity is written in orthonormal bases [V_s v_g] of the multipliers and [U_s u_g] of
/// the residuals, v_g the symmetry's multiplier direction dC(s_0) (adding it changes no
/// control: lambda_k + a dC(s_k) solves the same recursion, B^T dC = 0) and u_g = D^{-T} dC(s_N)
/// (dC(s_N)^T Psi12 = 0: no lambda_0 changes the conserved quantity); then
/// U^T (dr/dlambda) V = [S 0; 0 0] and d = -V_s S^{-1} U_s^T r. The line search tests
/// options.merit (|r| or its momentum-weighted version); convergence is always |r| <= tolerance.
/// Never throws; bad input becomes status InvalidInput with a message naming the field.
ShootingResult<PendulumModel> solve_indirect(const Pendulum3D& system, const TransferProblem& problem,
                                             const ShootingOptions& options);
ShootingResult<DumbbellModel> solve_indirect(const DumbbellSpacecraft& system,
                                             const TransferProblem& problem, const ShootingOptions& options);

/// The free body's rest-to-rest (or any) attitude transfer with a body-frame control moment.
ShootingResult<FreeBodyModel> solve_indirect(const FreeRigidBody& system, const TransferProblem& problem,
                                             const ShootingOptions& options);

extern template class StateMultiplierFlow<PendulumModel>;
extern template class StateMultiplierFlow<FreeBodyModel>;
extern template class StateMultiplierFlow<DumbbellModel>;

}  // namespace lgvi::ocp
