#include "experiments/scene.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <span>
#include <sstream>
#include <vector>

#include <toml++/toml.h>

#include "experiments/data_dir.hpp"
#include "experiments/ocp_scene.hpp"
#include "experiments/scene_reader.hpp"
#include "experiments/toml_text.hpp"
#include "experiments/system_bindings.hpp"
#include "lgvi/so3.hpp"

namespace lgvi::experiments {

namespace fs = std::filesystem;

/// SceneTable's handle is a toml::table; only this file sees toml++.
struct SceneTableAccess {
  static SceneTable make(const toml::table& t, std::string path) { return SceneTable(&t, std::move(path)); }
  static const toml::table& get(const SceneTable& t) { return *static_cast<const toml::table*>(t.table_); }
};

namespace {

/// The message on one line: control characters (a parser's excerpt of the input may carry a
/// newline) written as escapes, "\n", "\t", "\r" or "\xHH".
std::string one_line(const std::string& text) {
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

std::string join_message(const std::string& file, const std::string& field, const std::string& reason) {
  std::string s;
  for (const std::string* part : {&file, &field}) {
    if (!part->empty()) s += *part + ": ";
  }
  return one_line(s + reason);
}

std::string format_number(double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.12g", x);
  return buf;
}

std::string join_key(const std::string& prefix, std::string_view key) {
  return prefix.empty() ? std::string(key) : prefix + "." + std::string(key);
}

/// The reason part of an InvalidInput ("field: reason").
std::string reason_of(const InvalidInput& e) {
  const std::string what = e.what();
  const std::string prefix = e.field() + ": ";
  return what.compare(0, prefix.size(), prefix) == 0 ? what.substr(prefix.size()) : what;
}

const char* type_name(const toml::node& n) {
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

std::string describe(const toml::node& n) {
  if (const toml::array* a = n.as_array()) {
    return "an array of " + std::to_string(a->size()) + (a->size() == 1 ? " element" : " elements");
  }
  return type_name(n);
}

/// Typed, validated access to the TOML tree; every failure is a SceneError naming the field.
class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& field, const std::string& reason) const {
    throw SceneError(file_, field, reason);
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

  /// The required `key` of table `t` read by `read` (&Reader::number, &Reader::vec3, ...), named
  /// "prefix.key" in every message.
  template <class T>
  T required(const toml::table& t, std::string_view key, const std::string& prefix,
             T (Reader::*read)(const toml::node&, const std::string&) const) const {
    return (this->*read)(required(t, key, prefix), join_key(prefix, key));
  }

  double number(const toml::node& n, const std::string& field) const {
    double v = 0.0;
    if (const auto* f = n.as_floating_point()) {
      v = f->get();
    } else if (const auto* i = n.as_integer()) {
      v = static_cast<double>(i->get());
    } else {
      fail(field, std::string("must be a number (got ") + describe(n) + ")");
    }
    if (!std::isfinite(v)) fail(field, "must be finite (got " + format_number(v) + ")");
    if (v != 0.0 && !(std::abs(v) >= kMinSceneMagnitude && std::abs(v) <= kMaxSceneMagnitude)) {
      fail(field, "must be 0 or of magnitude between 1e-100 and 1e100 (got " + format_number(v) +
                      "; products of larger values overflow)");
    }
    return v;
  }

  std::int64_t integer(const toml::node& n, const std::string& field) const {
    const auto* i = n.as_integer();
    if (i == nullptr) fail(field, std::string("must be an integer (got ") + describe(n) + ")");
    return i->get();
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

  Sinusoid sinusoid(const toml::table& t, const std::string& prefix) const {
    Sinusoid s;
    s.amplitude = required(t, "amplitude", prefix, &Reader::vec3);
    s.frequency = required(t, "frequency", prefix, &Reader::vec3);
    if (const toml::node* p = t.get("phase")) s.phase = vec3(*p, prefix + ".phase");
    return s;
  }

  /// A sinusoid with 2 components (the cart's forces); the third component stays 0.
  Sinusoid sinusoid2(const toml::table& t, const std::string& prefix) const {
    Sinusoid s;
    s.amplitude.head<2>() = required(t, "amplitude", prefix, &Reader::vec2);
    s.frequency.head<2>() = required(t, "frequency", prefix, &Reader::vec2);
    if (const toml::node* p = t.get("phase")) s.phase.head<2>() = vec2(*p, prefix + ".phase");
    return s;
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
};

/// Rejects text that would drive toml++'s recursive descent too deep, before it parses: the
/// nesting at any point is the number of open '[' / '{' plus the dots of the dotted keys being
/// opened (outside strings and comments), accumulated over the enclosing levels. A float's dot
/// counts too (harmless: one per value). Strings are skipped with TOML's rules (basic with
/// escapes, literal, multi-line with up to two extra closing quotes); an unterminated one ends
/// the scan (toml++ then reports it).
void check_structure(std::string_view text, const Reader& r) {
  int line = 1;
  std::size_t line_start = 0;
  std::vector<int> enclosing;  // per open bracket: the nesting outside it, bracket included
  int base = 0;                // nesting of the enclosing levels
  int dots = 0;                // dots since the last separator at this level
  const auto fail_at = [&](std::size_t i, const std::string& reason) {
    r.fail("line " + std::to_string(line) + ", column " + std::to_string(i - line_start + 1), reason);
  };
  const std::size_t n = text.size();
  for (std::size_t i = 0; i < n; ++i) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
      line_start = i + 1;
      dots = 0;
    } else if (c == '#') {
      while (i + 1 < n && text[i + 1] != '\n') ++i;
    } else if (c == '"' || c == '\'') {
      const bool basic = c == '"';
      const bool multi = i + 2 < n && text[i + 1] == c && text[i + 2] == c;
      std::size_t j = i + (multi ? 3 : 1);
      bool closed = false;
      for (; j < n; ++j) {
        if (basic && text[j] == '\\') {
          ++j;  // the escaped character (a line-ending backslash escapes the newline)
          if (j < n && text[j] == '\n') {
            ++line;
            line_start = j + 1;
          }
        } else if (text[j] == '\n') {
          if (!multi) break;  // unterminated: toml++ reports it
          ++line;
          line_start = j + 1;
        } else if (text[j] == c) {
          if (!multi) {
            closed = true;
            break;
          }
          if (j + 2 < n && text[j + 1] == c && text[j + 2] == c) {
            j += 2;
            // Up to two more quotes belong to the content ("""a""""" is the string a"").
            for (int extra = 0; extra < 2 && j + 1 < n && text[j + 1] == c; ++extra) ++j;
            closed = true;
            break;
          }
        }
      }
      if (!closed) return;
      i = j;
    } else if (c == '[' || c == '{') {
      enclosing.push_back(base);
      base += dots + 1;
      dots = 0;
      if (base > kMaxSceneNesting) {
        fail_at(i, "nested more than " + std::to_string(kMaxSceneNesting) + " levels deep (scene files need 4)");
      }
    } else if (c == ']' || c == '}') {
      if (!enclosing.empty()) {
        base = enclosing.back();
        enclosing.pop_back();
      }
      dots = 0;
    } else if (c == ',') {
      dots = 0;
    } else if (c == '.') {
      if (base + ++dots > kMaxSceneNesting) {
        fail_at(i, "a dotted key nested more than " + std::to_string(kMaxSceneNesting) +
                       " levels deep (scene files need 4)");
      }
    }
  }
}

/// make_state's field names in scene-file terms: "R0" is "initial.R", "R1_0" "initial.R1".
std::string initial_field(const std::string& field) {
  std::string name = field;
  if (name.ends_with("_0")) {
    name.resize(name.size() - 2);
  } else if (name.size() > 1 && name.ends_with("0")) {
    name.pop_back();
  }
  return "initial." + name;
}

constexpr const char* kOverflowHint =
    " is not finite: the parameters and initial values overflow together (scene.hpp: admissible input)";

/// The model of binding B's system from the scene's tables, checking every table's keys before
/// reading any value (a misspelt key is the likeliest cause of a missing one).
template <class B>
Model read_system(const SceneReader& r, const SceneTable& parameters, const SceneTable& initial,
                  const SceneTable& integration, const std::optional<SceneTable>& control) {
  B::check_keys(r, parameters, initial);
  r.check_keys(integration, {"h", "t_final", "form", "output_every"});
  if (control) B::check_control_keys(r, *control);
  return B::read(r, parameters, initial, control);
}

/// The model of the scene's `system` (the name of a Model alternative), read by its binding.
Model read_model(const SceneReader& r, const std::string& system, const SceneTable& parameters,
                 const SceneTable& initial, const SceneTable& integration, const std::optional<SceneTable>& control) {
  std::optional<Model> model;
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    const auto try_one = [&]<class M>(std::type_identity<M>) {
      if (!model && system == M::name) {
        model.emplace(read_system<SystemBinding<M>>(r, parameters, initial, integration, control));
      }
    };
    (try_one(std::type_identity<std::variant_alternative_t<I, Model>>{}), ...);
  }(std::make_index_sequence<std::variant_size_v<Model>>{});
  if (!model) r.fail("system", "unknown system '" + system + "'");  // parse_scene checked the name
  return std::move(*model);
}

}  // namespace

void SceneReader::fail(const std::string& field, const std::string& reason) const {
  throw SceneError(file_, field, reason);
}

void SceneReader::check_keys(const SceneTable& t, std::span<const std::string_view> allowed) const {
  Reader(file_).check_keys(SceneTableAccess::get(t), t.path(), allowed);
}

std::optional<SceneTable> SceneReader::table(const SceneTable& t, std::string_view key, bool required) const {
  const toml::table* sub = Reader(file_).table(SceneTableAccess::get(t), key, t.path(), required);
  if (sub == nullptr) return std::nullopt;
  return SceneTableAccess::make(*sub, join_key(t.path(), key));
}

double SceneReader::number(const SceneTable& t, std::string_view key) const {
  return Reader(file_).required(SceneTableAccess::get(t), key, t.path(), &Reader::number);
}
Vec2 SceneReader::vec2(const SceneTable& t, std::string_view key) const {
  return Reader(file_).required(SceneTableAccess::get(t), key, t.path(), &Reader::vec2);
}
Vec3 SceneReader::vec3(const SceneTable& t, std::string_view key) const {
  return Reader(file_).required(SceneTableAccess::get(t), key, t.path(), &Reader::vec3);
}
Mat3 SceneReader::inertia(const SceneTable& t, std::string_view key) const {
  return Reader(file_).required(SceneTableAccess::get(t), key, t.path(), &Reader::inertia);
}

bool SceneReader::has(const SceneTable& t, std::string_view key) const {
  return SceneTableAccess::get(t).get(key) != nullptr;
}
std::string SceneReader::string(const SceneTable& t, std::string_view key) const {
  return Reader(file_).required(SceneTableAccess::get(t), key, t.path(), &Reader::string);
}
std::int64_t SceneReader::integer(const SceneTable& t, std::string_view key) const {
  return Reader(file_).required(SceneTableAccess::get(t), key, t.path(), &Reader::integer);
}
bool SceneReader::boolean(const SceneTable& t, std::string_view key) const {
  const Reader r(file_);
  const toml::node& n = r.required(SceneTableAccess::get(t), key, t.path());
  const auto* b = n.as_boolean();
  if (b == nullptr) r.fail(join_key(t.path(), key), std::string("must be true or false (got ") + describe(n) + ")");
  return b->get();
}
Eigen::VectorXd SceneReader::vector(const SceneTable& t, std::string_view key, int n) const {
  const Reader r(file_);
  const std::string field = join_key(t.path(), key);
  const toml::node& node = r.required(SceneTableAccess::get(t), key, t.path());
  const toml::array* a = node.as_array();
  if (a == nullptr || a->size() != static_cast<std::size_t>(n)) {
    r.fail(field, "must be an array of " + std::to_string(n) + " numbers (got " + describe(node) + ")");
  }
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) v(i) = r.number(*a->get(i), field + "[" + std::to_string(i) + "]");
  return v;
}
Eigen::MatrixXd SceneReader::matrix(const SceneTable& t, std::string_view key, int n) const {
  const Reader r(file_);
  const std::string field = join_key(t.path(), key);
  const toml::node& node = r.required(SceneTableAccess::get(t), key, t.path());
  const std::string shape = std::to_string(n) + "x" + std::to_string(n);
  const toml::array* a = node.as_array();
  if (a == nullptr || a->size() != static_cast<std::size_t>(n)) {
    r.fail(field, "must be a " + shape + " array of arrays (" + std::to_string(n) + " rows of " + std::to_string(n) +
                      " numbers; got " + describe(node) + ")");
  }
  Eigen::MatrixXd m(n, n);
  for (int i = 0; i < n; ++i) {
    const toml::node& row = *a->get(i);
    const toml::array* ra = row.as_array();
    if (ra == nullptr || ra->size() != static_cast<std::size_t>(n)) {
      r.fail(field, "must be a " + shape + " array of arrays (row " + std::to_string(i) + " is " + describe(row) + ")");
    }
    for (int j = 0; j < n; ++j) {
      m(i, j) = r.number(*ra->get(j), field + "[" + std::to_string(i) + "][" + std::to_string(j) + "]");
    }
  }
  return m;
}

Mat3 SceneReader::attitude(const SceneTable& t, std::string_view key) const {
  const toml::node* n = SceneTableAccess::get(t).get(key);
  return n == nullptr ? Mat3::Identity() : Reader(file_).mat3(*n, join_key(t.path(), key));
}

Sinusoid SceneReader::sinusoid(const SceneTable& t) const { return Reader(file_).sinusoid(SceneTableAccess::get(t), t.path()); }
Sinusoid SceneReader::sinusoid2(const SceneTable& t) const {
  return Reader(file_).sinusoid2(SceneTableAccess::get(t), t.path());
}

void SceneReader::fail_invalid(const std::string& prefix, const InvalidInput& e) const {
  fail(prefix + e.field(), reason_of(e));
}
void SceneReader::fail_invalid_initial(const InvalidInput& e) const { fail(initial_field(e.field()), reason_of(e)); }
void SceneReader::check_initial_finite(const char* non_finite_part, bool energy_finite) const {
  if (non_finite_part != nullptr) fail("initial", std::string("the initial ") + non_finite_part + kOverflowHint);
  if (!energy_finite) fail("initial", std::string("the initial energy") + kOverflowHint);
}

SceneError::SceneError(std::string file, std::string field, std::string reason)
    : std::runtime_error(join_message(file, field, reason)),
      file_(std::move(file)),
      field_(std::move(field)),
      reason_(std::move(reason)) {}

Vec3 Sinusoid::operator()(double t) const {
  const Eigen::Array3d angle = 2.0 * M_PI * t * frequency.array() + phase.array();
  return amplitude.cwiseProduct(angle.sin().matrix());
}

const char* system_name(const Model& model) {
  return std::visit([](const auto& m) { return std::decay_t<decltype(m)>::name; }, model);
}

Horizon make_horizon(double h, double t_final, std::int64_t output_every) {
  require_positive(h, "h");
  require_positive(t_final, "t_final");
  const double n = t_final / h;
  constexpr double kMaxSteps = 1e12;
  if (!(n <= kMaxSteps)) {
    throw InvalidInput("t_final", "needs too many steps (t_final / h = " + format_number(n) +
                                      ", limit " + format_number(kMaxSteps) + ")");
  }
  const double steps = std::round(n);
  if (steps < 1.0) {
    throw InvalidInput("t_final", "is shorter than one step (t_final = " + format_number(t_final) +
                                      ", h = " + format_number(h) + ")");
  }
  if (std::abs(steps * h - t_final) > 1e-9 * t_final) {
    throw InvalidInput("t_final", "is not a whole number of steps of h = " + format_number(h) +
                                      " (t_final / h = " + format_number(n) + ")");
  }
  if (output_every < 1) {
    throw InvalidInput("output_every", "must be an integer >= 1 (got " + std::to_string(output_every) + ")");
  }
  Horizon horizon;
  horizon.h = h;
  horizon.t_final = t_final;
  horizon.steps = static_cast<std::size_t>(steps);
  horizon.output_every = static_cast<std::size_t>(output_every);
  return horizon;
}

void check_toml_text(std::string_view text, const std::string& file, const std::string& kind) {
  const Reader r(file);
  if (text.size() > kMaxSceneBytes) {
    r.fail("", "is larger than 1 MiB (more than " + std::to_string(kMaxSceneBytes) + " bytes); " + kind +
                   " files take a few kB");
  }
  check_structure(text, r);
}

Scene parse_scene(std::string_view toml_text, const fs::path& file, const SceneOverrides& overrides) {
  const std::string file_name = file.string();
  const Reader r(file_name);
  check_toml_text(toml_text, file_name, "scene");
  toml::table doc;
  try {
    doc = toml::parse(toml_text, std::string_view(file_name));
  } catch (const toml::parse_error& e) {
    const auto& begin = e.source().begin;
    r.fail("line " + std::to_string(begin.line) + ", column " + std::to_string(begin.column),
           std::string(e.description()));
  }

  // Unknown keys first, everywhere: a misspelt key is the likeliest cause of a missing one.
  r.check_keys(doc, "", {"system", "description", "parameters", "initial", "integration", "control", "ocp"});
  const std::string system = r.required(doc, "system", "", &Reader::string);
  std::string known;
  bool is_known = false;
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    for (const std::string_view name : {std::string_view(std::variant_alternative_t<I, Model>::name)...}) {
      known += (known.empty() ? "" : ", ") + std::string(name);
      is_known = is_known || system == name;
    }
  }(std::make_index_sequence<std::variant_size_v<Model>>{});
  if (!is_known) r.fail("system", "unknown system '" + system + "' (expected one of: " + known + ")");
  const toml::table* parameters = r.table(doc, "parameters", "", true);
  const toml::table* initial = r.table(doc, "initial", "", true);
  const toml::table* integration = r.table(doc, "integration", "", true);
  const toml::table* control = r.table(doc, "control", "", false);
  const toml::table* ocp = r.table(doc, "ocp", "", false);

  // The system's tables, read by its binding (keys first, everywhere).
  const SceneReader reader(file_name);
  std::optional<SceneTable> control_table;
  if (control != nullptr) control_table = SceneTableAccess::make(*control, "control");
  Scene scene{file.stem().string(), file, "",
              read_model(reader, system, SceneTableAccess::make(*parameters, "parameters"),
                         SceneTableAccess::make(*initial, "initial"), SceneTableAccess::make(*integration, "integration"),
                         control_table),
              Horizon{}, LgviForm::Symmetric, nullptr};
  if (const toml::node* d = doc.get("description")) scene.description = r.string(*d, "description");

  // [integration], with the command-line overrides named in messages.
  double h = r.required(*integration, "h", "integration", &Reader::number);
  double t_final = r.required(*integration, "t_final", "integration", &Reader::number);
  std::int64_t every = 1;
  if (const toml::node* e = integration->get("output_every")) every = r.integer(*e, "integration.output_every");
  if (const toml::node* f = integration->get("form")) {
    const std::string form = r.string(*f, "integration.form");
    scene.form = r.physics("integration.", [&] { return parse_lgvi_form(form); });
  }
  if (overrides.h) h = *overrides.h;
  if (overrides.t_final) t_final = *overrides.t_final;
  if (overrides.output_every) every = *overrides.output_every;
  if (overrides.form) scene.form = *overrides.form;
  try {
    scene.horizon = make_horizon(h, t_final, every);
  } catch (const InvalidInput& e) {
    std::vector<std::string> notes;  // which values came from the command line
    if (e.field() == "h" && overrides.h) notes.push_back("--h");
    if (e.field() == "t_final" && overrides.t_final) notes.push_back("--t-final");
    if (e.field() == "t_final" && overrides.h) notes.push_back("h from --h");
    if (e.field() == "output_every" && overrides.output_every) notes.push_back("--every");
    std::string field = "integration." + e.field();
    for (std::size_t i = 0; i < notes.size(); ++i) field += (i == 0 ? " (" : ", ") + notes[i];
    if (!notes.empty()) field += ")";
    r.fail(field, reason_of(e));
  }
  if (ocp != nullptr) {
    scene.ocp = read_ocp_table(reader, scene.model, SceneTableAccess::make(*parameters, "parameters"),
                               SceneTableAccess::make(*ocp, "ocp"));
  }
  return scene;
}

Scene load_scene(const fs::path& file, const SceneOverrides& overrides) {
  std::ifstream in(file, std::ios::binary);
  std::error_code ec;
  if (!in || fs::is_directory(file, ec)) {
    const int err = errno;
    throw SceneError(file.string(), "", std::string("cannot read the scene file: ") +
                                            (fs::is_directory(file, ec) ? "is a directory" : std::strerror(err)));
  }
  // At most one byte past the limit: /dev/zero or a huge file is refused, not read whole.
  std::string text(kMaxSceneBytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (in.bad()) {
    throw SceneError(file.string(), "", "cannot read the scene file: " + std::string(std::strerror(errno)));
  }
  return parse_scene(text, file, overrides);
}

fs::path default_scenes_dir() { return data_dir("scenes", "experiments/scenes"); }

std::vector<std::string> scene_names(const fs::path& scenes_dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (fs::directory_iterator it(scenes_dir, ec), end; !ec && it != end; it.increment(ec)) {
    if (it->path().extension() == ".toml" && it->is_regular_file(ec)) names.push_back(it->path().stem().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

fs::path resolve_scene(const std::string& name_or_path, const fs::path& scenes_dir) {
  const bool is_path = name_or_path.find('/') != std::string::npos ||
                       (name_or_path.size() > 5 && name_or_path.ends_with(".toml"));
  if (is_path) return name_or_path;
  const fs::path file = scenes_dir / (name_or_path + ".toml");
  std::error_code ec;
  if (!name_or_path.empty() && fs::is_regular_file(file, ec)) return file;
  std::string known;
  for (const std::string& n : scene_names(scenes_dir)) known += (known.empty() ? "" : ", ") + n;
  throw SceneError(name_or_path, "",
                   "unknown scene; known scenes: " + (known.empty() ? std::string("(none)") : known) +
                       " (in " + scenes_dir.string() + "); or give the path of a .toml file");
}

}  // namespace lgvi::experiments
