// Continuous direct collocation of the paper's optimal control examples: the continuous problem
// the discrete methods approximate, transcribed by Hermite-Simpson collocation of the quaternion
// model and solved by IPOPT. The method:
// C. R. Hargraves and S. W. Paris, "Direct trajectory optimization using nonlinear programming
// and collocation", J. Guidance, Control, and Dynamics 10(4), 338-342, 1987; J. T. Betts,
// "Practical Methods for Optimal Control and Estimation Using Nonlinear Programming", 2nd ed.,
// SIAM, 2010, sec. 4.6 (the separated Hermite-Simpson form used here).
//
// One transcription over a system's state y, control u and rate f(y, u, mu); the systems are its
// instances (collocation.cpp), each in the baselines' quaternion layout (baselines/model.hpp)
// y = [q_1 .. q_NQ | x | w]: the unit quaternions of the NQ attitudes (scalar first), the further
// coordinates x, the velocity state w:
//   pendulum (3.2), free body:  y = (q, Omega),                   u the moment (3)
//       q' = 1/2 q (x) (0, Omega) + mu q,   J Omega' = J Omega x Omega + M(R) + tau(R, u)
//   dumbbell (3.1):             y = (q, x, Omega, v),             u = (u^m, u^f) (6)
//       J Omega' = J Omega x Omega + M(R, x) + u^m,   m v' = f(R, x) + u^f,   x' = v
//   cart-pendulum (4.1):        y = (q, x_c, Pi, p) (momenta of eq. 37),   u the cart force (2)
//       [Omega; x_c'] = A(R)^{-1} [Pi; p],  Pi' = Pi x Omega + M(R) + X_c,  p' = u
//   connected bodies (4.2):     y = (q1, q2, Pi1, Pi2) (momenta of eq. 47),   u the joint moment (3)
//       [Omega1; Omega2] = A(R1, R2)^{-1} [Pi1; Pi2],  Pi_i' = Pi_i x Omega_i + X_i +- R_i^T u
// R(q) the rotation of the quaternion ((w^2 - |v|^2) I + 2 v v^T + 2 w hat(v), the baselines'
// quaternion model), the physics (moments, mass matrices, coupling moments) the systems' own
// functions (lgvi/systems). The multibody systems evaluate theirs at R(q) / |q|^2, the rotation of
// q / |q|: the same on the unit sphere, and their mass matrices stay positive definite off it (at
// the midpoints and IPOPT's iterates, where R(q) is a scaled rotation). Minimize
// int_0^T u^T W u / 2 dt, y(0) given, the terminal state given.
//
// Unit quaternions, imposed: |q_i,k|^2 = 1 is an equality constraint at every mesh node k >= 1
// (node 0 is fixed at the unit quaternions of the initial attitudes). Hermite-Simpson does not
// conserve |q| exactly (its local error changes |q| by O(h^5)), so the norm equalities alone would
// overdetermine the quaternions' defects; each interval k therefore carries one free scalar mu_i,k
// per quaternion, the rate of the kinematics along q_i (a multiplier of the norm constraint: zero
// for the exact flow, O(h^4) here, reported as max_normal_rate). The drift reported is
// max | |q| - 1 | over the quaternions at the nodes and the interval midpoints (the midpoints are
// not constrained).
//
// Transcription (K uniform intervals of h = T / K):
//   variables   per interval k: y_k, u_k, y_m, u_m (the midpoint's), mu_k (NQ); then y_K, u_K
//   defects     y_m - (y_k + y_{k+1}) / 2 - h/8 (f_k - f_{k+1}) = 0             (Hermite interpolant)
//               y_{k+1} - y_k - h/6 (f_k + 4 f_m + f_{k+1}) = 0                 (Simpson's rule)
//               |q_i,k+1|^2 - 1 = 0, i = 1..NQ
//   boundary    y_0 fixed (the variables' bounds); per attitude vec(conj(q_i,f) (x) q_i,K) = 0,
//               which with |q_i,K| = 1 is q_i,K = +-q_i,f, i.e. R_i(T) = R_i,f; the velocity state's
//               terminal entries equal the target's (linear rows). The velocity state is the
//               momenta for the multibody systems: with the attitudes at their targets, momenta
//               equal to the target's momenta are the target velocities (eqs. 37, 47). The connected
//               bodies impose Pi1 only, as the discrete problem drops Omega2 (direct.hpp): with
//               zero total angular momentum R1 Pi1 + R2 Pi2 conserved, Pi2 follows (imposed, its
//               rows would be dependent up to the O(h^4) defect of that invariant). The dumbbell
//               imposes x and (Omega, v). The violation reported is the full one (Omega2 included).
//   cost        sum_k h/6 (L(u_k) + 4 L(u_m) + L(u_{k+1})), L(u) = u^T W u / 2 (Simpson's rule)
// with f evaluated with mu_k at both ends and the midpoint of interval k. The constraint Jacobian
// is exact and sparse (each interval's defect rows depend on its own variables only). The RHS
// Jacobians are analytic: the quaternion kinematics' and Euler's equation's by hand; the
// multibody systems' by the chain rule through v = A(R)^{-1} w (dv = A^{-1} (dw - dA v)) and the
// systems' physics functions, each of which is linear in each of its arguments (the mass matrices
// affine in the attitudes, the moments and coupling moments multilinear in (R, Omega, x')), so its
// directional derivative along one argument is the function evaluated at the direction: exact.
// All are checked against central differences in tests/ocp/test_collocation.cpp, and so is the
// whole constraint Jacobian of a small mesh. The Hessian of the Lagrangian (options.hessian), by
// default exact: sparse, each interval's curvature that of the rate at its three points, each
// point's block by central differences of the exact gradient J_f^T w (collocation.cpp,
// lagrangian_hessian; checked against differences of the whole Lagrangian's gradient); or
// IPOPT's limited-memory (L-BFGS) approximation, or the cost's Hessian alone. Measured (`ocp NAME
// --solver collocation`, K = 100, exact against L-BFGS): pendulum 7 against 20 iterations, the
// same optimum; cart-pendulum 17 against 81 (260.02, L-BFGS another local optimum 601.11);
// connected bodies 23 against 117, the same optimum, 2.2 against 6.5 s CPU; the dumbbell 58
// iterations, 3.6 s, where L-BFGS took 1500-1900 (22 s at K = 50).
//
// The control between the nodes is the quadratic through u_k, u_m, u_{k+1} (the Hermite-Simpson
// interpolant of Betts sec. 4.6.6): what the replay interprets (baselines/ocp_replay.hpp,
// PiecewiseQuadratic).
// Initial guess: each attitude's rest-to-rest slew from R_i,0 to R_i,f about the fixed body axis
// of R_i,0^T R_i,f with the smooth profile s(t) = t/T - sin(2 pi t / T) / (2 pi) (the attitude
// systems and the cart-pendulum with a tilt about a perpendicular axis, out and back, see
// collocation.cpp; the connected bodies' second body turning a half turn the other way round, as
// the direct method's geodesic guess), the other coordinates along the same profile (the
// dumbbell's position along the circular arc from x_0 to x_f), the velocity state from these
// rates; zero control, mu = 0.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "lgvi/range.hpp"
#include "lgvi/ocp/direct.hpp"
#include "lgvi/ocp/indirect.hpp"
#include "lgvi/systems/cart_pendulum.hpp"
#include "lgvi/systems/connected_bodies.hpp"
#include "lgvi/systems/dumbbell.hpp"
#include "lgvi/systems/free_rigid_body.hpp"
#include "lgvi/systems/pendulum.hpp"

namespace lgvi::ocp {

struct CollocationOptions {
  int intervals = 100;          ///< K, uniform mesh intervals
  Eigen::MatrixXd W;            ///< n_u x n_u symmetric positive definite; empty: identity
  double tolerance = 1e-10;     ///< on every defect and terminal constraint (max abs)
  int max_iterations = 3000;    ///< IPOPT iterations
  /// Exact: the Lagrangian's Hessian (the rate's curvature by central differences of its exact
  /// Jacobian, point by point); LimitedMemory: IPOPT's L-BFGS; CostOnly: the cost's W blocks.
  IpoptHessian hessian = IpoptHessian::Exact;
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
  int hessian_nonzeros = 0;  ///< lower triangle; 0 with the limited-memory approximation
  double cost = std::numeric_limits<double>::infinity();  ///< Simpson's rule of the cost
  /// The 2-norm of the system's full terminal residual at the last node (the attitudes R(q / |q|)),
  /// the other methods' violation norm (baselines/ocp_replay.hpp lists them)
  double violation = std::numeric_limits<double>::infinity();
  Eigen::VectorXd residual;
  double max_defect = std::numeric_limits<double>::infinity();  ///< max abs of the collocation defects
  double quaternion_drift = 0.0;  ///< max | |q| - 1 | over the quaternions at the nodes and the midpoints
  double max_normal_rate = 0.0;   ///< max |mu_i,k|
  double wall_seconds = 0.0;
  double cpu_seconds = 0.0;       ///< the calling thread's CPU time (lgvi/cpu_time.hpp)
  bool converged() const { return status == CollocationStatus::Converged; }
  /// One line, e.g. "converged (Solve_Succeeded) in 85 iterations: cost 7.2, violation 1e-12, ...".
  std::string brief() const;
};

struct CollocationResult {
  CollocationSummary summary;
  double h = 0.0;             ///< T / K
  Eigen::MatrixXd states;     ///< n_y x (K + 1): y at the nodes t_k = k h (layout in the header comment)
  Eigen::MatrixXd controls;   ///< n_u x (2 K + 1): u at t = j h / 2 (nodes even, midpoints odd)
  std::vector<double> history_cost, history_infeasibility;  ///< per IPOPT iteration
};

/// Never throws: bad input is status InvalidInput with a message naming the field.
CollocationResult solve_collocation(const Pendulum3D& system, const TransferProblem& problem,
                                    const CollocationOptions& options);
CollocationResult solve_collocation(const FreeRigidBody& system, const TransferProblem& problem,
                                    const CollocationOptions& options);
CollocationResult solve_collocation(const DumbbellSpacecraft& system, const TransferProblem& problem,
                                    const CollocationOptions& options);
CollocationResult solve_collocation(const CartPendulum& system, const CartPendulumTransfer& problem,
                                    const CollocationOptions& options);
CollocationResult solve_collocation(const ConnectedBodies& system, const ConnectedBodiesTransfer& problem,
                                    const CollocationOptions& options);

namespace collocation_detail {
/// The quaternion model's rate f(y, u, mu) and its Jacobian [df/dy, df/du, df/dmu] (7 x 11), for
/// the tests' central-difference check.
void attitude_rhs(const Pendulum3D& system, const Eigen::Matrix<double, 7, 1>& y, const Vec3& u, double mu,
                  Eigen::Matrix<double, 7, 1>& f, Eigen::Matrix<double, 7, 11>* jacobian);
void attitude_rhs(const FreeRigidBody& system, const Eigen::Matrix<double, 7, 1>& y, const Vec3& u, double mu,
                  Eigen::Matrix<double, 7, 1>& f, Eigen::Matrix<double, 7, 11>* jacobian);
/// The same for every system, sizes checked: f(y, u, mu) and [df/dy, df/du, df/dmu]
/// (n_y x (n_y + n_u + NQ)); y in the layout of the header comment, mu one rate per quaternion.
void rhs(const DumbbellSpacecraft& system, const Eigen::VectorXd& y, const Eigen::VectorXd& u,
         const Eigen::VectorXd& mu, Eigen::VectorXd& f, Eigen::MatrixXd* jacobian);
void rhs(const CartPendulum& system, const Eigen::VectorXd& y, const Eigen::VectorXd& u, const Eigen::VectorXd& mu,
         Eigen::VectorXd& f, Eigen::MatrixXd* jacobian);
void rhs(const ConnectedBodies& system, const Eigen::VectorXd& y, const Eigen::VectorXd& u,
         const Eigen::VectorXd& mu, Eigen::VectorXd& f, Eigen::MatrixXd* jacobian);

/// The transcription with K intervals at the variables x (empty: the initial guess): the
/// constraints g(x), the dense constraint Jacobian assembled from the sparse one, the cost and its
/// gradient, and with HessianProbe::lambda given (m entries) the dense Hessian of the Lagrangian
/// sigma J + lambda^T g assembled from the sparse one (`hessian`: Exact or CostOnly); for the
/// tests' central-difference checks.
struct HessianProbe {
  Eigen::VectorXd lambda;
  double sigma = 1.0;
  IpoptHessian hessian = IpoptHessian::Exact;
};
struct TranscriptionProbe {
  Eigen::VectorXd x, g, cost_gradient;
  Eigen::MatrixXd jacobian, hessian;
  double cost = 0.0;
};
TranscriptionProbe probe(const CartPendulum& system, const CartPendulumTransfer& problem, int K,
                         const Eigen::VectorXd& x = {}, const HessianProbe& hessian = {});
TranscriptionProbe probe(const ConnectedBodies& system, const ConnectedBodiesTransfer& problem, int K,
                         const Eigen::VectorXd& x = {}, const HessianProbe& hessian = {});
TranscriptionProbe probe(const DumbbellSpacecraft& system, const TransferProblem& problem, int K,
                         const Eigen::VectorXd& x = {}, const HessianProbe& hessian = {});
TranscriptionProbe probe(const Pendulum3D& system, const TransferProblem& problem, int K,
                         const Eigen::VectorXd& x = {}, const HessianProbe& hessian = {});
}  // namespace collocation_detail

}  // namespace lgvi::ocp
