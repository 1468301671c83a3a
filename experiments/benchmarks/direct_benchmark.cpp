// Direct method (sections 4.1, 4.2): exact gradients (forward sensitivities through the
// linearized LGVI) against central finite differences, per gradient and per SLSQP solve.
// Then single shooting (SLSQP) against multiple shooting (IPOPT) and iLQR on free node controls
// (DDP, lgvi/ocp/ddp.hpp), the connected bodies' multistart; and Hermite-Simpson collocation of
// the continuous problems (lgvi/ocp/collocation.hpp). The speed targets read from this
// table: docs/paper-examples.md ("The paper's claim, measured").
// Counters: SQP iterations, LGVI simulations, final cost and violation of the solve. The ratios
// (finite-difference / exact) of wall time and iterations are reported in lgvi/ocp/README.md.
#include <benchmark/benchmark.h>

#include <string>

#include "lgvi/ocp/collocation.hpp"
#include "lgvi/ocp/ddp.hpp"
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

// One evaluation of the multiple-shooting constraints (range 0: values only; 1: with the exact
// sparse Jacobian; 2: the Jacobian alone, along the states stored by a values run), connected bodies, segments of 20 steps, geodesic references, random start 1's
// knots. The cost of a Hessian of the Lagrangian by differences of these Jacobians follows
// (README "Multiple shooting with IPOPT": 21 knot directions + 3 colours x 12 state directions).
void BM_ConnectedBodiesShootingJacobian(benchmark::State& bench) {
  using Model = ocp::ConnectedBodiesDirectModel;
  const ConnectedBodies system = ConnectedBodies::paper();
  const ocp::DirectOptions o;
  const ocp::DirectTranscription<Model> tr(system, ocp::ConnectedBodiesTransfer::paper(), o);
  const Eigen::VectorXd c = ocp::start_knots(system, o, 1);
  ocp::DirectTranscription<Model>::ShootingNodes n;
  ocp::DirectTranscription<Model>::Evaluation unused;
  tr.shooting_nodes(c, 20, ocp::ShootingStateGuess::Geodesic, n, unused);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(tr.shooting_variables(n));
  x.head(tr.parameters()) = c;
  ocp::DirectTranscription<Model>::ShootingEvaluation e;
  if (bench.range(0) == 2) {
    if (!tr.evaluate_shooting(n, x, false, e)) bench.SkipWithError("simulation failed");
    for (auto _ : bench) {
      tr.shooting_gradients(n, x, e);
      benchmark::DoNotOptimize(e.jacobian_values.data());
    }
    return;
  }
  for (auto _ : bench) {
    if (!tr.evaluate_shooting(n, x, bench.range(0) == 1, e)) bench.SkipWithError("simulation failed");
    benchmark::DoNotOptimize(e.constraints.data());
  }
}

// Single shooting (SLSQP, the paper's) against multiple shooting (IPOPT, limited-memory Hessian),
// exact gradients both. Cart-pendulum from the default guess; connected bodies as the CLI runs
// it: the 8-start multistart (seed 1), counters per run (feasible starts: violation <= 1e-10).
// Arguments: solver (0 SLSQP, 1 IPOPT), steps per shooting segment (IPOPT), initial states of
// the shooting nodes (IPOPT; 0 simulated from the start's guess control, 1 geodesic between the
// boundary states, the default).
ocp::DirectOptions solver_options(const benchmark::State& bench) {
  ocp::DirectOptions o;
  if (bench.range(0) == 1) {
    o.solver = ocp::DirectSolver::IpoptMultipleShooting;
    o.shooting_interval = static_cast<int>(bench.range(1));
    o.max_evaluations = 1000;  // the CLI's IPOPT iteration cap
    o.state_guess = bench.range(2) == 1 ? ocp::ShootingStateGuess::Geodesic : ocp::ShootingStateGuess::Simulated;
  }
  return o;
}

template <class System, class Transfer>
void multistart(benchmark::State& bench, const System& system, const Transfer& problem, const ocp::DirectOptions& o) {
  ocp::DirectSummary last;
  for (auto _ : bench) last = ocp::solve_direct(system, problem, o).summary;
  int feasible = 0;
  for (const ocp::DirectStart& st : last.starts) feasible += st.violation <= o.tolerance ? 1 : 0;
  bench.counters["starts"] = static_cast<double>(last.starts.size());
  bench.counters["feasible"] = feasible;
  bench.counters["iterations"] = last.iterations;
  bench.counters["simulations"] = static_cast<double>(last.simulations);
  bench.counters["gradients"] = last.gradient_evaluations;
  bench.counters["best_cost"] = last.cost;
  bench.counters["violation"] = last.violation;
  // Per start k: solver iterations, wall seconds, cost and violation of the returned point.
  for (std::size_t k = 0; k < last.starts.size(); ++k) {
    const ocp::DirectStart& st = last.starts[k];
    const std::string i = std::to_string(st.index);
    bench.counters["s" + i + "_iter"] = st.iterations;
    bench.counters["s" + i + "_sec"] = st.seconds;
    bench.counters["s" + i + "_cost"] = st.cost;
    bench.counters["s" + i + "_viol"] = st.violation;
  }
}

void BM_CartPendulumSolver(benchmark::State& bench) {
  multistart(bench, CartPendulum::paper(), ocp::CartPendulumTransfer::paper(), solver_options(bench));
}
void BM_ConnectedBodiesMultistart(benchmark::State& bench) {
  ocp::DirectOptions o = solver_options(bench);
  o.starts = 8;
  multistart(bench, ConnectedBodies::paper(), ocp::ConnectedBodiesTransfer::paper(), o);
}

// DDP (iLQR with the augmented Lagrangian, ddp.hpp) on the same discrete problems and starts:
// cart-pendulum from the default guess, connected bodies the 8-start multistart (seed 1).
// Counters per run: iterations (backward passes), rollouts, CPU seconds per iteration, best cost.
template <class System, class Transfer>
void ddp_multistart(benchmark::State& bench, const System& system, const Transfer& problem, const ocp::DdpOptions& o) {
  ocp::DdpSummary last;
  for (auto _ : bench) last = ocp::solve_ddp(system, problem, o).summary;
  int feasible = 0;
  for (const ocp::DdpStart& st : last.starts) feasible += st.status == ocp::DdpStatus::Converged ? 1 : 0;
  bench.counters["starts"] = static_cast<double>(last.starts.size());
  bench.counters["converged"] = feasible;
  bench.counters["iterations"] = last.iterations;
  bench.counters["outer"] = last.outer_iterations;
  bench.counters["rollouts"] = static_cast<double>(last.rollouts);
  bench.counters["cpu_s"] = last.cpu_seconds;
  bench.counters["ms_per_iter"] = last.iterations > 0 ? 1e3 * last.cpu_seconds / last.iterations : 0.0;
  bench.counters["best_cost"] = last.cost;
  bench.counters["violation"] = last.violation;
  for (const ocp::DdpStart& st : last.starts) {
    const std::string i = std::to_string(st.index);
    bench.counters["s" + i + "_iter"] = st.iterations;
    bench.counters["s" + i + "_cost"] = st.cost;
    bench.counters["s" + i + "_viol"] = st.violation;
  }
}

void BM_CartPendulumDdp(benchmark::State& bench) {
  ddp_multistart(bench, CartPendulum::paper(), ocp::CartPendulumTransfer::paper(), ocp::DdpOptions{});
}
void BM_ConnectedBodiesDdpMultistart(benchmark::State& bench) {
  ocp::DdpOptions o;
  o.starts = 8;
  ddp_multistart(bench, ConnectedBodies::paper(), ocp::ConnectedBodiesTransfer::paper(), o);
}

// Hermite-Simpson collocation of the continuous problem (collocation.hpp) with K = range(0)
// intervals from its one deterministic guess, range(1) = 0 the exact Hessian (the default), 1
// IPOPT's L-BFGS: iterations, the calling thread's CPU seconds of the solve (also the CPU
// column), cost, terminal violation (the system's norm) and max defect.
template <class System, class Transfer>
void collocation(benchmark::State& bench, const System& system, const Transfer& problem) {
  ocp::CollocationOptions o;
  o.intervals = static_cast<int>(bench.range(0));
  o.hessian = bench.range(1) == 0 ? ocp::IpoptHessian::Exact : ocp::IpoptHessian::LimitedMemory;
  ocp::CollocationSummary last;
  for (auto _ : bench) {
    last = ocp::solve_collocation(system, problem, o).summary;
    if (!last.converged()) bench.SkipWithError(last.brief().c_str());
  }
  bench.counters["iterations"] = last.iterations;
  bench.counters["cpu_s"] = last.cpu_seconds;
  bench.counters["cost"] = last.cost;
  bench.counters["violation"] = last.violation;
  bench.counters["max_defect"] = last.max_defect;
}
void BM_CartPendulumCollocation(benchmark::State& bench) {
  collocation(bench, CartPendulum::paper(), ocp::CartPendulumTransfer::paper());
}
void BM_ConnectedBodiesCollocation(benchmark::State& bench) {
  collocation(bench, ConnectedBodies::paper(), ocp::ConnectedBodiesTransfer::paper());
}
void BM_DumbbellCollocation(benchmark::State& bench) {
  collocation(bench, DumbbellSpacecraft::paper(), ocp::TransferProblem::dumbbell_paper());
}

// Argument: 0 = exact gradients, 1 = central finite differences.
BENCHMARK(BM_CartPendulumGradient)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ConnectedBodiesGradient)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CartPendulumSolve)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_ConnectedBodiesSolve)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_ConnectedBodiesShootingJacobian)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CartPendulumSolver)->Args({0, 0, 0})->Args({1, 20, 0})->Args({1, 40, 1})->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_ConnectedBodiesMultistart)
    ->Args({0, 0, 0})
    ->Args({1, 20, 0})
    ->Args({1, 20, 1})
    ->Args({1, 40, 1})
    ->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_CartPendulumDdp)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_ConnectedBodiesDdpMultistart)->Unit(benchmark::kMillisecond)->Iterations(1);
// Arguments: K intervals (the CLI's default 100; 50 and 200 the suite's 2h and h/2), the Hessian
// (0 exact, 1 L-BFGS). The dumbbell by L-BFGS (1500-1900 iterations, over 20 s) is left out.
BENCHMARK(BM_CartPendulumCollocation)
    ->Args({50, 0})->Args({100, 0})->Args({100, 1})
    ->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_ConnectedBodiesCollocation)
    ->Args({50, 0})->Args({100, 0})->Args({100, 1})
    ->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_DumbbellCollocation)->Args({50, 0})->Args({100, 0})->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
