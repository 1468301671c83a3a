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

/// The LGVI of an attitude system under feedback u = law(t, R, Omega) (control_moment linear in
/// u): the discrete Lagrange-d'Alembert impulses c0 tau(t_k, x_k) + c1 tau(t_{k+1}, x_{k+1}) (symmetric:
/// h/2, h/2; printed: 0, h) with the feedback evaluated at both ends of the step, so the
/// symmetric form stays second order in the control. The end impulse is implicit, but only
/// through Pi_{k+1}: R_{k+1} solves the rotation update with the start impulse alone. So the
/// flow map steps once with u_{k+1} = u_k and then iterates
///     Pi_{k+1} <- Pi_{k+1} + c1 (tau(R_{k+1}, law(t_{k+1}, R_{k+1}, J^{-1} Pi_{k+1})) - tau applied),
/// a fixed point with contraction factor about c1 kd / J_min (kd the rate gain), to rounding
/// (|change| <= 8 eps (|Pi_{k+1}| + c1 |tau|)); after kMaxIterations the step fails (status
/// NotConverged, as a rotation update failure: h is too large for the gain). Its Control is the
/// step's start and end times, as the one-step driver's flows' (experiments/methods/one_step.hpp):
/// the driver and a composition (lgvi/composition.hpp, step_at) sample control(t) = t.
template <class Lgvi, class Law>
class FeedbackLgvi {
 public:
  using State = typename Lgvi::State;
  using Control = double;  ///< the step's start and end times t_k, t_{k+1}
  static constexpr int potential_evaluations_per_step = Lgvi::potential_evaluations_per_step;
  static constexpr int kMaxIterations = 100;

  FeedbackLgvi(const Lgvi& lgvi, Law law) : lgvi_(lgvi), law_(std::move(law)) {}

  /// t_k, t_k1: the step's start and end times, at which the law is evaluated.
  RotationUpdateSummary step(const State& in, double h, const Control& t_k, const Control& t_k1, State& out) const {
    const typename Lgvi::Control u_k = law_(t_k, in.R, lgvi_.omega(in));  // before `out` (may alias `in`) is written
    RotationUpdateSummary summary = lgvi_.step(in, h, u_k, u_k, out);
    if (!summary.converged()) return summary;
    const double c1 = impulse_weights(lgvi_.form(), h).end;
    const auto& system = lgvi_.system();
    Vec3 applied = system.control_moment(out.R, u_k);
    for (int i = 0; i < kMaxIterations; ++i) {
      const Vec3 wanted = system.control_moment(out.R, law_(t_k1, out.R, lgvi_.omega(out)));
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
