// The suite case of the integrator suites: a scene (optionally edited in code: inertia, initial
// rates) integrated by one method (LGVI, composed LGVI or baseline on a coordinate model) into
// its own CSV, reported with cost (steps, evaluations, integrator wall time) and accuracy
// (energy, orthogonality, momentum and, against a shared reference run or the scene's exact
// solution, the final state).
#pragma once

#include <exception>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "experiments/systems/exact_reference.hpp"
#include "experiments/methods/method.hpp"
#include "experiments/methods/recorder.hpp"
#include "experiments/scene/scene.hpp"
#include "experiments/suites/suite.hpp"

namespace lgvi::experiments {

/// A change of a loaded scene made in code (what a scene file cannot say for a sweep).
struct SceneEdit {
  std::string description;              ///< recorded as "variant" ("|Omega0| = 100 rad/s")
  std::function<void(Scene&)> apply;    ///< may throw InvalidInput (recorded as "rejected-input")
};

class EnsembleSample;  // experiments/suites/ensemble.hpp

struct SimulateSpec {
  std::string scene;  ///< name in the scenes directory
  SceneOverrides overrides;
  /// An ensemble's sample: the scene file with the sample's drawn values in place (then
  /// `overrides`, then `edit`); its fields (sample, seed, drawn values) go into the case's CSV
  /// metadata. A drawn value the scene refuses is the case's status "rejected-input".
  std::shared_ptr<const EnsembleSample> sample;
  std::optional<SceneEdit> edit;
  std::string method = "lgvi";
  MethodOptions options;
  /// The case's cost is a result (work-precision, long-horizon): the harness times it again
  /// alone and repeated (SimulateJob::prepare_timing).
  bool timed = false;

  /// Loads (the sample's scene, if any), overrides and edits the scene. Throws SceneError;
  /// InvalidInput from the edit.
  Scene load(const std::filesystem::path& scenes_dir) const;
};

/// The reference the cases of a scene are compared with: a fine run of the scene, computed once
/// on first use (thread-safe) and shared, or the scene's exact solution (ExactReference),
/// evaluated at each case's own final time. Nothing is written for it: its description goes
/// into the cases' metadata.
class ReferenceRun {
 public:
  /// The fine run `spec`.
  explicit ReferenceRun(SimulateSpec spec);
  /// The exact solution of spec's scene when it has one (ExactReference::of), else the fine run
  /// `spec`. Loads the scene to decide; a scene that does not load gets the run (its cases then
  /// report the scene's error themselves).
  static std::shared_ptr<const ReferenceRun> exact_or_run(SimulateSpec spec, const std::filesystem::path& scenes_dir);

  /// "lgvi-kahan-li6, h = 0.0001" (method, model, step or tolerance), or the exact solution's
  /// "exact (closed form, Celledoni et al. 2008)".
  std::string description() const;
  bool is_exact() const { return exact_description_.has_value(); }
  /// The reference state for a case that ended at time t: the exact solution at t, or the final
  /// sample of the fine run (final_state_error compares its time with the case's). Runs the
  /// reference, or builds the exact solution, on the first call. Throws std::runtime_error when
  /// the reference run does not complete or the scene has no exact solution after all (each case
  /// using it then records status "error").
  Sample sample_at(double t, const std::filesystem::path& scenes_dir) const;
  /// The phase fit of a case's final sample against the exact solution (ExactReference::phase_fit);
  /// nullopt for a fine-run reference (no trajectory to shift along). Prepares like sample_at.
  std::optional<PhaseFit> phase_fit(const Sample& final_sample, const std::filesystem::path& scenes_dir) const;

 private:
  void prepare(const std::filesystem::path& scenes_dir) const;

  SimulateSpec spec_;
  std::optional<std::string> exact_description_;
  mutable std::once_flag once_;
  mutable Sample final_;
  mutable std::optional<ExactReference> exact_;
  mutable std::string error_;
};

/// Dimensionless distance of two final states of the same scene: the largest of
/// ||R - R_ref||_F (and R2), |Omega - Omega_ref| / |Omega_ref| (and Omega2), and for the
/// dumbbell and cart |x - x_ref| / |x_ref|, |v - v_ref| / |v_ref| (a zero reference norm makes
/// that term absolute). NaN when the times differ (a run that stopped early).
double final_state_error(const Model& model, const Sample& s, const Sample& ref);

class SimulateJob final : public Job {
 public:
  explicit SimulateJob(SimulateSpec spec, std::shared_ptr<const ReferenceRun> reference = nullptr);
  void validate(const std::filesystem::path& scenes_dir) const override;
  /// Writes ctx.case_id + ".csv". Fields: RunSummary::to_fields() plus "variant", "h_omega"
  /// (h |Omega0|), "evaluations" (baselines: RHS evaluations of the integration, without the
  /// output_rhs_evaluations spent on interpolating output times; LGVI: substeps, one force and
  /// moment evaluation each = steps x stages), "integrator_seconds" (wall time minus recording,
  /// of this one run, which may share the machine with other cases)
  /// and, with a reference, "final_error" and "reference"; with an exact one also "phase_shift",
  /// "phase_drift_rate" (phase_shift / t_final) and "shape_error" (ExactReference::phase_fit).
  JobResult run(const JobContext& ctx) const override;
  bool timed() const override { return spec_.timed; }
  /// Force (RHS) evaluations the run is expected to make: steps x stages for a fixed-step
  /// method; for an adaptive one (stages vary) a rough t_final x rtol^(-1/5) steps of 7
  /// evaluations (a 5th-order pair; only the ETA uses it). Loads the scene.
  double expected_cost(const std::filesystem::path& scenes_dir) const override;
  /// The same integration as run() with a recorder that writes nothing; the recorder's own time
  /// (diagnostics) is the uncounted part, as run() takes it out of integrator_seconds.
  std::function<TimedRun()> prepare_timing(const JobContext& ctx, const JobResult& result) const override;
  /// "integrator_seconds_min" (minimum wall time per run, recording excluded),
  /// "integrator_seconds_median", "integrator_cpu_seconds" (minimum thread CPU time per run) and
  /// "timing_repetitions".
  Fields timing_fields(const Timing& timing) const override;
  const SimulateSpec& spec() const { return spec_; }

 private:
  SimulateSpec spec_;
  std::shared_ptr<const ReferenceRun> reference_;
};

}  // namespace lgvi::experiments
