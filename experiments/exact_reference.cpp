#include "experiments/exact_reference.hpp"

namespace lgvi::experiments {

namespace {

const char* const kFreeBodyDescription = "exact (closed form, Celledoni et al. 2008)";
const char* const kLagrangeTopDescription = "exact (Lagrange top: Jacobi sn and elliptic integrals of the third kind)";

}  // namespace

std::optional<ExactReference> ExactReference::of(const Model& model, std::string* why_not) {
  const auto none = [why_not](std::string reason) -> std::optional<ExactReference> {
    if (why_not != nullptr) *why_not = std::move(reason);
    return std::nullopt;
  };
  try {
    if (const auto* body = std::get_if<FreeBodyModel>(&model)) {
      if (body->control) return none("the free body is controlled");
      return ExactReference(baselines::FreeRigidBodyExact(body->system.inertia.J, body->initial.R, body->initial.Omega),
                            kFreeBodyDescription);
    }
    if (const auto* pendulum = std::get_if<PendulumModel>(&model)) {
      if (pendulum->control) return none("the pendulum is controlled");
      if (!baselines::is_lagrange_top(pendulum->system)) {
        return none("the pendulum is not a Lagrange top (J not axisymmetric about rho)");
      }
      baselines::LagrangeTopExact top(pendulum->system, pendulum->initial.R, pendulum->initial.Omega);
      const char* description = top.is_free_body() ? kFreeBodyDescription : kLagrangeTopDescription;
      return ExactReference(std::move(top), description);
    }
  } catch (const InvalidInput& e) {
    return none(std::string("no closed form for this initial state: ") + e.what());
  }
  return none(std::string("the ") + system_name(model) + " has no closed-form solution here");
}

baselines::ExactState ExactReference::state(double t) const {
  return std::visit([t](const auto& solution) { return solution.state(t); }, solution_);
}

std::optional<baselines::ExactState> exact_state(const Model& model, double t) {
  const std::optional<ExactReference> exact = ExactReference::of(model);
  if (!exact) return std::nullopt;
  return exact->state(t);
}

}  // namespace lgvi::experiments
