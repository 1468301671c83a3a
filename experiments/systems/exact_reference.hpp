// Exact references for the harness: the closed-form solution of a scene's model, where one exists
// (baselines/exact/): the free rigid body without control, and the 3D pendulum without control
// that is a Lagrange top (J axisymmetric about rho, or no gravity torque). The work-precision
// suite grades against it; the regression gate can ask it for the exact state at any time,
// without switching on systems itself. A system's binding says whether it has one
// (SystemBinding<M>::exact_solution, experiments/systems/).
#pragma once

#include <optional>
#include <string>
#include <variant>

#include "baselines/exact/free_rigid_body_exact.hpp"
#include "baselines/exact/lagrange_top.hpp"

namespace lgvi::experiments {

struct Sample;  // systems.hpp
/// A sample of attitude system M (its State is {R, Omega}) in the exact state x at t; defined in
/// exact_reference.cpp for the systems with a closed form.
template <class M>
Sample attitude_sample(const baselines::ExactState& x, double t);

inline constexpr const char* kFreeBodyExactDescription = "exact (closed form, Celledoni et al. 2008)";
inline constexpr const char* kLagrangeTopExactDescription =
    "exact (Lagrange top: Jacobi sn and elliptic integrals of the third kind)";

class ExactReference {
 public:
  using Solution = std::variant<baselines::FreeRigidBodyExact, baselines::LagrangeTopExact>;

  /// The exact solution of `model` from its initial state, or nullopt when there is none: another
  /// system, a control, a pendulum that is not a Lagrange top, or an initial state the closed
  /// forms reject (on or within 1 - k = 1e-8 of a separatrix). `why_not`, when given, receives
  /// the reason in one line. Asks the model's binding (exact_solution).
  /// (A template on the list of systems' variant, Model: this header sits below the list.)
  template <class ModelVariant>
  static std::optional<ExactReference> of(const ModelVariant& model, std::string* why_not = nullptr);

  /// The solution of an attitude system M (its State is {R, Omega}), named `description`; made by
  /// M's binding.
  template <class M>
  static ExactReference of_attitude(Solution solution, std::string description) {
    return ExactReference(std::move(solution), std::move(description), &attitude_sample<M>);
  }

  /// R(t) (body to inertial) and Omega(t) (body frame) at any finite t; allocation-free.
  baselines::ExactState state(double t) const;
  /// The exact state at t as a sample of the model's system.
  Sample sample(double t) const;
  /// "exact (closed form, Celledoni et al. 2008)" for the free body, "exact (Lagrange top, ...)"
  /// for the pendulum: what CSV metadata and summaries name as the reference.
  const std::string& description() const { return description_; }

 private:
  using ToSample = Sample (*)(const baselines::ExactState&, double);
  ExactReference(Solution solution, std::string description, ToSample to_sample)
      : solution_(std::move(solution)), description_(std::move(description)), to_sample_(to_sample) {}

  Solution solution_;
  std::string description_;
  ToSample to_sample_;
};

/// The exact state of `model` at time t, or nullopt when it has no exact solution
/// (ExactReference::of). Builds the solution each call: for many times, keep an ExactReference.
template <class ModelVariant>
std::optional<baselines::ExactState> exact_state(const ModelVariant& model, double t);

}  // namespace lgvi::experiments
