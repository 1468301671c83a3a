#include "experiments/methods/simulate.hpp"

namespace lgvi::experiments {

const char* git_describe() { return LGVI_GIT_DESCRIBE; }
const char* version() { return LGVI_VERSION; }

}  // namespace lgvi::experiments
