// Allocation counting for the test programs that check "no heap allocation inside a step"
// (test_lgvi, test_baselines; tests/CMakeLists.txt links allocation_counter.cpp into both):
// allocation_counter.cpp replaces the global allocation functions with ones that count calls.
// It is its own translation unit so that the compiler never inlines the replaced operator delete
// into code whose allocation it sees as the built-in operator new (GCC's -Wmismatched-new-delete).
#pragma once

#include <cstddef>

namespace lgvi::test {

/// Calls of the global operator new (every form: plain, array, nothrow, aligned) since the
/// program started.
std::size_t allocation_count();

}  // namespace lgvi::test
