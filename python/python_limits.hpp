// What the Python module checks beyond the library's own validation, shared by its two halves
// (lgvi_module.cpp, harness_bindings.cpp): the numbers it is given follow the scene files' rules
// (lgvi/range.hpp: finite, 0 or of magnitude in [1e-100, 1e100]; at most kMaxSteps steps), the
// tolerances the adaptive methods' (baselines/tolerance.hpp), through the same functions; and,
// the module's own limit, the rows a call returns in memory.
#pragma once

#include <cstddef>
#include <string>

#include "lgvi/range.hpp"

namespace lgvi::python {

/// The most rows a call returns (a trajectory or a CSV read back in memory): 10^7 rows of the
/// LGVI's t, R, Omega, energy are 1.1 GB, held twice while they become numpy arrays. The CLI
/// streams its CSV instead and has no such limit; a longer run asks for a coarser output grid
/// (every, output_every, samples).
inline constexpr double kMaxRows = 1e7;

/// Throws InvalidInput(field, ...) naming what to raise unless `rows` <= kMaxRows.
inline void require_rows(double rows, const std::string& field, const std::string& what) {
  if (rows <= kMaxRows) return;
  throw InvalidInput(field, what + " give " + Range::text(rows) + " rows; a call returns at most " +
                                Range::text(kMaxRows) + " (held in memory): raise " + field);
}

}  // namespace lgvi::python
