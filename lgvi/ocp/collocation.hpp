// Continuous direct collocation of an attitude transfer (the pendulum of section 3.2, the free
// body's slew): the continuous problem the discrete methods approximate, transcribed by
// Hermite-Simpson collocation of the quaternion model and solved by IPOPT. The method:
// C. R. Hargraves and S. W. Paris, "Direct trajectory optimization using nonlinear programming
// and collocation", J. Guidance, Control, and Dynamics 10(4), 338-342, 1987; J. T. Betts,
// "Practical Methods for Optimal Control and Estimation Using Nonlinear Programming", 2nd ed.,
// SIAM, 2010, sec. 4.6 (the separated Hermite-Simpson form used here).
//
// Continuous problem: minimize int_0^T u^T W u / 2 dt subject to the quaternion model
//     q' = 1/2 q (x) (0, Omega) + mu q,   J Omega' = J Omega x Omega + M(R(q)) + tau(R(q), u),
// R(q) the rotation of the quaternion (scalar first; (w^2 - |v|^2) I + 2 v v^T + 2 w hat(v), the
// baselines' quaternion model), M and tau the system's moments (eq. 13; the pendulum's
// R^T e3 x u, eq. 23; the free body's u), q(0), Omega(0) given, R(T) = R_f, Omega(T) = Omega_f.
//
// Unit quaternions, imposed: |q_k|^2 = 1 is an equality constraint at every mesh node k >= 1
// (node 0 is fixed at the unit quaternion of R_0). Hermite-Simpson does not conserve |q| exactly
// (its local error changes |q| by O(h^5)), so the norm equalities alone would overdetermine the
// quaternion's defects; each interval k therefore carries one free scalar mu_k, the rate of the
// kinematics along q (a multiplier of the norm constraint: zero for the exact flow, O(h^4) here,
// reported as max_normal_rate). The drift reported is max | |q| - 1 | over the nodes and the
// interval midpoints (the midpoints are not constrained).
//
// Transcription (K uniform intervals of h = T / K; y = (q, Omega) of 7 entries, f its rate):
//   variables   per interval k: y_k, u_k, y_m, u_m (the midpoint's), mu_k; then y_K, u_K
//   defects     y_m - (y_k + y_{k+1}) / 2 - h/8 (f_k - f_{k+1}) = 0             (Hermite interpolant)
//               y_{k+1} - y_k - h/6 (f_k + 4 f_m + f_{k+1}) = 0                 (Simpson's rule)
//               |q_{k+1}|^2 - 1 = 0
//   boundary    y_0 fixed (the variables' bounds); vec(conj(q_f) (x) q_K) = 0, which with |q_K| = 1
//               is q_K = +-q_f, i.e. R(q_K) = R_f; Omega_K - Omega_f = 0
//   cost        sum_k h/6 (L(u_k) + 4 L(u_m) + L(u_{k+1})), L(u) = u^T W u / 2 (Simpson's rule)
// with f evaluated with mu_k at both ends and the midpoint of interval k. The constraint Jacobian
// is exact and sparse (each interval's 14 defect rows depend on its 31 variables only): the RHS
// Jacobians are analytic (the quaternion kinematics', Euler's equation's, and the moments'
// through R(q), collocation.cpp), checked against central differences in the tests. The Hessian
// of the Lagrangian: IPOPT's limited-memory (L-BFGS) approximation.
//
// The control between the nodes is the quadratic through u_k, u_m, u_{k+1} (the Hermite-Simpson
// interpolant of Betts sec. 4.6.6): what the replay interprets (baselines/ocp_replay.hpp).
// Initial guess: the rest-to-rest slew from R_0 to R_f about the fixed body axis of R_0^T R_f
// with the smooth profile s(t) = t/T - sin(2 pi t / T) / (2 pi), zero control, mu = 0.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "lgvi/range.hpp"
#include "lgvi/ocp/indirect.hpp"
#include "lgvi/systems/free_rigid_body.hpp"
#include "lgvi/systems/pendulum.hpp"

namespace lgvi::ocp {

struct CollocationOptions {
  int intervals = 100;          ///< K, uniform mesh intervals
  Eigen::MatrixXd W;            ///< 3 x 3 symmetric positive definite; empty: identity
  double tolerance = 1e-10;     ///< on every defect and terminal constraint (max abs)
  int max_iterations = 3000;    ///< IPOPT iterations
  static constexpr Range kIntervals = Range::integers(2, 100000);
  static constexpr Range kTolerance = Range::above(0, 0.1);
  static constexpr Range kMaxIterations = Range::integers(1, 1e8);
  /// Throws InvalidInput naming the field ("intervals", "tolerance", "max_iterations", "W").
  void validate() const;
};

enum class CollocationStatus {
  Converged,       ///< IPOPT succeeded and every constraint within the tolerance
  IterationLimit,  ///< max_iterations reached
  Failed,          ///< IPOPT stopped otherwise (its status in ipopt_status), or above the tolerance
  InvalidInput,    ///< bad options or problem (message names the field)
};
const char* to_string(CollocationStatus s);

struct CollocationSummary {
  CollocationStatus status = CollocationStatus::Failed;
  std::string message;      ///< InvalidInput: the field and reason
  std::string ipopt_status;  ///< IPOPT's return status by name
  int iterations = 0;
  int intervals = 0;
  int variables = 0, constraints = 0, jacobian_nonzeros = 0;
  double cost = std::numeric_limits<double>::infinity();  ///< Simpson's rule of the cost
  /// |[log(R_f^T R(q_K / |q_K|)); Omega_K - Omega_f]|, the indirect method's violation norm
  double violation = std::numeric_limits<double>::infinity();
  Eigen::VectorXd residual;
  double max_defect = std::numeric_limits<double>::infinity();  ///< max abs of the collocation defects
  double quaternion_drift = 0.0;  ///< max | |q| - 1 | over the nodes and the midpoints
  double max_normal_rate = 0.0;   ///< max_k |mu_k|
  double wall_seconds = 0.0, cpu_seconds = 0.0;
  bool converged() const { return status == CollocationStatus::Converged; }
  /// One line, e.g. "converged (Solve_Succeeded) in 85 iterations: cost 7.2, violation 1e-12, ...".
  std::string brief() const;
};

struct CollocationResult {
  CollocationSummary summary;
  double h = 0.0;             ///< T / K
  Eigen::MatrixXd states;     ///< 7 x (K + 1): (q; Omega) at the nodes t_k = k h
  Eigen::MatrixXd controls;   ///< 3 x (2 K + 1): u at t = j h / 2 (nodes even, midpoints odd)
  std::vector<double> history_cost, history_infeasibility;  ///< per IPOPT iteration
};

/// Never throws: bad input is status InvalidInput with a message naming the field.
CollocationResult solve_collocation(const Pendulum3D& system, const TransferProblem& problem,
                                    const CollocationOptions& options);
CollocationResult solve_collocation(const FreeRigidBody& system, const TransferProblem& problem,
                                    const CollocationOptions& options);

namespace collocation_detail {
/// The quaternion model's rate f(y, u, mu) and its Jacobian [df/dy, df/du, df/dmu] (7 x 11), for
/// the tests' central-difference check.
void attitude_rhs(const Pendulum3D& system, const Eigen::Matrix<double, 7, 1>& y, const Vec3& u, double mu,
                  Eigen::Matrix<double, 7, 1>& f, Eigen::Matrix<double, 7, 11>* jacobian);
void attitude_rhs(const FreeRigidBody& system, const Eigen::Matrix<double, 7, 1>& y, const Vec3& u, double mu,
                  Eigen::Matrix<double, 7, 1>& f, Eigen::Matrix<double, 7, 11>* jacobian);
}  // namespace collocation_detail

}  // namespace lgvi::ocp
