// Moment of inertia, validated once, with the quantities every step needs precomputed.
#pragma once

#include <stdexcept>
#include <string>

#include "lgvi/types.hpp"

namespace lgvi {

/// Bad physical input, naming the offending field (e.g. "inertia", "h", "R0").
/// Thrown only at construction or validation boundaries, never inside a step.
class InvalidInput : public std::invalid_argument {
 public:
  InvalidInput(std::string field, const std::string& reason)
      : std::invalid_argument(field + ": " + reason), field_(std::move(field)) {}
  const std::string& field() const { return field_; }

 private:
  std::string field_;
};

/// Throws InvalidInput(field, ...) unless every entry of the matrix/vector is finite.
template <class Derived>
void require_finite(const Eigen::MatrixBase<Derived>& a, const std::string& field) {
  if (!a.allFinite()) throw InvalidInput(field, "has a non-finite entry");
}

/// Throws InvalidInput(field, ...) unless value is finite and > 0.
void require_positive(double value, const std::string& field);

/// Which inertias Inertia::from accepts.
///  - Physical: symmetric positive definite with the triangle inequality (a body's moments).
///  - PositiveDefinite: symmetric positive definite only. The Euler (Lie-Poisson) equations
///    J Omega' = J Omega x Omega and the LGVI are defined for any such J (the discrete Lagrangian
///    tr((I - F) J_d) / h still gives 1/2 Omega^T J Omega, since tr(hat(w) J_d hat(w)^T) = w^T J w
///    for J_d = tr(J)/2 I - J of any sign): the test sets' bodies, e.g. Hairer, Lubich and
///    Wanner's (2, 1, 2/3), which no mass distribution has (J_d indefinite).
enum class InertiaDomain { Physical, PositiveDefinite };

/// A rigid body's inertia J (body frame) with J_d = tr(J)/2 I - J (eq. 7) and J^{-1}.
///
/// Valid inertias are symmetric (to 1e-12 relative), positive definite and, in the Physical
/// domain, satisfy the triangle inequality J_i + J_j >= J_k on the principal moments, which is
/// exactly the condition for J_d to be positive semi-definite (its eigenvalues are
/// (J_i + J_j - J_k)/2). Equality is a flat body (J_d singular); it is allowed since a lamina is
/// physical, and the rotation update stays well posed because it involves J, not J_d^{-1}.
struct Inertia {
  Mat3 J;
  Mat3 Jd;
  Mat3 J_inverse;
  /// The principal moments satisfy the triangle inequality (always so in the Physical domain).
  bool physical = true;

  /// Validates J (see above) and precomputes J_d, J^{-1}. Throws InvalidInput(field, reason).
  static Inertia from(const Mat3& J, const std::string& field = "inertia",
                      InertiaDomain domain = InertiaDomain::Physical);
  /// The domain that accepts this inertia again (Physical when the triangle inequality holds).
  InertiaDomain domain() const { return physical ? InertiaDomain::Physical : InertiaDomain::PositiveDefinite; }
};

}  // namespace lgvi
