// Methods: the ways a scene can be integrated. The LGVI is the first; the continuous-time
// baselines (quaternion / Euler-angle / rotation-matrix models on CVODE, odeint, GSL) join it
// behind this interface. The choice is made at run time (CLI, suites), hence the virtual
// dispatch; inside run() everything is static.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "experiments/fields.hpp"
#include "experiments/recorder.hpp"
#include "experiments/scene.hpp"
#include "lgvi/integrate.hpp"

namespace lgvi::experiments {

class Method {
 public:
  virtual ~Method() = default;
  /// Short identifier used in file names, metadata and summaries: "lgvi".
  virtual std::string name() const = 0;
  /// The method's settings for a scene (CSV metadata and JSON summary), e.g. the LGVI form and
  /// the rotation-update tolerance.
  virtual Fields settings(const Scene& scene) const = 0;
  /// Integrates scene.horizon from the scene's initial state, passing `recorder` the state at
  /// the output grid's times only: t_k for k = 0, output_every, 2 output_every, ..., and the last
  /// step computed (steps, or the last good step of a failed run). Never prints. The output grid
  /// does not change the integration: the LGVI skips the other steps, the adaptive baselines
  /// step freely and interpolate the grid's times.
  virtual Stats run(const Scene& scene, Recorder& recorder) const = 0;
  /// True for the quaternion baselines: the recorder adds the quaternion_norm_error column.
  virtual bool records_quaternion_norm() const { return false; }
};

/// Options of the continuous-time baselines (experiments/baseline_method.cpp); the LGVI takes
/// none. model: quaternion | quaternion-renormalized | euler | matrix (required by the
/// baselines); rtol, atol: adaptive baselines only (default 1e-6, atol = rtol). Fixed-step
/// baselines step with the scene's h.
struct MethodOptions {
  std::optional<std::string> model;
  std::optional<double> rtol;
  std::optional<double> atol;
  /// The single-body LGVIs' rotation-update solver settings (default: RotationUpdateOptions{}).
  /// Not a CLI option: `validate --rotation-tolerance` sets it to show the gate catches a
  /// degraded solver. Rejected for the baselines.
  std::optional<RotationUpdateOptions> rotation_update;
};

/// The method names make_method accepts: "lgvi" (order 2), the composed LGVIs "lgvi-yoshida4",
/// "lgvi-suzuki4" (order 4), "lgvi-yoshida6", "lgvi-kahan-li6" (order 6; symmetric form only,
/// lgvi/composition.hpp), then baselines::solver_names().
std::vector<std::string> method_names();

/// Method by name. Throws InvalidInput("method", ...) for an unknown name.
std::unique_ptr<Method> make_method(const std::string& name);
/// Method by name with options, validated here (before anything runs or is written): throws
/// InvalidInput("method" | "model" | "rtol" | "atol", ...) for an unknown name or model, a
/// baseline without a model, options the method does not take (the LGVI takes none; fixed-step
/// baselines take no tolerances), non-positive tolerances, or a renormalized model on a solver
/// without a post-step hook.
std::unique_ptr<Method> make_method(const std::string& name, const MethodOptions& options);

/// Baseline method (experiments/baseline_method.cpp); `name` is one of baselines::solver_names().
std::unique_ptr<Method> make_baseline_method(const std::string& name, const MethodOptions& options);

}  // namespace lgvi::experiments
