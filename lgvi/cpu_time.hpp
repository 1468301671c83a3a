// CPU time of the calling thread, the one clock of the solvers' and the suites' cost figures:
// clock_gettime(CLOCK_THREAD_CPUTIME_ID). Not std::clock(), which sums every thread of the
// process (a suite runs cases on two threads at once; IPOPT's MUMPS may start its own).
#pragma once

#include <ctime>
#include <limits>

namespace lgvi {

/// Seconds of CPU time the calling thread has used; NaN if the clock is unavailable.
inline double thread_cpu_seconds() {
  timespec ts{};
  if (::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) != 0) return std::numeric_limits<double>::quiet_NaN();
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace lgvi
