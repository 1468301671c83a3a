// The check of a parameter that may be zero (gravity, a sphere radius), quoting the value.
#pragma once

#include <cmath>
#include <sstream>
#include <string>

#include "lgvi/inertia.hpp"

namespace lgvi {

/// Throws InvalidInput(field, "must be finite and >= 0 (got VALUE)") unless value is finite and >= 0.
inline void require_nonnegative(double value, const std::string& field) {
  if (!std::isfinite(value) || value < 0.0) {
    std::ostringstream s;
    s << "must be finite and >= 0 (got " << value << ")";
    throw InvalidInput(field, s.str());
  }
}

}  // namespace lgvi
