// The scene reader as the system bindings see it: typed, validated access to a scene file's
// tables, every failure a SceneError naming the file, the dotted field and the reason on one
// line (scene.hpp). Each binding (experiments/systems/) reads its own [parameters], [initial]
// and [control] with it; scene.cpp reads the rest ([integration], description) and picks the
// binding by the scene's `system`. toml++ stays inside scene.cpp: a table is an opaque handle.
//
// The shared pieces every binding uses the same way (so that a new input form is one change):
// attitude() reads an attitude (a rotation matrix "R", a unit quaternion "quaternion" or Euler
// angles "euler"; identity when absent), body_rate() an angular velocity (body frame "Omega" or
// space frame "omega_space"), sinusoid() and sinusoid2() a control, and attitude_keys() /
// body_rate_keys() / kSinusoidKeys are their keys for check_keys.
#pragma once

#include <array>
#include <cstdint>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <stdexcept>
#include <initializer_list>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "experiments/input/controls.hpp"
#include "lgvi/range.hpp"
#include "lgvi/types.hpp"

namespace lgvi::experiments {

inline constexpr std::size_t kMaxSceneBytes = std::size_t{1} << 20;
inline constexpr int kMaxSceneNesting = 32;
inline constexpr double kMaxSceneMagnitude = kMaxMagnitude;  // lgvi/range.hpp, shared with Python
inline constexpr double kMinSceneMagnitude = kMinMagnitude;

/// Bad scene input. `field` is the dotted TOML path ("parameters.inertia", "integration.h"),
/// with " (--h)" appended when the value came from a command-line override, or a position
/// ("line 3, column 7") for malformed TOML. what() is "file: field: reason".
class SceneError : public std::runtime_error {
 public:
  SceneError(std::string file, std::string field, std::string reason);
  const std::string& file() const { return file_; }
  const std::string& field() const { return field_; }
  const std::string& reason() const { return reason_; }

 private:
  std::string file_;
  std::string field_;
  std::string reason_;
};

/// A table of the scene file with its dotted path ("initial", "control.force").
class SceneTable {
 public:
  const std::string& path() const { return path_; }

 private:
  friend class SceneReader;
  friend struct SceneTableAccess;  // scene.cpp
  SceneTable(const void* table, std::string path) : table_(table), path_(std::move(path)) {}
  const void* table_;  ///< a toml::table (scene.cpp)
  std::string path_;
};

class SceneReader {
 public:
  explicit SceneReader(std::string file) : file_(std::move(file)) {}
  const std::string& file() const { return file_; }
  /// The files read so far besides the scene file (the samples of piecewise-linear controls).
  const std::vector<std::filesystem::path>& inputs() const { return inputs_; }

  [[noreturn]] void fail(const std::string& field, const std::string& reason) const;

  /// Rejects keys of t outside `allowed` (typos must not silently fall back to defaults).
  void check_keys(const SceneTable& t, std::span<const std::string_view> allowed) const;
  void check_keys(const SceneTable& t, std::initializer_list<std::string_view> allowed) const {
    check_keys(t, std::span<const std::string_view>(allowed.begin(), allowed.size()));
  }
  /// The sub-table `key` of t, nullopt when absent and not required.
  std::optional<SceneTable> table(const SceneTable& t, std::string_view key, bool required) const;

  // The required value `key` of t (named "t.key" in messages).
  double number(const SceneTable& t, std::string_view key) const;
  Vec2 vec2(const SceneTable& t, std::string_view key) const;
  Vec3 vec3(const SceneTable& t, std::string_view key) const;
  /// Principal moments [J1, J2, J3] (J = diag) or the full 3x3 matrix (rows).
  Mat3 inertia(const SceneTable& t, std::string_view key) const;

  // Further typed values (the [ocp] table, experiments/scene/ocp_scene.cpp). has() says whether `key`
  // is present; the readers require it.
  bool has(const SceneTable& t, std::string_view key) const;
  std::string string(const SceneTable& t, std::string_view key) const;
  std::int64_t integer(const SceneTable& t, std::string_view key) const;
  bool boolean(const SceneTable& t, std::string_view key) const;
  /// An array of exactly n numbers.
  Eigen::VectorXd vector(const SceneTable& t, std::string_view key, int n) const;
  /// An n x n matrix written as an array of its n rows.
  Eigen::MatrixXd matrix(const SceneTable& t, std::string_view key, int n) const;

  /// The attitude `key` of t (body to inertial; key "R", "R1" or "R2", the digit the body's) from
  /// at most one of: key itself, a 3x3 array of rows (its orthonormality is checked by the flow's
  /// make_state, validate_initial_state); "quaternion<digit>", a unit quaternion [w, x, y, z]
  /// (scalar first; |norm - 1| <= kQuaternionNormTolerance, then normalized); "euler<digit>", a
  /// table {sequence, angles} (euler_rotation). Identity when none is given.
  Mat3 attitude(const SceneTable& t, std::string_view key) const;
  /// The keys attitude(t, key) reads (for check_keys): {"R", "quaternion", "euler"} for "R".
  static std::vector<std::string_view> attitude_keys(std::string_view key);
  static constexpr double kQuaternionNormTolerance = 1e-9;

  /// The body-frame angular velocity `key` of t ("Omega", "Omega1", "Omega2"), required, from
  /// exactly one of: key itself (body frame) or "omega_space<digit>" (space frame w, converted
  /// to Omega = R^T w with the body's attitude R).
  Vec3 body_rate(const SceneTable& t, std::string_view key, const Mat3& R) const;
  /// The keys body_rate(t, key, R) reads: {"Omega", "omega_space"} for "Omega".
  static std::vector<std::string_view> body_rate_keys(std::string_view key);

  /// The open-loop control of table t, by its `type` (default "sinusoid"):
  ///  "sinusoid": amplitude, frequency, (optional) phase; "constant": value; "piecewise-linear":
  ///  file, a CSV of rows t, u1..u3 (path relative to the scene file's directory).
  /// 3-vectors; sinusoid2() reads 2-vectors (the cart's forces), the third component 0.
  TimeControl sinusoid(const SceneTable& t) const;
  TimeControl sinusoid2(const SceneTable& t) const;
  /// The keys of every control type (check_keys); time_control() and feedback() then refuse
  /// the keys of another type.
  static constexpr std::array<std::string_view, 11> kSinusoidKeys = {
      "type", "amplitude", "frequency", "phase", "value", "file", "kp", "kd", "target", "target_quaternion",
      "target_euler"};
  /// t's `type` ("sinusoid" when absent).
  std::string control_type(const SceneTable& t) const;
  /// A [control] of type "pd": kp, kd (numbers >= 0) and the target attitude (target,
  /// target_quaternion or target_euler, as attitude(); identity when absent).
  AttitudeFeedback feedback(const SceneTable& t) const;

  /// Runs a physics constructor or validator f(), re-raising its InvalidInput as a SceneError on
  /// field prefix + its field ("parameters." + "inertia").
  template <class F>
  auto physics(const std::string& prefix, F&& f) const {
    try {
      return f();
    } catch (const InvalidInput& e) {
      fail_invalid(prefix, e);
    }
  }

  /// The initial state as the flow map builds it, lgvi.make_state(args...) (validation of R,
  /// momenta, the cached forces and moments), every entry finite, and `energy` finite. Fails on
  /// "initial.<field>" (make_state's R0 is initial.R) or "initial" with the quantity named.
  template <class Flow, class... Args>
  void validate_initial_state(const Flow& lgvi, double energy, const Args&... args) const {
    const char* part = nullptr;
    try {
      const auto state = lgvi.make_state(args...);
      part = non_finite_part(state);
    } catch (const InvalidInput& e) {
      fail_invalid_initial(e);
    }
    check_initial_finite(part, std::isfinite(energy));
  }

 private:
  [[noreturn]] void fail_invalid(const std::string& prefix, const InvalidInput& e) const;
  [[noreturn]] void fail_invalid_initial(const InvalidInput& e) const;
  void check_initial_finite(const char* non_finite_part, bool energy_finite) const;

  std::string file_;
  mutable std::vector<std::filesystem::path> inputs_;  ///< a record of reading, not of the reader's state
};

/// The rotation (body to inertial) of Euler angles [a1, a2, a3] (radians) about the axes of a
/// 3-letter sequence: upper case is intrinsic (rotations about the body's axes, each after the
/// previous), R = R_s1(a1) R_s2(a2) R_s3(a3); lower case is extrinsic (about the fixed axes, the
/// first applied first), R = R_s3(a3) R_s2(a2) R_s1(a1). The 12 sequences without two equal
/// neighbours of each case: Tait-Bryan XYZ XZY YXZ YZX ZXY ZYX, proper XYX XZX YXY YZY ZXZ ZYZ.
/// "ZYX" is yaw-pitch-roll; intrinsic "ZYX" [a, b, c] equals extrinsic "xyz" [c, b, a].
/// Throws InvalidInput("sequence", ...) for any other sequence.
Mat3 euler_rotation(std::string_view sequence, const Vec3& angles);

/// The keys of several lists, in order: concat_keys({SceneReader::attitude_keys("R"), {"Omega"}}).
inline std::vector<std::string_view> concat_keys(std::initializer_list<std::vector<std::string_view>> lists) {
  std::vector<std::string_view> keys;
  for (const auto& list : lists) keys.insert(keys.end(), list.begin(), list.end());
  return keys;
}

}  // namespace lgvi::experiments
