// Direct discrete optimal control (sections 4.1, 4.2): controls parameterized by their values at
// n knots per component, interpolated by cubic splines (spline.hpp), the LGVI run forward, the
// cost (eqs. 38, 48) and the terminal constraints on the Lie group with exact gradients through
// the linearized discrete flow, optimized by SQP (NLopt's SLSQP).
//
// Discrete problem. Controls sit at the grid nodes t_j = j h, j = 0..N, sampled from the spline:
// u_j = S_j c (S: spline_sampling_matrix, c the knot values; u_j(a) = S(j, :) c_a for component
// a, c = [c_0; c_1; ...] component by component). Step k is the integrator's
// step(s_k, h, u_k, u_{k+1}); cost J = sum_j w_j/2 u_j^T W u_j with w_0 = c0, w_N = c1,
// w_j = h otherwise (printed form: w_0 = 0, exactly eqs. 38, 48; see indirect.hpp).
//
// Terminal constraints r(s_N) = 0:
//   cart-pendulum:    [log(R_N^T R_f)^vee; q_N - q_f; Omega_N - Omega_f; q'_N - q'_f]       (10)
//   connected bodies: [log(R1_N^T R1_f)^vee; log(R2_N^T R2_f)^vee; Omega1_N - Omega1_f]    (9)
// For the connected bodies the terminal Omega2 is dropped (section 4.2): the control is
// internal, R1 Pi1 + R2 Pi2 is conserved, so with zero initial momentum and the other nine
// conditions met Omega2_N = Omega2_f = 0 follows; kept, it makes the constraint Jacobian rank
// deficient by 3 (DirectOptions::keep_redundant_constraint, tested). The reported violation is the
// 2-norm of the FULL terminal condition (with Omega2), in the paper's variables.
//
// Gradients (derivation in README.md): forward sensitivities. Each step is linearized at its
// converged solution by the implicit function theorem in left-trivialized tangent coordinates
// (dR = R hat(eta)): w_{k+1} = A_k w_k + B0_k du_k + B1_k du_{k+1}, and
// Phi_{k+1} = dw_{k+1}/dc = A_k Phi_k + B0_k S_k + B1_k S_{k+1}; dr/dc = D Phi_N, D = dr/dw_N.
// Forward rather than adjoint: one sweep carries all n_u n columns (14, 21) together with the
// simulation; the adjoint needs the stored trajectory and one backward sweep per constraint row
// (10, 9), i.e. about the same work, more memory, and a second pass.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "lgvi/multibody_lgvi.hpp"
#include "lgvi/range.hpp"
#include "lgvi/ocp/spline.hpp"
#include "lgvi/ocp/step_failure.hpp"

namespace lgvi::ocp {

/// Section 4.1 boundary conditions: rest to rest, R0 = I, Rf = diag(-1, -1, 1), cart back at the
/// origin, T = 2 s.
struct CartPendulumTransfer {
  Mat3 R0 = Mat3::Identity();
  Vec2 q0 = Vec2::Zero();
  Vec3 Omega0 = Vec3::Zero();
  Vec2 q_dot0 = Vec2::Zero();
  Mat3 Rf = Mat3::Identity();
  Vec2 qf = Vec2::Zero();
  Vec3 Omegaf = Vec3::Zero();
  Vec2 q_dotf = Vec2::Zero();
  double t_final = 2.0;
  static CartPendulumTransfer paper();
};

/// Section 4.2 boundary conditions: rest to rest, R1_0 = R2_0 = I, R1_f = R2_f = diag(1, -1, -1),
/// T = 4 s.
struct ConnectedBodiesTransfer {
  Mat3 R1_0 = Mat3::Identity(), R2_0 = Mat3::Identity();
  Vec3 Omega1_0 = Vec3::Zero(), Omega2_0 = Vec3::Zero();
  Mat3 R1_f = Mat3::Identity(), R2_f = Mat3::Identity();
  Vec3 Omega1_f = Vec3::Zero(), Omega2_f = Vec3::Zero();
  double t_final = 4.0;
  static ConnectedBodiesTransfer paper();
};

/// The fixed-size types of a direct model: tangent dimension NW, NU control components, NR
/// terminal conditions imposed of NR_FULL (the full terminal residual).
template <int NW, int NU, int NR, int NR_FULL>
struct DirectModelDimensions {
  static constexpr int nw = NW, nu = NU, nr = NR, nr_full = NR_FULL;
  using VecU = Eigen::Matrix<double, nu, 1>;
  using MatW = Eigen::Matrix<double, nw, nw>;
  using MatWU = Eigen::Matrix<double, nw, nu>;
  using VecR = Eigen::Matrix<double, nr_full, 1>;
  using MatRW = Eigen::Matrix<double, nr_full, nw>;
  using VecW = Eigen::Matrix<double, nw, 1>;
};

/// The linearized step and the terminal residual of the cart-pendulum. Tangent coordinates
/// w = [eta (3); dq (2); dPi (3); dp (2)], R -> R exp(hat eta).
struct CartPendulumDirectModel : DirectModelDimensions<10, 2, 10, 10> {
  using System = CartPendulum;
  using Lgvi = CartPendulumLgvi;
  using State = CartPendulumState;
  using Transfer = CartPendulumTransfer;

  // The linearized step (A, B0, B1): Lgvi::linearize, beside the flow (lgvi/multibody_lgvi.*).
  /// Full terminal residual (see the header comment) and its Jacobian D = dr/dw_N.
  static VecR residual(const Lgvi& lgvi, const Transfer& p, const State& sN);
  static MatRW residual_jacobian(const Lgvi& lgvi, const Transfer& p, const State& sN);
  static State initial_state(const Lgvi& lgvi, const Transfer& p) {
    return lgvi.make_state(p.R0, p.q0, p.Omega0, p.q_dot0);
  }
  static State final_state(const Lgvi& lgvi, const Transfer& p) {
    return lgvi.make_state(p.Rf, p.qf, p.Omegaf, p.q_dotf);
  }
  /// Multiple shooting's chart: the first 3 * rotations tangent coordinates are rotation vectors
  /// (R -> R exp(hat eta)), the rest is added. retract(a, w) moves a by w; difference(a, b) is the
  /// w with retract(a, w) = b (log(R_a^T R_b) for the rotation, |angle| < pi).
  static constexpr int rotations = 1;
  static State retract(const Lgvi& lgvi, const State& a, const VecW& w);
  static VecW difference(const State& a, const State& b);
  /// The chart vector of the geodesic guess (ShootingStateGuess::Geodesic): difference(a, b).
  static VecW geodesic_difference(const Lgvi&, const State& a, const State& b) { return difference(a, b); }
};

/// The same for the connected bodies: w = [eta1; eta2; dPi1; dPi2]. The residual's last three
/// rows (Omega2_N - Omega2_f) are the redundant ones, dropped unless kept on request.
struct ConnectedBodiesDirectModel : DirectModelDimensions<12, 3, 9, 12> {
  using System = ConnectedBodies;
  using Lgvi = ConnectedBodiesLgvi;
  using State = ConnectedBodiesState;
  using Transfer = ConnectedBodiesTransfer;

  static VecR residual(const Lgvi& lgvi, const Transfer& p, const State& sN);
  static MatRW residual_jacobian(const Lgvi& lgvi, const Transfer& p, const State& sN);
  static State initial_state(const Lgvi& lgvi, const Transfer& p) {
    return lgvi.make_state(p.R1_0, p.R2_0, p.Omega1_0, p.Omega2_0);
  }
  static State final_state(const Lgvi& lgvi, const Transfer& p) {
    return lgvi.make_state(p.R1_f, p.R2_f, p.Omega1_f, p.Omega2_f);
  }
  static constexpr int rotations = 2;  ///< see CartPendulumDirectModel::retract
  static State retract(const Lgvi& lgvi, const State& a, const VecW& w);
  static VecW difference(const State& a, const State& b);
  /// The chart vector of the geodesic guess: difference(a, b), except that where body 2's
  /// rotation is a half turn (angle within 1e-9 of pi, the cut locus: +phi and -phi are both
  /// minimal geodesics) turning the same way as body 1, body 2 takes the other branch: the bodies
  /// turn in opposite directions. A choice by measurement (README): for section 4.2's half turns
  /// about x the opposite turns lead all 8 starts to the 0.0651 / 0.1015 optima, the same-way
  /// turns to 0.3456..0.4658. (Not the guess of smaller angular momentum: by eq. 47's momentum
  /// map at the initial attitudes the same-way turns carry less.)
  static VecW geodesic_difference(const Lgvi& lgvi, const State& a, const State& b);
};

/// Tangent retraction for tests: the state moved by w (R -> R exp(hat eta), the rest added).
CartPendulumState perturb(const CartPendulumState& s, const CartPendulum& system,
                          const Eigen::Matrix<double, 10, 1>& w);
ConnectedBodiesState perturb(const ConnectedBodiesState& s, const Eigen::Matrix<double, 12, 1>& w);

enum class GradientMethod { Exact, FiniteDifference };
const char* to_string(GradientMethod g);
/// Parses "exact" or "finite-difference"; throws InvalidInput("gradients", ...).
GradientMethod parse_gradient_method(const std::string& name);

/// The optimizer of the direct method. Slsqp: the paper's single shooting, SLSQP on the knot
/// values. IpoptMultipleShooting: the same problem (same knots, cost, terminal constraints)
/// transcribed by multiple shooting (the states at every shooting_interval-th node become
/// variables, the LGVI runs between them become equality constraints) and solved by IPOPT
/// (README "Multiple shooting with IPOPT").
enum class DirectSolver { Slsqp, IpoptMultipleShooting };
const char* to_string(DirectSolver s);
/// Parses "slsqp" or "ipopt"; throws InvalidInput("solver", ...).
DirectSolver parse_direct_solver(const std::string& name);

/// The Hessian of the Lagrangian IPOPT uses. LimitedMemory: IPOPT's L-BFGS. CostOnly: the
/// exact Hessian of the cost, the constraints' curvature left out (generalized Gauss-Newton).
/// Exact: the Hessian of the Lagrangian sigma J + y^T g, by forward differences of its exact
/// gradient sigma grad J + Jac(g)^T y (the step linearizations' exact first derivatives), one
/// colour group of columns per difference (direct_ipopt.cpp); not analytic second derivatives.
enum class IpoptHessian { LimitedMemory, CostOnly, Exact };
const char* to_string(IpoptHessian h);
/// Parses "limited-memory", "cost" or "exact"; throws InvalidInput("hessian", ...).
IpoptHessian parse_ipopt_hessian(const std::string& name);

/// Multiple shooting's initial guess for the state variables (the references ref_j, z_j = 0).
/// Simulated: the LGVI run under the start's guess control (zero defects, the single-shooting
/// start). Geodesic: the boundary states interpolated in the chart of Model::retract at the
/// nodes' times, ref_j = retract(s_0, t_j/T d), d = Model::geodesic_difference(s_0, s_f): rotations
/// along a geodesic R_0 exp(t/T phi), phi = log(R_0^T R_f) (at half turns the model picks the
/// branch), the other coordinates (positions, momenta) linearly.
enum class ShootingStateGuess { Simulated, Geodesic };
const char* to_string(ShootingStateGuess g);
/// Parses "simulated" or "geodesic"; throws InvalidInput("state_guess", ...).
ShootingStateGuess parse_shooting_state_guess(const std::string& name);

struct DirectOptions {
  LgviForm form = LgviForm::Printed;  ///< printed: the paper's eqs. 34-35, 44-45 and cost 38, 48
  double h = 0.01;                    ///< t_final / h must be an integer (to 1e-9 relative)
  int knots = 7;                      ///< per control component, >= 3
  SplineEnd spline = SplineEnd::NotAKnot;
  GradientMethod gradients = GradientMethod::Exact;
  Eigen::MatrixXd W;              ///< n_u x n_u symmetric positive definite; empty: identity
  Eigen::VectorXd initial_knots;  ///< n_u * knots values, component by component; empty: default
  DirectSolver solver = DirectSolver::Slsqp;
  /// IPOPT: LGVI steps per shooting segment (1: every state a variable, DMOC's full transcription;
  /// 40 measured best with the geodesic guess, README).
  int shooting_interval = 40;
  IpoptHessian ipopt_hessian = IpoptHessian::LimitedMemory;
  ShootingStateGuess state_guess = ShootingStateGuess::Geodesic;  ///< IPOPT's state variables
  int max_evaluations = 3000;     ///< SLSQP function evaluations per start; IPOPT: iterations per start
  double tolerance = 1e-10;       ///< on the violation (2-norm), checked on the returned point
  double ftol_rel = 1e-14;        ///< SLSQP's relative cost tolerance
  /// The objective handed to SLSQP is J / objective_scale; 0: automatic, the mean diagonal of
  /// the cost's Hessian in the knots (README "SLSQP").
  double objective_scale = 0.0;
  /// Multistart: start 0 from initial_knots (or the default guess), starts 1.. from seeded
  /// N(0, guess_scale^2) knot values (guess_scale 0: the system's default_guess_scale). The
  /// result is the feasible start of lowest cost.
  int starts = 1;
  /// The number of the first start run: starts first_start .. first_start + starts - 1 of the
  /// seeded sequence (start 0 is the default guess), so one start of a multistart can be rerun
  /// alone (the regression gate reruns the connected bodies' converging start) or a multistart
  /// split over processes.
  int first_start = 0;
  std::uint64_t seed = 1;
  double guess_scale = 0.0;
  /// Connected bodies: keep the terminal Omega2 among the constraints (rank deficient; tests).
  bool keep_redundant_constraint = false;
  /// Rows of the full terminal residual handed to SLSQP (free terminal components are left out);
  /// empty: the model's default (all but the redundant ones). Overrides keep_redundant_constraint.
  std::vector<int> constraint_rows;
  GroupNewtonOptions newton;

  // The ranges of the settings (the [ocp.direct] table, the ocp command's options and the
  // Python module state and check the same, through validate() or these Ranges).
  static constexpr Range kKnots = Range::integers(3, 1000);
  static constexpr Range kShootingInterval = Range::integers(1, 1e6);
  static constexpr Range kMaxEvaluations = Range::integers(1, 1e8);
  /// On the violation (2-norm; rad, m, rad/s, m/s): above 0.1 no solution of the transfer.
  static constexpr Range kTolerance = Range::above(0, 0.1);
  static constexpr Range kStarts = Range::integers(1, 10000);
  /// Start K draws K knot sets from the seeded sequence: 10^6 of them take a fraction of a second.
  static constexpr Range kFirstStart = Range::integers(0, 1e6);
  /// The seeds a reader of the options accepts (a scene's integer, a command-line option; the
  /// generator takes any 64-bit seed, validate() does not check it).
  static constexpr Range kSeed = Range::integers(0, 2147483647);

  /// Throws InvalidInput naming the first setting outside its range (by its member's name:
  /// "knots", "max_evaluations") with the range and the value, "must be an integer in [3, 1000]
  /// (got 2)"; an initial_knots entry that is not finite or not admissible (range.hpp). The
  /// sizes and the knots' fit in the grid are the transcription's (DirectTranscription).
  void validate() const;
};

enum class DirectStatus {
  Converged,         ///< SLSQP reported success and the returned point's violation <= tolerance
  Infeasible,        ///< SLSQP reported success but the violation is above the tolerance
  RoundoffLimited,   ///< SLSQP stopped on round-off (e.g. rank-deficient constraints)
  MaxEvaluations,    ///< evaluation cap reached
  SimulationFailed,  ///< a rotation update did not converge (message: step, time, residual)
  SolverFailure,     ///< any other NLopt failure
  InvalidInput,      ///< bad problem or options (message names the field)
  /// A start's history or result holds a non-finite value (the summary's message names the first
  /// such start and value); the start is not a candidate for the best.
  NonFiniteValue,
};
const char* to_string(DirectStatus s);

/// One SLSQP function evaluation at a new point: NLopt's SLSQP asks for gradients at each new
/// iterate (one per SQP iteration) and for values only at its line-search trials.
struct DirectIteration {
  int evaluation = 0;
  int start = 0;           ///< which start of a multistart (DirectOptions::starts)
  bool gradient = false;   ///< an SQP iterate (gradients requested), not a line-search trial
  double cost = 0.0;
  double violation = 0.0;  ///< 2-norm of the constraints handed to SLSQP
  double seconds = 0.0;    ///< cumulative wall time
};

/// The outcome of one start of a multistart.
struct DirectStart {
  int index = 0;
  DirectStatus status = DirectStatus::SolverFailure;
  std::string nlopt_result;  ///< the solver's return code (NLopt's, or IPOPT's e.g. "Solve_Succeeded")
  double cost = std::numeric_limits<double>::infinity();
  double violation = std::numeric_limits<double>::infinity();
  int iterations = 0;
  int evaluations = 0;
  int gradient_evaluations = 0;
  double seconds = 0.0;
  Eigen::VectorXd initial_knots, knot_values;
};

struct DirectSummary {
  DirectStatus status = DirectStatus::InvalidInput;
  std::string message;
  std::string nlopt_result;  ///< the solver's return code, e.g. "NLOPT_FTOL_REACHED" or IPOPT's "Solve_Succeeded"
  std::string system;
  LgviForm form = LgviForm::Printed;
  SplineEnd spline = SplineEnd::NotAKnot;
  GradientMethod gradients = GradientMethod::Exact;
  DirectSolver solver = DirectSolver::Slsqp;
  double h = 0.0;
  std::size_t steps = 0;
  int knots = 0;
  int constraints = 0;            ///< rows handed to SLSQP
  int iterations = 0;             ///< SQP iterations: points where SLSQP asked for gradients
  int evaluations = 0;            ///< points evaluated (iterates and line-search trials)
  int gradient_evaluations = 0;   ///< evaluations of the gradients (exact or by differences)
  long simulations = 0;           ///< forward runs of the LGVI (incl. the difference runs)
  int failed_simulations = 0;     ///< trial points whose LGVI run failed (cost reported as +inf)
  double cost = std::numeric_limits<double>::infinity();
  double violation = std::numeric_limits<double>::infinity();  ///< full terminal condition
  double constraint_violation = std::numeric_limits<double>::infinity();  ///< rows given to SLSQP
  Eigen::VectorXd residual;       ///< full terminal residual at the end
  Eigen::VectorXd initial_knots;
  Eigen::VectorXd knot_values;    ///< at the end, component by component
  double wall_seconds = 0.0;
  std::vector<DirectIteration> history;  ///< all starts
  std::vector<DirectStart> starts;
  int best_start = -1;            ///< position in `starts` of the start reported (status, cost, knots)
  std::string last_failure;       ///< the last failed trial simulation, if any

  bool converged() const { return status == DirectStatus::Converged; }
  /// One line, e.g. "converged (NLOPT_FTOL_REACHED) after 45 iterations (60 evaluations, ...): cost ...".
  std::string brief() const;
};

/// The transcription: knot values -> node controls -> LGVI run -> cost, constraints and their
/// exact gradients. Immutable after construction; evaluate() allocates only on its first call
/// with a given Evaluation (buffers are reused).
template <class Model>
class DirectTranscription {
 public:
  static constexpr int nw = Model::nw;
  static constexpr int nu = Model::nu;
  using System = typename Model::System;
  using State = typename Model::State;
  using Transfer = typename Model::Transfer;
  using VecU = typename Model::VecU;
  using NodeControls = Eigen::Matrix<double, nu, Eigen::Dynamic>;  ///< u_0..u_N as columns

  /// Validates h, t_final / h integral, knots >= 3, W, the boundary rotations. Throws InvalidInput.
  DirectTranscription(const System& system, const Transfer& problem, const DirectOptions& options);

  struct Evaluation {
    bool ok = false;
    std::size_t failed_step = 0;
    RotationUpdateSummary failure;
    const char* non_finite = nullptr;  ///< the part of s_{k+1} that overflowed (failure converged)
    double cost = 0.0;
    Eigen::VectorXd cost_gradient;           ///< n_u * knots
    Eigen::VectorXd constraints;             ///< rows handed to the optimizer
    Eigen::MatrixXd constraint_jacobian;     ///< constraints x (n_u * knots)
    typename Model::VecR residual;           ///< full terminal residual
    Eigen::Matrix<double, nw, Eigen::Dynamic> Phi, Phi_next;  ///< sensitivity buffers
    NodeControls controls;                                     ///< u_0..u_N (columns)
  };

  int parameters() const { return nu * knots_; }
  int constraints() const { return static_cast<int>(rows_.size()); }
  /// Runs the LGVI with the controls of knot values c; with `gradients`, also the exact gradients
  /// of the cost and of the constraints. Returns e.ok.
  bool evaluate(const Eigen::VectorXd& c, bool gradients, Evaluation& e) const;
  /// The same gradients by central differences (step a (1 + |c_i|), a = cbrt(eps)).
  bool evaluate_finite_difference(const Eigen::VectorXd& c, Evaluation& e) const;
  /// The states s_0..s_N for output (empty on failure).
  std::vector<State> trajectory(const Eigen::VectorXd& c) const;
  /// u_0..u_N (columns) of knot values c.
  NodeControls node_controls(const Eigen::VectorXd& c) const;
  std::string failure_message(const Evaluation& e) const;

  // --- multiple shooting (DirectSolver::IpoptMultipleShooting) ---------------------------------
  // Variables x = [c (n_u * knots); z_1; ...; z_{K-1}]: the knot values, then the states at the
  // shooting nodes n_1 < ... < n_{K-1} (n_j = j * interval, n_0 = 0, n_K = N) in the chart
  // s_j = retract(ref_j, z_j) about reference states ref_j. Constraints: the defects
  // difference(s_{j+1}, Phi_j(s_j, c)) = 0, j = 0..K-2 (Phi_j: the LGVI from n_j to n_{j+1} under
  // the spline controls), then the terminal rows r(Phi_{K-1}(s_{K-1}, c)) = 0. The cost, the
  // terminal rows and the controls are those of single shooting: one problem, two transcriptions.
  struct ShootingNodes {
    std::vector<std::size_t> nodes;  ///< n_0 = 0 < n_1 < ... < n_K = N
    std::vector<State> reference;    ///< ref_1..ref_{K-1} (at nodes[1..K-1])
    int segments() const { return static_cast<int>(nodes.size()) - 1; }
  };
  /// Nodes every `interval` steps, references by `guess`: simulating the knot values c (the guess
  /// control) or the geodesic between the boundary states (ShootingStateGuess). Returns false
  /// (and leaves the failure in e) when the simulation fails.
  bool shooting_nodes(const Eigen::VectorXd& c, int interval, ShootingStateGuess guess, ShootingNodes& nodes,
                      Evaluation& e) const;
  int shooting_variables(const ShootingNodes& n) const { return parameters() + (n.segments() - 1) * nw; }
  int shooting_constraints(const ShootingNodes& n) const { return (n.segments() - 1) * nw + constraints(); }
  /// The constraint Jacobian's dense blocks in the order evaluate_shooting fills jacobian_values
  /// (each block row-major): for segment j, rows j*nw.., the columns of c, of z_j (j >= 1) and of
  /// z_{j+1} (j < K-1). Appends (row, column) pairs of all nonzeros to rows/cols.
  void shooting_structure(const ShootingNodes& n, std::vector<int>& rows, std::vector<int>& cols) const;
  struct ShootingEvaluation {
    bool ok = false;
    std::size_t failed_step = 0;
    RotationUpdateSummary failure;
    const char* non_finite = nullptr;  ///< the part of s_{k+1} that overflowed (failure converged)
    double cost = 0.0;
    Eigen::VectorXd cost_gradient;     ///< with respect to x (zero on the z block)
    Eigen::VectorXd constraints;       ///< defects, then the terminal rows
    std::vector<double> jacobian_values;  ///< in shooting_structure's order
    Eigen::Matrix<double, nw, Eigen::Dynamic> knot_rows;  ///< a segment's rows' derivatives in c (buffer)
    NodeControls controls;
    /// The simulated states, segment by segment: segment j's start state and the states after
    /// each of its steps at positions n_j + j .. n_{j+1} + j (N + K states).
    std::vector<State> states;
  };
  /// The constraints (and with `gradients` their exact sparse Jacobian, by a reverse sweep of
  /// the step linearizations per segment, and the cost gradient) at x. Returns e.ok.
  bool evaluate_shooting(const ShootingNodes& n, const Eigen::VectorXd& x, bool gradients,
                         ShootingEvaluation& e) const;
  /// The gradients of evaluate_shooting(n, x, true, e) for an e that holds a successful
  /// evaluate_shooting(n, x, false, e) at the same x: the step linearizations along the stored
  /// states, no rotation update solved again (the same numbers as evaluating with gradients).
  void shooting_gradients(const ShootingNodes& n, const Eigen::VectorXd& x, ShootingEvaluation& e) const;

  const typename Model::Lgvi& lgvi() const { return lgvi_; }
  const Transfer& problem() const { return problem_; }
  const Eigen::MatrixXd& sampling() const { return S_; }
  double node_weight(Eigen::Index j) const { return node_weights_(j); }
  const Eigen::Matrix<double, nu, nu>& weight() const { return W_; }
  std::size_t steps() const { return steps_; }
  double h() const { return h_; }
  int knots() const { return knots_; }

 private:
  /// u_j = (S c)_j at the N+1 nodes into e.controls and the cost sum_j w_j u_j^T W u_j / 2 into
  /// e.cost; with `gradients`, its gradient in the knots added to the head of e.cost_gradient
  /// (sized and zeroed by the caller).
  template <class E>
  void sample_controls_and_cost(const Eigen::VectorXd& c, bool gradients, E& e) const;
  /// Steps `s` over [k_begin, k_end) with e.controls; with `gradients` (an Evaluation: single
  /// shooting), carries e.Phi (knot columns first) through the step linearizations. With
  /// `trajectory`, stores the states s_{k_begin}..s_{k_end} there (k_end - k_begin + 1 of them). False, with e.failed_step and
  /// e.failure, at the first rotation update that does not converge (`s` then is the last good state).
  template <class E>
  bool advance(State& s, std::size_t k_begin, std::size_t k_end, bool gradients, E& e,
               State* trajectory = nullptr) const;
  /// Phi <- A_k Phi + B0_k S_k + B1_k S_{k+1} (per component) for step k from s to next.
  void propagate_sensitivity(const State& s, const State& next, std::size_t k, Evaluation& e) const;

  typename Model::Lgvi lgvi_;
  Transfer problem_;
  double h_;
  std::size_t steps_;
  int knots_;
  std::vector<int> rows_;  ///< rows of the full residual that are constraints
  Eigen::MatrixXd S_;  ///< (N+1) x knots
  Eigen::Matrix<double, nu, nu> W_;
  Eigen::VectorXd node_weights_;  ///< w_j
  State initial_;
};

template <class Model>
struct DirectResult {
  DirectSummary summary;
  std::vector<typename Model::State> states;               ///< s_0..s_N at the returned knots
  Eigen::Matrix<double, Model::nu, Eigen::Dynamic> controls;  ///< u_0..u_N
};

/// The default initial guess (no information about the answer; the zero control is degenerate:
/// at rest with u = 0 the linearization cannot turn the pendulum about the vertical, nor the
/// connected bodies about x, and log(R_N^T R_f) is at its cut locus): documented in README.md.
Eigen::VectorXd default_initial_knots(const CartPendulum&, int knots);
Eigen::VectorXd default_initial_knots(const ConnectedBodies&, int knots);
/// The standard deviation of the random starts: the default guess's amplitude.
double default_guess_scale(const CartPendulum&);
double default_guess_scale(const ConnectedBodies&);
/// The initial knots of random start `start` >= 1 of a multistart (DirectOptions: knots, seed,
/// guess_scale): the start-th block of n_u * knots draws of N(0, sigma^2) from mt19937_64(seed).
Eigen::VectorXd start_knots(const CartPendulum& system, const DirectOptions& options, int start);
Eigen::VectorXd start_knots(const ConnectedBodies& system, const DirectOptions& options, int start);

/// SLSQP on the knot values. The returned point's violation is checked here: NLopt's success
/// codes become Converged only when it is within options.tolerance. Never throws; bad input
/// becomes status InvalidInput with a message naming the field.
DirectResult<CartPendulumDirectModel> solve_direct(const CartPendulum& system,
                                                    const CartPendulumTransfer& problem,
                                                    const DirectOptions& options);
DirectResult<ConnectedBodiesDirectModel> solve_direct(const ConnectedBodies& system,
                                                       const ConnectedBodiesTransfer& problem,
                                                       const DirectOptions& options);

extern template class DirectTranscription<CartPendulumDirectModel>;
extern template class DirectTranscription<ConnectedBodiesDirectModel>;

}  // namespace lgvi::ocp
