#include "experiments/suites/process_memory.hpp"

#include <fstream>
#include <sstream>
#include <string>

namespace lgvi::experiments {

namespace {

/// The value of a "Key:   N kB" line of /proc/self/status, in bytes.
std::optional<double> status_kilobytes(const std::string& key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (!line.starts_with(key + ":")) continue;
    std::istringstream fields(line.substr(key.size() + 1));
    double kilobytes = 0.0;
    std::string unit;
    if (fields >> kilobytes >> unit && unit == "kB") return kilobytes * 1024.0;
    return std::nullopt;
  }
  return std::nullopt;
}

}  // namespace

std::optional<double> resident_bytes() { return status_kilobytes("VmRSS"); }

std::optional<double> peak_resident_bytes() { return status_kilobytes("VmHWM"); }

bool reset_peak_resident() {
  std::ofstream out("/proc/self/clear_refs");
  out << "5";
  out.flush();
  return static_cast<bool>(out);
}

}  // namespace lgvi::experiments
