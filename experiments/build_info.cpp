#include "experiments/simulate.hpp"

namespace lgvi::experiments {

const char* git_describe() { return LGVI_GIT_DESCRIBE; }

}  // namespace lgvi::experiments
