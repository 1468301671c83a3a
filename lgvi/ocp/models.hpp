// The two systems of the indirect optimal-control examples (sections 3.1, 3.2), seen as
// "kick-drift" maps for their linearization (lgvi/ocp/linearization.hpp).
//
// Every LGVI step of the project factors into
//     kick(c0, u_k) at q_k  ->  drift  ->  kick(c1, u_{k+1}) at q_{k+1}
// (lgvi.hpp: c0 = c1 = h/2 in the symmetric form, c0 = 0 and c1 = h in the printed form), where
//   - the drift moves the configuration q = (R[, x]) with the momenta P = (Pi[, p = m v]) by the
//     implicit rotation update h hat(Pi) = F J_d - J_d F^T, R' = R F, Pi' = F^T Pi
//     [, x' = x + h p / m], and is the same for every system;
//   - the kick changes the momenta only: P' = P + c (phi(q) + B(q) u), with phi = [M; f] the
//     generalized force of the potential (eq. 13) and B(q) u the control (linear in u).
// A model supplies the system-specific pieces of the kick and their derivatives. Derivatives
// with respect to q are right-trivialized: q -> (R exp(eta), x + dx), the tangent is
// [eta; dx] (eq. 16). Momenta tangents are [dPi; dp]; the z = [eta; dx; dOmega; dv]
// follows by dOmega = J^{-1} dPi, dv = dp / m (momentum_per_velocity()).
//
// Notation of the model interface (n_q = 3 or 6 configuration tangent, n_u controls):
//   phi(q)             generalized force, n_q
//   B(q)               control matrix, n_q x n_u (the kick adds c B u)
//   G(q, u)            d(phi + B u)/dq, n_q x n_q
//   H(q, u, nu)        d(G(q, u)^T nu)/dq, n_q x n_q   (second derivatives, for the sensitivities)
//   C(q, nu)           d(B(q)^T nu)/dq, n_u x n_q; also d(G(q, u)^T nu)/du = C(q, nu)^T.
#pragma once

#include <Eigen/Dense>

#include "lgvi/lgvi.hpp"
#include "lgvi/so3.hpp"
#include "lgvi/systems/dumbbell.hpp"
#include "lgvi/systems/free_rigid_body.hpp"
#include "lgvi/systems/pendulum.hpp"
#include "lgvi/types.hpp"

namespace lgvi::ocp {

/// Dimensions and fixed-size types of a model: n_q configuration (and momentum) coordinates,
/// n_u controls; a state variation is 2 n_q long.
template <int NQ, int NU>
struct ModelDimensions {
  static constexpr int nq = NQ;
  static constexpr int nu = NU;
  using VecQ = Eigen::Matrix<double, nq, 1>;
  using VecU = Eigen::Matrix<double, nu, 1>;
  using VecS = Eigen::Matrix<double, 2 * nq, 1>;
  using MatQ = Eigen::Matrix<double, nq, nq>;
  using MatQU = Eigen::Matrix<double, nq, nu>;
  using MatUQ = Eigen::Matrix<double, nu, nq>;
  using MatU = Eigen::Matrix<double, nu, nu>;
  using MatS = Eigen::Matrix<double, 2 * nq, 2 * nq>;
};

/// The 3D pendulum with the symmetric control moment R^T e3 x u (eq. 23): n_q = n_u = 3.
///
/// With a = R^T e3 (gravity in the body frame; d a = hat(a) eta under R -> R exp(eta)):
///   phi = m g rho x a,  B = hat(a) (so B u = a x u),
///   G   = hat(w) hat(a) with w = m g rho - u (the control moment's own dependence on R
///         enters with u),
///   H   = -hat(w x nu) hat(a),   C = hat(nu) hat(a).
/// The vertical momentum C_v = e3^T R Pi = a . Pi is conserved by every kick and drift for any
/// u, with gradient dC_v = [Pi x a; a] (the symmetry of section 3.2).
struct PendulumModel : ModelDimensions<3, 3> {
  static constexpr bool has_translation = false;
  static constexpr bool has_symmetry = true;
  using System = Pendulum3D;
  using Lgvi = AttitudeLgvi<Pendulum3D>;
  using State = AttitudeState;
  using Control = Vec3;

  explicit PendulumModel(const Pendulum3D& s) : system(s) {}
  const Pendulum3D& system;

  static const char* name() { return "pendulum"; }
  static Control control(const VecU& u) { return u; }
  static VecU control_vector(const Control& u) { return u; }
  static Vec3 position(const State&) { return Vec3::Zero(); }
  static VecQ momenta(const State& s) { return s.Pi; }
  /// dP / dvelocity: Pi = J Omega.
  MatQ momentum_per_velocity() const { return system.inertia.J; }

  /// The momentum that the drift of AttitudeLgvi::step sees after its first kick, with the
  /// same arithmetic (so that the rotation update here and in step() agree bit for bit).
  VecQ kicked_momenta(const State& s, double c0, const VecU& u) const {
    Vec3 kick = s.Pi;
    if (c0 != 0.0) kick += c0 * (s.M + system.control_moment(s.R, u));
    return kick;
  }

  MatQU control_matrix(const Mat3& R, const Vec3& /*x*/) const { return so3::hat(R.row(2).transpose()); }
  MatQ force_jacobian(const Mat3& R, const Vec3& /*x*/, const VecU& u) const { return system.J_moment_eta(R, u); }
  MatQ force_jacobian_transpose_derivative(const Mat3& R, const Vec3& /*x*/, const VecU& u,
                                           const VecQ& nu) const {
    const Vec3 a = R.row(2).transpose();
    const Vec3 w = system.mass * system.gravity * system.rho - u;
    return -so3::hat(w.cross(nu)) * so3::hat(a);
  }
  MatUQ control_matrix_transpose_derivative(const Mat3& R, const Vec3& /*x*/, const VecQ& nu) const {
    return so3::hat(nu) * so3::hat(R.row(2).transpose());
  }
  /// Gradient of the conserved vertical momentum e3^T R Pi in the tangent [eta; dPi].
  static VecS conserved_gradient(const State& s) { return Pendulum3D::vertical_momentum_gradient(s.R, s.Pi); }
};

/// The free rigid body with a body-frame control moment u (FreeRigidBody::control_moment): a
/// spacecraft slew, n_q = n_u = 3. No potential and B = I, so phi = 0, G = H = C = 0: the kicks
/// are P' = P + c u and the necessary conditions reduce to u_j = -W^{-1} lambda_{j,Pi} with the
/// drift's linearization alone carrying the dynamics (eqs. 17-19 with M = 0). Not the pendulum's
/// model with m g rho = 0: its control R^T e3 x u has no component along the vertical.
/// The spatial angular momentum R Pi is changed by u, so no symmetry remains for the shooting.
struct FreeBodyModel : ModelDimensions<3, 3> {
  static constexpr bool has_translation = false;
  static constexpr bool has_symmetry = false;
  using System = FreeRigidBody;
  using Lgvi = AttitudeLgvi<FreeRigidBody>;
  using State = AttitudeState;
  using Control = Vec3;

  explicit FreeBodyModel(const FreeRigidBody& s) : system(s) {}
  const FreeRigidBody& system;

  static const char* name() { return "free-body"; }
  static Control control(const VecU& u) { return u; }
  static VecU control_vector(const Control& u) { return u; }
  static Vec3 position(const State&) { return Vec3::Zero(); }
  static VecQ momenta(const State& s) { return s.Pi; }
  MatQ momentum_per_velocity() const { return system.inertia.J; }

  /// The momentum after AttitudeLgvi::step's first kick, with its arithmetic.
  VecQ kicked_momenta(const State& s, double c0, const VecU& u) const {
    Vec3 kick = s.Pi;
    if (c0 != 0.0) kick += c0 * (s.M + system.control_moment(s.R, u));
    return kick;
  }

  static MatQU control_matrix(const Mat3&, const Vec3&) { return MatQU::Identity(); }
  static MatQ force_jacobian(const Mat3&, const Vec3&, const VecU&) { return MatQ::Zero(); }
  static MatQ force_jacobian_transpose_derivative(const Mat3&, const Vec3&, const VecU&, const VecQ&) {
    return MatQ::Zero();
  }
  static MatUQ control_matrix_transpose_derivative(const Mat3&, const Vec3&, const VecQ&) { return MatUQ::Zero(); }
  static VecS conserved_gradient(const State&) { return VecS::Zero(); }
};

/// The dumbbell spacecraft on SE(3) (section 3.1): q = (R, x), P = (Pi, p = m v),
/// u = [u^m (body moment); u^f (inertial force)] in the order of the momenta, n_q = n_u = 6.
///
/// Sphere q (= 1, 2) at p_q = x + R rho_q (rho_1 = rho, rho_2 = -rho) carries the Newtonian
/// potential V(p) = -k / |p|, k = mu m / 2; its force f_q = -k p / |p|^3 has Jacobian
/// K_q = -k (I / r^3 - 3 p p^T / r^5). With P_q = [-R hat(rho_q), I] (d p_q = P_q [eta; dx]):
///   phi = sum_q P_q^T f_q = [sum rho_q x R^T f_q; sum f_q]                       (eq. 13)
///   G   = sum_q P_q^T K_q P_q + blockdiag(hat(rho_q) hat(R^T f_q), 0)
///   B   = I (the controls act on the momenta directly), C = 0.
/// H (the derivative of G^T nu) needs the third derivative of V, N_q(y) = dK_q[y]/dp:
///   N(p, y) = -k (-3 (y p^T + p y^T + (p.y) I) / r^5 + 15 (p.y) p p^T / r^7).
struct DumbbellModel : ModelDimensions<6, 6> {
  static constexpr bool has_translation = true;
  static constexpr bool has_symmetry = false;
  using System = DumbbellSpacecraft;
  using Lgvi = DumbbellLgvi;
  using State = RigidBodyState;
  using Control = DumbbellSpacecraft::Control;

  explicit DumbbellModel(const DumbbellSpacecraft& s) : system(s) {}
  const DumbbellSpacecraft& system;

  static const char* name() { return "dumbbell"; }
  static Control control(const VecU& u) {
    Control c;
    c.moment = u.head<3>();
    c.force = u.tail<3>();
    return c;
  }
  static VecU control_vector(const Control& c) {
    VecU u;
    u << c.moment, c.force;
    return u;
  }
  static Vec3 position(const State& s) { return s.x; }
  VecQ momenta(const State& s) const {
    VecQ P;
    P << s.Pi, system.mass * s.v;
    return P;
  }
  MatQ momentum_per_velocity() const {
    MatQ T = MatQ::Zero();
    T.topLeftCorner<3, 3>() = system.inertia.J;
    T.bottomRightCorner<3, 3>() = system.mass * Mat3::Identity();
    return T;
  }
  /// [Pi; p] after the first kick, with the arithmetic of DumbbellLgvi::step.
  VecQ kicked_momenta(const State& s, double c0, const VecU& u) const {
    Vec3 kick = s.Pi;
    Vec3 p = system.mass * s.v;
    if (c0 != 0.0) {
      kick += c0 * (s.forces.moment + u.head<3>());
      p += c0 * (s.forces.force + u.tail<3>());
    }
    VecQ P;
    P << kick, p;
    return P;
  }

  MatQU control_matrix(const Mat3&, const Vec3&) const { return MatQU::Identity(); }
  MatQ force_jacobian(const Mat3& R, const Vec3& x, const VecU& u) const;
  MatQ force_jacobian_transpose_derivative(const Mat3& R, const Vec3& x, const VecU& u,
                                           const VecQ& nu) const;
  MatUQ control_matrix_transpose_derivative(const Mat3&, const Vec3&, const VecQ&) const {
    return MatUQ::Zero();
  }
  static VecS conserved_gradient(const State&) { return VecS::Zero(); }
};

}  // namespace lgvi::ocp
