// The scene controls' evaluation (controls.hpp).
#include "experiments/input/controls.hpp"

#include <cmath>

#include "lgvi/so3.hpp"

namespace lgvi::experiments {

Vec3 TimeControl::operator()(double t_now) const {
  const double t = t_now - delay;
  switch (kind) {
    case Kind::Constant: return value;
    case Kind::PiecewiseLinear: return (*samples)(t);
    case Kind::Sinusoid: break;
  }
  const Eigen::Array3d angle = 2.0 * M_PI * t * frequency.array() + phase.array();
  return amplitude.cwiseProduct(angle.sin().matrix());
}

Vec3 AttitudeFeedback::moment(double t, const Mat3& R, const Vec3& Omega) const {
  if (law) return law(t, R, Omega);
  const Mat3 E = target.transpose() * R;
  return -kp * (0.5 * so3::vee(E - E.transpose())) - kd * Omega;
}

}  // namespace lgvi::experiments
