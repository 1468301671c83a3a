#include "experiments/systems/exact_reference.hpp"

#include "experiments/systems/systems.hpp"

namespace lgvi::experiments {

template <class ModelVariant>
std::optional<ExactReference> ExactReference::of(const ModelVariant& model, std::string* why_not) {
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

template <class M>
Sample attitude_sample(const baselines::ExactState& x, double t) {
  Sample s = sample_of<M>();
  s.t = t;
  state_of<M>(s) = typename M::State{x.R, x.Omega};
  return s;
}
template Sample attitude_sample<FreeBodyModel>(const baselines::ExactState&, double);
template Sample attitude_sample<PendulumModel>(const baselines::ExactState&, double);

Sample ExactReference::sample(double t) const { return to_sample_(state(t), t); }

baselines::ExactState ExactReference::state(double t) const {
  return std::visit([t](const auto& solution) { return solution.state(t); }, solution_);
}

template <class ModelVariant>
std::optional<baselines::ExactState> exact_state(const ModelVariant& model, double t) {
  const std::optional<ExactReference> exact = ExactReference::of(model);
  if (!exact) return std::nullopt;
  return exact->state(t);
}

// The one instantiation: the list of systems (systems.hpp).
template std::optional<ExactReference> ExactReference::of<Model>(const Model&, std::string*);
template std::optional<baselines::ExactState> exact_state<Model>(const Model&, double);

}  // namespace lgvi::experiments
