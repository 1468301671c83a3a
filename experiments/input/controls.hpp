// The controls a scene file describes: open-loop controls of time and PD attitude feedback
// ([control] tables, read by SceneReader; scenes/README.md).
#pragma once

#include <functional>
#include <memory>

#include "baselines/control.hpp"
#include "lgvi/types.hpp"

namespace lgvi::experiments {

/// An open-loop control u(t) of a scene's [control] table (`type`):
///  - Sinusoid (default): component-wise u_i(t) = amplitude_i sin(2 pi frequency_i t + phase_i);
///    frequency in cycles per unit time (Hz in SI scenes), phase in radians.
///  - Constant: u(t) = value.
///  - PiecewiseLinear: linear interpolation of samples (t_j, u_j) read from a CSV file, the end
///    values held outside [t_0, t_last] (baselines/control.hpp's SampledControl).
/// Components a system does not use (the cart's third) stay 0.
struct TimeControl {
  enum class Kind { Sinusoid, Constant, PiecewiseLinear };
  Kind kind = Kind::Sinusoid;
  Vec3 amplitude = Vec3::Zero();
  Vec3 frequency = Vec3::Zero();
  Vec3 phase = Vec3::Zero();
  Vec3 value = Vec3::Zero();  ///< Constant
  std::shared_ptr<const baselines::SampledControl<3>> samples;  ///< PiecewiseLinear
  /// The control is late by this much: u(t) is the law's value at t - delay. No scene key sets
  /// it; `validate --degrade control-timing` does, to misplace every impulse by one step.
  double delay = 0.0;

  Vec3 operator()(double t) const;
};

/// PD attitude feedback toward a constant target attitude R_d ([control] type = "pd"): the
/// body-frame moment
///     tau(R, Omega) = -kp e_R - kd Omega,   e_R = 1/2 vee(R_d^T R - R^T R_d),
/// e_R = sin(theta) n for an attitude error R_d^T R = exp(theta hat(n)): the first-order part of
/// log(R_d^T R), smooth on all of SO(3) (no branch at theta = pi). kp in N m (per unit e_R),
/// kd in N m s.
/// A law of the user's in place of the PD one (`law`: Python's potential_scene torque, any t,
/// R, Omega; it must not throw, a failure is a non-finite value).
struct AttitudeFeedback {
  Mat3 target = Mat3::Identity();
  double kp = 0.0;
  double kd = 0.0;
  std::function<Vec3(double, const Mat3&, const Vec3&)> law = {};  ///< set: tau = law(t, R, Omega)

  Vec3 moment(double t, const Mat3& R, const Vec3& Omega) const;
  bool depends_on_time() const { return static_cast<bool>(law); }
};

}  // namespace lgvi::experiments
