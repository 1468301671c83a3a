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

/// Solves G = 0 from the initial guess A (A_i = F_i - I, updated in place on success only). The
/// residual callable is residual(const std::array<Mat3, N>& A, Vector& G, Matrix& DG) -> double
/// scale.
/// Returns a RotationUpdateSummary (parametrization: exponential, the update's retraction).
template <int N, class Residual>
RotationUpdateSummary solve_on_rotations(std::array<Mat3, N>& A, Residual&& residual,
                                         const GroupNewtonOptions& o = {}) {
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
  Matrix DG;
  for (;;) {
    const double scale = residual(std::as_const(iterate), G, DG);
    const double g = G.norm();
    s.rhs_norm = scale;
    s.residual = scale > 0.0 ? g / scale : g;
    if (!std::isfinite(g)) break;
    if (g <= o.relative_tolerance * scale + o.absolute_tolerance) {
      // Polish: one more Newton step, kept if it lowers |G|. The tolerance test is relative to
      // the largest terms of G; a conserved momentum along a weak inertia axis is far smaller and
      // would accumulate the leftover residual step after step.
      if (s.iterations < o.max_iterations && g > 0.0) {
        const Vector xi = Eigen::PartialPivLU<Matrix>(DG).solve(-G);
        std::array<Mat3, N> polished = iterate;
        update(polished, xi);
        Vector G2;
        Matrix DG2;
        residual(std::as_const(polished), G2, DG2);
        ++s.iterations;
        s.polished = true;
        if (G2.norm() < g) {
          iterate = polished;
          s.residual = scale > 0.0 ? G2.norm() / scale : G2.norm();
        }
      }
      s.status = RotationUpdateStatus::Converged;
      A = iterate;
      return s;
    }
    if (s.iterations >= o.max_iterations) break;
    const Vector xi = Eigen::PartialPivLU<Matrix>(DG).solve(-G);
    if (!xi.allFinite()) break;
    update(iterate, xi);
    ++s.iterations;
  }
  s.status = RotationUpdateStatus::NotConverged;
  return s;
}

/// d/dxi vee(F exp(hat xi) K - K exp(hat xi)^T F^T) at xi = 0 for symmetric K (F = I + A):
/// F (tr(K F) I - K F) (from hat(xi) B + B^T hat(xi) = hat((tr B I - B) xi), B = K F).
inline Mat3 rotation_update_jacobian(const Mat3& F, const Mat3& K) {
  const Mat3 KF = K * F;
  return F * (KF.trace() * Mat3::Identity() - KF);
}

}  // namespace lgvi
