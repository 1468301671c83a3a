// Exact references for the harness: the closed-form solution of a scene's model, where one exists
// (baselines/exact/): the free rigid body without control, and the 3D pendulum without control
// that is a Lagrange top (J axisymmetric about rho, or no gravity torque). The work-precision
// suite grades against it; the regression gate can ask it for the exact state at any time,
// without switching on systems itself.
#pragma once

#include <optional>
#include <string>
#include <variant>

#include "baselines/exact/free_rigid_body_exact.hpp"
#include "baselines/exact/lagrange_top.hpp"
#include "experiments/scene.hpp"

namespace lgvi::experiments {

class ExactReference {
 public:
  /// The exact solution of `model` from its initial state, or nullopt when there is none: another
  /// system, a control, a pendulum that is not a Lagrange top, or an initial state the closed
  /// forms reject (on or within 1 - k = 1e-8 of a separatrix). `why_not`, when given, receives
  /// the reason in one line.
  static std::optional<ExactReference> of(const Model& model, std::string* why_not = nullptr);

  /// R(t) (body to inertial) and Omega(t) (body frame) at any finite t; allocation-free.
  baselines::ExactState state(double t) const;
  /// "exact (closed form, Celledoni et al. 2008)" for the free body, "exact (Lagrange top, ...)"
  /// for the pendulum: what CSV metadata and summaries name as the reference.
  const std::string& description() const { return description_; }

 private:
  using Solution = std::variant<baselines::FreeRigidBodyExact, baselines::LagrangeTopExact>;
  ExactReference(Solution solution, std::string description)
      : solution_(std::move(solution)), description_(std::move(description)) {}

  Solution solution_;
  std::string description_;
};

/// The exact state of `model` at time t, or nullopt when it has no exact solution
/// (ExactReference::of). Builds the solution each call: for many times, keep an ExactReference.
std::optional<baselines::ExactState> exact_state(const Model& model, double t);

}  // namespace lgvi::experiments
