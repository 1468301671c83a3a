// The list of systems: every system binding (one file each in experiments/systems/: the scene
// model, its state record and what the harness knows of the system), the variant Model of their
// scene models, the recorder's Sample of any of them, and the dispatch on a scene's model:
// visit_binding(model, f) calls f(SystemBinding<M>{}, m) with the model's alternative m.
// A new system: its binding file, its include below and its alternative in Model.
#pragma once

#include <string_view>
#include <utility>
#include <type_traits>
#include <variant>

#include "experiments/systems/cart_pendulum.hpp"
#include "experiments/systems/connected_bodies.hpp"
#include "experiments/systems/dumbbell.hpp"
#include "experiments/systems/free_body.hpp"
#include "experiments/systems/pendulum.hpp"
#include "experiments/systems/potential_body.hpp"
#include "experiments/systems/potential_body_se3.hpp"

namespace lgvi::experiments {

using Model = std::variant<FreeBodyModel, PendulumModel, DumbbellModel, CartPendulumModel,
                           ConnectedBodiesModel, PotentialBodyModel, PotentialBodySE3Model>;

/// "free-body", "pendulum", "dumbbell", "cart-pendulum", "connected-bodies", "potential-body" or
/// "potential-body-se3".
inline const char* system_name(const Model& model) {
  return std::visit([](const auto& m) { return std::decay_t<decltype(m)>::name; }, model);
}

/// The state record of every system of Model, in Model's order: alternative i is
/// std::variant_alternative_t<i, Model>::State (a free body and a pendulum share one type, so
/// alternatives are addressed by index: state_of<M>).
template <class V>
struct StatesOfModels;
template <class... Ms>
struct StatesOfModels<std::variant<Ms...>> {
  using type = std::variant<typename Ms::State...>;
};
using SystemState = StatesOfModels<Model>::type;

/// The index of scene model M in Model.
template <class M, class V = Model>
struct ModelIndex;
template <class M, class... Ms>
struct ModelIndex<M, std::variant<Ms...>> {
  static constexpr std::size_t value = [] {
    constexpr bool same[] = {std::is_same_v<M, Ms>...};
    std::size_t i = 0;
    while (!same[i]) ++i;
    return i;
  }();
};

/// The state at t_k in the paper's variables: the record of the scene's system only (its model's
/// State: R, Omega; the dumbbell's x, v; the cart's q, q_dot; the two bodies' R1, R2, Omega1,
/// Omega2), so a scene records only what it models.
struct Sample {
  double t = 0.0;
  SystemState state;
  int newton_iterations = 0;  ///< of the step that produced this sample (0 at k = 0)
  /// | |q| - 1 | of a quaternion baseline's state (written only by a Recorder made with
  /// quaternion_column; see baselines/coordinates.hpp).
  double quaternion_norm_error = 0.0;
};

/// The state of model M's system in sample s. Precondition: s is a sample of an M scene (made by
/// sample_of(model) or sample_of<M>()); otherwise std::bad_variant_access.
template <class M>
typename M::State& state_of(Sample& s) {
  return std::get<ModelIndex<M>::value>(s.state);
}
template <class M>
const typename M::State& state_of(const Sample& s) {
  return std::get<ModelIndex<M>::value>(s.state);
}
/// A sample of model M's system at t = 0 in the record's default state (identity, zero).
template <class M>
Sample sample_of() {
  Sample s;
  s.state.template emplace<ModelIndex<M>::value>();
  return s;
}
/// A sample of `model`'s system at t = 0 in the model's initial state.
Sample sample_of(const Model& model);

MomentumMap momentum_map(const Model& model);

/// Distance of two samples of `model`'s system over every part of its state: the sum of the
/// attitudes' Frobenius and the vectors' 2-norms (SystemBinding::distance). Precondition: both
/// are samples of that system.
double state_distance(const Model& model, const Sample& a, const Sample& b);

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

/// Calls f(SystemBinding<M>{}) for the system M named `system` (a scene's "system"); false when
/// no system has that name.
template <class F>
bool visit_binding_named(std::string_view system, F&& f) {
  return [&]<std::size_t... I>(std::index_sequence<I...>) {
    return ((system == std::variant_alternative_t<I, Model>::name
                 ? (f(SystemBinding<std::variant_alternative_t<I, Model>>{}), true)
                 : false) ||
            ...);
  }(std::make_index_sequence<std::variant_size_v<Model>>{});
}

/// The figure labels of the system named `system`; for a name no system has (a summary row
/// without a run), the free body's SI labels.
inline SystemLabels system_labels(std::string_view system) {
  SystemLabels labels = SystemBinding<FreeBodyModel>::labels();
  visit_binding_named(system, [&](auto binding) { labels = decltype(binding)::labels(); });
  return labels;
}

/// The units of the CSV columns and diagnostics of the system named `system`, one line: SI for
/// the physical systems, the normalized units of the dumbbell (mass 1, orbit radius 1, mu = 1);
/// for a name no system has, the free body's.
inline std::string system_units(std::string_view system) {
  std::string units = SystemBinding<FreeBodyModel>::units();
  visit_binding_named(system, [&](auto binding) { units = decltype(binding)::units(); });
  return units;
}

}  // namespace lgvi::experiments
