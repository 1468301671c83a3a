// The one TOML reader of the harness's input files (scenes, [ocp] tables, studies, the paper's
// values): typed, validated access to a toml++ tree, every failure a SceneError naming the file,
// the dotted field and the reason on one line (scene_reader.hpp). The input room's own sources,
// the scene loader (scene/scene.cpp) and the study reader (suites/study.cpp) include it;
// everything else reads through SceneReader, whose tables are opaque handles.
#pragma once

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <memory>
#include <optional>
#include <span>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include "experiments/input/read_file.hpp"
#include "experiments/input/scene_reader.hpp"
#include "experiments/input/toml_text.hpp"
#include "experiments/output/csv_writer.hpp"
#include "lgvi/so3.hpp"

namespace lgvi::experiments {

namespace fs = std::filesystem;

/// SceneTable's handle is a toml::table; only the input room and the scene loader see toml++.
struct SceneTableAccess {
  static SceneTable make(const toml::table& t, std::string path) { return SceneTable(&t, std::move(path)); }
  static const toml::table& get(const SceneTable& t) { return *static_cast<const toml::table*>(t.table_); }
};


/// The message on one line: control characters (a parser's excerpt of the input may carry a
/// newline) written as escapes, "\n", "\t", "\r" or "\xHH".
inline std::string one_line(const std::string& text) {
  std::string s;
  s.reserve(text.size());
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '\n') {
      s += "\\n";
    } else if (c == '\t') {
      s += "\\t";
    } else if (c == '\r') {
      s += "\\r";
    } else if (u < 0x20 || u == 0x7f) {
      static constexpr char kHex[] = "0123456789abcdef";
      s += "\\x";
      s += kHex[u >> 4];
      s += kHex[u & 0xf];
    } else {
      s += c;
    }
  }
  return s;
}

inline std::string join_message(const std::string& file, const std::string& field, const std::string& reason) {
  std::string s;
  for (const std::string* part : {&file, &field}) {
    if (!part->empty()) s += *part + ": ";
  }
  return one_line(s + reason);
}

inline std::string format_number(double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.12g", x);
  return buf;
}

inline std::string join_key(const std::string& prefix, std::string_view key) {
  return prefix.empty() ? std::string(key) : prefix + "." + std::string(key);
}

/// The reason part of an InvalidInput ("field: reason").
inline std::string reason_of(const InvalidInput& e) {
  const std::string what = e.what();
  const std::string prefix = e.field() + ": ";
  return what.compare(0, prefix.size(), prefix) == 0 ? what.substr(prefix.size()) : what;
}

static_assert(kMaxTomlFileBytes == kMaxSceneBytes, "one limit on TOML input files");

/// The text of a TOML input file: a regular file of at most 1 MiB (read_regular_file, which says
/// why this limit). `what` names it: "the scene file". Throws SceneError(file, "", "cannot read
/// WHAT: is a FIFO, not a regular file") and the like.
inline std::string read_toml_file(const fs::path& file, std::string_view what) {
  try {
    return read_regular_file(file, kMaxTomlFileBytes, what);
  } catch (const UnreadableFile& e) {
    throw SceneError(file.string(), "", reason_of(e));
  }
}

inline const char* type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::table: return "a table";
    case toml::node_type::array: return "an array";
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a float";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::date:
    case toml::node_type::time:
    case toml::node_type::date_time: return "a date/time";
    case toml::node_type::none: break;
  }
  return "nothing";
}

inline std::string describe(const toml::node& n) {
  if (const toml::array* a = n.as_array()) {
    return "an array of " + std::to_string(a->size()) + (a->size() == 1 ? " element" : " elements");
  }
  return type_name(n);
}

/// How a value of the wrong type is named in messages: with an array's size ("an array of 2
/// elements": scenes) or by its kind only ("an array": studies).
enum class TypeDescription { KindAndSize, Kind };

/// Typed, validated access to the TOML tree; every failure is a SceneError naming the field.
class TomlReader {
 public:
  explicit TomlReader(std::string file, TypeDescription types = TypeDescription::KindAndSize)
      : file_(std::move(file)), types_(types) {}

  [[noreturn]] void fail(const std::string& field, const std::string& reason) const {
    throw SceneError(file_, field, reason);
  }

  /// The document of `text`, checked first (check_toml_text; `kind` names the file in its
  /// messages: "scene", "study"); a syntax error names "line L, column C".
  toml::table parse(std::string_view text, const std::string& kind) const {
    check_toml_text(text, file_, kind);
    try {
      return toml::parse(text, std::string_view(file_));
    } catch (const toml::parse_error& e) {
      const auto& begin = e.source().begin;
      fail("line " + std::to_string(begin.line) + ", column " + std::to_string(begin.column),
           std::string(e.description()));
    }
  }

  /// The type of n as this reader's messages name it (TypeDescription).
  std::string describe(const toml::node& n) const {
    return types_ == TypeDescription::KindAndSize ? experiments::describe(n) : type_name(n);
  }

  /// Rejects keys outside `allowed`: typos must not silently fall back to defaults.
  void check_keys(const toml::table& t, const std::string& prefix,
                  std::initializer_list<std::string_view> allowed) const {
    check_keys(t, prefix, std::span<const std::string_view>(allowed.begin(), allowed.size()));
  }
  void check_keys(const toml::table& t, const std::string& prefix, std::span<const std::string_view> allowed) const {
    for (auto&& entry : t) {
      const auto& key = entry.first;
      if (std::find(allowed.begin(), allowed.end(), key.str()) != allowed.end()) continue;
      std::string expected;
      for (std::string_view a : allowed) expected += (expected.empty() ? "" : ", ") + std::string(a);
      fail(join_key(prefix, key.str()), "unknown key (expected one of: " + expected + ")");
    }
  }

  const toml::table* table(const toml::table& parent, std::string_view key, const std::string& prefix,
                           bool required) const {
    const std::string field = join_key(prefix, key);
    const toml::node* n = parent.get(key);
    if (n == nullptr) {
      if (required) fail(field, "is required (a [" + field + "] table)");
      return nullptr;
    }
    if (!n->is_table()) fail(field, std::string("must be a table (got ") + describe(*n) + ")");
    return n->as_table();
  }

  const toml::node& required(const toml::table& t, std::string_view key, const std::string& prefix) const {
    const toml::node* n = t.get(key);
    if (n == nullptr) fail(join_key(prefix, key), "is required");
    return *n;
  }

  /// The required `key` of table `t` read by `read` (&TomlReader::number, &TomlReader::vec3, ...), named
  /// "prefix.key" in every message.
  template <class T>
  T required(const toml::table& t, std::string_view key, const std::string& prefix,
             T (TomlReader::*read)(const toml::node&, const std::string&) const) const {
    return (this->*read)(required(t, key, prefix), join_key(prefix, key));
  }

  /// A finite float or integer.
  double finite_number(const toml::node& n, const std::string& field) const {
    double v = 0.0;
    if (const auto* f = n.as_floating_point()) {
      v = f->get();
    } else if (const auto* i = n.as_integer()) {
      v = static_cast<double>(i->get());
    } else {
      fail(field, std::string("must be a number (got ") + describe(n) + ")");
    }
    if (!std::isfinite(v)) fail(field, "must be finite (got " + format_number(v) + ")");
    return v;
  }

  /// A finite number, 0 or of magnitude in [kMinSceneMagnitude, kMaxSceneMagnitude].
  double number(const toml::node& n, const std::string& field) const {
    const double v = finite_number(n, field);
    const std::string problem = magnitude_problem(v);  // lgvi/range.hpp: the Python module's rule too
    if (!problem.empty()) fail(field, problem);
    return v;
  }

  /// A finite number > 0 in [kMinSceneMagnitude, kMaxSceneMagnitude].
  double positive(const toml::node& n, const std::string& field) const {
    const double v = finite_number(n, field);
    if (!(v > 0.0)) fail(field, "must be > 0 (got " + format_number(v) + ")");
    if (v < kMinSceneMagnitude || v > kMaxSceneMagnitude) {
      fail(field, "must be between 1e-100 and 1e100 (got " + format_number(v) + ")");
    }
    return v;
  }

  std::int64_t integer(const toml::node& n, const std::string& field) const {
    const auto* i = n.as_integer();
    if (i == nullptr) fail(field, std::string("must be an integer (got ") + describe(n) + ")");
    return i->get();
  }

  std::int64_t integer_at_least(const toml::node& n, const std::string& field, std::int64_t min) const {
    const std::int64_t i = integer(n, field);
    if (i < min) fail(field, "must be an integer >= " + std::to_string(min) + " (got " + std::to_string(i) + ")");
    return i;
  }

  /// A sweep: a non-empty array.
  const toml::array& sweep(const toml::node& n, const std::string& field) const {
    const toml::array* a = n.as_array();
    if (a == nullptr) fail(field, std::string("must be an array (got ") + describe(n) + ")");
    if (a->empty()) fail(field, "is an empty sweep (give at least one value)");
    return *a;
  }

  /// A sweep of numbers > 0 (positive; at most `max` when given), without repeats.
  std::vector<double> positive_sweep(const toml::node& n, const std::string& field,
                                     std::optional<double> max = std::nullopt) const {
    std::vector<double> v;
    const toml::array& a = sweep(n, field);
    for (std::size_t i = 0; i < a.size(); ++i) {
      const std::string f = field + "[" + std::to_string(i) + "]";
      const double x = positive(*a.get(i), f);
      if (max && x > *max) fail(f, "must be at most " + format_number(*max) + " (got " + format_number(x) + ")");
      if (std::find(v.begin(), v.end(), x) != v.end()) fail(f, "repeats " + format_number(x));
      v.push_back(x);
    }
    return v;
  }

  /// A sweep of integers >= 1, without repeats.
  std::vector<std::int64_t> count_sweep(const toml::node& n, const std::string& field) const {
    std::vector<std::int64_t> v;
    const toml::array& a = sweep(n, field);
    for (std::size_t i = 0; i < a.size(); ++i) {
      const std::string f = field + "[" + std::to_string(i) + "]";
      const std::int64_t x = integer_at_least(*a.get(i), f, 1);
      if (std::find(v.begin(), v.end(), x) != v.end()) fail(f, "repeats " + std::to_string(x));
      v.push_back(x);
    }
    return v;
  }

  std::string string(const toml::node& n, const std::string& field) const {
    const auto* s = n.as_string();
    if (s == nullptr) fail(field, std::string("must be a string (got ") + describe(n) + ")");
    return s->get();
  }

  Vec3 vec3(const toml::node& n, const std::string& field) const {
    const toml::array* a = n.as_array();
    if (a == nullptr || a->size() != 3) fail(field, "must be an array of 3 numbers (got " + describe(n) + ")");
    Vec3 v;
    for (int i = 0; i < 3; ++i) v(i) = number(*a->get(i), field + "[" + std::to_string(i) + "]");
    return v;
  }

  Vec2 vec2(const toml::node& n, const std::string& field) const {
    const toml::array* a = n.as_array();
    if (a == nullptr || a->size() != 2) fail(field, "must be an array of 2 numbers (got " + describe(n) + ")");
    return Vec2(number(*a->get(0), field + "[0]"), number(*a->get(1), field + "[1]"));
  }

  /// A 3x3 matrix written as an array of its 3 rows.
  Mat3 mat3(const toml::node& n, const std::string& field) const {
    const toml::array* a = n.as_array();
    const auto shape_error = [&](const toml::node& got) {
      fail(field, "must be a 3x3 array of arrays (3 rows of 3 numbers; got " + describe(got) + ")");
    };
    if (a == nullptr || a->size() != 3) shape_error(n);
    Mat3 m;
    for (int r = 0; r < 3; ++r) {
      const toml::node& row = *a->get(r);
      const toml::array* ra = row.as_array();
      if (ra == nullptr || ra->size() != 3) {
        fail(field, "must be a 3x3 array of arrays (row " + std::to_string(r) + " is " + describe(row) + ")");
      }
      for (int c = 0; c < 3; ++c) {
        m(r, c) = number(*ra->get(c), field + "[" + std::to_string(r) + "][" + std::to_string(c) + "]");
      }
    }
    return m;
  }

  /// Inertia: principal moments [J1, J2, J3] (J = diag) or the full 3x3 matrix.
  Mat3 inertia(const toml::node& n, const std::string& field) const {
    const toml::array* a = n.as_array();
    if (a != nullptr && a->size() == 3 && !a->get(0)->is_array()) return vec3(n, field).asDiagonal();
    if (a != nullptr && a->size() == 3) return mat3(n, field);
    fail(field, "must be the principal moments [J1, J2, J3] or a 3x3 array of arrays (got " + describe(n) + ")");
  }

  /// The control of table t (TimeControl) with `dim` components (3, or 2 for the cart's forces);
  /// `scene_dir` resolves a piecewise-linear control's file, which is appended to `read_files`.
  TimeControl time_control(const toml::table& t, const std::string& prefix, int dim, const fs::path& scene_dir,
                           std::vector<fs::path>& read_files) const {
    TimeControl c;
    std::string type = "sinusoid";
    if (const toml::node* n = t.get("type")) type = string(*n, prefix + ".type");
    std::vector<std::string_view> keys;
    if (type == "sinusoid") {
      keys = {"type", "amplitude", "frequency", "phase"};
    } else if (type == "constant") {
      keys = {"type", "value"};
      c.kind = TimeControl::Kind::Constant;
    } else if (type == "piecewise-linear") {
      keys = {"type", "file"};
      c.kind = TimeControl::Kind::PiecewiseLinear;
    } else if (type == "pd") {
      fail(prefix + ".type", "type \"pd\" (attitude feedback) is available for the free-body, pendulum and potential-body systems only");
    } else {
      fail(prefix + ".type", "unknown control type '" + type +
                                 "' (expected one of: sinusoid, constant, piecewise-linear; pd for free-body, pendulum and potential-body)");
    }
    for (auto&& entry : t) {
      const std::string_view key = entry.first.str();
      if (std::find(keys.begin(), keys.end(), key) != keys.end()) continue;
      std::string expected;
      for (std::string_view k : keys) expected += (expected.empty() ? "" : ", ") + std::string(k);
      fail(join_key(prefix, key), "is not a key of a " + type + " control (type = \"" + type + "\" takes: " + expected + ")");
    }
    const auto vec = [&](std::string_view key, bool is_required) -> Vec3 {
      const toml::node* n = t.get(key);
      if (n == nullptr) {
        if (is_required) required(t, key, prefix);
        return Vec3::Zero();
      }
      Vec3 v = Vec3::Zero();
      if (dim == 2) {
        v.head<2>() = vec2(*n, join_key(prefix, key));
      } else {
        v = vec3(*n, join_key(prefix, key));
      }
      return v;
    };
    switch (c.kind) {
      case TimeControl::Kind::Sinusoid:
        c.amplitude = vec("amplitude", true);
        c.frequency = vec("frequency", true);
        c.phase = vec("phase", false);
        break;
      case TimeControl::Kind::Constant: c.value = vec("value", true); break;
      case TimeControl::Kind::PiecewiseLinear: {
        const std::string file = required(t, "file", prefix, &TomlReader::string);
        const fs::path path = scene_dir / file;
        c.samples = read_samples(path, prefix + ".file", dim);
        read_files.push_back(path);
        break;
      }
    }
    return c;
  }

  /// Samples t, u_1..u_dim from a CSV file: '#' comments and blank lines skipped, an optional
  /// header row (a first row whose first cell is not a number), then rows of dim + 1 finite
  /// numbers with t strictly increasing, at least 2 rows. Errors name field and "FILE:LINE".
  std::shared_ptr<const baselines::SampledControl<3>> read_samples(const fs::path& path, const std::string& field,
                                                                   int dim) const {
    std::string text;
    try {
      text = read_regular_file(path, kMaxDataFileBytes, "the control samples");
    } catch (const UnreadableFile& e) {
      fail(field, "cannot read the control samples '" + path.string() + "': " + e.reason());
    }
    return parse_samples(text, path.string(), field, dim);
  }

  /// Same from the CSV's text in memory; `where` names it in messages ("WHERE:LINE").
  std::shared_ptr<const baselines::SampledControl<3>> parse_samples(std::string_view text, const std::string& where,
                                                                    const std::string& field, int dim) const {
    std::istringstream in{std::string(text)};
    return parse_samples(in, where, field, dim);
  }

  /// Same from a stream.
  std::shared_ptr<const baselines::SampledControl<3>> parse_samples(std::istream& in, const std::string& where,
                                                                    const std::string& field, int dim) const {
    std::vector<double> times;
    std::vector<Vec3> values;
    std::string line;
    const auto at = [&](std::size_t n) { return where + ":" + std::to_string(n) + ": "; };
    const auto parse = [](const std::string& cell, double& x) {
      const char* begin = cell.c_str();
      while (*begin == ' ' || *begin == '\t') ++begin;
      char* end = nullptr;
      x = std::strtod(begin, &end);
      if (end == begin) return false;
      while (*end == ' ' || *end == '\t' || *end == '\r') ++end;
      return *end == '\0';
    };
    constexpr std::size_t kMaxSamples = 10'000'000;
    bool first_row = true;
    for (std::size_t n = 1; std::getline(in, line); ++n) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (line.find_first_not_of(" \t") == std::string::npos || line[line.find_first_not_of(" \t")] == '#') continue;
      const std::vector<std::string> cells = split_csv_row(line);
      double x = 0.0;
      if (first_row && !cells.empty() && !parse(cells[0], x)) {
        first_row = false;  // a header
        continue;
      }
      first_row = false;
      if (cells.size() != static_cast<std::size_t>(dim) + 1) {
        fail(field, at(n) + "has " + std::to_string(cells.size()) + " columns (expected " + std::to_string(dim + 1) +
                        ": t, u1.." + "u" + std::to_string(dim) + ")");
      }
      Vec3 u = Vec3::Zero();
      double t_row = 0.0;
      for (std::size_t i = 0; i < cells.size(); ++i) {
        double v = 0.0;
        if (!parse(cells[i], v) || !std::isfinite(v)) {
          fail(field, at(n) + "column " + std::to_string(i + 1) + " ('" + cells[i] + "') is not a finite number");
        }
        if (v != 0.0 && !(std::abs(v) >= kMinSceneMagnitude && std::abs(v) <= kMaxSceneMagnitude)) {
          fail(field, at(n) + "column " + std::to_string(i + 1) + " (" + format_number(v) +
                          ") must be 0 or of magnitude between 1e-100 and 1e100");
        }
        if (i == 0) {
          t_row = v;
        } else {
          u(static_cast<int>(i) - 1) = v;
        }
      }
      if (!times.empty() && !(t_row > times.back())) {
        fail(field, at(n) + "t = " + format_number(t_row) + " is not greater than the previous t = " +
                        format_number(times.back()) + " (times must be strictly increasing)");
      }
      if (times.size() >= kMaxSamples) fail(field, at(n) + "more than " + std::to_string(kMaxSamples) + " samples");
      times.push_back(t_row);
      values.push_back(u);
    }
    if (in.bad()) fail(field, "cannot read the control samples '" + where + "': " + std::strerror(errno));
    if (times.size() < 2) {
      fail(field, where + ": has " + std::to_string(times.size()) + " sample rows (at least 2 needed)");
    }
    return std::make_shared<const baselines::SampledControl<3>>(std::move(times), std::move(values),
                                                               baselines::Interpolation::PiecewiseLinear);
  }

  /// Runs a physics constructor/validator, re-raising its InvalidInput with `prefix` + field.
  template <class F>
  auto physics(const std::string& prefix, F&& f) const {
    try {
      return f();
    } catch (const InvalidInput& e) {
      fail(prefix + e.field(), reason_of(e));
    }
  }

 private:
  std::string file_;
  TypeDescription types_;
};

}  // namespace lgvi::experiments
