// The FlowMap concept: a one-step method the integrate() driver (lgvi/integrate.hpp) and the
// composition (lgvi/composition.hpp) accept. The LGVIs, the composed LGVIs and any later
// one-step method on a Lie group satisfy it (static_assert beside each).
#pragma once

#include <concepts>

#include "lgvi/rotation_update.hpp"

namespace lgvi {

/// A flow map: types State (the discrete state) and Control, and
///   step(in, h, u_k, u_k1, out) -> RotationUpdateSummary
/// advancing `in` by h with the controls at both ends of the step into `out` (out may alias in),
/// the summary telling whether its implicit solve converged and at what cost; plus the number of
/// potential evaluations a step costs (a constant potential_evaluations_per_step or a member
/// potential_evaluations()).
template <class F>
concept FlowMap = std::copy_constructible<typename F::State> && std::copy_constructible<typename F::Control> &&
                  requires(const F& f, const typename F::State& in, typename F::State& out, double h,
                           const typename F::Control& u) {
                    { f.step(in, h, u, u, out) } -> std::same_as<RotationUpdateSummary>;
                  } &&
                  (requires { { F::potential_evaluations_per_step } -> std::convertible_to<int>; } ||
                   requires(const F& f) { { f.potential_evaluations() } -> std::convertible_to<int>; });

}  // namespace lgvi
