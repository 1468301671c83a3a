// The System concept: what every physical system of lgvi/systems/ provides, whatever its
// configuration space (SO(3), SE(3), SO(3) x R^2, SO(3) x SO(3)).
#pragma once

#include <concepts>

#include "lgvi/types.hpp"

namespace lgvi {

/// A physical system: immutable parameters validated at construction (a copyable value), the
/// type of its control (copyable; the LGVIs and baselines sample it from a function of time) and
/// its total energy (one member function `energy`, whose arguments are the system's
/// configuration and velocities: eqs. 12, 28, 37, 46 and the dumbbell's sec. 2.3).
template <class S>
concept System = std::copy_constructible<S> && std::copy_constructible<typename S::Control> && requires {
  &S::energy;
};

/// A force and a moment on a body moving in SE(3): the force on the mass centre in the inertial
/// frame, the moment in the body frame (the frames of eqs. 13 and 21-23). The potential's
/// derivatives (f = -dU/dx, M of eq. 13) and the controls (u^f, u^m) of the SE(3) systems.
struct Wrench {
  Vec3 force = Vec3::Zero();   ///< inertial frame
  Vec3 moment = Vec3::Zero();  ///< body frame
};

}  // namespace lgvi
