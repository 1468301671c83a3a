// What output costs (Google Benchmark): the bare LGVI integration of a scene (lgvi::integrate
// with a null observer) against the whole `simulate` path (recorder, diagnostics, CSV written to
// a temporary file and renamed) at --every 1000, 10 and 1, on the same scene and horizon.
// Each iteration is one whole run; steps/s is the scene's steps per second. The ratios of the
// simulate rows to the bare row are the cost of output.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>
#include <unistd.h>

#include "experiments/method.hpp"
#include "experiments/scene.hpp"
#include "experiments/simulate.hpp"
#include "lgvi/integrate.hpp"
#include "lgvi/lgvi.hpp"

namespace {

using namespace lgvi;
using namespace lgvi::experiments;
namespace fs = std::filesystem;

/// The pendulum scene (tumbling, h = 1e-3, 20 s: 20000 steps) with output every `every` steps.
Scene pendulum_scene(std::int64_t every) {
  SceneOverrides o;
  o.output_every = every;
  return load_scene(resolve_scene("pendulum", default_scenes_dir()), o);
}

/// A private directory for the benchmark's CSVs, removed at exit.
struct ScratchDir {
  fs::path path = fs::temp_directory_path() / ("lgvi-output-benchmark-" + std::to_string(::getpid()));
  ScratchDir() { fs::create_directories(path); }
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};
const fs::path& scratch() {
  static const ScratchDir dir;
  return dir.path;
}

void BM_BareIntegration(benchmark::State& bench) {
  const Scene scene = pendulum_scene(1);
  const auto& m = std::get<PendulumModel>(scene.model);
  const AttitudeLgvi<Pendulum3D> lgvi(m.system, scene.form, RotationUpdateOptions{});
  const auto control = zero_control<Vec3>();
  for (auto _ : bench) {
    AttitudeState state = lgvi.make_state(m.initial.R, m.initial.Omega);
    const Stats stats = integrate(lgvi, state, 0.0, scene.horizon.h, scene.horizon.steps, control, null_observer());
    benchmark::DoNotOptimize(state);
    benchmark::DoNotOptimize(stats.steps);
  }
  bench.SetItemsProcessed(bench.iterations() * static_cast<std::int64_t>(scene.horizon.steps));
}

void BM_Simulate(benchmark::State& bench) {
  const Scene scene = pendulum_scene(bench.range(0));
  const auto method = make_method("lgvi");
  const SimulateOptions options{scratch() / ("every-" + std::to_string(bench.range(0)) + ".csv"), "benchmark", {}};
  std::size_t rows = 0;
  for (auto _ : bench) {
    const RunSummary s = simulate(scene, *method, options);
    rows = s.csv_rows;
    benchmark::DoNotOptimize(rows);
  }
  bench.SetItemsProcessed(bench.iterations() * static_cast<std::int64_t>(scene.horizon.steps));
  bench.counters["rows"] = static_cast<double>(rows);
}

BENCHMARK(BM_BareIntegration)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Simulate)->Arg(1000)->Arg(10)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
