// Direct method (sections 4.1, 4.2): exact gradients (forward sensitivities through the
// linearized LGVI) against central finite differences, per gradient and per SLSQP solve.
// Counters: SQP iterations, LGVI simulations, final cost and violation of the solve. The ratios
// (finite-difference / exact) of wall time and iterations are reported in lgvi/ocp/README.md.
#include <benchmark/benchmark.h>

#include "lgvi/ocp/direct.hpp"

namespace {

using namespace lgvi;

ocp::DirectOptions options(bool exact) {
  ocp::DirectOptions o;  // the paper's h = 0.01, 7 knots, not-a-knot, printed form
  o.gradients = exact ? ocp::GradientMethod::Exact : ocp::GradientMethod::FiniteDifference;
  return o;
}

// The connected bodies from random start 6 of the default multistart (seed 1): the start that
// reaches the lowest cost (README), so both gradient methods solve the same converging problem.
constexpr int kConnectedBodiesStart = 6;

template <class Model, class System, class Transfer>
void gradient(benchmark::State& bench, const System& system, const Transfer& problem,
              const Eigen::VectorXd& c, bool exact) {
  const ocp::DirectTranscription<Model> tr(system, problem, options(exact));
  typename ocp::DirectTranscription<Model>::Evaluation e;
  for (auto _ : bench) {
    const bool ok = exact ? tr.evaluate(c, true, e) : tr.evaluate_finite_difference(c, e);
    if (!ok) bench.SkipWithError("simulation failed");
    benchmark::DoNotOptimize(e.constraint_jacobian.data());
  }
}

void BM_CartPendulumGradient(benchmark::State& bench) {
  const CartPendulum system = CartPendulum::paper();
  gradient<ocp::CartPendulumDirectModel>(bench, system, ocp::CartPendulumTransfer::paper(),
                                         ocp::default_initial_knots(system, 7), bench.range(0) == 0);
}
void BM_ConnectedBodiesGradient(benchmark::State& bench) {
  const ConnectedBodies system = ConnectedBodies::paper();
  gradient<ocp::ConnectedBodiesDirectModel>(bench, system, ocp::ConnectedBodiesTransfer::paper(),
                                            ocp::default_initial_knots(system, 7), bench.range(0) == 0);
}

template <class System, class Transfer>
void solve(benchmark::State& bench, const System& system, const Transfer& problem, ocp::DirectOptions o) {
  ocp::DirectSummary last;
  for (auto _ : bench) {
    last = ocp::solve_direct(system, problem, o).summary;
    if (last.status != ocp::DirectStatus::Converged) bench.SkipWithError(last.brief().c_str());
  }
  bench.counters["iterations"] = last.iterations;
  bench.counters["evaluations"] = last.evaluations;
  bench.counters["simulations"] = static_cast<double>(last.simulations);
  bench.counters["cost"] = last.cost;
  bench.counters["violation"] = last.violation;
}

void BM_CartPendulumSolve(benchmark::State& bench) {
  solve(bench, CartPendulum::paper(), ocp::CartPendulumTransfer::paper(), options(bench.range(0) == 0));
}
void BM_ConnectedBodiesSolve(benchmark::State& bench) {
  const ConnectedBodies system = ConnectedBodies::paper();
  ocp::DirectOptions o = options(bench.range(0) == 0);
  o.initial_knots = ocp::start_knots(system, o, kConnectedBodiesStart);
  solve(bench, system, ocp::ConnectedBodiesTransfer::paper(), o);
}

// Argument: 0 = exact gradients, 1 = central finite differences.
BENCHMARK(BM_CartPendulumGradient)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ConnectedBodiesGradient)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CartPendulumSolve)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_ConnectedBodiesSolve)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
