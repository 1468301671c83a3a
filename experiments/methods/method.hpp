// Methods: the ways a scene can be integrated. The LGVI is the first; the continuous-time
// baselines (quaternion / Euler-angle / rotation-matrix models on CVODE, odeint, GSL) join it
// behind this interface. The choice is made at run time (CLI, suites), hence the virtual
// dispatch; inside run() everything is static.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "baselines/model.hpp"
#include "baselines/solver.hpp"
#include "experiments/output/fields.hpp"
#include "experiments/methods/recorder.hpp"
#include "experiments/scene/scene.hpp"
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

/// The coordinate model a baseline runs when none is named (simulate, Python, study files).
inline constexpr const char* kDefaultCoordinateModel = "quaternion";

/// Options of the continuous-time baselines (experiments/methods/baseline_method.cpp); the LGVI takes
/// none. model: quaternion | quaternion-renormalized | euler | matrix (the baselines';
/// kDefaultCoordinateModel when not given); rtol, atol: adaptive baselines only (default 1e-6,
/// atol = rtol). Fixed-step baselines step with the scene's h.
struct MethodOptions {
  std::optional<std::string> model;
  std::optional<double> rtol;
  std::optional<double> atol;
  /// The single-body LGVIs' rotation-update solver settings (default: RotationUpdateOptions{}).
  /// Not a CLI option: `validate --rotation-tolerance` sets it to show the gate catches a
  /// degraded solver. Rejected for the baselines.
  std::optional<RotationUpdateOptions> rotation_update;
};

/// What a method is, registered once (experiments/methods/registry.cpp) and read by the CLI, the
/// suites and studies (rosters, labels, evaluation counts), validate and Python: nothing else
/// looks at its name. The family is the method's identity (Python's "family"); what a user of
/// the method asks of it is a trait below, and rosters select by traits (methods_where).
enum class MethodFamily {
  Lgvi,          ///< the LGVI flow map itself (symmetric or printed form)
  ComposedLgvi,  ///< the symmetric LGVI composed to higher order (lgvi/composition.hpp)
  OneStep,       ///< another one-step method on the group, run by the one-step driver (one_step.hpp)
  Baseline,      ///< a continuous-time solver on a coordinate model (baselines/)
};

struct MethodInfo {
  std::string name;  ///< CLI, file names, metadata: "lgvi-yoshida4", "cvode-bdf"
  MethodFamily family;
  int order;           ///< nominal order (symmetric form for the LGVIs); 0: error-controlled
  std::size_t stages;  ///< force (LGVI) or RHS evaluations per step; 0: varies (adaptive)
  baselines::StepControl step_control;
  bool uses_jacobian;  ///< Newton iterations on the model's Jacobian (baselines)
  /// Coordinate models it accepts (--model); empty: it works on the Lie group itself.
  std::vector<baselines::CoordinateModel> models;
  /// Evaluations are counted by the method (Stats::rhs_evaluations); otherwise steps x stages.
  bool counts_evaluations;
  /// Takes the scene's LGVI form (symmetric | printed); the composed LGVIs need the symmetric one.
  bool takes_form;
  std::string legend;  ///< figure legend: "LGVI order 4 (yoshida4)"; baselines: the name
  /// Validates the options (see make_method) and builds the method.
  std::function<std::unique_ptr<Method>(const MethodOptions& options)> make;

  // Traits: what the method guarantees, as the suites, studies and validate ask it.
  /// Self-adjoint (time-symmetric) at fixed step: even order, bounded energy error.
  bool symmetric = false;
  /// The flow of a discrete variational principle (eqs. 7-9): symplectic, and by its discrete
  /// Noether theorem it keeps the momentum maps of the symmetries of its discrete Lagrangian.
  /// The LGVI family, solved as the paper solves eqs. 7-9 (rattle reaches the symmetric LGVI's
  /// map by another route and is listed as symplectic only, beside the splittings).
  bool variational = false;
  /// Its flow is a symplectic map of T*SO(3) (x T*R^3): the LGVIs, the splittings, NO_SQUISH, RATTLE.
  bool symplectic = false;
  /// Its attitudes stay on SO(3) to round-off at every step (a Lie group method); a coordinate
  /// model's baseline on quaternions or matrices drifts off it.
  bool stays_on_group = false;
  /// Keeps the system's momentum map to round-off (the recorder's momentum drift is gated as
  /// round-off, validate's conservation group).
  bool preserves_momentum_map = false;
  /// Takes RotationUpdateOptions (the LGVIs' rotation update; validate --rotation-tolerance).
  bool takes_rotation_update = false;
  /// Stats::newton_iterations counts its steps' own Newton iterations (the rotation update):
  /// validate's "newton" metrics.
  bool reports_step_iterations = false;
  /// The extremes suite expects every case of it to complete (a failure is a finding, not a
  /// limit of the method): the LGVIs at the steps the suite sweeps.
  bool must_complete_at_extremes = false;
  /// Integrates the uncontrolled free rigid body exactly (splitting-exact): its differences of
  /// successive step sizes there are rounding, so no order is measured on such a scene.
  bool exact_for_free_body = false;
  /// Scene systems it applies to ("pendulum", ...); empty: every system.
  std::vector<std::string> systems = {};

  bool fixed_step() const { return step_control == baselines::StepControl::Fixed; }
  bool adaptive() const { return !fixed_step(); }
  bool on_group() const { return models.empty(); }
  bool applies_to(const std::string& system) const;
};

/// Every method, in registration order: the LGVI, the composed LGVIs, the other one-step
/// methods, the baselines.
const std::vector<MethodInfo>& method_registry();
/// The registered methods with `trait(info)` true, in registration order: a roster by traits.
std::vector<const MethodInfo*> methods_where(const std::function<bool(const MethodInfo&)>& trait);
/// The registered methods whose traits satisfy `query`, in registration order: trait names
/// joined by " and ", each optionally preceded by "not ", e.g. "on_group and not variational"
/// (the Lie group methods). Trait names: symmetric, variational, symplectic, stays_on_group,
/// preserves_momentum_map, on_group, fixed_step, adaptive. Throws InvalidInput("methods", ...)
/// for an empty query or an unknown trait (naming the known ones). The study files' method lists
/// take such a query ({ where = "..." }).
std::vector<const MethodInfo*> methods_matching(std::string_view query);
/// Throws InvalidInput for any option in `options` (a method that takes none: the one-step
/// methods over the mechanics): model, rtol, atol, rotation_update.
void refuse_options(const std::string& method, const MethodOptions& options);
/// The registered method `name`. Throws InvalidInput("method", ...) naming the known ones.
const MethodInfo& method_info(const std::string& name);

/// The names of method_registry(): "lgvi" (order 2), the composed LGVIs "lgvi-yoshida4",
/// "lgvi-suzuki4" (order 4), "lgvi-yoshida6", "lgvi-kahan-li6" (order 6; symmetric form only,
/// lgvi/composition.hpp), then baselines::solver_names().
std::vector<std::string> method_names();

/// Method by name. Throws InvalidInput("method", ...) for an unknown name.
std::unique_ptr<Method> make_method(const std::string& name);
/// Method by name with options, validated here (before anything runs or is written): throws
/// InvalidInput("method" | "model" | "rtol" | "atol", ...) for an unknown name or model, a
/// baseline without a model, options the method does not take (the LGVI takes none; fixed-step
/// baselines take no tolerances), non-positive tolerances, or a renormalized model on a solver
/// without a post-step hook. Same as method_info(name).make(options).
std::unique_ptr<Method> make_method(const std::string& name, const MethodOptions& options);

}  // namespace lgvi::experiments
