#include "experiments/simulate.hpp"

namespace lgvi::experiments {

const char* git_describe() { return LGVI_GIT_DESCRIBE; }
const char* version() { return LGVI_VERSION; }

std::string units_of(const std::string& system) {
  if (system == "dumbbell") {
    return "normalized: mass 1, reference orbit radius 1, mu = 1 (period 2 pi); t, x, v, Omega, energy, "
           "momentum in these units";
  }
  std::string units = "t [s], R [1], Omega [rad/s], energy [J], momentum [kg m^2/s]";
  if (system == "cart-pendulum") units += ", x y [m], xdot ydot [m/s]";
  return units;
}

}  // namespace lgvi::experiments
