// The interface between a continuous-time model and the solver adapters: a first-order ODE
// y' = f(t, y) of run-time dimension, its Jacobian, and the two things a rigid-body model adds
// to a plain ODE: a singular set (Euler angles at gimbal lock) and an optional renormalization
// (unit quaternions). The solver is chosen at run time, so this is the one virtual boundary;
// models are templates behind it (baselines/model.hpp).
#pragma once

#include <string>

namespace lgvi::baselines {

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
};

}  // namespace lgvi::baselines
