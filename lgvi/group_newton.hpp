// Newton's method on SO(3)^N for the coupled implicit updates of the multibody LGVIs
// (cart-pendulum eqs. 30-32, connected bodies eqs. 40-41).
//
// Unknowns F_1..F_N in SO(3), carried as A_i = F_i - I: the implicit equations involve F - I
// (F J_d - J_d F^T = A J_d - J_d A^T, (F - I) d), and for the small rotations of a time step
// forming F - I from F would cancel all but ~|log F| of the digits; A_i is updated directly,
// A <- A + (I + A) E with E = exp(hat xi) - I, and keeps full relative accuracy.
// Residual G in R^{3N}; Jacobian right-trivialized: G((I + A_i) exp(hat xi_i)) = G + DG xi + O(xi^2).
// Each iteration solves DG xi = -G, so every iterate is a rotation and convergence is quadratic.
// Converged when |G| <= relative_tolerance * scale + absolute_tolerance, where `scale` (returned
// by the residual) is the sum of the magnitudes of the terms of G, the round-off floor of its
// evaluation. Fixed-size types only: no heap.
//
// Cost: DG is formed only when a Newton step is taken (the residual and the Jacobian
// are separate callables), and DG xi = -G is solved in closed form: by the adjugate for N = 1,
// by block elimination with adjugate 3x3 inverses for N = 2 (pivoted LU when a block is nearly
// singular). The Newton steps change by round-off only; the converged A is the same to round-off.
#pragma once

#include <array>
#include <cmath>
#include <utility>

#include <Eigen/LU>

#include "lgvi/rotation_update.hpp"
#include "lgvi/so3.hpp"
#include "lgvi/types.hpp"

namespace lgvi {

struct GroupNewtonOptions {
  double relative_tolerance = 16.0 * 2.220446049250313e-16;
  double absolute_tolerance = 1e-300;
  int max_iterations = 50;
};

namespace group_newton_detail {

/// A^{-1} by the adjugate (rows: the cross products of A's columns over det A); false, X
/// untouched, when nearly singular (the guard of rotation_update_detail::solve_adjugate).
inline bool inverse_adjugate(const Mat3& A, Mat3& X) {
  const Vec3 k0 = A.col(1).cross(A.col(2)), k1 = A.col(2).cross(A.col(0)),
             k2 = A.col(0).cross(A.col(1));
  const double det = A.col(0).dot(k0);
  const double frobenius2 = A.squaredNorm();
  if (!(det * det > kEps * (frobenius2 * frobenius2 * frobenius2))) {
    return false;
  }
  const double inverse = 1.0 / det;
  X.row(0) = inverse * k0.transpose();
  X.row(1) = inverse * k1.transpose();
  X.row(2) = inverse * k2.transpose();
  return true;
}

/// DG^{-1} b for the Newton matrix of N = 1 or 2 rotations (see the header comment).
template <int N>
Eigen::Matrix<double, 3 * N, 1> solve_newton_matrix(const Eigen::Matrix<double, 3 * N, 3 * N>& DG,
                                                     const Eigen::Matrix<double, 3 * N, 1>& b) {
  if constexpr (N == 1) {
    return rotation_update_detail::solve3(DG.col(0), DG.col(1), DG.col(2), b);
  } else if constexpr (N == 2) {
    // [P Q; R S] [x1; x2] = [b1; b2]: x2 = (S - R P^{-1} Q)^{-1} (b2 - R P^{-1} b1),
    // x1 = P^{-1} b1 - P^{-1} Q x2. The diagonal blocks are the bodies' own rotation-update
    // Jacobians (~ their locked inertias) and the Schur complement that of the other body given
    // the first, both well conditioned for physical parameters; otherwise the pivoted LU.
    Mat3 P_inverse;
    if (inverse_adjugate(DG.template topLeftCorner<3, 3>(), P_inverse)) {
      const Mat3 PiQ = P_inverse * DG.template topRightCorner<3, 3>();
      const Vec3 Pib1 = P_inverse * b.template head<3>();
      const Mat3 schur = DG.template bottomRightCorner<3, 3>() - DG.template bottomLeftCorner<3, 3>() * PiQ;
      const Vec3 r = b.template tail<3>() - DG.template bottomLeftCorner<3, 3>() * Pib1;
      Vec3 x2;
      if (rotation_update_detail::solve_adjugate(schur.col(0), schur.col(1), schur.col(2), r, x2)) {
        Eigen::Matrix<double, 6, 1> x;
        x << Pib1 - PiQ * x2, x2;
        return x;
      }
    }
    return Eigen::PartialPivLU<Eigen::Matrix<double, 6, 6>>(DG).solve(b);
  } else {
    return Eigen::PartialPivLU<Eigen::Matrix<double, 3 * N, 3 * N>>(DG).solve(b);
  }
}

/// DG^{-1} B for a matrix right-hand side (the implicit-function solve of a step linearization,
/// LinearizationSolve::ClosedForm): N = 1 by the adjugate inverse, N = 2 by the block
/// elimination of solve_newton_matrix with adjugate inverses of P and of the Schur complement
/// (S - R P^{-1} Q)^{-1}; the pivoted LU when either is nearly singular. For C columns (N = 2)
/// ~4 x 27 + 36 C multiply-adds in fixed-size products, against Eigen's LU, whose matrix
/// triangular solves go through its blocked (packing) kernels even at fixed size.
template <int N, int C>
Eigen::Matrix<double, 3 * N, C> solve_newton_matrix_columns(const Eigen::Matrix<double, 3 * N, 3 * N>& DG,
                                                            const Eigen::Matrix<double, 3 * N, C>& B) {
  if constexpr (N == 1) {
    Mat3 inverse;
    if (inverse_adjugate(DG, inverse)) return inverse.lazyProduct(B);
  } else if constexpr (N == 2) {
    Mat3 P_inverse, schur_inverse;
    if (inverse_adjugate(DG.template topLeftCorner<3, 3>(), P_inverse)) {
      const Mat3 PiQ = P_inverse * DG.template topRightCorner<3, 3>();
      const Mat3 schur = DG.template bottomRightCorner<3, 3>() - DG.template bottomLeftCorner<3, 3>() * PiQ;
      if (inverse_adjugate(schur, schur_inverse)) {
        const Eigen::Matrix<double, 3, C> PiB1 = P_inverse.lazyProduct(B.template topRows<3>());
        Eigen::Matrix<double, 3 * N, C> X;
        X.template bottomRows<3>() =
            schur_inverse.lazyProduct(B.template bottomRows<3>() - DG.template bottomLeftCorner<3, 3>().lazyProduct(PiB1));
        X.template topRows<3>() = PiB1 - PiQ.lazyProduct(X.template bottomRows<3>());
        return X;
      }
    }
  }
  return Eigen::PartialPivLU<Eigen::Matrix<double, 3 * N, 3 * N>>(DG).solve(B);
}

}  // namespace group_newton_detail

/// How a step linearization solves its implicit-function system J_G_xi X = -J_G_in.
enum class LinearizationSolve {
  /// Eigen's partial-pivoting LU: the single-shooting (SLSQP) gradients' arithmetic, kept so
  /// that the paper method's iterates stay the same to the last bit.
  PivotedLu,
  /// solve_newton_matrix_columns (adjugate inverses, block elimination; LU when nearly
  /// singular): the same X to round-off, faster (multiple shooting's Jacobians; with the reverse
  /// sweeps, a connected-bodies Jacobian sweep 1.64 -> 1.07 ms, lgvi/ocp/README.md).
  ClosedForm,
};

/// Solves G = 0 from the initial guess A (A_i = F_i - I, updated in place on success only).
/// The callables: residual(const std::array<Mat3, N>& A, Vector& G) -> double scale (the sum of
/// the magnitudes of G's terms), and jacobian(const std::array<Mat3, N>& A, Matrix& DG), the
/// right-trivialized derivative at the A last passed to residual.
/// Returns a RotationUpdateSummary (parametrization: exponential, the update's retraction).
template <int N, class Residual, class Jacobian>
RotationUpdateSummary solve_on_rotations(std::array<Mat3, N>& A, Residual&& residual,
                                         Jacobian&& jacobian, const GroupNewtonOptions& o = {}) {
  using Vector = Eigen::Matrix<double, 3 * N, 1>;
  using Matrix = Eigen::Matrix<double, 3 * N, 3 * N>;
  RotationUpdateSummary s;
  s.parametrization = Parametrization::Exponential;
  std::array<Mat3, N> iterate = A;
  const auto update = [](std::array<Mat3, N>& X, const Vector& xi) {
    for (int i = 0; i < N; ++i) {
      const Mat3 E = so3::exp_minus_identity(xi.template segment<3>(3 * i));
      X[i] += E + X[i] * E;
    }
  };
  Vector G;
  for (;;) {
    const double scale = residual(std::as_const(iterate), G);
    const double g = G.norm();
    s.rhs_norm = scale;
    s.set_residual(scale > 0.0 ? g / scale : g);
    if (!std::isfinite(g)) break;
    if (g <= o.relative_tolerance * scale + o.absolute_tolerance) {
      // Polish: one more Newton step, kept if it lowers |G|. The tolerance test is relative to
      // the largest terms of G; a conserved momentum along a weak inertia axis is far smaller and
      // would accumulate the leftover residual step after step.
      if (s.iterations < o.max_iterations && g > 0.0) {
        Matrix DG;
        jacobian(std::as_const(iterate), DG);
        const Vector xi = group_newton_detail::solve_newton_matrix<N>(DG, Vector(-G));
        std::array<Mat3, N> polished = iterate;
        update(polished, xi);
        Vector G2;
        residual(std::as_const(polished), G2);
        ++s.iterations;
        s.polished = true;
        if (G2.norm() < g) {
          iterate = polished;
          s.set_residual(scale > 0.0 ? G2.norm() / scale : G2.norm());
        }
      }
      s.status = RotationUpdateStatus::Converged;
      A = iterate;
      return s;
    }
    if (s.iterations >= o.max_iterations) break;
    Matrix DG;
    jacobian(std::as_const(iterate), DG);
    const Vector xi = group_newton_detail::solve_newton_matrix<N>(DG, Vector(-G));
    if (!xi.allFinite()) break;
    update(iterate, xi);
    ++s.iterations;
  }
  s.status = RotationUpdateStatus::NotConverged;
  return s;
}

/// vee(A K - K A^T) for symmetric K (the term of eqs. 32, 40, 41 in A = F - I): with X = A K,
/// K A^T = X^T, so it is (X21 - X12, X02 - X20, X10 - X01), six entries of one product instead of
/// two whole products. Precondition: K exactly symmetric (Inertia::from makes J_d so).
inline Vec3 vee_of_skew_product(const Mat3& A, const Mat3& K) {
  const auto x = [&](int i, int j) { return A.row(i).dot(K.col(j)); };
  return Vec3(x(2, 1) - x(1, 2), x(0, 2) - x(2, 0), x(1, 0) - x(0, 1));
}

/// J_G_xi: d/dxi vee(F exp(hat xi) K - K exp(hat xi)^T F^T) at xi = 0 for symmetric K (F = I +
/// A), the Jacobian of the rotation update's residual G (eqs. 32, 40, 41) on a right
/// perturbation of F: F (tr(K F) I - K F) (from hat(xi) B + B^T hat(xi) = hat((tr B I - B) xi),
/// B = K F). In exact arithmetic it equals ocp::J_hPi_xi(F, K) (the same derivative, read as
/// that of h Pi); the two keep their own product orders, which the solver's and the
/// linearization's round-off depend on.
inline Mat3 J_G_xi(const Mat3& F, const Mat3& K) {
  const Mat3 KF = K * F;
  return F * (KF.trace() * Mat3::Identity() - KF);
}

}  // namespace lgvi
