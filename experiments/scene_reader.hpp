// The scene reader as the system bindings see it: typed, validated access to a scene file's
// tables, every failure a SceneError naming the file, the dotted field and the reason on one
// line (scene.hpp). Each binding (experiments/systems/) reads its own [parameters], [initial]
// and [control] with it; scene.cpp reads the rest ([integration], description) and picks the
// binding by the scene's `system`. toml++ stays inside scene.cpp: a table is an opaque handle.
//
// The shared pieces every binding uses the same way (so that a new input form is one change):
// attitude() reads an attitude ("R", a rotation matrix, identity when absent), sinusoid() and
// sinusoid2() a control, and attitude_keys() / kSinusoidKeys are their keys for check_keys.
#pragma once

#include <array>
#include <cstdint>
#include <cmath>
#include <initializer_list>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "experiments/scene.hpp"
#include "lgvi/types.hpp"

namespace lgvi::experiments {

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

  // Further typed values (the [ocp] table, experiments/ocp_scene.cpp). has() says whether `key`
  // is present; the readers require it.
  bool has(const SceneTable& t, std::string_view key) const;
  std::string string(const SceneTable& t, std::string_view key) const;
  std::int64_t integer(const SceneTable& t, std::string_view key) const;
  bool boolean(const SceneTable& t, std::string_view key) const;
  /// An array of exactly n numbers.
  Eigen::VectorXd vector(const SceneTable& t, std::string_view key, int n) const;
  /// An n x n matrix written as an array of its n rows.
  Eigen::MatrixXd matrix(const SceneTable& t, std::string_view key, int n) const;

  /// The attitude `key` of t (body to inertial): a 3x3 array of rows, identity when absent; its
  /// orthonormality is checked by the flow's make_state (validate_initial_state).
  Mat3 attitude(const SceneTable& t, std::string_view key) const;
  /// The keys attitude(t, key) reads (for check_keys).
  static std::vector<std::string_view> attitude_keys(std::string_view key) { return {key}; }

  /// u_i(t) = amplitude_i sin(2 pi frequency_i t + phase_i) from t's amplitude, frequency and
  /// (optional) phase, 3-vectors.
  Sinusoid sinusoid(const SceneTable& t) const;
  /// The same with 2-vectors (the cart's forces); the third component stays 0.
  Sinusoid sinusoid2(const SceneTable& t) const;
  static constexpr std::array<std::string_view, 3> kSinusoidKeys = {"amplitude", "frequency", "phase"};

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
};

/// The keys of several lists, in order: concat_keys({SceneReader::attitude_keys("R"), {"Omega"}}).
inline std::vector<std::string_view> concat_keys(std::initializer_list<std::vector<std::string_view>> lists) {
  std::vector<std::string_view> keys;
  for (const auto& list : lists) keys.insert(keys.end(), list.begin(), list.end());
  return keys;
}

}  // namespace lgvi::experiments
