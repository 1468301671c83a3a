// Allocation counting for the test_baselines program: allocation_counter.cpp replaces the global
// allocation functions with ones that count calls. It is its own translation unit so that the
// compiler never inlines the replaced operator delete into code whose allocation it sees as the
// built-in operator new (GCC's -Wmismatched-new-delete).
#pragma once

#include <cstddef>

namespace lgvi::test {

/// Calls of the global operator new (every form) since the program started.
std::size_t allocation_count();

}  // namespace lgvi::test
