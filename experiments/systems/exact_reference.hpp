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
/// The attitude state {R, Omega} of a sample of attitude system M.
template <class M>
baselines::ExactState attitude_state(const Sample& s);

inline constexpr const char* kFreeBodyExactDescription = "exact (closed form, Celledoni et al. 2008)";
inline constexpr const char* kLagrangeTopExactDescription =
    "exact (Lagrange top: Jacobi sn and elliptic integrals of the third kind)";

/// The phase (time-shift) error of a computed state x_h at time t against the exact trajectory x:
/// the shift tau whose x(t + tau) lies nearest x_h. A symplectic method's error over a long run
/// is mostly such a shift (its energy error stays bounded, its flips come early or late); what is
/// left after the shift is the error in the orbit's shape.
struct PhaseFit {
  double shift = 0.0;        ///< tau (time unit)
  double shape_error = 0.0;  ///< max(||R_h - R(t+tau)||_F, |Omega_h - Omega(t+tau)| / |Omega(t+tau)|)
  int iterations = 0;
  bool converged = false;
};

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
    return ExactReference(std::move(solution), std::move(description), &attitude_sample<M>, &attitude_state<M>);
  }

  /// R(t) (body to inertial) and Omega(t) (body frame) at any finite t; allocation-free.
  baselines::ExactState state(double t) const;
  /// The exact state at t as a sample of the model's system.
  Sample sample(double t) const;
  /// A state x at t as a sample of the model's system (a stored reference, a computed state).
  Sample sample_of(const baselines::ExactState& x, double t) const;
  /// The local minimizer tau nearest initial_shift of |r(tau)|^2, r = (R_h - R(t+tau), (Omega_h - Omega(t+tau))
  /// / |Omega(t)|) (Frobenius and Euclidean norms; the same scaling as final_state_error), for
  /// the state of `computed` at computed.t: damped Gauss-Newton on tau with the trajectory's
  /// velocity from central differences of the closed form (step 1e-4 / |Omega|: its relative
  /// error (1e-4)^2 / 6 only slows the convergence, the fixed point <r, dx/dtau> = 0 moves by
  /// ~2e-9 |r| / |dx/dtau|), each update capped at 0.1 / |Omega| (a tenth of a radian of rotation),
  /// stopped when it moves the exact state by less than 8 eps (1 + |Omega| t) (a few times the
  /// closed form's own rounding of its phase at t) or after 50 updates
  /// (converged = false). A shift beyond half a period is ambiguous (the nearest minimum is
  /// reported; start from a nearby `initial_shift` to follow a growing shift). At rest
  /// (Omega = 0) the shift is 0.
  PhaseFit phase_fit(const Sample& computed, double initial_shift = 0.0) const;
  /// "exact (closed form, Celledoni et al. 2008)" for the free body, "exact (Lagrange top, ...)"
  /// for the pendulum: what CSV metadata and summaries name as the reference.
  const std::string& description() const { return description_; }

 private:
  using ToSample = Sample (*)(const baselines::ExactState&, double);
  using FromSample = baselines::ExactState (*)(const Sample&);
  ExactReference(Solution solution, std::string description, ToSample to_sample, FromSample from_sample)
      : solution_(std::move(solution)),
        description_(std::move(description)),
        to_sample_(to_sample),
        from_sample_(from_sample) {}

  Solution solution_;
  std::string description_;
  ToSample to_sample_;
  FromSample from_sample_;
};

/// The exact state of `model` at time t, or nullopt when it has no exact solution
/// (ExactReference::of). Builds the solution each call: for many times, keep an ExactReference.
template <class ModelVariant>
std::optional<baselines::ExactState> exact_state(const ModelVariant& model, double t);

}  // namespace lgvi::experiments
