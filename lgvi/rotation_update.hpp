// The implicit rotation update of every LGVI of the project (eqs. 8, 21, 32):
//
//     h hat(p) = F J_d - J_d F^T,   F in SO(3),   J_d = tr(J)/2 I - J.
//
// With F = I + a hat(f) + b hat(f)^2 (a parametrization of SO(3) by f in R^3) the matrix
// equation is equivalent to the vector equation
//
//     G(f) = a J f + b f x (J f) - h p = 0
//
// because hat(f) J_d + J_d hat(f) = hat(J f) and hat(f)^2 J_d - J_d hat(f)^2 = hat(f x J f).
//   Cayley:       a = b = 2 / (1 + |f|^2), f = tan(theta/2) n; solved as the polynomial
//                 H(f) = J f + f x J f - (1 + |f|^2) h p / 2 = (1 + |f|^2)/2 G(f).
//   Exponential:  a = sin(t)/t, b = (1 - cos t)/t^2, t = |f|, f = theta n.
// Newton's method with the analytic Jacobian of H (or G), from the linearized warm start
// J f = h p (exponential) or J f = h p / 2 (Cayley). Converged when
// |G(f)| <= relative_tolerance (|h p| + ||J||_F (a |f| + b |f|^2)) + absolute_tolerance, i.e.
// relative to the size of the terms of G (a |f| + b |f|^2 = sin(theta) + 1 - cos(theta) in both
// charts), which is the round-off floor of evaluating G. If the primary parametrization fails,
// the other one is tried from its own warm start.
//
// A solution exists only for |h p| <= max_F |vee(F J_d - J_d F^T)| <= sqrt(2) ||J_d||_F; beyond
// that bound the solver reports OutsideDomain without iterating.
#pragma once

#include <string>

#include "lgvi/inertia.hpp"
#include "lgvi/types.hpp"

namespace lgvi {

enum class Parametrization { Cayley, Exponential };
const char* to_string(Parametrization p);

enum class RotationUpdateStatus {
  Converged,
  OutsideDomain,  ///< |h p| exceeds the bound above: no rotation solves the equation.
  NotConverged,   ///< Newton hit the iteration cap or left the finite numbers in both charts.
};
const char* to_string(RotationUpdateStatus s);

struct RotationUpdateOptions {
  Parametrization primary = Parametrization::Cayley;
  bool fallback = true;  ///< try the other parametrization when the primary fails
  /// 16 eps, relative to the size of G's terms |h p| + ||J||_F (a |f| + b |f|^2) (see the
  /// convergence test above). Evaluating G costs <= 8 unit round-offs (4 eps) of that size (the
  /// 3-term products of J f, the cross product, the scalings and sums); near the root Newton's
  /// computed residual is the previous step's evaluation error plus the current one, so it
  /// settles at <= 8 eps and may oscillate there (observed: +-5.5 eps). 16 eps leaves a factor 2.
  double relative_tolerance = 16.0 * 2.220446049250313e-16;
  double absolute_tolerance = 1e-300;
  int max_iterations = 30;  ///< per parametrization
  /// One extra Newton step when |G| is still above 4 eps |h p| after the test above (see
  /// rotation_update.cpp). Switched off only to demonstrate that the regression gate catches a
  /// degraded solver (`validate --degraded-rotation-update`).
  bool polish = true;
};

struct RotationUpdateSummary {
  RotationUpdateStatus status = RotationUpdateStatus::NotConverged;
  Parametrization parametrization = Parametrization::Cayley;  ///< the one that produced F
  int iterations = 0;          ///< Newton iterations over all attempts
  bool used_fallback = false;
  bool polished = false;       ///< the last of `iterations` was the optional polishing step
  double residual = 0.0;       ///< |G(f)| / |h p| at return (absolute when h p = 0)
  double rhs_norm = 0.0;       ///< |h p|

  bool converged() const { return status == RotationUpdateStatus::Converged; }
  /// One line: "converged in 3 Newton iterations (cayley), residual 1.2e-16".
  std::string brief() const;
};

/// Solves h hat(p) = F J_d - J_d F^T for F. Immutable after construction; `solve` allocates
/// nothing and may be called concurrently.
class RotationUpdateSolver {
 public:
  explicit RotationUpdateSolver(const Inertia& inertia, RotationUpdateOptions options = {});

  /// Finds F for the right-hand side hp = h p. On success F is orthonormal to round-off; on
  /// failure F is left unchanged and the summary says why.
  RotationUpdateSummary solve(const Vec3& hp, Mat3& F) const;

  /// Solves in one given parametrization, without fallback; f is the converged parameter.
  RotationUpdateSummary solve_in(Parametrization p, const Vec3& hp, Vec3& f) const;

  /// Residual vee(F J_d - J_d F^T) - h p of the matrix equation (diagnostic).
  Vec3 matrix_residual(const Mat3& F, const Vec3& hp) const;

  /// Upper bound on |h p| for which a solution can exist: sqrt(2) ||J_d||_F.
  double domain_bound() const { return domain_bound_; }

  const Inertia& inertia() const { return inertia_; }
  const RotationUpdateOptions& options() const { return options_; }

 private:
  Inertia inertia_;
  RotationUpdateOptions options_;
  double domain_bound_;
};

/// F = I + a hat(f) + b hat(f)^2 for the given parametrization.
Mat3 rotation_from(Parametrization p, const Vec3& f);

}  // namespace lgvi
