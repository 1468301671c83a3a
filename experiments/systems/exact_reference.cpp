#include "experiments/systems/exact_reference.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

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

template <class M>
baselines::ExactState attitude_state(const Sample& s) {
  const auto& x = state_of<M>(s);
  return {x.R, x.Omega};
}
template baselines::ExactState attitude_state<FreeBodyModel>(const Sample&);
template baselines::ExactState attitude_state<PendulumModel>(const Sample&);

PhaseFit ExactReference::phase_fit(const Sample& computed, double initial_shift) const {
  using Vec12 = Eigen::Matrix<double, 12, 1>;
  const baselines::ExactState xh = from_sample_(computed);
  const double t = computed.t;
  const double rate = state(t).Omega.norm();
  PhaseFit fit;
  const auto distance = [&](double tau) {
    const baselines::ExactState x = state(t + tau);
    const double omega = x.Omega.norm();
    const double d_omega = omega > 0.0 ? (xh.Omega - x.Omega).norm() / omega : (xh.Omega - x.Omega).norm();
    return std::max((xh.R - x.R).norm(), d_omega);
  };
  if (!(rate > 0.0) || !xh.R.allFinite() || !xh.Omega.allFinite()) {
    fit.shift = initial_shift;
    fit.shape_error = distance(initial_shift);
    fit.converged = rate == 0.0;
    return fit;
  }
  // The scaled state (R, Omega / |Omega(t)|) as one vector.
  const auto scaled = [rate](const Mat3& R, const Vec3& Omega) {
    Vec12 v;
    v.head<9>() = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(R.data());
    v.tail<3>() = Omega / rate;
    return v;
  };
  const Vec12 target = scaled(xh.R, xh.Omega);
  const double delta = 1e-4 / rate;
  const double max_update = 0.1 / rate;
  // The closed form rounds its phase by ~eps |lambda t| (|lambda| <= |Omega|): an update that
  // moves the state by less than a few times that is noise.
  const double tolerance = 8.0 * std::numeric_limits<double>::epsilon() * (1.0 + rate * std::abs(t));
  double tau = initial_shift;
  for (fit.iterations = 1; fit.iterations <= 50; ++fit.iterations) {
    const baselines::ExactState x = state(t + tau);
    const baselines::ExactState plus = state(t + tau + delta);
    const baselines::ExactState minus = state(t + tau - delta);
    const Vec12 velocity = (scaled(plus.R, plus.Omega) - scaled(minus.R, minus.Omega)) / (2.0 * delta);
    const Vec12 residual = target - scaled(x.R, x.Omega);
    const double speed2 = velocity.squaredNorm();
    if (!(speed2 > 0.0)) break;
    const double update = std::clamp(residual.dot(velocity) / speed2, -max_update, max_update);
    tau += update;
    if (std::abs(update) * std::sqrt(speed2) <= tolerance) {
      fit.converged = true;
      break;
    }
  }
  fit.iterations = std::min(fit.iterations, 50);
  fit.shift = tau;
  fit.shape_error = distance(tau);
  return fit;
}

Sample ExactReference::sample(double t) const { return to_sample_(state(t), t); }
Sample ExactReference::sample_of(const baselines::ExactState& x, double t) const { return to_sample_(x, t); }

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
