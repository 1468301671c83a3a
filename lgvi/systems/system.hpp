// The System concept: what every physical system of lgvi/systems/ provides, whatever its
// configuration space (SO(3), SE(3), SO(3) x R^2, SO(3) x SO(3)).
#pragma once

#include <concepts>

namespace lgvi {

/// A physical system: immutable parameters validated at construction (a copyable value), the
/// type of its control (copyable; the LGVIs and baselines sample it from a function of time) and
/// its total energy (one member function `energy`, whose arguments are the system's
/// configuration and velocities: eqs. 12, 28, 37, 46 and the dumbbell's sec. 2.3).
template <class S>
concept System = std::copy_constructible<S> && std::copy_constructible<typename S::Control> && requires {
  &S::energy;
};

}  // namespace lgvi
