// Where the tests find the source tree and the CLI binary (set by tests/CMakeLists.txt for
// test_paths.cpp only).
#pragma once

namespace lgvi::test {

/// The source tree (its scenes, plot scripts, validation data).
const char* source_dir();
/// The lgvi-testbed binary of this build.
const char* testbed_exe();

}  // namespace lgvi::test
