// Cost of one step per system and method (Google Benchmark), side by side:
//   lgvi-cayley, lgvi-exponential      the LGVI step (rotation update in that chart);
//   reference-cayley, ...              the same step with the pre-optimization solver
//                                      (tests/lgvi/reference_rotation_update.hpp), so that one
//                                      run measures before and after;
//   rk4-quaternion, rk4-matrix         the yardsticks: one classical RK4 step of the quaternion
//                                      model and of the rotation-matrix model of the same system
//                                      (quaternion_rk4.hpp, matrix_rk4.hpp), same state, same h,
//                                      written for speed and compiled as the LGVI step is;
//   lgvi-minimal                       the floor: the same LGVI step (Cayley) written minimal
//                                      (minimal_lgvi.hpp; test_minimal_lgvi.cpp checks it
//                                      agrees with lgvi-cayley to round-off);
//   (multibody) rk4-quaternion, rkmk4  their yardsticks: one RK4 step of the quaternion model in
//                                      momentum form and one Lie group RK4 step of the same
//                                      equations (register_momentum_form);
//   lie-euler, rkmk2, rkmk4, cg3,      one step of each Lie group method (baselines/lie_group.hpp)
//   cg4, cf4                           over the system's continuous mechanics, same state, same h;
//   splitting-dlm, splitting-exact,    one step of each symplectic method (baselines/splitting.hpp),
//   nosquish, rattle                   same state, same h.
// Each iteration is one step along a trajectory from the same initial state; items/s is steps
// per second, newton_per_step the rotation update's Newton iterations per step (the polishing
// step included, as RotationUpdateSummary counts them). After the runs a table gives the CPU
// time per step (the median over repetitions when there are several) and its ratios, computed in
// this one process, to the three yardsticks of the same system and to the reference. Before
// that, each system's RK4 and LGVI trajectories over 1000 steps are compared, to show that all
// integrate the same equations (they differ by the methods' O(h^2) and O(h^4) errors).
//
// The table of the docs comes from one run of
//   ./build/experiments/benchmarks/lgvi-benchmarks --benchmark_repetitions=9
//     --benchmark_enable_random_interleaving=true
// (on the shared development machine under `flock /tmp/lgvi-build.lock`, so that no build runs
// beside it): the repetitions interleaved at random, so that a slow spell of the machine spreads
// over all methods rather than landing on one, and CPU time, so that preemption is not counted.
//
// Instructions per step, which do not depend on the machine's load (this VM exposes no hardware
// counters): `--count-instructions=N` runs N steps of each attitude case's LGVI (Cayley), minimal
// LGVI and RK4 yardsticks, each in its own instance of steps_of<Stepper>, and nothing else.
// Under callgrind
//   valgrind --tool=callgrind --callgrind-out-file=steps.cg
//     ./build/experiments/benchmarks/lgvi-benchmarks --count-instructions=100000
//   callgrind_annotate --inclusive=yes steps.cg | grep steps_of
// each instance's inclusive count over N is the instructions per step.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "baselines/lie_group.hpp"
#include "baselines/splitting.hpp"
#include "baselines/mechanics.hpp"
#include "baselines/model.hpp"
#include "lgvi/composition.hpp"
#include "lgvi/lgvi.hpp"
#include "lgvi/multibody_lgvi.hpp"
#include "lgvi/systems/dumbbell.hpp"
#include "lgvi/systems/free_rigid_body.hpp"
#include "lgvi/systems/pendulum.hpp"
#include "matrix_rk4.hpp"
#include "minimal_lgvi.hpp"
#include "quaternion_rk4.hpp"
#include "step_cases.hpp"
#include "tests/lgvi/reference_rotation_update.hpp"

namespace {

using namespace lgvi;
using benchmarks::AttitudeCase;
using benchmarks::MatrixRk4;
using benchmarks::MinimalLgvi;
using benchmarks::QuaternionRk4;
namespace lg = baselines::lie_group;

RotationUpdateOptions with_primary(Parametrization p) {
  RotationUpdateOptions o;
  o.primary = p;
  return o;
}

/// The benchmarks' names in the order they were registered: the closing table's row order (the
/// runs arrive shuffled under --benchmark_enable_random_interleaving).
std::vector<std::string>& registration_order() {
  static std::vector<std::string> names;
  return names;
}

/// benchmark::RegisterBenchmark, recording the name.
template <class Fn>
void register_step(const std::string& name, Fn&& fn) {
  registration_order().push_back(name);
  benchmark::RegisterBenchmark(name.c_str(), std::forward<Fn>(fn));
}

/// Steps `step(s)` (returning the summary) once per benchmark iteration; counts Newton iterations.
template <class State, class Step>
void run_steps(benchmark::State& bench, State s, Step&& step) {
  std::size_t newton = 0;
  for (auto _ : bench) {
    const RotationUpdateSummary r = step(s);
    if (!r.converged()) {
      bench.SkipWithError(r.brief().c_str());
      break;
    }
    newton += static_cast<std::size_t>(r.iterations);
    benchmark::DoNotOptimize(s);
  }
  bench.SetItemsProcessed(bench.iterations());
  bench.counters["newton_per_step"] =
      static_cast<double>(newton) / static_cast<double>(std::max<benchmark::IterationCount>(bench.iterations(), 1));
}

/// The case's initial state as a MechanicsState of its attitude mechanics.
template <class Mech, class System>
baselines::MechanicsState<Mech> mechanics_start(const AttitudeCase<System>& c) {
  baselines::MechanicsState<Mech> s;
  s.config.R[0] = c.R0;
  s.w = c.Omega0;
  return s;
}

/// Steps a flow over a system's mechanics (baselines/lie_group.hpp, baselines/splitting.hpp) from
/// `s` at step h.
template <class Flow, class State>
void run_flow_steps(benchmark::State& bench, const Flow& flow, State s, double h) {
  double t = 0.0;
  for (auto _ : bench) {
    flow.step(s, h, t, t + h, s);
    t += h;
    benchmark::DoNotOptimize(s);
  }
  bench.SetItemsProcessed(bench.iterations());
}

template <class System, class Tableau, template <class, class> class FlowOf>
void register_lie_group(const AttitudeCase<System>& c, const char* name) {
  register_step(c.name + "/" + name, [c](benchmark::State& bench) {
    using Mech = baselines::AttitudeMechanics<System>;
    const Mech mech(c.system);
    run_flow_steps(bench, FlowOf<Mech, Tableau>(mech), mechanics_start<Mech>(c), c.h);
  });
}

/// Steps a symplectic method's flow (baselines/splitting.hpp) over the case's attitude mechanics.
template <template <class> class FlowOf, class System>
void register_splitting(const AttitudeCase<System>& c, const char* name) {
  register_step(c.name + "/" + name, [c](benchmark::State& bench) {
    using Mech = baselines::AttitudeMechanics<System>;
    const Mech mech(c.system);
    const FlowOf<Mech> flow(mech);
    run_flow_steps(bench, flow, flow.make_state(mechanics_start<Mech>(c), 0.0), c.h);
  });
}

/// Steps an RK4 yardstick (quaternion_rk4.hpp, matrix_rk4.hpp) from the case's state.
template <class Rk4, class System>
void register_yardstick(const AttitudeCase<System>& c, const char* name) {
  register_step(c.name + "/" + name, [c](benchmark::State& bench) {
    const Rk4 rk4(c.system);
    auto s = rk4.make_state(c.R0, c.Omega0);
    for (auto _ : bench) {
      rk4.step(s, c.h);
      benchmark::DoNotOptimize(s);
    }
    bench.SetItemsProcessed(bench.iterations());
  });
}

template <class System>
void register_attitude(const AttitudeCase<System>& c) {
  for (const Parametrization p : {Parametrization::Cayley, Parametrization::Exponential}) {
    register_step(c.name + "/lgvi-" + to_string(p), [c, p](benchmark::State& bench) {
      const AttitudeLgvi<System> lgvi(c.system, LgviForm::Symmetric, with_primary(p));
      const Vec3 u = Vec3::Zero();
      run_steps(bench, lgvi.make_state(c.R0, c.Omega0),
                [&](AttitudeState& s) { return lgvi.step(s, c.h, u, u, s); });
    });
    register_step(c.name + "/reference-" + to_string(p), [c, p](benchmark::State& bench) {
      const AttitudeLgvi<System> lgvi(c.system, LgviForm::Symmetric, with_primary(p));
      const reference::RotationUpdateSolver solver(c.system.inertia, with_primary(p));
      const Vec3 u = Vec3::Zero();
      run_steps(bench, lgvi.make_state(c.R0, c.Omega0), [&](AttitudeState& s) {
        return reference::attitude_step(c.system, LgviForm::Symmetric, solver, s, c.h, u, u, s);
      });
    });
  }
  register_yardstick<QuaternionRk4<System>>(c, "rk4-quaternion");
  register_yardstick<MatrixRk4<System>>(c, "rk4-matrix");
  register_step(c.name + "/lgvi-minimal", [c](benchmark::State& bench) {
    const MinimalLgvi<System> lgvi(c.system);
    auto s = lgvi.make_state(c.R0, c.Omega0);
    std::size_t newton = 0;
    for (auto _ : bench) {
      const int iterations = lgvi.step(s, c.h);
      if (iterations < 0) {
        bench.SkipWithError("the minimal LGVI's Newton iteration did not converge");
        break;
      }
      newton += static_cast<std::size_t>(iterations);
      benchmark::DoNotOptimize(s);
    }
    bench.SetItemsProcessed(bench.iterations());
    bench.counters["newton_per_step"] =
        static_cast<double>(newton) / static_cast<double>(std::max<benchmark::IterationCount>(bench.iterations(), 1));
  });
  register_lie_group<System, lg::EulerTableau, lg::RkmkFlow>(c, "lie-euler");
  register_lie_group<System, lg::HeunTableau, lg::RkmkFlow>(c, "rkmk2");
  register_lie_group<System, lg::ClassicalRk4Tableau, lg::RkmkFlow>(c, "rkmk4");
  register_lie_group<System, lg::CrouchGrossman3Tableau, lg::CrouchGrossmanFlow>(c, "cg3");
  register_lie_group<System, lg::CrouchGrossman4aTableau, lg::CrouchGrossmanFlow>(c, "cg4");
  register_step(c.name + "/cf4", [c](benchmark::State& bench) {
    using Mech = baselines::AttitudeMechanics<System>;
    const Mech mech(c.system);
    run_flow_steps(bench, lg::CommutatorFree4Flow<Mech>(mech), mechanics_start<Mech>(c), c.h);
  });
  register_splitting<baselines::splitting::DlmFlow>(c, "splitting-dlm");
  register_splitting<baselines::splitting::ExactFreeFlow>(c, "splitting-exact");
  register_splitting<baselines::splitting::NoSquishFlow>(c, "nosquish");
  register_splitting<baselines::splitting::RattleFlow>(c, "rattle");
}

/// |R_lgvi - R|_F + |Omega_lgvi - Omega| after `steps` steps from the case's state, for the
/// rk4-quaternion, rk4-matrix and lgvi-minimal trajectories (R, Omega).
struct TrajectoryDifferences {
  double rk4_quaternion, rk4_matrix, lgvi_minimal;
};
template <class System>
TrajectoryDifferences trajectory_differences(const AttitudeCase<System>& c, int steps) {
  const AttitudeLgvi<System> lgvi(c.system);
  const QuaternionRk4<System> quaternion(c.system);
  const MatrixRk4<System> matrix(c.system);
  const MinimalLgvi<System> minimal(c.system);
  auto a = lgvi.make_state(c.R0, c.Omega0);
  auto b = quaternion.make_state(c.R0, c.Omega0);
  auto m = matrix.make_state(c.R0, c.Omega0);
  auto n = minimal.make_state(c.R0, c.Omega0);
  const Vec3 u = Vec3::Zero();
  const double nan = std::nan("");
  for (int k = 0; k < steps; ++k) {
    if (!lgvi.step(a, c.h, u, u, a).converged() || minimal.step(n, c.h) < 0) return {nan, nan, nan};
    quaternion.step(b, c.h);
    matrix.step(m, c.h);
  }
  const Vec3 Omega = lgvi.omega(a);
  return {(a.R - quaternion.rotation(b.q)).norm() + (Omega - b.Omega).norm(),
          (a.R - m.R).norm() + (Omega - m.Omega).norm(),
          (a.R - n.R).norm() + (Omega - minimal.omega(n)).norm()};
}

void register_dumbbell() {
  for (const Parametrization p : {Parametrization::Cayley, Parametrization::Exponential}) {
    const auto make = [](const DumbbellLgvi& lgvi) {
      Mat3 R0;
      R0 << 0, -1, 0, 1, 0, 0, 0, 0, 1;
      return lgvi.make_state(R0, Vec3(1, 0, 0), Vec3(0.1, -0.2, 1.3), Vec3(0.05, 0.95, 0.1));
    };
    register_step(std::string("dumbbell/lgvi-") + to_string(p),
                  [p, make](benchmark::State& bench) {
      const DumbbellSpacecraft dumbbell = DumbbellSpacecraft::paper();
      const DumbbellLgvi lgvi(dumbbell, LgviForm::Symmetric, with_primary(p));
      const DumbbellSpacecraft::Control u;
      run_steps(bench, make(lgvi), [&](RigidBodyState& s) { return lgvi.step(s, 1e-2, u, u, s); });
    });
    register_step(std::string("dumbbell/reference-") + to_string(p),
                  [p, make](benchmark::State& bench) {
      const DumbbellSpacecraft dumbbell = DumbbellSpacecraft::paper();
      const DumbbellLgvi lgvi(dumbbell, LgviForm::Symmetric, with_primary(p));
      const reference::RotationUpdateSolver solver(dumbbell.inertia, with_primary(p));
      const DumbbellSpacecraft::Control u;
      run_steps(bench, make(lgvi), [&](RigidBodyState& s) {
        return reference::dumbbell_step(dumbbell, LgviForm::Symmetric, solver, s, 1e-2, u, u, s);
      });
    });
  }
}

/// The yardsticks of a multibody system: one classical RK4 step of its quaternion model in
/// momentum form (baselines/model.hpp CoordinateOde<QuaternionChart, Mech>: fixed-size state,
/// the right-hand side the CVODE/odeint baselines integrate, one factorization of the mass matrix
/// per evaluation, called directly, not through the Ode interface) as "rk4-quaternion", and one
/// step of the Lie group RK4 (RKMK, classical tableau) over the same mechanics as "rkmk4"; from
/// the LGVI's initial state, at its h. Uncontrolled, as the LGVI steps beside them.
template <class Mech>
void register_momentum_form(const std::string& system, const Mech& mech, const std::array<Mat3, Mech::bodies>& R,
                            const std::array<Vec3, Mech::bodies>& Omega, const baselines::Vector<Mech::positions>& x,
                            const baselines::Vector<Mech::positions>& x_dot, double h) {
  using Model = baselines::CoordinateOde<baselines::QuaternionChart, Mech>;
  register_step(system + "/rk4-quaternion", [=](benchmark::State& bench) {
    const Model model(mech);
    typename Model::State y = model.initial_state(R, Omega, x, x_dot);
    typename Model::State k1, k2, k3, k4, stage;
    double t = 0.0;
    for (auto _ : bench) {
      model.Model::rhs(t, y.data(), k1.data());
      stage = y + (0.5 * h) * k1;
      model.Model::rhs(t + 0.5 * h, stage.data(), k2.data());
      stage = y + (0.5 * h) * k2;
      model.Model::rhs(t + 0.5 * h, stage.data(), k3.data());
      stage = y + h * k3;
      model.Model::rhs(t + h, stage.data(), k4.data());
      y += (h / 6.0) * (k1 + 2.0 * (k2 + k3) + k4);
      t += h;
      benchmark::DoNotOptimize(y);
    }
    bench.SetItemsProcessed(bench.iterations());
  });
  register_step(system + "/rkmk4", [=](benchmark::State& bench) {
    baselines::MechanicsState<Mech> start;
    start.config.R = R;
    start.config.x = x;
    start.w = mech.velocity_state(start.config, Omega, x_dot);
    run_flow_steps(bench, lg::RkmkFlow<Mech, lg::ClassicalRk4Tableau>(mech), start, h);
  });
}

void register_multibody() {
  // Shared by the LGVI, its reference and the yardsticks (which outlive this function's scope:
  // the benchmarks run later).
  static const CartPendulum cart = CartPendulum::paper();
  static const ConnectedBodies bodies = ConnectedBodies::paper();
  const Mat3 cart_R = so3::exp(Vec3(0.5, -0.3, 0.2));
  const Vec2 cart_q(0.1, -0.2), cart_q_dot(0.3, 0.1);
  const Vec3 cart_Omega(1.0, -0.5, 2.0);
  const auto cart_state = [=](const CartPendulumLgvi& lgvi) { return lgvi.make_state(cart_R, cart_q, cart_Omega, cart_q_dot); };
  register_step("cart-pendulum/lgvi", [cart_state](benchmark::State& bench) {
    const CartPendulumLgvi lgvi(cart);
    const Vec2 u = Vec2::Zero();
    run_steps(bench, cart_state(lgvi), [&](CartPendulumState& s) { return lgvi.step(s, 1e-3, u, u, s); });
  });
  register_step("cart-pendulum/reference", [cart_state](benchmark::State& bench) {
    const CartPendulumLgvi lgvi(cart);
    const Vec2 u = Vec2::Zero();
    run_steps(bench, cart_state(lgvi), [&](CartPendulumState& s) {
      return reference::cart_pendulum_step(cart, LgviForm::Symmetric, {}, s, 1e-3, u, u, s);
    });
  });
  register_momentum_form("cart-pendulum", baselines::CartPendulumMechanics(cart), {cart_R}, {cart_Omega}, cart_q,
                         cart_q_dot, 1e-3);
  const Mat3 bodies_R1 = Mat3::Identity(), bodies_R2 = so3::exp(Vec3(0.3, 0.2, -0.1));
  const Vec3 bodies_Omega1(0.5, -0.4, 0.3), bodies_Omega2(-0.2, 0.6, 0.1);
  const auto bodies_state = [=](const ConnectedBodiesLgvi& lgvi) {
    return lgvi.make_state(bodies_R1, bodies_R2, bodies_Omega1, bodies_Omega2);
  };
  register_step("connected-bodies/lgvi", [bodies_state](benchmark::State& bench) {
    const ConnectedBodiesLgvi lgvi(bodies);
    const Vec3 u = Vec3::Zero();
    run_steps(bench, bodies_state(lgvi),
              [&](ConnectedBodiesState& s) { return lgvi.step(s, 1e-2, u, u, s); });
  });
  register_step("connected-bodies/reference", [bodies_state](benchmark::State& bench) {
    const ConnectedBodiesLgvi lgvi(bodies);
    const Vec3 u = Vec3::Zero();
    run_steps(bench, bodies_state(lgvi), [&](ConnectedBodiesState& s) {
      return reference::connected_bodies_step(bodies, LgviForm::Symmetric, {}, s, 1e-2, u, u, s);
    });
  });
  register_momentum_form("connected-bodies", baselines::ConnectedBodiesMechanics(bodies), {bodies_R1, bodies_R2},
                         {bodies_Omega1, bodies_Omega2}, baselines::Vector<0>(), baselines::Vector<0>(), 1e-2);
}

/// One composed step (all substeps) of the pendulum LGVI.
void register_composed() {
  for (const char* scheme : {"yoshida4", "kahan-li6"}) {
    register_step(std::string("pendulum-composed/") + scheme,
                  [scheme](benchmark::State& bench) {
      const Pendulum3D pendulum = Pendulum3D::paper();
      const AttitudeLgvi base(pendulum);
      const ComposedLgvi composed(base, composition_scheme(scheme));
      auto s = base.make_state(Mat3::Identity(), Vec3(4.14, 4.14, 4.14));
      const Vec3 u = Vec3::Zero();
      for (auto _ : bench) {
        composed.step(s, 1e-3, u, u, s);
        benchmark::DoNotOptimize(s);
      }
      bench.SetItemsProcessed(bench.iterations());
    });
  }
}

/// The console output plus a summary table: per benchmark "system/method", the CPU time per step
/// (the median over the repetitions when --benchmark_repetitions > 1), its ratios to the system's
/// yardsticks "system/rk4-quaternion", "system/rk4-matrix", "system/lgvi-minimal" and to
/// "system/reference-<chart>" (or "system/reference"), and the Newton iterations per step; rows in
/// the order of registration.
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& r : runs) {
      if (r.error_occurred) continue;
      const bool aggregate = r.run_type == Run::RT_Aggregate;
      if (aggregate && r.aggregate_name != "median") continue;
      if (!aggregate && r.repetitions > 1) continue;
      Row& row = rows_[r.run_name.function_name];
      row.ns = r.GetAdjustedCPUTime() * time_unit_to_ns(r.time_unit);
      const auto it = r.counters.find("newton_per_step");
      row.newton = it == r.counters.end() ? -1.0 : static_cast<double>(it->second);
    }
  }

  void Finalize() override {
    ConsoleReporter::Finalize();
    std::printf("\n%-34s %12s %10s %10s %10s %12s %7s\n", "step", "CPU ns/step", "/ rk4-quat",
                "/ rk4-mat", "/ minimal", "/ reference", "newton");
    for (const std::string& name : registration_order()) {
      const auto it = rows_.find(name);
      if (it == rows_.end()) continue;  // filtered out, or failed
      const Row& row = it->second;
      const std::string system = name.substr(0, name.find('/'));
      const std::string method = name.substr(name.find('/') + 1);
      const bool has_reference = method.rfind("lgvi", 0) == 0 && method != "lgvi-minimal";
      std::printf("%-34s %12.1f %10s %10s %10s %12s %7s\n", name.c_str(), row.ns,
                  ratio(row.ns, system + "/rk4-quaternion").c_str(),
                  ratio(row.ns, system + "/rk4-matrix").c_str(),
                  ratio(row.ns, system + "/lgvi-minimal").c_str(),
                  has_reference ? ratio(row.ns, system + "/reference" + method.substr(4)).c_str() : "",
                  row.newton >= 0.0 ? format("%.2f", row.newton).c_str() : "");
    }
  }

 private:
  struct Row {
    double ns = 0.0;
    double newton = -1.0;
  };
  static double time_unit_to_ns(benchmark::TimeUnit u) {
    switch (u) {
      case benchmark::kNanosecond: return 1.0;
      case benchmark::kMicrosecond: return 1e3;
      case benchmark::kMillisecond: return 1e6;
      case benchmark::kSecond: return 1e9;
    }
    return 1.0;
  }
  static std::string format(const char* fmt, double x) {
    char buf[64];
    std::snprintf(buf, sizeof buf, fmt, x);
    return buf;
  }
  std::string ratio(double ns, const std::string& denominator) const {
    const auto it = rows_.find(denominator);
    return it == rows_.end() || it->second.ns <= 0.0 ? "" : format("%.2f", ns / it->second.ns);
  }
  std::map<std::string, Row> rows_;
};

/// N steps from `s` by `step_once(s)` (false: the step failed) for --count-instructions: one
/// instance per stepper type, so that callgrind counts each apart. Returns the number of steps
/// taken.
template <class Stepper, class State, class StepOnce>
[[gnu::noinline]] long steps_of(const Stepper& /*names the instance*/, State s, long n,
                                StepOnce&& step_once) {
  for (long k = 0; k < n; ++k) {
    if (!step_once(s)) return k;
    benchmark::DoNotOptimize(s);
  }
  return n;
}

/// --count-instructions=N: N steps of each attitude case's LGVI (Cayley), minimal LGVI and RK4
/// yardsticks, and nothing else.
template <class System>
void count_steps(const AttitudeCase<System>& c, long n) {
  const AttitudeLgvi<System> lgvi(c.system);
  const MinimalLgvi<System> minimal(c.system);
  const QuaternionRk4<System> quaternion(c.system);
  const MatrixRk4<System> matrix(c.system);
  const Vec3 u = Vec3::Zero();
  const long taken[] = {
      steps_of(lgvi, lgvi.make_state(c.R0, c.Omega0), n,
               [&](AttitudeState& s) { return lgvi.step(s, c.h, u, u, s).converged(); }),
      steps_of(minimal, minimal.make_state(c.R0, c.Omega0), n,
               [&](AttitudeState& s) { return minimal.step(s, c.h) >= 0; }),
      steps_of(quaternion, quaternion.make_state(c.R0, c.Omega0), n, [&](auto& s) {
        quaternion.step(s, c.h);
        return true;
      }),
      steps_of(matrix, matrix.make_state(c.R0, c.Omega0), n, [&](auto& s) {
        matrix.step(s, c.h);
        return true;
      })};
  std::printf("%s: steps taken: lgvi-cayley %ld, lgvi-minimal %ld, rk4-quaternion %ld, rk4-matrix %ld\n",
              c.name.c_str(), taken[0], taken[1], taken[2], taken[3]);
}

}  // namespace

int main(int argc, char** argv) {
  const std::string count_flag = "--count-instructions=";
  if (argc == 2 && std::string(argv[1]).rfind(count_flag, 0) == 0) {
    const std::string value = std::string(argv[1]).substr(count_flag.size());
    char* end = nullptr;
    const long n = std::strtol(value.c_str(), &end, 10);
    if (value.empty() || *end != '\0' || n <= 0) {
      std::fprintf(stderr, "%s: --count-instructions wants a positive number of steps, not '%s'\n",
                   argv[0], value.c_str());
      return 2;
    }
    count_steps(benchmarks::free_body_case(), n);
    count_steps(benchmarks::pendulum_case(), n);
    return 0;
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;

  const AttitudeCase<FreeRigidBody> free_body = benchmarks::free_body_case();
  const AttitudeCase<Pendulum3D> pendulum = benchmarks::pendulum_case();
  std::printf("|R - R_lgvi|_F + |Omega - Omega_lgvi| after 1000 steps from the same state, against\n"
              "the LGVI (Cayley): the RK4s differ by O(h^2), the minimal LGVI by round-off:\n");
  const TrajectoryDifferences free_body_differences = trajectory_differences(free_body, 1000);
  const TrajectoryDifferences pendulum_differences = trajectory_differences(pendulum, 1000);
  for (const auto& [name, d] : {std::pair{"free-body (h = 1e-2)", free_body_differences},
                                std::pair{"pendulum (h = 1e-3)", pendulum_differences}}) {
    std::printf("  %-21s rk4-quaternion %.3g, rk4-matrix %.3g, lgvi-minimal %.3g\n", name,
                d.rk4_quaternion, d.rk4_matrix, d.lgvi_minimal);
  }

  register_attitude(free_body);
  register_attitude(pendulum);
  register_dumbbell();
  register_multibody();
  register_composed();

  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();
  return 0;
}
