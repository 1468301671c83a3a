#include "experiments/exact_reference.hpp"

#include "experiments/system_bindings.hpp"

namespace lgvi::experiments {

std::optional<ExactReference> ExactReference::of(const Model& model, std::string* why_not) {
  std::string reason;
  std::optional<ExactReference> exact;
  try {
    exact = visit_binding(model, [&](auto binding, const auto& m) -> std::optional<ExactReference> {
      using B = decltype(binding);
      if constexpr (requires { B::exact_solution(m, reason); }) {
        return B::exact_solution(m, reason);
      } else {
        reason = std::string("the ") + system_name(model) + " has no closed-form solution here";
        return std::nullopt;
      }
    });
  } catch (const InvalidInput& e) {
    reason = std::string("no closed form for this initial state: ") + e.what();
  }
  if (!exact && why_not != nullptr) *why_not = std::move(reason);
  return exact;
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
