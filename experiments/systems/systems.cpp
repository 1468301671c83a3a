// The list of systems' dispatching functions (systems.hpp).
#include "experiments/systems/systems.hpp"

namespace lgvi::experiments {

MomentumMap momentum_map(const Model& model) {
  return visit_binding(model, [](auto binding, const auto&) { return decltype(binding)::momentum_map(); });
}

Sample sample_of(const Model& model) {
  return visit_binding(model, [](auto, const auto& m) {
    Sample s = sample_of<std::decay_t<decltype(m)>>();
    state_of<std::decay_t<decltype(m)>>(s) = m.initial;
    return s;
  });
}

double state_distance(const Model& model, const Sample& a, const Sample& b) {
  return visit_binding(model, [&](auto binding, const auto& m) {
    using M = std::decay_t<decltype(m)>;
    return decltype(binding)::distance(state_of<M>(a), state_of<M>(b));
  });
}

}  // namespace lgvi::experiments
