// The stated range of a setting, and its one check. The options structs validate their settings
// with it (lgvi/ocp: ShootingOptions::validate, DirectOptions::validate; the baselines'
// tolerances, baselines/solver.hpp), and the readers of those settings (scene tables, command-line
// options, the Python module) check a value they read against the same Range before storing it,
// so every message about a setting reads the same: "must be an integer in [1, 1000000] (got 0)".
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "lgvi/inertia.hpp"

namespace lgvi {

/// Numbers (or integers) x with lo <= x <= hi (lo < x with lo_open, x < hi with hi_open), finite.
struct Range {
  double lo = 0.0;
  double hi = 0.0;
  bool lo_open = false;
  bool hi_open = false;
  bool integer = false;

  static constexpr Range integers(double lo, double hi) { return {lo, hi, false, false, true}; }
  static constexpr Range numbers(double lo, double hi) { return {lo, hi, false, false, false}; }
  /// (lo, hi]: e.g. a tolerance or a step, (0, 0.1].
  static constexpr Range above(double lo, double hi) { return {lo, hi, true, false, false}; }
  /// (lo, hi): e.g. a fraction, (0, 1).
  static constexpr Range open(double lo, double hi) { return {lo, hi, true, true, false}; }

  bool contains(double x) const {
    if (!std::isfinite(x) || (lo_open ? !(x > lo) : !(x >= lo)) || (hi_open ? !(x < hi) : !(x <= hi))) return false;
    return !integer || x == std::floor(x);
  }

  /// A bound or value as written in messages: integers in full below 1e9 ("1000000"), other
  /// numbers in the shortest form that reads back ("0.1", "1e-14", "1e12", "2147483647").
  static std::string text(double x) {
    char buf[40];
    if (std::isfinite(x) && x == std::floor(x) && std::abs(x) < 1e9) {
      std::snprintf(buf, sizeof buf, "%.0f", x);
      return buf;
    }
    for (int digits = 1; digits <= 17; ++digits) {
      std::snprintf(buf, sizeof buf, "%.*g", digits, x);
      if (std::strtod(buf, nullptr) == x || !std::isfinite(x)) break;
    }
    std::string s = buf;
    // "1e-05" -> "1e-5", "1e+100" -> "1e100".
    const std::size_t e = s.find('e');
    if (e != std::string::npos) {
      std::string exponent = s.substr(e + 1);
      const bool negative = !exponent.empty() && exponent[0] == '-';
      if (!exponent.empty() && (exponent[0] == '-' || exponent[0] == '+')) exponent.erase(0, 1);
      while (exponent.size() > 1 && exponent[0] == '0') exponent.erase(0, 1);
      s = s.substr(0, e + 1) + (negative ? "-" : "") + exponent;
    }
    return s;
  }

  /// "[1, 1000000]", "(0, 0.1]", "(0, 1)".
  std::string text() const {
    return std::string(lo_open ? "(" : "[") + text(lo) + ", " + text(hi) + (hi_open ? ")" : "]");
  }

  /// What is wrong with x: "" when contains(x), else "must be an integer in [1, 1000000] (got 0)".
  std::string problem(double x) const {
    if (contains(x)) return "";
    return std::string("must be ") + (integer ? "an integer" : "a number") + " in " + text() + " (got " + text(x) +
           ")";
  }

  /// Throws InvalidInput(field, problem(x)) unless contains(x).
  void require(double x, const std::string& field) const {
    if (!contains(x)) throw InvalidInput(field, problem(x));
  }
};

/// The most steps of one run, t_final / h: the scene files' horizon (experiments/scene,
/// make_horizon), a fixed-step baseline's grid (baselines::integrate), the Python module's
/// simulate. 10^12 steps of the cheapest method take days; a larger count is a mistyped h.
inline constexpr double kMaxSteps = 1e12;

/// The most steps of a discrete optimal control problem (lgvi/ocp: t_final / h): its solvers keep
/// every step's state and sensitivities (10^7 steps took 3.8 GB, 10^8 ended in
/// std::bad_alloc); the paper's problems take 1000. The [ocp] scenes and the ocp command share it.
inline constexpr double kMaxOcpSteps = 1e6;

/// The magnitudes of admissible input (the scene files' rule, experiments/scene/scene.hpp, and
/// the Python module's numbers and arrays): 0, or |x| in [kMinMagnitude, kMaxMagnitude], so that
/// products and quotients of three such values stay finite and nonzero.
inline constexpr double kMinMagnitude = 1e-100;
inline constexpr double kMaxMagnitude = 1e100;

/// What is wrong with x as admissible input: "" when it is, else "must be finite (got inf)" or
/// "must be 0 or of magnitude between 1e-100 and 1e100 (got 1e300; products of larger values
/// overflow)".
inline std::string magnitude_problem(double x) {
  if (!std::isfinite(x)) return "must be finite (got " + Range::text(x) + ")";
  if (x == 0.0 || (std::abs(x) >= kMinMagnitude && std::abs(x) <= kMaxMagnitude)) return "";
  return "must be 0 or of magnitude between 1e-100 and 1e100 (got " + Range::text(x) +
         "; products of larger values overflow)";
}

/// Throws InvalidInput(field, magnitude_problem(x)) unless x is admissible.
inline void require_admissible(double x, const std::string& field) {
  const std::string problem = magnitude_problem(x);
  if (!problem.empty()) throw InvalidInput(field, problem);
}

}  // namespace lgvi
