// Ensembles of a study (the [ensemble] table, experiments/studies/README.md): N samples of a scene,
// each the scene file with drawn values in place of some of its own (attitude, angular velocity,
// principal moments, any other number of [parameters] or [initial]), so that every metric of a
// study becomes a distribution over initial conditions and bodies.
//
// Reproducibility: sample k draws from its own generator, seeded from (seed, k) alone
// (sample_seed), so a sample is the same whatever N, the shard or the other samples; `study FILE
// --sample K` runs sample K alone. The draws are taken in a fixed order: attitude, angular
// velocity, moments, then the other values in the order of their keys.
//
// The generator: SplitMix64 (Steele, Lea, Flood, "Fast splittable pseudorandom number generators",
// OOPSLA 2014), written here so that its numbers do not depend on the standard library (the
// std:: distributions are implementation-defined); doubles in [0, 1) from its top 53 bits, normal
// numbers by the Box-Muller transform.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "experiments/input/toml_reader.hpp"
#include "experiments/output/fields.hpp"
#include "experiments/scene/scene.hpp"

namespace lgvi::experiments {

/// SplitMix64: a 64-bit state advanced by the golden-ratio increment, each output the state
/// through the MurmurHash3-style finalizer.
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t state) : state_(state) {}
  std::uint64_t next() {
    state_ += 0x9E3779B97F4A7C15ULL;
    return mix(state_);
  }
  /// A double uniform in [0, 1): the top 53 bits times 2^-53.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  /// A standard normal number (Box-Muller: sqrt(-2 ln u1) cos(2 pi u2), u1 in (0, 1]).
  double normal();
  /// The SplitMix64 finalizer.
  static std::uint64_t mix(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }

 private:
  std::uint64_t state_;
};

/// The initial state of sample k of an ensemble seeded `seed`: mix(seed XOR mix(k + golden)),
/// a function of (seed, k) alone.
std::uint64_t sample_seed(std::uint64_t seed, std::uint64_t k);

/// A law of one number: uniform on [a, b] or normal with mean a and standard deviation b.
struct ScalarLaw {
  enum class Kind { Uniform, Normal } kind = Kind::Uniform;
  double a = 0.0;
  double b = 0.0;
  double draw(SplitMix64& g) const { return kind == Kind::Uniform ? a + (b - a) * g.uniform() : a + b * g.normal(); }
};

/// A dispersed number of the scene file: [table] key, or element `index` of the array `key`.
struct ScalarDispersion {
  std::string name;  ///< as written: "parameters.mass", "parameters.rho[2]"
  std::string field;  ///< where it was written in the study ("ensemble.values.\"parameters.mass\"")
  std::string table;
  std::string key;
  std::optional<std::size_t> index;
  ScalarLaw law;
};

/// The [ensemble] table read and checked.
struct EnsembleLaws {
  std::int64_t samples = 1;
  std::uint64_t seed = 0;
  std::string field = "ensemble";  ///< "ensemble" (what quick.ensemble changed is named by its own field)

  /// attitude: the file's (none given), uniform on SO(3) (Shoemake's quaternion), or the file's
  /// times exp(hat(theta a)), a uniform on the unit sphere and theta uniform in [0, spread].
  enum class Attitude { File, Uniform, AboutNominal } attitude = Attitude::File;
  double attitude_spread = 0.0;

  /// omega: |Omega| uniform in [norm_lo, norm_hi] (default the file's |Omega|), its direction
  /// uniform on the sphere or on the cap of half-angle `spread` about the file's direction.
  bool omega = false;
  std::optional<double> omega_norm_lo, omega_norm_hi;
  bool omega_uniform_direction = true;
  double omega_spread = 0.0;

  /// moments: J1, J2, J3 uniform on [lo, hi]^3 conditioned on the triangle inequality
  /// J_i <= J_j + J_k (rejection: each try accepted with probability >= 1/2).
  bool moments = false;
  double moments_lo = 0.0, moments_hi = 0.0;

  std::vector<ScalarDispersion> values;

  std::string attitude_field, omega_field, moments_field;  ///< where each law was written
};

/// One [ensemble] table of a study and its field ("ensemble", "quick.ensemble",
/// "scenes[1].ensemble"); null node: absent.
struct EnsembleLayer {
  const toml::node* node = nullptr;
  std::string field;
};

/// Reads the [ensemble] tables `layers`, each key of a later one replacing the same key of the
/// earlier ones (the top level's, then quick.ensemble, then a scene's own); each value is named
/// by the field it came from. Throws SceneError naming the file, the field and the reason
/// (N < 1, an empty range, a negative spread, an unknown law or key).
EnsembleLaws read_ensemble(const TomlReader& r, const std::vector<EnsembleLayer>& layers);

/// Checks that the laws apply to `nominal` (the scene loaded from its file, whose table is
/// `nominal_doc`): attitude and omega need a system of one body with an attitude and a body rate
/// (its state has R and Omega), moments a [parameters] inertia in the file, each value a number in
/// the file at that place. Throws
/// SceneError naming the study file (r) and the law's field.
void check_ensemble(const TomlReader& r, const EnsembleLaws& laws, const Scene& nominal, const toml::table& nominal_doc);

/// The names of the drawn values (summary columns, CSV metadata), in draw order: the attitude as
/// initial.quaternion[0..3] (w, x, y, z), initial.Omega[0..2], parameters.inertia[0..2], then
/// each value's name.
std::vector<std::string> drawn_columns(const EnsembleLaws& laws);

/// One sample: the scene file's table with the drawn values in place.
class EnsembleSample {
 public:
  /// Draws sample k of `laws` about `nominal` (loaded from `nominal_doc`).
  EnsembleSample(std::shared_ptr<const toml::table> nominal_doc, const EnsembleLaws& laws, const Scene& nominal,
                 std::uint64_t k);
  /// The sample's scene: the table with the drawn values, then `overrides`, validated as a scene
  /// file (parse_scene_table; `file` names it). Throws SceneError for a drawn value the scene
  /// refuses (a normal law's negative mass).
  Scene load(const std::filesystem::path& file, const SceneOverrides& overrides) const;
  /// sample (k), sample_seed (decimal text) and each drawn value (drawn_columns).
  const Fields& fields() const { return fields_; }
  std::uint64_t index() const { return k_; }

 private:
  struct Edit {
    std::string table;
    std::string key;
    std::vector<std::string> remove;  ///< keys of `table` the value replaces (R, quaternion, euler)
    std::optional<std::size_t> index;
    std::vector<double> values;  ///< the whole array, or the one element at index
  };
  std::shared_ptr<const toml::table> doc_;
  std::uint64_t k_;
  std::vector<Edit> edits_;
  Fields fields_;
};

}  // namespace lgvi::experiments
