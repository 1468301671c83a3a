// One yardstick for every optimal control answer: its control history replayed by a tight
// continuous integration of the quaternion model (baselines/model.hpp), giving the true terminal
// violation and the true cost of the continuous problem, beside the method's own figures (which
// judge a discrete answer by its own discrete dynamics).
//
// The control history is the node controls u_0..u_N at t_j = j h, as every solver of lgvi/ocp
// returns them (indirect: the sweep's controls; direct SLSQP / IPOPT: the spline's samples at the
// nodes, which are what the LGVI run sees; DDP: the free node controls). Between the nodes the
// replay interprets them as the discrete method applies them, so that over every step the
// replayed control's impulse equals the method's kick:
//   ZeroOrderHold     (the printed form, the paper's: the kick h u_{k+1} lands at t_{k+1}):
//                     u(t) = u_{k+1} on (t_k, t_{k+1}]; its integral over the step is h u_{k+1}
//                     and its cost int u^T W u / 2 is exactly the printed cost
//                     sum_{j>=1} h/2 u_j^T W u_j (eqs. 38, 48), so only the violation is new;
//   PiecewiseLinear   (the symmetric form: kicks h/2 u_k at t_k and h/2 u_{k+1} at t_{k+1}):
//                     the linear interpolant of u_k, u_{k+1} on [t_k, t_{k+1}], whose integral over
//                     the step is the trapezoidal h (u_k + u_{k+1}) / 2; its cost per step is exact,
//                     h/6 (u_k^T W u_k + u_k^T W u_{k+1} + u_{k+1}^T W u_{k+1}) (Simpson's rule is
//                     exact for this quadratic), not the method's trapezoidal sum;
//   PiecewiseQuadratic (continuous collocation, lgvi/ocp/collocation.hpp: Hermite-Simpson's
//                     controls at the nodes and the interval midpoints): the quadratic through
//                     u_k, u_{k+1/2}, u_{k+1} on each interval; its cost by 3-point Gauss-Legendre
//                     (exact for the quartic integrand).
// (In either case the moment of a control that depends on the attitude, the pendulum's
// R^T e3 x u, is evaluated along the continuous attitude.)
// The integration restarts at every node, one solver call per step interval from the previous
// call's end state: the control is smooth inside each interval, so its kinks (or jumps) at the
// nodes cost the error-controlled solver nothing. Default gsl-rk8pd at rtol = atol = 1e-13 (the
// quaternion model, |q| = 1 not enforced: its drift is reported).
//
// The terminal violation is the same 2-norm of the same residual as each method's own
// (experiments/systems/ocp.hpp violation_norm):
//   pendulum, free body:  [log(R_f^T R(T)); Omega(T) - Omega_f]                 (indirect.hpp)
//   dumbbell:             [log(R_f^T R(T)); x - x_f; Omega - Omega_f; v - v_f]   (indirect.hpp)
//   cart-pendulum:        [log(R(T)^T R_f); q - q_f; Omega - Omega_f; q' - q'_f] (direct.hpp)
//   connected bodies:     [log(R1^T R1_f); log(R2^T R2_f); Omega1 - Omega1_f; Omega2 - Omega2_f]
#pragma once

#include <cstddef>
#include <limits>
#include <string>

#include <Eigen/Dense>

#include "lgvi/lgvi.hpp"
#include "lgvi/ocp/direct.hpp"
#include "lgvi/ocp/indirect.hpp"
#include "lgvi/systems/cart_pendulum.hpp"
#include "lgvi/systems/connected_bodies.hpp"
#include "lgvi/systems/dumbbell.hpp"
#include "lgvi/systems/free_rigid_body.hpp"
#include "lgvi/systems/pendulum.hpp"

namespace lgvi::baselines {

/// How the node controls act between the nodes (see the top of this file).
enum class ReplayInterpolation { ZeroOrderHold, PiecewiseLinear, PiecewiseQuadratic };

/// "zero-order-hold", "piecewise-linear" or "piecewise-quadratic".
const char* to_string(ReplayInterpolation interpolation);
/// The interpretation of an LGVI form's kicks: printed -> ZeroOrderHold, symmetric -> PiecewiseLinear.
ReplayInterpolation replay_interpolation(LgviForm form);

/// A solved answer's control history.
struct ReplayControls {
  /// n_u x (N + 1): column j is u_j at t_j = j h; PiecewiseQuadratic: n_u x (2 N + 1), column j
  /// at t = j h / 2 (the nodes even, the midpoints odd)
  Eigen::MatrixXd u;
  double h = 0.0;     ///< node spacing (N h = the horizon)
  ReplayInterpolation interpolation = ReplayInterpolation::ZeroOrderHold;
  Eigen::MatrixXd W;  ///< the cost's weight, n_u x n_u; empty: the identity
};

struct ReplayOptions {
  std::string method = "gsl-rk8pd";  ///< an adaptive baseline solver (baselines/solver.hpp)
  double rtol = 1e-13;
  double atol = 1e-13;
  /// Solver steps over all intervals; a history that needs more (a diverging answer's, a horizon of
  /// thousands of turns) is a failed replay, not a hang (the paper's four examples take 1000-4000).
  std::size_t max_steps = 100'000;
};

struct ReplayResult {
  bool ok = false;
  std::string message;  ///< why the replay failed (a solver's status, at which interval)
  double cost = std::numeric_limits<double>::quiet_NaN();       ///< int_0^T u^T W u / 2 dt, exact
  double violation = std::numeric_limits<double>::quiet_NaN();  ///< |residual|
  Eigen::VectorXd residual;                                     ///< in the method's layout
  double quaternion_drift = 0.0;  ///< max over bodies of | |q(T)| - 1 |
  std::size_t steps = 0;          ///< solver steps, all intervals
  std::size_t rhs_evaluations = 0;
  double seconds = 0.0;           ///< wall time of the replay
  double cpu_seconds = 0.0;       ///< CPU time of the calling thread in the replay
  ReplayInterpolation interpolation = ReplayInterpolation::ZeroOrderHold;
};

/// The cost int_0^{N h} u^T W u / 2 dt of the interpolated controls, exact for either
/// interpolation. Throws InvalidInput("controls", ...) for a bad history (see replay).
double replayed_cost(const ReplayControls& c);

/// Replays c on the system's quaternion model from the problem's initial state over N h and
/// measures the problem's terminal residual. Throws InvalidInput ("controls": fewer than 2 nodes,
/// wrong n_u, non-finite values, h not positive and finite; "W": wrong size; the solver's own
/// settings errors) for bad input; a solver failure is ok = false with the message.
ReplayResult replay(const Pendulum3D& system, const ocp::TransferProblem& problem, const ReplayControls& c,
                    const ReplayOptions& options = {});
ReplayResult replay(const FreeRigidBody& system, const ocp::TransferProblem& problem, const ReplayControls& c,
                    const ReplayOptions& options = {});
ReplayResult replay(const DumbbellSpacecraft& system, const ocp::TransferProblem& problem, const ReplayControls& c,
                    const ReplayOptions& options = {});
ReplayResult replay(const CartPendulum& system, const ocp::CartPendulumTransfer& problem, const ReplayControls& c,
                    const ReplayOptions& options = {});
ReplayResult replay(const ConnectedBodies& system, const ocp::ConnectedBodiesTransfer& problem,
                    const ReplayControls& c, const ReplayOptions& options = {});

}  // namespace lgvi::baselines
