// Cost of one LGVI step per system and rotation-update parametrization (Google Benchmark).
// Each iteration is one step on a tumbling state; items/s is steps per second.
#include <benchmark/benchmark.h>

#include "lgvi/integrate.hpp"
#include "lgvi/composition.hpp"
#include "lgvi/lgvi.hpp"
#include "lgvi/multibody_lgvi.hpp"
#include "lgvi/systems/dumbbell.hpp"
#include "lgvi/systems/free_rigid_body.hpp"
#include "lgvi/systems/pendulum.hpp"

namespace {

using namespace lgvi;

RotationUpdateOptions with_primary(Parametrization p) {
  RotationUpdateOptions o;
  o.primary = p;
  return o;
}

template <class System>
void attitude_step(benchmark::State& bench, const System& system, const Vec3& Omega0, double h,
                   Parametrization p) {
  const AttitudeLgvi<System> lgvi(system, LgviForm::Symmetric, with_primary(p));
  auto s = lgvi.make_state(Mat3::Identity(), Omega0);
  const Vec3 u = Vec3::Zero();
  std::size_t newton = 0;
  for (auto _ : bench) {
    const RotationUpdateSummary r = lgvi.step(s, h, u, u, s);
    newton += static_cast<std::size_t>(r.iterations);
    benchmark::DoNotOptimize(s);
  }
  bench.SetItemsProcessed(bench.iterations());
  bench.counters["newton_per_step"] =
      static_cast<double>(newton) / static_cast<double>(bench.iterations());
}

void BM_PendulumStep(benchmark::State& bench) {
  attitude_step(bench, Pendulum3D::paper(), Vec3(4.14, 4.14, 4.14), 1e-3,
                static_cast<Parametrization>(bench.range(0)));
}
void BM_FreeBodyStep(benchmark::State& bench) {
  attitude_step(bench, FreeRigidBody(Vec3(0.13, 0.28, 0.17).asDiagonal()), Vec3(1.0, 2.0, -0.5),
                1e-2, static_cast<Parametrization>(bench.range(0)));
}

void BM_DumbbellStep(benchmark::State& bench) {
  const DumbbellSpacecraft dumbbell = DumbbellSpacecraft::paper();
  const DumbbellLgvi lgvi(dumbbell, LgviForm::Symmetric,
                          with_primary(static_cast<Parametrization>(bench.range(0))));
  Mat3 R0;
  R0 << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  auto s = lgvi.make_state(R0, Vec3(1, 0, 0), Vec3(0.1, -0.2, 1.3), Vec3(0.05, 0.95, 0.1));
  const DumbbellSpacecraft::Control u;
  std::size_t newton = 0;
  for (auto _ : bench) {
    const RotationUpdateSummary r = lgvi.step(s, 1e-2, u, u, s);
    newton += static_cast<std::size_t>(r.iterations);
    benchmark::DoNotOptimize(s);
  }
  bench.SetItemsProcessed(bench.iterations());
  bench.counters["newton_per_step"] =
      static_cast<double>(newton) / static_cast<double>(bench.iterations());
}

void BM_CartPendulumStep(benchmark::State& bench) {
  const CartPendulum cart = CartPendulum::paper();
  const CartPendulumLgvi lgvi(cart);
  auto s = lgvi.make_state(so3::exp(Vec3(0.5, -0.3, 0.2)), Vec2(0.1, -0.2), Vec3(1.0, -0.5, 2.0),
                           Vec2(0.3, 0.1));
  const Vec2 u = Vec2::Zero();
  std::size_t newton = 0;
  for (auto _ : bench) {
    newton += static_cast<std::size_t>(lgvi.step(s, 1e-3, u, u, s).iterations);
    benchmark::DoNotOptimize(s);
  }
  bench.SetItemsProcessed(bench.iterations());
  bench.counters["newton_per_step"] = static_cast<double>(newton) / static_cast<double>(bench.iterations());
}

void BM_ConnectedBodiesStep(benchmark::State& bench) {
  const ConnectedBodies bodies = ConnectedBodies::paper();
  const ConnectedBodiesLgvi lgvi(bodies);
  auto s = lgvi.make_state(Mat3::Identity(), so3::exp(Vec3(0.3, 0.2, -0.1)), Vec3(0.5, -0.4, 0.3),
                           Vec3(-0.2, 0.6, 0.1));
  const Vec3 u = Vec3::Zero();
  std::size_t newton = 0;
  for (auto _ : bench) {
    newton += static_cast<std::size_t>(lgvi.step(s, 1e-2, u, u, s).iterations);
    benchmark::DoNotOptimize(s);
  }
  bench.SetItemsProcessed(bench.iterations());
  bench.counters["newton_per_step"] = static_cast<double>(newton) / static_cast<double>(bench.iterations());
}

/// One composed step (all substeps) of the pendulum LGVI; argument: 0 yoshida4, 1 kahan-li6.
void BM_ComposedPendulumStep(benchmark::State& bench) {
  const Pendulum3D pendulum = Pendulum3D::paper();
  const AttitudeLgvi base(pendulum);
  const ComposedLgvi composed(base, composition_scheme(bench.range(0) == 0 ? "yoshida4" : "kahan-li6"));
  auto s = base.make_state(Mat3::Identity(), Vec3(4.14, 4.14, 4.14));
  const Vec3 u = Vec3::Zero();
  for (auto _ : bench) {
    composed.step(s, 1e-3, u, u, s);
    benchmark::DoNotOptimize(s);
  }
  bench.SetItemsProcessed(bench.iterations());
}

BENCHMARK(BM_CartPendulumStep);
BENCHMARK(BM_ConnectedBodiesStep);
BENCHMARK(BM_ComposedPendulumStep)->Arg(0)->Arg(1);

// Argument: 0 = Cayley, 1 = exponential coordinates for the rotation update.
BENCHMARK(BM_PendulumStep)->Arg(0)->Arg(1);
BENCHMARK(BM_FreeBodyStep)->Arg(0)->Arg(1);
BENCHMARK(BM_DumbbellStep)->Arg(0)->Arg(1);

}  // namespace

BENCHMARK_MAIN();
