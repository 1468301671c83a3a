// The LGVI of an attitude system under a state-feedback control (the scenes' PD attitude
// feedback, experiments/scenes/README.md): the discrete Lagrange-d'Alembert impulses of the
// feedback evaluated at both ends of each step.
#pragma once

#include <cmath>
#include <limits>
#include <utility>

#include "lgvi/flow_map.hpp"
#include "lgvi/lgvi.hpp"

namespace lgvi {

/// The LGVI of an attitude system under state feedback u = law(R, Omega) (control_moment linear
/// in u): the discrete Lagrange-d'Alembert impulses c0 tau(x_k) + c1 tau(x_{k+1}) (symmetric:
/// h/2, h/2; printed: 0, h) with the feedback evaluated at both ends of the step, so the
/// symmetric form stays second order in the control. The end impulse is implicit, but only
/// through Pi_{k+1}: R_{k+1} solves the rotation update with the start impulse alone. So the
/// flow map steps once with u_{k+1} = u_k and then iterates
///     Pi_{k+1} <- Pi_{k+1} + c1 (tau(R_{k+1}, law(R_{k+1}, J^{-1} Pi_{k+1})) - tau applied),
/// a fixed point with contraction factor about c1 kd / J_min (kd the rate gain), to rounding
/// (|change| <= 8 eps (|Pi_{k+1}| + c1 |tau|)); after kMaxIterations the step fails (status
/// NotConverged, as a rotation update failure: h is too large for the gain).
template <class Lgvi, class Law>
class FeedbackLgvi {
 public:
  using State = typename Lgvi::State;
  using Control = typename Lgvi::Control;
  static constexpr int potential_evaluations_per_step = Lgvi::potential_evaluations_per_step;
  static constexpr int kMaxIterations = 100;

  FeedbackLgvi(const Lgvi& lgvi, Law law) : lgvi_(lgvi), law_(std::move(law)) {}

  /// The controls passed are ignored: the feedback law gives them.
  RotationUpdateSummary step(const State& in, double h, const Control& /*u_k*/, const Control& /*u_k1*/,
                             State& out) const {
    const Control u_k = law_(in.R, lgvi_.omega(in));  // before `out`, which may alias `in`, is written
    RotationUpdateSummary summary = lgvi_.step(in, h, u_k, u_k, out);
    if (!summary.converged()) return summary;
    const double c1 = impulse_weights(lgvi_.form(), h).end;
    const auto& system = lgvi_.system();
    Vec3 applied = system.control_moment(out.R, u_k);
    for (int i = 0; i < kMaxIterations; ++i) {
      const Vec3 wanted = system.control_moment(out.R, law_(out.R, lgvi_.omega(out)));
      const Vec3 change = c1 * (wanted - applied);
      out.Pi += change;
      applied = wanted;
      if (change.norm() <= 8.0 * std::numeric_limits<double>::epsilon() * (out.Pi.norm() + std::abs(c1) * wanted.norm())) {
        return summary;
      }
    }
    summary.status = RotationUpdateStatus::NotConverged;
    return summary;
  }

  LgviForm form() const { return lgvi_.form(); }
  const auto& system() const { return lgvi_.system(); }
  Vec3 omega(const State& s) const { return lgvi_.omega(s); }

 private:
  const Lgvi& lgvi_;
  Law law_;
};

}  // namespace lgvi
