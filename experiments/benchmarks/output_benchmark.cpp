// What output costs (Google Benchmark): the bare LGVI integration of a scene (lgvi::integrate
// with a null observer) against the whole `simulate` path (recorder, diagnostics, CSV written to
// a temporary file and renamed) at --every 1000, 10 and 1, on the same scene and horizon, and
// the parts of a row (formatting alone; formatting and writing; diagnostics). Each iteration is
// one whole run (or its 20001 rows); items/s is steps (rows) per second. The ratios of the
// simulate rows to the bare row are the cost of output.
//
// The numbers of docs/cli.md ("Cost of output") come from runs of
//   lgvi-output-benchmarks --benchmark_repetitions=5 --benchmark_enable_random_interleaving=true
// (2 cores shared with other work, under the build lock; CPU-time medians of the 5 repetitions
// interleaved at random). What bounds --every 1: 4x the bare run leaves 3 times the bare run's
// time for the 20001 rows, and formatting their numbers alone (BM_FormatRows/1/20) takes more
// than that; the rest of a recorded row (BM_RecordRows) is its diagnostics and the writing.
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <charconv>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "experiments/output/csv_writer.hpp"
#include "experiments/output/shortest.hpp"
#include "experiments/methods/method.hpp"
#include "experiments/methods/recorder.hpp"
#include "experiments/scene/scene.hpp"
#include "experiments/methods/simulate.hpp"
#include "lgvi/integrate.hpp"
#include "lgvi/lgvi.hpp"
#include "lgvi/so3.hpp"

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
    rows = s.output_rows;
    benchmark::DoNotOptimize(rows);
  }
  bench.SetItemsProcessed(bench.iterations() * static_cast<std::int64_t>(scene.horizon.steps));
  bench.counters["rows"] = static_cast<double>(rows);
}

/// The pendulum's 20001 samples of a tumble, as the LGVI would record them (R on SO(3)).
std::vector<Sample> tumbling_samples() {
  std::vector<Sample> samples(20001, sample_of<PendulumModel>());
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const double t = 1e-3 * static_cast<double>(k);
    samples[k].t = t;
    AttitudeInitial& state = state_of<PendulumModel>(samples[k]);
    state.R = so3::exp(Vec3(4.14 * t, 2.0 * std::sin(t), 0.5 * std::cos(3.0 * t)));
    state.Omega = Vec3(4.14 + std::sin(t), 4.14 * std::cos(t), 4.14);
    samples[k].newton_iterations = 2;
  }
  return samples;
}

/// The rows of BM_CsvRows and BM_FormatRows: `columns` numbers, the sample's time, then the
/// entries of its R scaled by the column's index (16 or 17 significant digits, like a
/// recorded row). 20 columns are the pendulum's row, 25 the yardstick of a row's cost.
std::vector<std::string> row_columns(std::size_t columns) { return std::vector<std::string>(columns, "c"); }
void fill_row(const Sample& s, std::vector<double>& row) {
  row[0] = s.t;
  const double* R = state_of<PendulumModel>(s).R.data();
  for (std::size_t i = 1; i < row.size(); ++i) row[i] = R[i % 9] * static_cast<double>(i);
}

/// The parts of a row: CsvWriter::write_row alone (Arg: numbers a row, formatted and written),
/// the formatting alone (BM_FormatRows), and Recorder::record (energy, momentum, orthogonality
/// and determinant errors, then the pendulum's row of 20 numbers). Each iteration writes the
/// 20001 rows of a whole --every 1 pendulum run to a temporary file (removed: no commit).
void BM_CsvRows(benchmark::State& bench) {
  const std::vector<Sample> samples = tumbling_samples();
  std::vector<double> row(static_cast<std::size_t>(bench.range(0)));
  for (auto _ : bench) {
    CsvWriter csv(scratch() / "rows.csv", row_columns(row.size()), {{"scene", std::string("pendulum")}});
    for (const Sample& s : samples) {
      fill_row(s, row);
      csv.write_row(row);
    }
  }
  bench.SetItemsProcessed(bench.iterations() * static_cast<std::int64_t>(samples.size()));
}

/// BM_CsvRows's rows (Args: formatter, numbers a row) formatted alone into a buffer reused when
/// full, no file: write_csv_numbers (1), as CsvWriter writes them, or std::to_chars (0), whose
/// bytes they are.
void BM_FormatRows(benchmark::State& bench) {
  const std::vector<Sample> samples = tumbling_samples();
  std::vector<double> row(static_cast<std::size_t>(bench.range(1)));
  std::vector<char> buffer(CsvWriter::kRowBufferSize);
  const bool shortest = bench.range(0) == 1;
  for (auto _ : bench) {
    char* p = buffer.data();
    for (const Sample& s : samples) {
      fill_row(s, row);
      if (buffer.data() + buffer.size() - p < 2048) p = buffer.data();
      if (shortest) {
        p = write_csv_numbers(p, row);
        continue;
      }
      for (const double x : row) {
        p = std::to_chars(p, p + kShortestRoom, x).ptr;
        *p++ = ',';
      }
      p[-1] = '\n';
    }
    benchmark::DoNotOptimize(buffer.data());
    benchmark::ClobberMemory();
  }
  bench.SetItemsProcessed(bench.iterations() * static_cast<std::int64_t>(samples.size()));
}

void BM_RecordRows(benchmark::State& bench) {
  const Scene scene = pendulum_scene(1);
  const std::vector<Sample> samples = tumbling_samples();
  for (auto _ : bench) {
    CsvWriter csv(scratch() / "rows.csv", Recorder::columns(scene.model), {{"scene", scene.name}});
    Recorder recorder(scene.model, 1, &csv);
    for (std::size_t k = 0; k < samples.size(); ++k) recorder.record(k, samples[k]);
    recorder.finish();
  }
  bench.SetItemsProcessed(bench.iterations() * static_cast<std::int64_t>(samples.size()));
}

BENCHMARK(BM_BareIntegration)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CsvRows)->Arg(20)->Arg(25)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FormatRows)->Args({0, 25})->Args({1, 20})->Args({1, 25})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RecordRows)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Simulate)->Arg(1000)->Arg(10)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
