// What an ensemble costs beyond its integrations (Google Benchmark): 10^4 samples of random free
// bodies (attitude uniform on SO(3), |Omega| uniform in [0.5, 3] rad/s in a uniform direction,
// principal moments uniform in [0.2, 1] within the triangle inequality; experiments/suites/
// ensemble.hpp), each integrated by the LGVI over a short horizon. BM_EnsembleRuns/STEPS draws
// each sample, builds its scene (the scene file's table with the drawn values, validated as a
// scene file) and integrates it; BM_Integrations/STEPS integrates the same 10^4 scenes, built
// beforehand: the sum of the ensemble's integrations. Both record as a study's cases do in
// memory (diagnostics at every output row, the two ends), writing no file. One iteration is the
// whole ensemble; the ratio of the two times is the ensemble's overhead.
//
// The numbers of docs/suites.md ("Ensembles") come from
//   lgvi-ensemble-benchmarks --benchmark_repetitions=3 --benchmark_enable_random_interleaving=true
// (under the build lock; CPU-time medians of the repetitions).
#include <benchmark/benchmark.h>

#include <memory>
#include <vector>

#include "experiments/methods/method.hpp"
#include "experiments/methods/recorder.hpp"
#include "experiments/scene/scene.hpp"
#include "experiments/suites/ensemble.hpp"

namespace {

using namespace lgvi;
using namespace lgvi::experiments;

constexpr std::uint64_t kSamples = 10000;

/// The free-body scene over STEPS steps of h = 0.01 s, its rows the two ends.
SceneOverrides overrides(std::int64_t steps) {
  SceneOverrides o;
  o.h = 0.01;
  o.t_final = 0.01 * static_cast<double>(steps);
  o.output_every = steps;
  return o;
}

struct Ensemble {
  Scene nominal;
  std::shared_ptr<const toml::table> doc;
  EnsembleLaws laws;
  explicit Ensemble(std::int64_t steps)
      : nominal(load_scene(resolve_scene("free-body", default_scenes_dir()), overrides(steps))),
        doc(std::make_shared<const toml::table>(toml::parse(*nominal.text))) {
    laws.samples = static_cast<std::int64_t>(kSamples);
    laws.seed = 1;
    laws.attitude = EnsembleLaws::Attitude::Uniform;
    laws.omega = true;
    laws.omega_norm_lo = 0.5;
    laws.omega_norm_hi = 3.0;
    laws.moments = true;
    laws.moments_lo = 0.2;
    laws.moments_hi = 1.0;
  }
};

Stats run(const Method& method, const Scene& scene) {
  Recorder recorder(scene.model, scene.horizon.output_every, nullptr, method.records_quaternion_norm());
  return method.run(scene, recorder);
}

void BM_EnsembleRuns(benchmark::State& bench) {
  const Ensemble e(bench.range(0));
  const auto method = make_method("lgvi");
  const SceneOverrides o = overrides(bench.range(0));
  for (auto _ : bench) {
    for (std::uint64_t k = 0; k < kSamples; ++k) {
      const EnsembleSample sample(e.doc, e.laws, e.nominal, k);
      const Stats stats = run(*method, sample.load(e.nominal.file, o));
      benchmark::DoNotOptimize(stats.steps);
    }
  }
  bench.SetItemsProcessed(bench.iterations() * static_cast<std::int64_t>(kSamples));
}

void BM_Integrations(benchmark::State& bench) {
  const Ensemble e(bench.range(0));
  const auto method = make_method("lgvi");
  const SceneOverrides o = overrides(bench.range(0));
  std::vector<Scene> scenes;
  for (std::uint64_t k = 0; k < kSamples; ++k) scenes.push_back(EnsembleSample(e.doc, e.laws, e.nominal, k).load(e.nominal.file, o));
  for (auto _ : bench) {
    for (const Scene& scene : scenes) {
      const Stats stats = run(*method, scene);
      benchmark::DoNotOptimize(stats.steps);
    }
  }
  bench.SetItemsProcessed(bench.iterations() * static_cast<std::int64_t>(kSamples));
}

}  // namespace

BENCHMARK(BM_EnsembleRuns)->Arg(100)->Arg(1000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Integrations)->Arg(100)->Arg(1000)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
