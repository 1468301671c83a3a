// Higher order by composition (Hairer, Lubich, Wanner, "Geometric Numerical Integration",
// II.4 and V.3): for a symmetric (self-adjoint) one-step map Phi_h of order 2, the composition
//     Phi_{gamma_s h} o ... o Phi_{gamma_1 h},   sum gamma_i = 1,  gamma_i = gamma_{s+1-i},
// with the coefficients below has order 4 or 6. Every LGVI of the project in its symmetric form
// is such a map (single bodies, cart-pendulum, connected bodies), so one template serves all.
// Composition of symplectic, momentum-preserving maps is symplectic and momentum preserving.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <string>

#include "lgvi/inertia.hpp"
#include "lgvi/lgvi.hpp"
#include "lgvi/rotation_update.hpp"

namespace lgvi {

struct CompositionScheme {
  const char* name;
  int order;
  std::span<const double> gammas;
};

namespace composition_coefficients {
/// Yoshida's triple jump, order 4: gamma_1 = gamma_3 = 1/(2 - 2^(1/3)), gamma_2 = 1 - 2 gamma_1.
inline const std::array<double, 3> yoshida4 = [] {
  const double g = 1.0 / (2.0 - std::cbrt(2.0));
  return std::array<double, 3>{g, 1.0 - 2.0 * g, g};
}();
/// Suzuki's fractal, order 4, 5 stages: p = 1/(4 - 4^(1/3)), (p, p, 1 - 4p, p, p). Smaller
/// error constant than the triple jump at 5/3 the cost.
inline const std::array<double, 5> suzuki4 = [] {
  const double p = 1.0 / (4.0 - std::cbrt(4.0));
  return std::array<double, 5>{p, p, 1.0 - 4.0 * p, p, p};
}();
/// Yoshida's triple jump of the order-4 triple jump, order 6, 9 stages:
/// (g4 g6, (1 - 2 g4) g6, g4 g6, ...) with g6 = 1/(2 - 2^(1/5)) on the outer level.
inline const std::array<double, 9> yoshida6 = [] {
  const double g6 = 1.0 / (2.0 - std::pow(2.0, 0.2));
  const double outer[3] = {g6, 1.0 - 2.0 * g6, g6};
  std::array<double, 9> c{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) c[3 * i + j] = outer[i] * yoshida4[j];
  }
  return c;
}();
/// Kahan and Li's s9odr6a, order 6, 9 stages (HLW, V.3.2, eq. (3.11)).
inline constexpr std::array<double, 9> kahan_li6 = {
    0.39216144400731413928,  0.33259913678935943860, -0.70624617255763935981,
    0.08221359629355080023,  0.79854399093482996340, 0.08221359629355080023,
    -0.70624617255763935981, 0.33259913678935943860, 0.39216144400731413928};
}  // namespace composition_coefficients

/// The schemes by name: "yoshida4", "suzuki4", "yoshida6", "kahan-li6". Throws InvalidInput.
CompositionScheme composition_scheme(const std::string& name);

/// A composed LGVI: `Base` is any flow map with State, Control and
/// step(in, h, u_k, u_k1, out) -> RotationUpdateSummary, in its symmetric form.
/// Controls are sampled at the substep times through step_at (the integrate() driver uses it);
/// `step` with end-point controls interpolates them linearly (second order in the control).
template <FlowMap Base>
class ComposedLgvi {
 public:
  using State = typename Base::State;
  using Control = typename Base::Control;

  /// Throws InvalidInput("form", ...) unless the base flow is symmetric: composing a non-
  /// symmetric map with these coefficients does not raise its order.
  ComposedLgvi(const Base& base, CompositionScheme scheme) : base_(base), scheme_(scheme) {
    if (base.form() != LgviForm::Symmetric) {
      throw InvalidInput("form", "composition needs the symmetric LGVI form");
    }
  }

  int stages() const { return static_cast<int>(scheme_.gammas.size()); }
  /// One potential evaluation per substep.
  int potential_evaluations() const { return stages() * Base::potential_evaluations_per_step; }
  const CompositionScheme& scheme() const { return scheme_; }
  const Base& base() const { return base_; }

  /// One composed step from t to t + h with controls u(tau) at the substep times.
  template <class ControlFn>
  RotationUpdateSummary step_at(const State& in, double t, double h, ControlFn&& u,
                                State& out) const {
    State s = in;
    double tau = t;
    Control u0 = u(tau);
    RotationUpdateSummary total;
    total.status = RotationUpdateStatus::Converged;
    for (const double gamma : scheme_.gammas) {
      const double hi = gamma * h;
      const Control u1 = u(tau + hi);
      const RotationUpdateSummary r = base_.step(s, hi, u0, u1, s);
      total.iterations += r.iterations;
      total.set_residual(std::max(total.residual(), r.residual()));
      total.rhs_norm = std::max(total.rhs_norm, r.rhs_norm);
      total.used_fallback = total.used_fallback || r.used_fallback;
      total.parametrization = r.parametrization;
      if (!r.converged()) {
        total.status = r.status;
        return total;
      }
      tau += hi;
      u0 = u1;
    }
    out = s;
    return total;
  }

  RotationUpdateSummary step(const State& in, double h, const Control& u_k, const Control& u_k1,
                             State& out) const {
    auto linear = [&](double tau) { return Control(u_k + (tau / h) * (u_k1 - u_k)); };
    return step_at(in, 0.0, h, linear, out);
  }

 private:
  const Base& base_;
  CompositionScheme scheme_;
};

}  // namespace lgvi
