// Every system binding (one file each in experiments/systems/) and the dispatch on a scene's
// model: visit_binding(model, f) calls f(SystemBinding<M>{}, m) with the model's alternative m.
#pragma once

#include <optional>
#include <string_view>
#include <utility>
#include <variant>

#include "experiments/systems/cart_pendulum.hpp"
#include "experiments/systems/connected_bodies.hpp"
#include "experiments/systems/dumbbell.hpp"
#include "experiments/systems/free_body.hpp"
#include "experiments/systems/pendulum.hpp"

namespace lgvi::experiments {

// Every system of the scene model has its binding.
static_assert([]<std::size_t... I>(std::index_sequence<I...>) {
  return (SystemBindingOf<SystemBinding<std::variant_alternative_t<I, Model>>, std::variant_alternative_t<I, Model>> &&
          ...);
}(std::make_index_sequence<std::variant_size_v<Model>>{}));

template <class F>
decltype(auto) visit_binding(const Model& model, F&& f) {
  return std::visit([&](const auto& m) -> decltype(auto) { return f(SystemBinding<std::decay_t<decltype(m)>>{}, m); },
                    model);
}

/// visit_binding on a model the binding may change (drop_controls).
template <class F>
decltype(auto) visit_binding(Model& model, F&& f) {
  return std::visit([&](auto& m) -> decltype(auto) { return f(SystemBinding<std::decay_t<decltype(m)>>{}, m); },
                    model);
}

/// The figure labels of the system named `system` (a scene's "system"), if it is one.
inline std::optional<SystemLabels> system_labels_of(std::string_view system) {
  std::optional<SystemLabels> labels;
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    ((system == std::variant_alternative_t<I, Model>::name
          ? void(labels = SystemBinding<std::variant_alternative_t<I, Model>>::labels())
          : void()),
     ...);
  }(std::make_index_sequence<std::variant_size_v<Model>>{});
  return labels;
}

}  // namespace lgvi::experiments
