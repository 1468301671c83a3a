// The paper's reported numbers, read from validation/paper_values.toml: the one source for
// `validate`, the `ocp` summaries and the figures. The file is embedded into the binary at
// configure time (CMake re-runs when it changes), so an installed or relocated binary carries
// exactly the values of its source tree.
#pragma once

#include <optional>
#include <string>

namespace lgvi::experiments {

/// One optimal control example of the paper (sections 3.1, 3.2, 4.1, 4.2).
struct PaperExample {
  std::string key;      ///< table name in paper_values.toml, e.g. "pendulum_reorientation"
  std::string section;  ///< "3.2"
  std::string system;   ///< the scene system it is an example of, e.g. "pendulum"
  double cost = 0.0;
  double terminal_violation = 0.0;
  std::optional<double> outer_iterations_approx;  ///< read off the paper's convergence plot
  std::optional<double> h;
  std::optional<double> horizon;
};

struct PaperValues {
  PaperExample dumbbell;          ///< section 3.1, indirect
  PaperExample pendulum;          ///< section 3.2, indirect, decomposed
  PaperExample cart_pendulum;     ///< section 4.1, direct
  PaperExample connected_bodies;  ///< section 4.2, direct
  /// Section 3.2: condition numbers of the decomposed shooting's matrix (a range read off the
  /// paper's plot) and of the undecomposed sensitivity.
  double decomposed_condition_min = 0.0;
  double decomposed_condition_max = 0.0;
  double undecomposed_condition = 0.0;

  /// The example whose `system` (paper_values.toml) is the scene system `system` ("pendulum",
  /// "dumbbell", "cart-pendulum", "connected-bodies"). Throws InvalidInput("system", ...) for another.
  const PaperExample& example(const std::string& system) const;
  /// The example whose table in paper_values.toml is `key` ("pendulum_reorientation"), or null.
  const PaperExample* find(const std::string& key) const;
  /// The four tables' names, comma-separated (for messages).
  std::string keys() const;
};

/// The values, parsed once (thread-safe). A malformed embedded file is a build defect: it throws
/// std::logic_error naming the key.
const PaperValues& paper_values();

/// The embedded text of validation/paper_values.toml (generated at configure time).
extern const char* const kPaperValuesToml;

}  // namespace lgvi::experiments
