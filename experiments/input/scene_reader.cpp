// The scene reader (scene_reader.hpp) and the checks of TOML text before toml++ parses it
// (toml_text.hpp): the input room's half of the scene files. The scene loader (scene/scene.cpp)
// picks the system's binding and reads [integration].
#include "experiments/input/scene_reader.hpp"

#include <algorithm>
#include <cstdio>
#include <mutex>
#include <set>

#include "experiments/input/toml_reader.hpp"
#include "experiments/input/toml_text.hpp"

namespace lgvi::experiments {

namespace {

/// Rejects text that would drive toml++'s recursive descent too deep, before it parses: the
/// nesting at any point is the number of open '[' / '{' plus the dots of the dotted keys being
/// opened (outside strings and comments), accumulated over the enclosing levels. A float's dot
/// counts too (harmless: one per value). Strings are skipped with TOML's rules (basic with
/// escapes, literal, multi-line with up to two extra closing quotes); an unterminated one ends
/// the scan (toml++ then reports it). A quote opens a string only where toml++ begins one: at
/// the start of a value (after the '=' that ends a key, '[' of an array, ',' or a line break in
/// an array) or of a key part (at a line's start, after '[' of a header, '{', ',' in an inline
/// table, or '.' in a key). Anywhere else, inside a bare value such as `1'x`, toml++ reads the quote as one more
/// character of the value and asks of each following one whether it is whitespace, so the scan
/// reads on there as outside strings (found by the [ocp] fuzzer).
/// It also refuses the non-ASCII characters toml++ 3.3 would ask "is this Unicode whitespace?"
/// of: its table for that (is_non_ascii_horizontal_whitespace) reaches __builtin_unreachable,
/// undefined behaviour, for U+00A1-U+0499 and two other ranges (found by the scene fuzzer). It
/// asks at every character outside strings and comments, where TOML allows no non-ASCII
/// character anyway, and in multi-line basic strings after a backslash: the escaped character
/// (no escape is non-ASCII) and the first one after a line-ending backslash's whitespace.
void check_structure(std::string_view text, const TomlReader& r) {
  int line = 1;
  std::size_t line_start = 0;
  std::vector<int> enclosing;  // per open bracket: the nesting outside it, bracket included
  std::vector<char> kinds;     // per open bracket: 'a' array, 'h' table header, 't' inline table
  int base = 0;                // nesting of the enclosing levels
  int dots = 0;                // dots since the last separator at this level
  bool in_key = true;          // reading a key (else a value)
  bool token_start = true;     // the next character other than a space or tab begins a key part or value
  const auto fail_at = [&](std::size_t i, const std::string& reason) {
    r.fail("line " + std::to_string(line) + ", column " + std::to_string(i - line_start + 1), reason);
  };
  // The position of byte k, counted afresh (the loop's line count lags inside strings).
  const auto fail_at_byte = [&](std::size_t k, const std::string& reason) {
    const std::size_t start = text.rfind('\n', k == 0 ? 0 : k - 1);
    const std::size_t begin = start == std::string_view::npos || k == 0 ? 0 : start + 1;
    const auto lines = std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(begin), '\n');
    r.fail("line " + std::to_string(lines + 1) + ", column " + std::to_string(k - begin + 1), reason);
  };
  const auto non_ascii = [&](std::size_t k) { return k < text.size() && static_cast<unsigned char>(text[k]) >= 0x80; };
  const std::size_t n = text.size();
  // A UTF-8 byte order mark, which toml++ skips.
  const std::size_t first = text.starts_with("\xEF\xBB\xBF") ? 3 : 0;
  for (std::size_t i = first; i < n; ++i) {
    const char c = text[i];
    if (non_ascii(i)) {
      fail_at_byte(i, "a non-ASCII character outside a string or comment (TOML allows them in strings, quoted keys "
                      "and comments only)");
    }
    const bool string_may_start = token_start;
    if (c != ' ' && c != '\t') {
      // A key part or value begins after a line break, '[' or '{'; after the '=' that ends a key
      // (a second '=' is inside the value); after '.' in a key; after ',' in an array or inline table.
      token_start = c == '\n' || c == '[' || c == '{' || ((c == '=' || c == '.') && in_key) ||
                    (c == ',' && !kinds.empty());
    }
    if (c == '\n') {
      ++line;
      line_start = i + 1;
      dots = 0;
      if (enclosing.empty()) in_key = true;
    } else if (c == '#') {
      while (i + 1 < n && text[i + 1] != '\n') ++i;
    } else if ((c == '"' || c == '\'') && string_may_start) {
      const bool basic = c == '"';
      const bool multi = i + 2 < n && text[i + 1] == c && text[i + 2] == c;
      std::size_t j = i + (multi ? 3 : 1);
      bool closed = false;
      for (; j < n; ++j) {
        if (basic && text[j] == '\\') {
          ++j;  // the escaped character (a line-ending backslash escapes the newline)
          if (multi) {
            std::size_t k = j;
            while (k < n && (text[k] == ' ' || text[k] == '\t' || text[k] == '\r' || text[k] == '\n')) ++k;
            if (non_ascii(j)) fail_at_byte(j, "a backslash before a non-ASCII character (not an escape)");
            if (k > j && non_ascii(k)) {
              fail_at_byte(k, "a non-ASCII character first after a line-ending backslash (toml++ misreads it: escape "
                              "it as \\uXXXX or begin with an ASCII character)");
            }
          }
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
      const char kind = c == '{' ? 't' : (in_key ? 'h' : 'a');
      kinds.push_back(kind);
      in_key = kind != 'a';
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
        kinds.pop_back();
      }
      dots = 0;
      in_key = !kinds.empty() && kinds.back() == 'h';
    } else if (c == ',') {
      dots = 0;
      in_key = !kinds.empty() && kinds.back() == 't';
    } else if (c == '=') {
      in_key = false;
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

}  // namespace

void check_toml_text(std::string_view text, const std::string& file, const std::string& kind) {
  const TomlReader r(file);
  if (text.size() > kMaxSceneBytes) {
    r.fail("", "is larger than 1 MiB (more than " + std::to_string(kMaxSceneBytes) + " bytes); " + kind +
                   " files take a few kB");
  }
  check_structure(text, r);
}

std::optional<std::string> truncation_warning(std::string_view text, const std::string& file) {
  if (text.empty() || text.back() == '\n') return std::nullopt;
  return join_message(file, "", "does not end with a newline: the file may be truncated");
}

void warn_once(const fs::path& file, const std::vector<std::string>& warnings) {
  if (warnings.empty()) return;
  static std::mutex warned_mutex;
  static std::set<std::string> warned;
  std::error_code ec;
  const std::lock_guard lock(warned_mutex);
  if (!warned.insert(fs::absolute(file, ec).lexically_normal().string()).second) return;
  std::string lines;
  for (const std::string& w : warnings) lines += "warning: " + w + "\n";
  std::fputs(lines.c_str(), stderr);
  std::fflush(stderr);
}

void SceneReader::fail(const std::string& field, const std::string& reason) const {
  throw SceneError(file_, field, reason);
}

void SceneReader::check_keys(const SceneTable& t, std::span<const std::string_view> allowed) const {
  TomlReader(file_).check_keys(SceneTableAccess::get(t), t.path(), allowed);
}

std::optional<SceneTable> SceneReader::table(const SceneTable& t, std::string_view key, bool required) const {
  const toml::table* sub = TomlReader(file_).table(SceneTableAccess::get(t), key, t.path(), required);
  if (sub == nullptr) return std::nullopt;
  return SceneTableAccess::make(*sub, join_key(t.path(), key));
}

double SceneReader::number(const SceneTable& t, std::string_view key) const {
  return TomlReader(file_).required(SceneTableAccess::get(t), key, t.path(), &TomlReader::number);
}
Vec2 SceneReader::vec2(const SceneTable& t, std::string_view key) const {
  return TomlReader(file_).required(SceneTableAccess::get(t), key, t.path(), &TomlReader::vec2);
}
Vec3 SceneReader::vec3(const SceneTable& t, std::string_view key) const {
  return TomlReader(file_).required(SceneTableAccess::get(t), key, t.path(), &TomlReader::vec3);
}
Mat3 SceneReader::inertia(const SceneTable& t, std::string_view key) const {
  return TomlReader(file_).required(SceneTableAccess::get(t), key, t.path(), &TomlReader::inertia);
}

bool SceneReader::has(const SceneTable& t, std::string_view key) const {
  return SceneTableAccess::get(t).get(key) != nullptr;
}
std::string SceneReader::string(const SceneTable& t, std::string_view key) const {
  return TomlReader(file_).required(SceneTableAccess::get(t), key, t.path(), &TomlReader::string);
}
std::int64_t SceneReader::integer(const SceneTable& t, std::string_view key) const {
  return TomlReader(file_).required(SceneTableAccess::get(t), key, t.path(), &TomlReader::integer);
}
bool SceneReader::boolean(const SceneTable& t, std::string_view key) const {
  const TomlReader r(file_);
  const toml::node& n = r.required(SceneTableAccess::get(t), key, t.path());
  const auto* b = n.as_boolean();
  if (b == nullptr) r.fail(join_key(t.path(), key), std::string("must be true or false (got ") + describe(n) + ")");
  return b->get();
}
Eigen::VectorXd SceneReader::vector(const SceneTable& t, std::string_view key, int n) const {
  const TomlReader r(file_);
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
  const TomlReader r(file_);
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

namespace {

/// Stable storage for the keys of attitude_keys / body_rate_keys (string_views point into it).
std::span<const std::string_view> keys_of(std::string_view key) {
  static constexpr std::array<std::array<std::string_view, 3>, 7> kKeys = {{
      {"R", "quaternion", "euler"},
      {"R1", "quaternion1", "euler1"},
      {"R2", "quaternion2", "euler2"},
      {"target", "target_quaternion", "target_euler"},
      {"Omega", "omega_space", ""},
      {"Omega1", "omega_space1", ""},
      {"Omega2", "omega_space2", ""},
  }};
  for (const auto& keys : kKeys) {
    if (keys[0] == key) return {keys.data(), keys[2].empty() ? 2u : 3u};
  }
  throw std::logic_error("no attitude or body rate keys for '" + std::string(key) + "'");
}

/// The first of `keys` present in t, failing when a second one is present too.
const toml::node* exactly_one(const TomlReader& r, const toml::table& t, const std::string& prefix,
                              std::span<const std::string_view> keys, std::string_view* found) {
  const toml::node* node = nullptr;
  for (const std::string_view key : keys) {
    const toml::node* n = t.get(key);
    if (n == nullptr) continue;
    if (node != nullptr) {
      std::string names;
      for (const std::string_view k : keys) names += (names.empty() ? "" : ", ") + join_key(prefix, k);
      r.fail(join_key(prefix, key), "conflicts with " + join_key(prefix, *found) + " (give at most one of " + names + ")");
    }
    node = n;
    *found = key;
  }
  return node;
}

}  // namespace

Mat3 euler_rotation(std::string_view sequence, const Vec3& angles) {
  const auto refuse = [&] {
    throw InvalidInput("sequence", "'" + std::string(sequence) +
                                       "' is not an Euler sequence (3 axes from XYZ, no two equal neighbours: "
                                       "Tait-Bryan XYZ XZY YXZ YZX ZXY ZYX or proper XYX XZX YXY YZY ZXZ ZYZ; upper "
                                       "case intrinsic, lower case extrinsic)");
  };
  if (sequence.size() != 3) refuse();
  const bool intrinsic = sequence[0] >= 'X' && sequence[0] <= 'Z';
  const char first = intrinsic ? 'X' : 'x';
  std::array<int, 3> axis{};
  for (int i = 0; i < 3; ++i) {
    axis[i] = sequence[i] - first;
    if (axis[i] < 0 || axis[i] > 2 || (i > 0 && axis[i] == axis[i - 1])) refuse();
  }
  Mat3 R = Mat3::Identity();
  for (int i = 0; i < 3; ++i) {
    const Mat3 Ri = so3::exp(angles(i) * Vec3::Unit(axis[i]));
    R = intrinsic ? Mat3(R * Ri) : Mat3(Ri * R);
  }
  return R;
}

std::vector<std::string_view> SceneReader::attitude_keys(std::string_view key) {
  const auto keys = keys_of(key);
  return {keys.begin(), keys.end()};
}
std::vector<std::string_view> SceneReader::body_rate_keys(std::string_view key) {
  const auto keys = keys_of(key);
  return {keys.begin(), keys.end()};
}

Mat3 SceneReader::attitude(const SceneTable& t, std::string_view key) const {
  const TomlReader r(file_);
  const toml::table& table = SceneTableAccess::get(t);
  std::string_view found;
  const toml::node* n = exactly_one(r, table, t.path(), keys_of(key), &found);
  if (n == nullptr) return Mat3::Identity();
  const std::string field = join_key(t.path(), found);
  const auto keys = keys_of(key);
  if (found == keys[0]) return r.mat3(*n, field);
  if (found == keys[1]) {
    const toml::array* a = n->as_array();
    if (a == nullptr || a->size() != 4) {
      r.fail(field, "must be a unit quaternion [w, x, y, z], scalar first (an array of 4 numbers; got " +
                        describe(*n) + ")");
    }
    Eigen::Vector4d q;
    for (int i = 0; i < 4; ++i) q(i) = r.number(*a->get(static_cast<std::size_t>(i)), field + "[" + std::to_string(i) + "]");
    const double norm = q.norm();
    if (!(std::abs(norm - 1.0) <= kQuaternionNormTolerance)) {
      r.fail(field, "is not a unit quaternion (|q| = " + format_number(norm) + "; |q| - 1 must be within " +
                        format_number(kQuaternionNormTolerance) + ")");
    }
    q /= norm;
    return Eigen::Quaterniond(q(0), q(1), q(2), q(3)).toRotationMatrix();
  }
  // Euler angles: a table {sequence, angles}.
  if (!n->is_table()) {
    r.fail(field, std::string("must be a table { sequence = \"ZYX\", angles = [a1, a2, a3] } (got ") + describe(*n) + ")");
  }
  const toml::table& euler = *n->as_table();
  r.check_keys(euler, field, {"sequence", "angles"});
  const std::string sequence = r.required(euler, "sequence", field, &TomlReader::string);
  const Vec3 angles = r.required(euler, "angles", field, &TomlReader::vec3);
  return r.physics(field + ".", [&] { return euler_rotation(sequence, angles); });
}

Vec3 SceneReader::body_rate(const SceneTable& t, std::string_view key, const Mat3& R) const {
  const TomlReader r(file_);
  std::string_view found;
  const toml::node* n = exactly_one(r, SceneTableAccess::get(t), t.path(), keys_of(key), &found);
  if (n == nullptr) {
    r.fail(join_key(t.path(), key), "is required (or " + join_key(t.path(), keys_of(key)[1]) + ", the space frame)");
  }
  const Vec3 w = r.vec3(*n, join_key(t.path(), found));
  return found == key ? w : Vec3(R.transpose() * w);
}

std::string SceneReader::control_type(const SceneTable& t) const {
  const toml::node* n = SceneTableAccess::get(t).get("type");
  return n == nullptr ? std::string("sinusoid") : TomlReader(file_).string(*n, join_key(t.path(), "type"));
}

AttitudeFeedback SceneReader::feedback(const SceneTable& t) const {
  const TomlReader r(file_);
  const toml::table& table = SceneTableAccess::get(t);
  static constexpr std::array<std::string_view, 6> kKeys = {"type", "kp", "kd", "target", "target_quaternion",
                                                            "target_euler"};
  for (auto&& entry : table) {
    const std::string_view key = entry.first.str();
    if (std::find(kKeys.begin(), kKeys.end(), key) != kKeys.end()) continue;
    r.fail(join_key(t.path(), key),
           "is not a key of a pd control (type = \"pd\" takes: type, kp, kd, target, target_quaternion, target_euler)");
  }
  AttitudeFeedback f;
  f.kp = number(t, "kp");
  f.kd = number(t, "kd");
  for (const auto& [gain, name] : {std::pair{f.kp, "kp"}, std::pair{f.kd, "kd"}}) {
    if (gain < 0.0) r.fail(join_key(t.path(), name), "must be >= 0 (got " + format_number(gain) + ")");
  }
  f.target = attitude(t, "target");
  if (!so3::is_rotation(f.target, 1e-10)) {
    r.fail(join_key(t.path(), "target"), "is not a rotation matrix (R^T R != I or det R != 1, to 1e-10)");
  }
  return f;
}

TimeControl SceneReader::sinusoid(const SceneTable& t) const {
  return TomlReader(file_).time_control(SceneTableAccess::get(t), t.path(), 3, fs::path(file_).parent_path(), inputs_);
}
TimeControl SceneReader::sinusoid2(const SceneTable& t) const {
  return TomlReader(file_).time_control(SceneTableAccess::get(t), t.path(), 2, fs::path(file_).parent_path(), inputs_);
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

}  // namespace lgvi::experiments
