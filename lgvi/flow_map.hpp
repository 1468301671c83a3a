// The FlowMap concept: a one-step method the integrate() driver (lgvi/integrate.hpp) and the
// composition (lgvi/composition.hpp) accept. The LGVIs, the composed LGVIs and any other
// one-step method (a Lie group Runge-Kutta method, a splitting) satisfy it (static_assert beside
// each). A step reports a summary: the LGVIs their rotation update's (RotationUpdateSummary),
// other methods a StepSummary, or any type with the same four members.
#pragma once

#include <concepts>

#include "lgvi/rotation_update.hpp"

namespace lgvi {

/// What a step says about itself: whether it succeeded, the iterations of its implicit solve
/// (0 for an explicit step), whether it needed a fallback, and the solve's residual.
template <class S>
concept StepReport = requires(const S& s) {
  { s.converged() } -> std::convertible_to<bool>;
  { s.iterations } -> std::convertible_to<int>;
  { s.used_fallback } -> std::convertible_to<bool>;
  { s.residual() } -> std::convertible_to<double>;
};

/// The step summary of a one-step method that is not an LGVI: an explicit step is converged
/// with no iterations; an implicit one sets its iterations and residual, and on failure
/// converged = false with `failure` naming what failed (a static string: no allocation in a step).
struct StepSummary {
  bool ok = true;
  int iterations = 0;
  bool used_fallback = false;
  double solve_residual = 0.0;  ///< the implicit solve's residual at return
  const char* failure = nullptr;
  double residual() const { return solve_residual; }

  bool converged() const { return ok; }
};
static_assert(StepReport<StepSummary> && StepReport<RotationUpdateSummary>);

/// A flow map: types State (the discrete state) and Control, and
///   step(in, h, u_k, u_k1, out) -> a StepReport (RotationUpdateSummary, StepSummary)
/// advancing `in` by h with the controls at both ends of the step into `out` (out may alias in),
/// the summary telling whether its implicit solve converged and at what cost; plus the number of
/// potential evaluations a step costs (a constant potential_evaluations_per_step or a member
/// potential_evaluations()).
template <class F>
concept FlowMap = std::copy_constructible<typename F::State> && std::copy_constructible<typename F::Control> &&
                  requires(const F& f, const typename F::State& in, typename F::State& out, double h,
                           const typename F::Control& u) {
                    { f.step(in, h, u, u, out) } -> StepReport;
                  } &&
                  (requires { { F::potential_evaluations_per_step } -> std::convertible_to<int>; } ||
                   requires(const F& f) { { f.potential_evaluations() } -> std::convertible_to<int>; });

}  // namespace lgvi
