// The Newton iterations of the shooting methods, compiled once per multiplier size
// (newton_armijo.hpp).
#include "lgvi/ocp/newton_armijo.hpp"

namespace lgvi::ocp {

LGVI_NEWTON_ITERATIONS(, 6)
LGVI_NEWTON_ITERATIONS(, 12)

}  // namespace lgvi::ocp
