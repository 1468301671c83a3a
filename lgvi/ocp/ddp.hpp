// Differential dynamic programming on the discrete LGVI dynamics: the direct method's discrete
// problem (direct.hpp: the same step(s_k, h, u_k, u_{k+1}), the same cost
// J = sum_j w_j/2 u_j^T W u_j, the same terminal residual r) with the node controls u_0..u_N free
// (no spline), solved by iLQR: DDP with the second derivatives of the dynamics dropped
// (Gauss-Newton; W. Li and E. Todorov, "Iterative linear quadratic regulator design for nonlinear
// biological movement systems", ICINCO 2004), with the control regularization and the backtracking
// line search on the expected change of Y. Tassa, T. Erez and E. Todorov, "Synthesis and
// stabilization of complex behaviors through online trajectory optimization", IROS 2012.
//
// Augmented state. Step k depends on u_k and u_{k+1}, so the state is x_k = (s_k, u_k), the
// decision v_k = u_{k+1} (k = 0..N-1), x_{k+1} = (step(s_k, h, u_k, v_k), v_k). In left-trivialized
// tangent coordinates dx = (w, du), w as Model::retract (R -> R exp(hat eta)):
//   F_x = [A_k  B0_k; 0  0],  F_v = [B1_k; I]              (Lgvi::linearize: A, B0, B1, eq. 16)
// Stage cost l_k(x_k) = w_k/2 u_k^T W u_k (k < N); terminal cost, the augmented Lagrangian of the
// imposed terminal rows r (Model::residual):
//   l_N(x_N) = w_N/2 u_N^T W u_N + lambda^T r(s_N) + mu/2 |r(s_N)|^2,
// with the Gauss-Newton Hessian V_xx,N = [mu D^T D, 0; 0, w_N W], D = dr/dw_N (residual_jacobian).
// Backward pass (k = N-1..0), P = V_xx,k+1 and p = V_x,k+1:
//   Q_x = l_x + F_x^T p,  Q_v = F_v^T p,  Q_xx = l_xx + F_x^T P F_x,  Q_vx = F_v^T P F_x,
//   Q_vv = F_v^T P F_v + rho I,  k_k = -Q_vv^{-1} Q_v,  K_k = -Q_vv^{-1} Q_vx,
//   V_x = Q_x + Q_xv k_k,  V_xx = Q_xx + Q_xv K_k  (symmetrized),
// the exact solution of the linear-quadratic model with rho/2 |dv|^2 added. u_0 (s_0 fixed) is
// optimized from the time-0 value function, quadratic in du_0: k_0 = -(V_uu,0 + rho I)^{-1} V_u,0.
// Expected change of the forward pass at step alpha (Tassa 2012, eq. 13):
//   dV(alpha) = alpha sum k^T Q_v + alpha^2/2 sum k^T Q_vv k   (the u_0 term included),
// whose first-order part is the directional derivative of the rolled-out objective (tested).
// Forward pass on the group: u_0 <- u_0 + alpha k_0, then for k = 0..N-1
//   v_k = u_{k+1} + alpha k_k + K_k [difference(s_k, s_k^new); u_k^new - u_k],
//   s_{k+1}^new = step(s_k^new, h, u_k^new, v_k),
// so the attitudes are only ever updated by the LGVI (R <- R F, F in SO(3)).
//
// Augmented Lagrangian (outer loop; schedule in README.md "DDP"): inner iLQR on the objective above
// until its gradient in the node controls is below DdpOptions::gradient_tolerance (relative), then
//   lambda <- lambda + mu r;  mu <- penalty_factor mu  if |r| > violation_decrease |r_previous|,
// converged when the full terminal violation (all rows, as the direct method reports it) is within
// tolerance and the inner gradient is small.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "lgvi/ocp/direct.hpp"

namespace lgvi::ocp {

struct DdpOptions {
  LgviForm form = LgviForm::Printed;  ///< the direct method's (printed: eqs. 34-35, 44-45, cost 38, 48)
  double h = 0.01;                    ///< t_final / h must be an integer
  Eigen::MatrixXd W;                  ///< n_u x n_u symmetric positive definite; empty: identity
  /// The starts are the direct method's: knot values (its knots, spline) sampled at the nodes.
  int knots = 7;
  SplineEnd spline = SplineEnd::NotAKnot;
  Eigen::VectorXd initial_knots;  ///< start 0's knot values; empty: default_initial_knots
  int starts = 1;                 ///< as DirectOptions::starts (same seeded sequence)
  int first_start = 0;
  std::uint64_t seed = 1;
  double guess_scale = 0.0;
  bool keep_redundant_constraint = false;  ///< connected bodies: impose the terminal Omega2 too
  int max_iterations = 1000;      ///< iLQR iterations (backward passes) per start, all outer ones
  double tolerance = 1e-8;        ///< on the full terminal violation (2-norm)
  /// Inner stop: |grad of the AL objective in the node controls|_inf <= omega (1 + |objective|),
  /// omega = inner_tolerance at the first outer iteration, divided by 10 at each one after, down
  /// to gradient_tolerance (the final inner solve's, and convergence's).
  double gradient_tolerance = 1e-6;
  double inner_tolerance = 1e-2;
  double penalty = 10.0;            ///< initial mu
  double penalty_factor = 100.0;    ///< mu <- factor mu when |r| did not drop enough
  double violation_decrease = 0.25; ///< "enough": |r| <= violation_decrease |r_previous|
  double penalty_max = 1e12;
  double regularization_min = 1e-10;  ///< rho is 0 or in [regularization_min, regularization_max]
  double regularization_max = 1e10;   ///< beyond it: line-search-failed
  int outer_inner_iterations = 200;   ///< cap on one inner solve before the multipliers are updated
  GroupNewtonOptions newton;

  static constexpr Range kKnots = DirectOptions::kKnots;
  static constexpr Range kStarts = DirectOptions::kStarts;
  static constexpr Range kFirstStart = DirectOptions::kFirstStart;
  static constexpr Range kSeed = DirectOptions::kSeed;
  static constexpr Range kMaxIterations = Range::integers(1, 1e8);
  static constexpr Range kTolerance = DirectOptions::kTolerance;
  static constexpr Range kGradientTolerance = Range::above(0, 1);
  static constexpr Range kPenalty = Range::above(0, 1e12);
  static constexpr Range kPenaltyFactor = Range::numbers(1, 1e6);
  static constexpr Range kViolationDecrease = Range::open(0, 1);
  static constexpr Range kRegularization = Range::above(0, 1e20);
  static constexpr Range kOuterInnerIterations = Range::integers(1, 1e8);

  /// Throws InvalidInput naming the first setting outside its range ("max_iterations", ...).
  void validate() const;
  /// The direct options of the same discrete problem (for DirectTranscription and the starts).
  DirectOptions direct() const;
};

enum class DdpStatus {
  Converged,         ///< full violation <= tolerance and the inner gradient small
  MaxIterations,     ///< max_iterations reached
  StepFailure,       ///< the LGVI's implicit rotation update failed on the start's own rollout
  NonFinite,         ///< a non-finite cost, violation or control
  LineSearchFailed,  ///< no step decreased the objective, even at regularization_max
  InvalidInput,      ///< bad problem or options (message names the field)
};
const char* to_string(DdpStatus s);

/// One iLQR iteration (an accepted or final forward pass).
struct DdpIteration {
  int start = 0;
  int iteration = 0;       ///< within the start
  int outer = 0;           ///< augmented-Lagrangian iteration
  double cost = 0.0;       ///< J
  double violation = 0.0;  ///< full terminal violation (2-norm)
  double objective = 0.0;  ///< J + lambda^T r + mu/2 |r|^2
  double gradient = 0.0;   ///< |grad objective|_inf in the node controls (before the step)
  double expected = 0.0;   ///< dV(alpha) of the accepted step
  double alpha = 0.0;
  double regularization = 0.0;
  double penalty = 0.0;
  double seconds = 0.0;    ///< cumulative CPU time of the start (the calling thread's, lgvi/cpu_time.hpp)
};

struct DdpStart {
  int index = 0;
  DdpStatus status = DdpStatus::MaxIterations;
  std::string message;
  double cost = std::numeric_limits<double>::infinity();
  double violation = std::numeric_limits<double>::infinity();
  int iterations = 0;
  int outer_iterations = 0;
  long rollouts = 0;          ///< forward LGVI runs (incl. rejected line-search trials)
  double cpu_seconds = 0.0;   ///< the calling thread's CPU time (lgvi/cpu_time.hpp)
  Eigen::VectorXd initial_knots;
  Eigen::MatrixXd controls;   ///< n_u x (N+1) at the end
};

struct DdpSummary {
  DdpStatus status = DdpStatus::InvalidInput;
  std::string message;
  std::string system;
  LgviForm form = LgviForm::Printed;
  double h = 0.0;
  std::size_t steps = 0;
  int constraints = 0;       ///< imposed terminal rows
  int iterations = 0;        ///< all starts
  int outer_iterations = 0;
  long rollouts = 0;
  double cost = std::numeric_limits<double>::infinity();
  double violation = std::numeric_limits<double>::infinity();  ///< full terminal condition
  Eigen::VectorXd residual;  ///< full terminal residual at the end
  double wall_seconds = 0.0;
  double cpu_seconds = 0.0;  ///< the calling thread's CPU time, all starts (lgvi/cpu_time.hpp)
  std::vector<DdpIteration> history;
  std::vector<DdpStart> starts;
  int best_start = -1;       ///< position in `starts` of the start reported

  bool converged() const { return status == DdpStatus::Converged; }
  std::string brief() const;
};

/// The iLQR machinery on one model: rollouts, the backward pass, the forward pass. Preallocated
/// trajectories; no heap allocation inside the per-step loops.
template <class Model>
class Ddp {
 public:
  static constexpr int nw = Model::nw, nu = Model::nu, nx = Model::nw + Model::nu;
  using State = typename Model::State;
  using VecU = typename Model::VecU;
  using VecR = typename Model::VecR;
  using VecX = Eigen::Matrix<double, nx, 1>;
  using MatX = Eigen::Matrix<double, nx, nx>;
  using MatUX = Eigen::Matrix<double, nu, nx>;
  using MatU = Eigen::Matrix<double, nu, nu>;
  using Controls = Eigen::Matrix<double, nu, Eigen::Dynamic>;

  /// Throws InvalidInput (h, W, the boundary rotations, knots).
  Ddp(const typename Model::System& system, const typename Model::Transfer& problem, const DdpOptions& options);

  struct Trajectory {
    std::vector<State> states;  ///< s_0..s_N
    Controls controls;          ///< u_0..u_N
    double cost = 0.0;
    VecR residual = VecR::Zero();  ///< full
    std::size_t failed_step = 0;
    std::string failure;        ///< set when the rollout failed
  };
  struct Gains {
    std::vector<MatUX> K;       ///< K_0..K_{N-1}
    Controls k;                 ///< columns: k_u0 (time 0), then k_0..k_{N-1} (for u_1..u_N)
    Controls gradient;          ///< exact gradient of the objective in u_0..u_N (adjoint)
    double expected_linear = 0.0, expected_quadratic = 0.0;  ///< dV = alpha lin + alpha^2/2 quad
    std::vector<typename Model::MatW> A;  ///< linearization buffers
    std::vector<typename Model::MatWU> B0, B1;
  };

  Trajectory make_trajectory() const;
  Gains make_gains() const;
  /// Runs the LGVI from s_0 under t.controls; false (failure set) when a rotation update fails.
  bool rollout(Trajectory& t) const;
  /// lambda^T r + mu/2 |r|^2 + J on the imposed rows (lambda: full-size, imposed rows used).
  double objective(const Trajectory& t, const VecR& lambda, double mu) const;
  /// Linearizes along t and runs the backward pass. False when Q_vv is not positive definite.
  bool backward(const Trajectory& t, const VecR& lambda, double mu, double rho, Gains& g) const;
  /// The forward pass at step alpha from nominal into trial; false when the rollout fails.
  bool forward(const Trajectory& nominal, const Gains& g, double alpha, Trajectory& trial) const;

  /// Step k of t (s_k, u_k, u_{k+1} -> s_{k+1}); false (failed_step, failure set) when the
  /// rotation update fails or s_{k+1} is not finite. rollout and forward share it.
  bool step(Trajectory& t, std::size_t k) const;
  /// t's cost and terminal residual, after a complete rollout.
  void finish(Trajectory& t) const;

  /// The imposed rows of r (others zeroed).
  VecR imposed(const VecR& r) const;
  const DirectTranscription<Model>& transcription() const { return tr_; }

 private:
  DirectTranscription<Model> tr_;
  int imposed_rows_;
};

template <class Model>
struct DdpResult {
  DdpSummary summary;
  std::vector<typename Model::State> states;
  Eigen::Matrix<double, Model::nu, Eigen::Dynamic> controls;
};

/// iLQR with the augmented Lagrangian from each start. Never throws; bad input becomes status
/// InvalidInput with a message naming the field. The result is the start within tolerance of
/// lowest cost (else the least violating).
DdpResult<CartPendulumDirectModel> solve_ddp(const CartPendulum& system, const CartPendulumTransfer& problem,
                                             const DdpOptions& options);
DdpResult<ConnectedBodiesDirectModel> solve_ddp(const ConnectedBodies& system, const ConnectedBodiesTransfer& problem,
                                                const DdpOptions& options);

extern template class Ddp<CartPendulumDirectModel>;
extern template class Ddp<ConnectedBodiesDirectModel>;

}  // namespace lgvi::ocp
