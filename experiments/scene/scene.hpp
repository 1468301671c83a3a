// Scenes: a physical system with its parameters, initial state, horizon and optional control,
// read from a TOML file (experiments/scenes/NAME.toml) and validated at this boundary.
// The full format, every key of every system with units, default and range: experiments/scenes/README.md.
//
// File format (every key below is the complete list; any other key is an error):
//
//   system = "free-body" | "pendulum" | "dumbbell" | "cart-pendulum" | "connected-bodies" |
//            "potential-body" | "potential-body-se3"
//   description = "one line"                    (optional)
//   [parameters], [initial], [control]   the system's own tables, read by its binding
//                  (experiments/systems/<system>.hpp: check_keys, read), e.g.
//                  free-body: [parameters] inertia; [initial] R (3x3 array of rows), quaternion
//                  ([w, x, y, z]) or euler ({sequence, angles}), default identity; Omega (body
//                  frame) or omega_space; [control] type = "sinusoid" (amplitude, frequency,
//                  phase), "constant" (value), "piecewise-linear" (file) or "pd" (kp, kd,
//                  target): TimeControl, AttitudeFeedback
//                  inertia = [J1, J2, J3] (principal moments) or a 3x3 array of arrays
//   [integration]  h, t_final, form = "symmetric" | "printed" (default symmetric),
//                  output_every (default 1), last_step = "error" | "shorter" (default error)
//
// The horizon must be a whole number of steps: steps = round(t_final / h) and
// |steps h - t_final| <= 1e-9 t_final. The state is sampled at t_k = k h, k = 0..steps.
// With last_step = "shorter" another t_final takes floor(t_final / h) steps of h and a shorter
// last one ending at t_final (Horizon::time).
//
// Admissible input (checked before and after parsing; everything else is a SceneError):
//  - at most kMaxSceneBytes (1 MiB) of text, and at most kMaxSceneNesting (32) levels of
//    nesting, counting the open tables/arrays/inline tables and the parts of dotted keys at any
//    point (the shipped scenes need 4). Checked by a scan of the text before toml++ sees it: its
//    recursive descent overflows the stack on a dotted key of 100,000 parts.
//  - every number 0 or of magnitude in [1e-100, 1e100] (kMinSceneMagnitude,
//    kMaxSceneMagnitude): products and quotients of three such values stay finite, so the
//    energies, momenta, forces and moments formed from them cannot overflow.
//  - the initial state as the integrator holds it (momenta, cached forces and moments) and its
//    energy finite: values in range can still overflow together (mu m / |x|^2 with |x| = 1e-100).
//    The field named is "initial" with the quantity in the reason.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "experiments/input/scene_reader.hpp"
#include "experiments/systems/systems.hpp"
#include "lgvi/lgvi.hpp"
#include "lgvi/types.hpp"

namespace lgvi::experiments {


/// What a t_final that is not a whole number of steps of h means ([integration] last_step):
/// an error (the default: a mistyped t_final is reported, not absorbed), or floor(t_final / h)
/// steps of h and one shorter final step of t_final - floor(t_final / h) h.
enum class LastStep { Error, Shorter };

/// "error" or "shorter"; throws InvalidInput("last_step", ...) for anything else.
LastStep parse_last_step(const std::string& name);

/// The time grid and output decimation of a run (validated: see make_horizon).
struct Horizon {
  double h = 0.0;
  double t_final = 0.0;
  std::size_t steps = 0;  ///< round(t_final / h); with a shorter last step, floor(t_final / h) + 1
  std::size_t output_every = 1;
  /// The last step (k = steps - 1 -> steps) is t_final - (steps - 1) h, shorter than h.
  bool shorter_last_step = false;

  /// t_k: k h, and t_final itself at the end of a shorter last step.
  double time(std::size_t k) const {
    return shorter_last_step && k == steps ? t_final : static_cast<double>(k) * h;
  }
  /// The steps of size h (all of them unless the last is shorter).
  std::size_t whole_steps() const { return shorter_last_step ? steps - 1 : steps; }
  double last_step() const { return shorter_last_step ? t_final - static_cast<double>(steps - 1) * h : h; }
  /// The output grid's steps: k = 0, output_every, 2 output_every, ..., and steps.
  std::vector<std::size_t> output_steps() const {
    std::vector<std::size_t> ks;
    for (std::size_t k = 0; k <= steps; k += output_every) ks.push_back(k);
    if (ks.back() != steps) ks.push_back(steps);
    return ks;
  }
};

/// Validates h > 0, t_final > 0 (finite), at most 1e12 steps, 1 <= output_every <= 1e12, and
/// t_final a whole number of steps to 1e-9 relative (|round(t_final / h) h - t_final| <=
/// 1e-9 t_final) unless `last_step` is Shorter: then a t_final beyond that tolerance takes
/// floor(t_final / h) >= 1 steps of h and one shorter step to t_final. Throws InvalidInput with
/// field "h", "t_final" or "output_every".
Horizon make_horizon(double h, double t_final, std::int64_t output_every, LastStep last_step = LastStep::Error);

struct OcpDefinition;  // experiments/scene/ocp_scene.hpp

struct Scene {
  std::string name;            ///< the file's stem: "pendulum" for .../pendulum.toml
  std::filesystem::path file;  ///< as given to load_scene
  std::string description;
  Model model;
  Horizon horizon;
  LgviForm form = LgviForm::Symmetric;
  /// The [ocp] table (the optimal control problem), null when the scene has none.
  std::shared_ptr<const OcpDefinition> ocp;
  /// Suspicious but accepted input, one line each naming the file: a text whose last line has no
  /// newline ("FILE: does not end with a newline: the file may be truncated"). load_scene prints
  /// them on stderr; parse_scene only fills them in.
  std::vector<std::string> warnings;
  /// [integration] last_step: how `horizon` was made from h and t_final (sweeps of h and t_final
  /// built from this scene use it too).
  LastStep last_step = LastStep::Error;
  /// The other files the scene was read from (a piecewise-linear control's samples), in reading
  /// order: what a run of it depends on besides `file` (the resume fingerprints hash them).
  std::vector<std::filesystem::path> inputs = {};
  /// The TOML text the scene was parsed from: a scene made in memory (Python's parse_scene,
  /// make_scene) is parsed again from it with other overrides (`solve_ocp(scene, t_final=...)`).
  std::shared_ptr<const std::string> text = {};

  const char* system() const { return system_name(model); }
};

/// Command-line replacements of the [integration] values, applied before validation.
struct SceneOverrides {
  std::optional<double> h;
  std::optional<double> t_final;
  std::optional<LgviForm> form;
  std::optional<std::int64_t> output_every;
};

/// Reads and validates a scene file (at most kMaxSceneBytes are read: a device or a huge file is
/// refused, not loaded). Throws SceneError (never anything else for bad input). The scene's
/// warnings go to stderr as "warning: ..." lines, once per file per process.
Scene load_scene(const std::filesystem::path& file, const SceneOverrides& overrides = {});

/// load_scene without printing: the warnings stay in Scene::warnings.
Scene parse_scene_file(const std::filesystem::path& file, const SceneOverrides& overrides = {});

/// Same from TOML text; `file` names the source in messages and gives the scene name.
Scene parse_scene(std::string_view toml_text, const std::filesystem::path& file,
                  const SceneOverrides& overrides = {});

/// The scenes directory compiled in: <source>/experiments/scenes.
std::filesystem::path default_scenes_dir();

/// Names of the scenes in a directory (stems of its *.toml files), sorted.
std::vector<std::string> scene_names(const std::filesystem::path& scenes_dir);

/// Maps a SCENE argument to a file. An argument containing '/' or ending in ".toml" is a path;
/// anything else is a scene name, looked up as scenes_dir/NAME.toml. Throws SceneError for an
/// unknown name (listing the known ones) or a missing file.
std::filesystem::path resolve_scene(const std::string& name_or_path,
                                    const std::filesystem::path& scenes_dir);

}  // namespace lgvi::experiments
