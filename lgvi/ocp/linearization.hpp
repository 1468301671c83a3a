// Linearization of the LGVI flow maps (eq. 16: z_{k+1} = A_k z_k + B_k du) and of the
// state-multiplier flow of the discrete necessary conditions (eqs. 17-19, 27, 28).
//
// Coordinates. Internally the tangent of a state is w = [eta; dx; dPi; dp] (the momenta the
// LGVI carries); the z = [eta; dx; dOmega; dv] (eq. 16) is z = T^{-1} w with
// T = blockdiag(I, J, m I) (models.hpp: momentum_per_velocity). Multipliers (costates) are
// covectors on w: lambda = [lambda_R; lambda_x; lambda_Pi; lambda_p], which are the paper's
// multipliers of eq. 15/25 (lambda^3, lambda^1, lambda^4, lambda^2 there; lambda^1, lambda^2 of
// eq. 25 for the pendulum): they multiply the constraints written for Pi = J Omega and m v.
//
// The step is kick(c0, u_k) - drift - kick(c1, u_{k+1}) (models.hpp), so
//     A_k = DK_1 DD DK_0,   DK = [I 0; c G I],
// and the drift's linearization DD follows from differentiating the rotation update
//     h hat(Pi) = F J_d - J_d F^T        with dF = F hat(xi):
//     h hat(dPi) = F hat(xi) J_d + J_d hat(xi) F^T = hat(L xi),
//     L = (tr(F J_d) I - F J_d) F                                                      (*)
// from the identity hat(w) A + A^T hat(w) = hat((tr(A) I - A) w) (any 3x3 A) applied to
// A = F J_d and w = F xi (F hat(xi) = hat(F xi) F). [At F = I, L = tr(J_d) I - J_d = J: the
// linearized update J f = h Pi.] Then R' = R F, Pi' = F^T Pi give
//     eta' = F^T eta + xi,   dPi' = F^T dPi + hat(Pi') xi,   xi = h L^{-1} dPi,
//     dx' = dx + (h/m) dp,   dp' = dp.
// L is invertible exactly when the rotation update's Newton Jacobian is (its solution is a
// regular point); tests/ocp checks (*) and A_k against finite differences of step().
//
// Multipliers forward. The necessary conditions (eq. 19) lambda_k = A_{k+1}^T lambda_{k+1}
// run backwards; shooting needs them forwards, lambda_{k+1} = A_{k+1}^{-T} lambda_k, and A_{k+1}
// depends on u_{k+2}, itself a function of lambda_{k+1}. Split into kicks and drifts this is
// explicit: across a kick the momentum part of the multiplier is unchanged
// (DK^T = [I c G^T; 0 I]), so the kick's control u = -W^{-1} B^T lambda_P (eqs. 17, 18, 27)
// is known before the kick, and lambda_q' = lambda_q - c G(q, u)^T lambda_P. Across the drift
// lambda' = DD^{-T} lambda is solved by block substitution (DD is block upper triangular):
//     lambda_R' = F^T lambda_R,
//     (L^T F - h hat(Pi')) lambda_Pi' = L^T lambda_Pi - h lambda_R'                      (**)
//     lambda_x' = lambda_x,  lambda_p' = lambda_p - (h/m) lambda_x.
// The 3x3 matrix of (**) is L^T F - h hat(Pi') = L^T (dPi'/dPi): invertible because the drift
// is a symplectic map (its inverse is the drift backwards in time), hence DD is invertible.
#pragma once

#include <Eigen/Dense>

#include "lgvi/lgvi.hpp"
#include "lgvi/ocp/models.hpp"
#include "lgvi/so3.hpp"

namespace lgvi::ocp {

/// J_hPi_xi = L = (tr(F J_d) I - F J_d) F: h dPi = L xi for dF = F hat(xi) on
/// h hat(Pi) = F J_d - J_d F^T (eq. 8). Precondition: J_d symmetric. Equal in exact arithmetic
/// to lgvi::J_G_xi(F, J_d), the rotation update's residual Jacobian (product order differs).
inline Mat3 J_hPi_xi(const Mat3& F, const Mat3& Jd) {
  const Mat3 A = F * Jd;
  return (A.trace() * Mat3::Identity() - A) * F;
}

/// The rotational drift (R, Pi) -> (R F, F^T Pi) linearized at a solved F, with the transposed
/// inverse for the multipliers and their derivatives (for the sensitivities). Fixed size, no heap.
struct RotationalDrift {
  double h;
  Mat3 Jd;
  Mat3 F;
  Vec3 Pi_in;
  Vec3 Pi_out;
  Mat3 L;
  Mat3 L_inverse;
  Mat3 Mc;  ///< L^T F - h hat(Pi_out), the matrix of (**)
  Eigen::PartialPivLU<Mat3> Mc_lu;

  RotationalDrift(const Mat3& Jd_, double h_, const Mat3& F_, const Vec3& Pi_in_)
      : h(h_), Jd(Jd_), F(F_), Pi_in(Pi_in_), Pi_out(F_.transpose() * Pi_in_),
        L(J_hPi_xi(F_, Jd_)), L_inverse(L.inverse()),
        Mc(L.transpose() * F - h * so3::hat(Pi_out)), Mc_lu(Mc) {}

  /// d eta'/d eta, d eta'/dPi, dPi'/dPi (dPi'/d eta = 0).
  Mat3 J_eta_eta() const { return F.transpose(); }
  Mat3 J_eta_Pi() const { return h * L_inverse; }
  Mat3 J_Pi_Pi() const { return F.transpose() + h * so3::hat(Pi_out) * L_inverse; }

  /// lambda_out = DD^{-T} lambda_in for the rotational block, by (**).
  void multiplier(const Vec3& lR_in, const Vec3& lP_in, Vec3& lR_out, Vec3& lP_out) const {
    lR_out = F.transpose() * lR_in;
    lP_out = Mc_lu.solve(L.transpose() * lP_in - h * lR_out);
  }

  /// Propagates one tangent direction: the state tangent (eta, dPi) at the drift's input becomes
  /// the output's, and the multiplier tangent (dlR, dlP) likewise; lR_in, lP_in, lR_out, lP_out are
  /// the multipliers of the nominal (from multiplier()).
  void tangent(Vec3& eta, Vec3& dPi, Vec3& dlR, Vec3& dlP, const Vec3& lP_in, const Vec3& lR_out,
               const Vec3& lP_out) const {
    const Vec3 xi = h * (L_inverse * dPi);
    const Mat3 Xi = so3::hat(xi);
    eta = F.transpose() * eta + xi;
    dPi = F.transpose() * dPi + Pi_out.cross(xi);
    // dlR' = d(F^T) lR + F^T dlR = -hat(xi) lR' + F^T dlR.
    const Vec3 dlR_out = lR_out.cross(xi) + F.transpose() * dlR;
    // dL from dF = F hat(xi): A = F J_d, dA = F hat(xi) J_d.
    const Mat3 A = F * Jd;
    const Mat3 dA = F * Xi * Jd;
    const Mat3 dL = (dA.trace() * Mat3::Identity() - dA) * F + (A.trace() * Mat3::Identity() - A) * F * Xi;
    const Mat3 dMc = dL.transpose() * F + L.transpose() * F * Xi - h * so3::hat(dPi);
    dlP = Mc_lu.solve(dL.transpose() * lP_in + L.transpose() * dlP - h * dlR_out - dMc * lP_out);
    dlR = dlR_out;
  }
};

/// Jacobians of one LGVI step s_{k+1} = Phi(s_k, u_k, u_{k+1}) (eq. 16) in w coordinates
/// [eta; dx; dPi; dp] or, after to_velocity_coordinates, in z = [eta; dx; dOmega; dv].
template <class Model>
struct StepJacobians {
  typename Model::MatS A;
  Eigen::Matrix<double, 2 * Model::nq, Model::nu> B_k;   ///< d s_{k+1} / d u_k (zero in the printed form)
  Eigen::Matrix<double, 2 * Model::nq, Model::nu> B_k1;  ///< d s_{k+1} / d u_{k+1}
};

/// A_k, B_k of one step at (s, u_k, u_{k+1}) in w coordinates. Solves the step's rotation
/// update (with the integrator's solver); returns its summary, and writes `jac` (and `next`,
/// the step's result, when given) only when it converged.
template <class Model>
RotationUpdateSummary linearize_step(const Model& model, const typename Model::Lgvi& lgvi,
                                     const typename Model::State& s, double h,
                                     const typename Model::VecU& u_k, const typename Model::VecU& u_k1,
                                     StepJacobians<Model>& jac, typename Model::State* next = nullptr) {
  constexpr int nq = Model::nq;
  using MatS = typename Model::MatS;
  const auto [c0, c1] = impulse_weights(lgvi.form(), h);
  const typename Model::VecQ P_plus = model.kicked_momenta(s, c0, u_k);
  Mat3 F;
  const RotationUpdateSummary summary = lgvi.solver().solve(h * P_plus.template head<3>(), F);
  if (!summary.converged()) return summary;
  const RotationalDrift drift(lgvi.system().inertia.Jd, h, F, P_plus.template head<3>());
  const Mat3 R1 = s.R * F;
  Vec3 x1 = Vec3::Zero();
  MatS DD = MatS::Zero();
  DD.template block<3, 3>(0, 0) = drift.J_eta_eta();
  DD.template block<3, 3>(0, nq) = drift.J_eta_Pi();
  DD.template block<3, 3>(nq, nq) = drift.J_Pi_Pi();
  if constexpr (Model::has_translation) {
    const double m = model.system.mass;
    x1 = s.x + (h / m) * P_plus.template tail<3>();
    DD.template block<3, 3>(3, 3) = Mat3::Identity();
    DD.template block<3, 3>(3, nq + 3) = (h / m) * Mat3::Identity();
    DD.template block<3, 3>(nq + 3, nq + 3) = Mat3::Identity();
  }
  const Vec3 x0 = Model::position(s);
  MatS DK0 = MatS::Identity();
  MatS DK1 = MatS::Identity();
  if (c0 != 0.0) DK0.template block<nq, nq>(nq, 0) = c0 * model.force_jacobian(s.R, x0, u_k);
  DK1.template block<nq, nq>(nq, 0) = c1 * model.force_jacobian(R1, x1, u_k1);
  jac.A = DK1 * DD * DK0;
  jac.B_k.setZero();
  jac.B_k1.setZero();
  if (c0 != 0.0) {
    jac.B_k.template bottomRows<nq>() = c0 * model.control_matrix(s.R, x0);
    jac.B_k = (DK1 * DD * jac.B_k).eval();
  }
  jac.B_k1.template bottomRows<nq>() = c1 * model.control_matrix(R1, x1);
  if (next != nullptr) {
    const RotationUpdateSummary again = lgvi.step(s, h, Model::control(u_k), Model::control(u_k1), *next);
    if (!again.converged()) return again;
  }
  return summary;
}

/// Converts step Jacobians from w = [eta; dx; dPi; dp] to z = [eta; dx; dOmega; dv]:
/// A_z = T^{-1} A_w T, B_z = T^{-1} B_w with T = blockdiag(I, momentum_per_velocity).
template <class Model>
StepJacobians<Model> to_velocity_coordinates(const Model& model, const StepJacobians<Model>& w) {
  constexpr int nq = Model::nq;
  typename Model::MatS T = Model::MatS::Identity();
  T.template bottomRightCorner<nq, nq>() = model.momentum_per_velocity();
  typename Model::MatS T_inverse = Model::MatS::Identity();
  T_inverse.template bottomRightCorner<nq, nq>() = model.momentum_per_velocity().inverse();
  StepJacobians<Model> z;
  z.A = T_inverse * w.A * T;
  z.B_k = T_inverse * w.B_k;
  z.B_k1 = T_inverse * w.B_k1;
  return z;
}

}  // namespace lgvi::ocp
