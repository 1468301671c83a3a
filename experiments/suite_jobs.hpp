// The suite case of the integrator suites: a scene (optionally edited in code: inertia, initial
// rates) integrated by one method (LGVI, composed LGVI or baseline on a coordinate model) into
// its own CSV, reported with cost (steps, evaluations, integrator wall time) and accuracy
// (energy, orthogonality, momentum and, against a shared reference run, the final state).
#pragma once

#include <exception>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "experiments/method.hpp"
#include "experiments/recorder.hpp"
#include "experiments/scene.hpp"
#include "experiments/suite.hpp"

namespace lgvi::experiments {

/// A change of a loaded scene made in code (what a scene file cannot say for a sweep).
struct SceneEdit {
  std::string description;              ///< recorded as "variant" ("|Omega0| = 100 rad/s")
  std::function<void(Scene&)> apply;    ///< may throw InvalidInput (recorded as "rejected-input")
};

struct SimulateSpec {
  std::string scene;  ///< name in the scenes directory
  SceneOverrides overrides;
  std::optional<SceneEdit> edit;
  std::string method = "lgvi";
  MethodOptions options;

  /// Loads, overrides and edits the scene. Throws SceneError; InvalidInput from the edit.
  Scene load(const std::filesystem::path& scenes_dir) const;
};

/// A fine run of a scene, computed once on first use (thread-safe) and shared by the cases
/// compared with it. Nothing is written for it: its description goes into the cases' metadata.
class ReferenceRun {
 public:
  explicit ReferenceRun(SimulateSpec spec);
  /// "lgvi-kahan-li6, h = 0.0001" (method, model, step or tolerance).
  std::string description() const;
  /// The final sample; runs the reference on the first call. Throws std::runtime_error when the
  /// reference run does not complete (each case using it then records status "error").
  const Sample& final_sample(const std::filesystem::path& scenes_dir) const;

 private:
  SimulateSpec spec_;
  mutable std::once_flag once_;
  mutable Sample final_;
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
  /// moment evaluation each = steps x stages), "integrator_seconds" (wall time minus recording)
  /// and, with a reference, "final_error" and "reference".
  JobResult run(const JobContext& ctx) const override;
  const SimulateSpec& spec() const { return spec_; }

 private:
  SimulateSpec spec_;
  std::shared_ptr<const ReferenceRun> reference_;
};

}  // namespace lgvi::experiments
