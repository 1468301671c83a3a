#include "tests/test_paths.hpp"

namespace lgvi::test {

const char* source_dir() { return LGVI_SOURCE_DIR; }
const char* testbed_exe() { return LGVI_TESTBED_EXE; }

}  // namespace lgvi::test
