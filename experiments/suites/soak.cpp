// The soak suite: each system's scene run by the symmetric LGVI for 10^7 steps (quick: 10^5),
// its controls dropped (so that energy and momentum are conserved quantities), reporting
// conservation (energy, momentum map, orthogonality) and the process's resident
// memory over the run, so that a leak or a per-step allocation (which would grow the memory
// with the steps: one byte a step is 10 MB at 10^7 steps) shows beside the conservation it
// must not cost.
//
// Memory is measured where nothing else of the suite runs: in the harness's timing passes, one
// case at a time (Job::timed, Job::timed_alone, suite.hpp), whose runs repeat the case's integration with a recorder that writes
// nothing. Before each repetition the peak resident size (VmHWM) is reset to the current one
// (reset_peak_resident); after it, the peak is read. Reported: the resident size before the
// run, the peak during it and their difference (the memory the run needed; flat in the steps
// when the step allocates nothing), the largest over the repetitions.
#include <algorithm>
#include <memory>
#include <mutex>

#include "experiments/suites/process_memory.hpp"
#include "experiments/scene/scene.hpp"
#include "experiments/suites/common.hpp"
#include "experiments/systems/systems.hpp"

namespace lgvi::experiments::suites {

namespace fs = std::filesystem;

namespace {

constexpr double kMebibyte = 1024.0 * 1024.0;

/// What the repetitions of one case measured of the process's memory.
struct MemoryRecord {
  std::mutex mutex;
  double before_bytes = 0.0;  ///< resident size before the repetition with the largest growth
  double peak_bytes = 0.0;    ///< largest peak resident size during a repetition
  double growth_bytes = 0.0;  ///< largest (peak - before) over the repetitions
  bool measured = false;
  bool peak_reset = true;     ///< every repetition's peak was reset before it ran
};

/// A SimulateJob (timed) whose timing repetitions also measure the resident memory.
class SoakJob final : public Job {
 public:
  explicit SoakJob(SimulateSpec spec) : inner_(std::make_shared<SimulateJob>(std::move(spec))) {}

  void validate(const fs::path& scenes_dir) const override { inner_->validate(scenes_dir); }
  JobResult run(const JobContext& ctx) const override { return inner_->run(ctx); }
  bool timed() const override { return true; }
  bool timed_alone() const override { return true; }  // the process's memory
  double expected_cost(const fs::path& scenes_dir) const override { return inner_->expected_cost(scenes_dir); }

  std::function<TimedRun()> prepare_timing(const JobContext& ctx, const JobResult& result) const override {
    std::function<TimedRun()> integrate = inner_->prepare_timing(ctx, result);
    if (!integrate) return {};
    return [integrate = std::move(integrate), memory = memory_]() {
      const bool reset = reset_peak_resident();
      const std::optional<double> before = resident_bytes();
      const TimedRun run = integrate();
      const std::optional<double> peak = peak_resident_bytes();
      if (before && peak) {
        const std::lock_guard lock(memory->mutex);
        memory->peak_reset = memory->peak_reset && reset;
        memory->peak_bytes = std::max(memory->peak_bytes, *peak);
        if (!memory->measured || *peak - *before > memory->growth_bytes) {
          memory->growth_bytes = *peak - *before;
          memory->before_bytes = *before;
        }
        memory->measured = true;
      }
      return run;
    };
  }

  Fields timing_fields(const Timing& timing) const override {
    Fields f = inner_->timing_fields(timing);
    const std::lock_guard lock(memory_->mutex);
    if (!memory_->measured) return f;
    f.push_back({"rss_before_mb", memory_->before_bytes / kMebibyte});
    f.push_back({"peak_rss_mb", memory_->peak_bytes / kMebibyte});
    // Without the reset the peak covers the process's life: no growth can be told.
    if (memory_->peak_reset) f.push_back({"rss_growth_mb", memory_->growth_bytes / kMebibyte});
    f.push_back({"peak_reset", memory_->peak_reset ? "yes" : "no (peak over the process's life)"});
    return f;
  }

 private:
  std::shared_ptr<SimulateJob> inner_;
  std::shared_ptr<MemoryRecord> memory_ = std::make_shared<MemoryRecord>();
};

/// One scene per system, in the order of the paper's sections.
const std::vector<std::string>& soak_scenes() {
  static const std::vector<std::string> scenes = {"free-body", "pendulum", "dumbbell", "cart-pendulum",
                                                  "connected-bodies"};
  return scenes;
}

std::string markdown_cell(const SummaryRow& r, const std::string& column) {
  const std::optional<double> x = r.number(column);
  return x ? fmt(*x) : (r.text(column).empty() ? "-" : r.text(column));
}

}  // namespace

Suite soak_suite(const SuiteParams& params) {
  Suite s;
  s.name = "soak";
  s.description = "10^7 steps (quick 10^5) of the symmetric LGVI per system: conservation and peak resident memory";
  s.columns = simulation_columns();
  for (const std::string& c : timing_columns()) s.columns.push_back(c);
  for (const char* c : {"grid_steps", "momentum_map", "rss_before_mb", "peak_rss_mb", "rss_growth_mb", "peak_reset"}) {
    s.columns.push_back(c);
  }
  const std::size_t steps = params.quick ? 100'000 : 10'000'000;
  // Rows kept per CSV: the curve of a long run, not its every step (the recorder writes every
  // K-th step only, so the memory does not depend on the steps through the output).
  constexpr std::size_t kRowsPerCsv = 1000;
  const MethodSpec lgvi("lgvi");
  for (const std::string& scene_name : soak_scenes()) {
    const Scene scene = load_scene(resolve_scene(scene_name, params.scenes_dir));
    SimulateSpec spec;
    spec.scene = scene_name;
    spec.overrides.t_final = static_cast<double>(steps) * scene.horizon.h;
    spec.overrides.output_every = static_cast<std::int64_t>(std::max<std::size_t>(1, steps / kRowsPerCsv));
    spec.timed = true;
    spec.edit = SceneEdit{"controls dropped", [](Scene& sc) {
                            visit_binding(sc.model, [](auto binding, auto& m) { decltype(binding)::drop_controls(m); });
                          }};
    SuiteCase c = simulate_case(scene_name + "-" + lgvi.id(), scene_name, spec, lgvi, Expectation::Complete);
    spec.method = lgvi.method;
    spec.options = lgvi.options();
    c.job = std::make_shared<SoakJob>(spec);
    s.cases.push_back(std::move(c));
  }
  s.render = [](const RenderContext& ctx, const std::vector<SummaryRow>& rows) {
    std::string table =
        "| scene | steps | status | max rel. energy error | max momentum drift | max orthogonality error | "
        "time per run (s) | resident before (MB) | peak (MB) | growth (MB) |\n"
        "|---|---|---|---|---|---|---|---|---|---|\n";
    for (const SummaryRow& r : rows) {
      table += "| " + r.text("scene") + " | " + markdown_cell(r, "grid_steps") + " | " + r.text("status") + " | " +
               markdown_cell(r, "max_energy_error_relative") + " | " + markdown_cell(r, "max_momentum_drift_absolute") +
               " | " + markdown_cell(r, "max_orthogonality_error") + " | " + markdown_cell(r, "integrator_seconds_min") +
               " | " + markdown_cell(r, "rss_before_mb") + " | " + markdown_cell(r, "peak_rss_mb") + " | " +
               markdown_cell(r, "rss_growth_mb") + " |\n";
    }
    std::vector<fs::path> files = {write_text_file(ctx, "soak-table.md", table)};
    std::vector<const SummaryRow*> all;
    for (const SummaryRow& r : rows) all.push_back(&r);
    // One curve per system, each labelled by its scene and styled by its system (one method).
    files.push_back(plot_time_series(ctx, "soak-energy", "energy error of the symmetric LGVI (order 2), every system",
                                     "|E - E_0| (each system's energy unit)", "energy_error", true, all,
                                     CurvesBy::System));
    return files;
  };
  return s;
}

}  // namespace lgvi::experiments::suites
