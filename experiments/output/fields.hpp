// Ordered key-value records describing a run. The same record is written as `# key: value`
// CSV metadata and as a JSON object, so the two never disagree.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace lgvi::experiments {

using FieldValue = std::variant<std::string, double, std::int64_t, bool>;

struct Field {
  std::string key;
  FieldValue value;
};

using Fields = std::vector<Field>;

/// Doubles with %.17g (round-trips), integers in decimal, booleans as true/false.
std::string to_text(const FieldValue& value);

/// One-line JSON object {"key": value, ...}; non-finite doubles become null (JSON has no NaN).
std::string to_json(const Fields& fields);

/// Shortest decimal text that reads back as the same double (std::to_chars).
std::string shortest(double x);

}  // namespace lgvi::experiments
