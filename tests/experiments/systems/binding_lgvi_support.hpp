// Runs of a scene model's LGVI as the harness drives it (its binding's run_lgvi), for the tests
// of the attitude extensions (PD feedback, the orbit's gravity gradient).
#pragma once

#include <cmath>
#include <cstddef>
#include <utility>

#include <gtest/gtest.h>

#include "experiments/systems/systems.hpp"
#include "lgvi/integrate.hpp"

namespace lgvi::test {

using experiments::SystemBinding;

/// The state after `steps` steps of h from t = 0; on_step(t, state) sees every step's state
/// (k = 0 included) in the model's variables.
template <class M, class OnStep>
typename M::State run_binding_lgvi(const M& m, LgviForm form, double h, std::size_t steps, OnStep&& on_step) {
  typename M::State last;
  const Stats stats = SystemBinding<M>::run_lgvi(
      m, form, RotationUpdateOptions{}, [&](const auto& lgvi, auto& state, auto&& control, auto&& to_state) {
        const Stats s = integrate(lgvi, state, 0.0, h, steps, control, [&](std::size_t, double t, const auto& x, const auto&) {
          to_state(x, last);
          on_step(t, std::as_const(last));
          return true;
        });
        to_state(state, last);
        return s;
      });
  EXPECT_TRUE(stats.ok()) << stats.brief();
  return last;
}
template <class M>
typename M::State run_binding_lgvi(const M& m, LgviForm form, double h, std::size_t steps) {
  return run_binding_lgvi(m, form, h, steps, [](double, const typename M::State&) {});
}

/// The discretization's order in h over t in [0, 1]: errors at h = 1/50 and 1/100 against 1/1600
/// (the same flow map), observed order log2(e(h) / e(h/2)): symmetric form 2, printed form 1,
/// within +-0.25 (the leading error term dominates at these steps for the tests' models).
template <class M>
void expect_form_orders(const M& m) {
  for (const auto& [form, order] : {std::pair{LgviForm::Symmetric, 2.0}, std::pair{LgviForm::Printed, 1.0}}) {
    const auto ref = run_binding_lgvi(m, form, 1.0 / 1600, 1600);
    const auto a = run_binding_lgvi(m, form, 1.0 / 50, 50);
    const auto b = run_binding_lgvi(m, form, 1.0 / 100, 100);
    const double ea = SystemBinding<M>::distance(a, ref);
    const double eb = SystemBinding<M>::distance(b, ref);
    EXPECT_NEAR(std::log2(ea / eb), order, 0.25) << to_string(form) << ": errors " << ea << ", " << eb;
  }
}

}  // namespace lgvi::test
