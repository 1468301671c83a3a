#include "experiments/suites/jobs.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "experiments/methods/simulate.hpp"
#include "experiments/suites/ensemble.hpp"
#include "experiments/systems/systems.hpp"

namespace lgvi::experiments {

namespace fs = std::filesystem;

Scene SimulateSpec::load(const fs::path& scenes_dir) const {
  Scene scene = sample ? sample->load(resolve_scene(this->scene, scenes_dir), overrides)
                       : load_scene(resolve_scene(this->scene, scenes_dir), overrides);
  if (edit) edit->apply(scene);
  return scene;
}

namespace {

std::string spec_description(const SimulateSpec& spec) {
  std::string d = spec.method;
  if (spec.options.model) d += " (" + *spec.options.model + ")";
  if (spec.options.rtol) d += ", rtol = " + shortest(*spec.options.rtol);
  if (spec.overrides.h && !spec.options.rtol) d += ", h = " + shortest(*spec.overrides.h);
  return d;
}

/// |Omega0| of the scene (the largest body's, for two bodies).
double initial_rate(const Model& model) {
  return visit_binding(model, [](auto binding, const auto& m) { return decltype(binding)::initial_rate(m); });
}

}  // namespace

ReferenceRun::ReferenceRun(SimulateSpec spec) : spec_(std::move(spec)) {}

std::shared_ptr<const ReferenceRun> ReferenceRun::exact_or_run(SimulateSpec spec, const fs::path& scenes_dir) {
  auto reference = std::make_shared<ReferenceRun>(std::move(spec));
  try {
    if (const std::optional<ExactReference> exact = ExactReference::of(reference->spec_.load(scenes_dir).model)) {
      reference->exact_description_ = exact->description();
    }
  } catch (const std::exception&) {
    // SceneError or InvalidInput: the cases report it; the fine run stays the reference.
  }
  return reference;
}

std::string ReferenceRun::description() const {
  return exact_description_ ? *exact_description_ : spec_description(spec_);
}

void ReferenceRun::prepare(const fs::path& scenes_dir) const {
  std::call_once(once_, [&] {
    try {
      const Scene scene = spec_.load(scenes_dir);
      if (exact_description_) {
        std::string why_not;
        exact_ = ExactReference::of(scene.model, &why_not);
        if (!exact_) error_ = "exact reference of scene " + spec_.scene + ": " + why_not;
        return;
      }
      const std::unique_ptr<Method> method = make_method(spec_.method, spec_.options);
      Recorder recorder(scene.model, scene.horizon.output_every, nullptr, method->records_quaternion_norm());
      const Stats stats = method->run(scene, recorder);
      if (!stats.ok()) {
        error_ = "reference run " + description() + " did not complete: " + stats.brief();
      } else {
        final_ = recorder.last();
      }
    } catch (const std::exception& e) {
      error_ = "reference run " + description() + ": " + e.what();
    }
  });
  if (!error_.empty()) throw std::runtime_error(error_);
}

Sample ReferenceRun::sample_at(double t, const fs::path& scenes_dir) const {
  prepare(scenes_dir);
  if (!exact_) return final_;
  return exact_->sample(t);
}

std::optional<PhaseFit> ReferenceRun::phase_fit(const Sample& final_sample, const fs::path& scenes_dir) const {
  prepare(scenes_dir);
  if (!exact_) return std::nullopt;
  return exact_->phase_fit(final_sample);
}

double final_state_error(const Model& model, const Sample& s, const Sample& ref) {
  if (std::abs(s.t - ref.t) > 1e-9 * std::max(1.0, std::abs(ref.t))) return std::numeric_limits<double>::quiet_NaN();
  return visit_binding(model, [&](auto binding, const auto& m) {
    using M = std::decay_t<decltype(m)>;
    return decltype(binding)::final_state_error(state_of<M>(s), state_of<M>(ref));
  });
}

SimulateJob::SimulateJob(SimulateSpec spec, std::shared_ptr<const ReferenceRun> reference)
    : spec_(std::move(spec)), reference_(std::move(reference)) {}

void SimulateJob::validate(const fs::path& scenes_dir) const {
  // The scene file and the method; the edit (a sweep's extreme value) is judged at run time.
  (void)load_scene(resolve_scene(spec_.scene, scenes_dir), spec_.overrides);
  (void)make_method(spec_.method, spec_.options);
}

double SimulateJob::expected_cost(const fs::path& scenes_dir) const {
  // A sample's steps are its file's (the laws change no horizon): the file alone is loaded.
  const Scene scene =
      spec_.sample ? load_scene(resolve_scene(spec_.scene, scenes_dir), spec_.overrides) : spec_.load(scenes_dir);
  const MethodInfo& kind = method_info(spec_.method);
  if (kind.fixed_step()) return static_cast<double>(scene.horizon.steps) * static_cast<double>(std::max<std::size_t>(1, kind.stages));
  const double rtol = spec_.options.rtol.value_or(1e-6);
  return scene.horizon.t_final * std::pow(std::max(rtol, 1e-16), -0.2) * 7.0;
}

JobResult SimulateJob::run(const JobContext& ctx) const {
  std::optional<Scene> loaded;
  try {
    loaded.emplace(spec_.load(ctx.scenes_dir));
  } catch (const InvalidInput& e) {
    // An edited scene outside the validated domain (e.g. an inertia past the triangle
    // inequality): a finding of an extremes sweep, not a crash.
    return {false, "rejected-input", e.what(), {{"variant", spec_.edit ? spec_.edit->description : std::string()}}};
  } catch (const SceneError& e) {
    if (!spec_.sample) throw;
    // A drawn value the scene refuses (a normal law's negative mass): a finding of the ensemble.
    return {false, "rejected-input", e.what(), {{"variant", std::string()}}};
  }
  const Scene& scene = *loaded;
  const MethodInfo& kind = method_info(spec_.method);
  const std::unique_ptr<Method> method = kind.make(spec_.options);
  SimulateOptions options{ctx.out_dir / (ctx.case_id + ".csv"), ctx.command_line, {}};
  const std::string variant = spec_.edit ? spec_.edit->description : std::string();
  if (!variant.empty()) options.extra_metadata.push_back({"variant", variant});
  if (spec_.sample) {
    for (const Field& f : spec_.sample->fields()) options.extra_metadata.push_back(f);
  }
  if (reference_) {
    // Prepared before the case runs: a reference that fails fails the case before its CSV.
    (void)reference_->sample_at(0.0, ctx.scenes_dir);
    options.extra_metadata.push_back({"reference", reference_->description()});
  }
  const RunSummary r = simulate(scene, *method, options);

  JobResult out;
  out.completed = r.stats.ok();
  out.status = to_string(r.stats.status);
  out.detail = r.stats.brief();
  out.fields = r.to_fields();
  // The integration's own evaluations: without those spent on interpolating output times.
  const std::size_t evaluations = kind.counts_evaluations ? r.stats.rhs_evaluations - r.stats.output_rhs_evaluations
                                                          : r.stats.steps * kind.stages;
  out.fields.push_back({"variant", variant});
  out.fields.push_back({"h_omega", scene.horizon.h * initial_rate(scene.model)});
  out.fields.push_back({"evaluations", static_cast<std::int64_t>(evaluations)});
  out.fields.push_back({"integrator_seconds", std::max(0.0, r.stats.wall_seconds - r.recording_seconds)});
  // The CSV's name relative to the suite's output directory (case ids may contain '/').
  out.fields.push_back({"csv_path", ctx.case_id + ".csv"});
  if (reference_) {
    const double e = out.completed
                         ? final_state_error(scene.model, r.final_sample, reference_->sample_at(r.final_sample.t, ctx.scenes_dir))
                         : std::numeric_limits<double>::quiet_NaN();
    out.fields.push_back({"final_error", e});
    if (out.completed) {
      if (const std::optional<PhaseFit> fit = reference_->phase_fit(r.final_sample, ctx.scenes_dir)) {
        const double nan = std::numeric_limits<double>::quiet_NaN();
        out.fields.push_back({"phase_shift", fit->converged ? fit->shift : nan});
        out.fields.push_back({"phase_drift_rate", fit->converged && r.final_sample.t > 0.0 ? fit->shift / r.final_sample.t : nan});
        out.fields.push_back({"shape_error", fit->converged ? fit->shape_error : nan});
      }
    }
    out.fields.push_back({"reference", reference_->description()});
  }
  return out;
}

std::function<TimedRun()> SimulateJob::prepare_timing(const JobContext& ctx, const JobResult& result) const {
  if (result.status == "rejected-input") return {};  // nothing ran
  const auto scene = std::make_shared<const Scene>(spec_.load(ctx.scenes_dir));
  const std::shared_ptr<const Method> method = make_method(spec_.method, spec_.options);
  return [scene, method]() {
    using Clock = std::chrono::steady_clock;
    Recorder recorder(scene->model, scene->horizon.output_every, nullptr, method->records_quaternion_norm());
    const double cpu_start = thread_cpu_seconds();
    const auto start = Clock::now();
    (void)method->run(*scene, recorder);
    const double wall = std::chrono::duration<double>(Clock::now() - start).count();
    const double cpu = thread_cpu_seconds() - cpu_start;
    return TimedRun{wall, cpu, recorder.seconds()};
  };
}

Fields SimulateJob::timing_fields(const Timing& t) const {
  return {{"integrator_seconds_min", t.wall_seconds_min},
          {"integrator_seconds_median", t.wall_seconds_median},
          {"integrator_cpu_seconds", t.cpu_seconds_min},
          {"timing_repetitions", static_cast<std::int64_t>(t.repetitions)}};
}

}  // namespace lgvi::experiments
