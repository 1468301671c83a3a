// The process's resident memory, read from /proc/self/status (Linux): what the soak suite
// reports beside a long run's conservation errors (experiments/suites/soak.cpp).
#pragma once

#include <optional>

namespace lgvi::experiments {

/// Resident set size now (VmRSS), in bytes; nullopt where /proc/self/status has no such line.
std::optional<double> resident_bytes();
/// The largest resident set size since the process started or since the last successful
/// reset_peak_resident() (VmHWM), in bytes; nullopt where unavailable.
std::optional<double> peak_resident_bytes();
/// Resets the peak (VmHWM) to the current resident size by writing "5" to /proc/self/clear_refs
/// (Linux >= 4.0). Returns false when the kernel refuses it: the peak then still covers the
/// process's whole life.
bool reset_peak_resident();

}  // namespace lgvi::experiments
