// The interface between a continuous-time model and the solver adapters: a first-order ODE
// y' = f(t, y) of run-time dimension, its Jacobian, and the two things a rigid-body model adds
// to a plain ODE: a singular set (Euler angles at gimbal lock) and an optional renormalization
// (unit quaternions). The solver is chosen at run time, so this is the one virtual boundary;
// models are templates behind it (baselines/model.hpp).
#pragma once

#include <array>
#include <string>

namespace lgvi::baselines {

/// Most constraints a model's manifold projection imposes (baselines/projection.hpp): the chart's
/// (6 per matrix body, 1 per quaternion) and the mechanics' invariants (at most 2), for at most
/// two bodies.
inline constexpr int kMaxProjectionConstraints = 16;

/// The values the projection keeps: one per constraint, in the model's order (the chart's
/// constraints of each body, then the invariants). Filled by Ode::projection_target from the
/// initial state.
struct ProjectionTarget {
  std::array<double, kMaxProjectionConstraints> value{};
  int count = 0;
};

/// Result of evaluating a model's right-hand side or Jacobian.
enum class RhsStatus {
  Ok,
  Singular,  ///< y lies in the model's singular set (gimbal lock): nothing was evaluated
};

class Ode {
 public:
  virtual ~Ode() = default;

  virtual int dimension() const = 0;
  /// The coordinate model's name: "quaternion", "quaternion-renormalized", "euler", "matrix".
  virtual std::string model_name() const = 0;

  /// ydot = f(t, y). Returns Singular (ydot untouched) on the singular set. Allocates nothing.
  virtual RhsStatus rhs(double t, const double* y, double* ydot) const = 0;
  /// df/dy at (t, y), row-major dimension() x dimension(). See the model for which parts are
  /// analytic.
  virtual RhsStatus jacobian(double t, const double* y, double* dfdy_row_major) const = 0;
  /// True when f depends on t (controls); false for autonomous models.
  virtual bool time_dependent() const = 0;

  /// True when the model has a singular set the solvers must watch (Euler angles).
  virtual bool has_singular_set() const { return false; }
  /// Continuous event function: > 0 away from the singular set, <= 0 on it or beyond; the
  /// solvers stop at its first zero (decreasing).
  virtual double singularity_function(const double* /*y*/) const { return 1.0; }
  /// One line naming the singularity at y, e.g. "gimbal lock: pitch theta = 89.9999991 deg
  /// (|cos theta| = 1.5e-08, threshold sqrt(eps) = 1.5e-08)".
  virtual std::string describe_singularity(const double* /*y*/) const { return {}; }

  /// True for models that are renormalized after every step (quaternion-renormalized).
  virtual bool renormalizes() const { return false; }
  /// Projects y onto the constraint set (each quaternion divided by its norm).
  virtual void renormalize(double* /*y*/) const {}
  /// Projects an error-estimate vector onto the tangent space of the constraint set at y (unit
  /// quaternions: err_q - q (q . err_q)); CVODE's projection interface uses it.
  virtual void project_error(const double* /*y*/, double* /*err*/) const {}

  /// Manifold projection (cvode-bdf-projected; baselines/projection.hpp): empty when the model
  /// offers it, else why not (one line, the method's InvalidInput).
  virtual std::string projection_refusal() const {
    return "the " + model_name() + " model offers no manifold projection (the coordinate models of "
           "baselines/model.hpp do)";
  }
  /// What the projection keeps, one line, e.g. "|q| = 1, E = E_0, |Pi| = |Pi_0|".
  virtual std::string projection_constraints() const { return {}; }
  /// The constraints' values to keep: the chart's exact ones (|q|^2 = 1, R^T R = I) and the
  /// invariants at the initial state y0. count 0: nothing to project.
  virtual ProjectionTarget projection_target(const double* /*y0*/) const { return {}; }
  /// Projects y onto {g(y) = target} (orthogonal in the model's state, simplified Newton) and,
  /// unless err is null, the error estimate err onto the tangent space there. Returns the
  /// Newton iterations (>= 0), or -1 when they did not converge (y is then the last iterate).
  /// Allocates nothing.
  virtual int project(const ProjectionTarget& /*target*/, double* /*y*/, double* /*err*/) const { return -1; }
};

}  // namespace lgvi::baselines
