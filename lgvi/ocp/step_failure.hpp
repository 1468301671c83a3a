// The message of a sweep that stopped, shared by the indirect (indirect.hpp) and direct
// (direct.hpp, direct_ipopt.hpp) solvers.
#pragma once

#include <cstddef>
#include <cstdio>
#include <string>

#include "lgvi/rotation_update.hpp"

namespace lgvi::ocp {

/// Why a sweep stopped at its step k -> k+1 (t = t_k): the rotation update's failure, or, when the
/// update converged but the state it gave left the range of double (an overflow: momenta of
/// |h p| / J past 1e308, a near-zero principal moment), the part non_finite_part names.
/// "rotation update failed at step k (t = ...): why" or "PART is not finite after step k (t =
/// ...): an overflow, past the range of double" (PART a state's part, the multiplier or the control).
inline std::string step_failure_message(std::size_t step, double t_k, const RotationUpdateSummary& failure,
                                        const char* non_finite, int digits = 17) {
  char t[64];
  std::snprintf(t, sizeof t, "%.*g", digits, t_k);
  if (non_finite != nullptr) {
    return std::string(non_finite) + " is not finite after step " + std::to_string(step) + " (t = " + t +
           "): an overflow, past the range of double";
  }
  return "rotation update failed at step " + std::to_string(step) + " (t = " + t + "): " + failure.brief();
}

}  // namespace lgvi::ocp
