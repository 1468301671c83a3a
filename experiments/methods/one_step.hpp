// The one-step driver: any flow map (lgvi/flow_map.hpp) run over a scene's horizon and handed to
// the recorder, and the Method of a one-step scheme over a system's continuous mechanics
// (baselines/mechanics.hpp), so that a Lie group Runge-Kutta method or a splitting joins the
// harness (simulate, studies, suites, validate, Python) as its own file plus one registry line:
//
//   struct LieEuler {                                       // experiments/methods/lie_euler.cpp
//     template <baselines::Mechanics Mech>
//     struct Flow {                                         // a FlowMap over MechanicsState<Mech>
//       using State = MechanicsState<Mech>;
//       using Control = double;                             // the step's start and end times
//       static constexpr int potential_evaluations_per_step = 1;   // accelerations per step
//       explicit Flow(const Mech& mech);
//       StepSummary step(const State& in, double h, double t_k, double t_k1, State& out) const;
//     };
//   };
//   MethodInfo lie_euler_method_info() { return mechanics_flow_method_info<LieEuler>({...traits...}); }
//
// The LGVIs run through drive_flow too (lgvi_method.cpp).
#pragma once

#include <cstddef>
#include <memory>
#include <type_traits>
#include <utility>

#include "baselines/mechanics.hpp"
#include "experiments/methods/method.hpp"
#include "experiments/methods/recorder.hpp"
#include "experiments/systems/systems.hpp"
#include "lgvi/flow_map.hpp"
#include "lgvi/integrate.hpp"

namespace lgvi::experiments {

/// Integrates `flow` from `state` over the horizon (integrate(), lgvi/integrate.hpp), handing the
/// recorder only the steps it writes: k = 0, output_every, 2 output_every, ..., and the last step
/// computed (t_final, or the last good step of a failed run). Other steps cost a comparison and
/// two stores: no sample, no conserved quantities, no clock. `to_state(flow_state, record)` writes
/// the flow's state into the system's record, `record`, the state of `sample`; `control(t)` is
/// sampled by integrate() at the grid's times.
template <FlowMap Flow, class ControlFn, class ToState, class Record>
Stats drive_flow(const Flow& flow, typename Flow::State& state, const Horizon& hz, ControlFn&& control,
                 ToState&& to_state, Sample& sample, Record& record, Recorder& recorder) {
  using State = typename Flow::State;
  std::size_t next_written = 0;  // the next k a row is written for
  int iterations_last = 0;       // iterations of the last step (a row if the run stops there)
  const auto observer = [&](std::size_t k, double t, const State& s, const auto& step_summary) {
    if (k == next_written || k == hz.steps) {
      to_state(s, record);
      sample.t = t;
      sample.newton_iterations = step_summary.iterations;
      if (!recorder.record(k, sample)) return false;  // a non-finite value: stop_on_non_finite below
      next_written += hz.output_every;
    }
    iterations_last = step_summary.iterations;
    return true;
  };
  // A shorter last step ends exactly on t_final (integrate's t_end).
  const double* t_end = hz.shorter_last_step ? &hz.t_final : nullptr;
  Stats stats = integrate(flow, state, 0.0, hz.h, hz.whole_steps(), control, observer, t_end);
  // A run stopped between written steps: `state` is its last good step k = stats.steps, at
  // t = k h (integrate's grid, from t0 = 0), and its row is still owed.
  if (stats.steps % hz.output_every != 0 && stats.steps != hz.steps) {
    to_state(std::as_const(state), record);
    sample.t = hz.time(stats.steps);
    sample.newton_iterations = iterations_last;
    (void)recorder.record(stats.steps, sample);
  }
  recorder.stop_on_non_finite(stats);
  return stats;
}

using baselines::MechanicsState;

/// Runs fn(mech, state) with the continuous mechanics of the scene's system (its binding's
/// run_baseline) and its initial MechanicsState, and hands fn a writer
/// record(state, sample-record) that fills the system's CSV record from a MechanicsState:
///   fn(const Mech& mech, MechanicsState<Mech>& state, Sample& sample, M::State& record,
///      const auto& to_state) -> Stats.
template <class Fn>
Stats with_mechanics(const Scene& scene, Fn&& fn) {
  return visit_binding(scene.model, [&](auto binding, const auto& m) {
    using Binding = decltype(binding);
    using M = std::decay_t<decltype(m)>;
    return Binding::run_baseline(m, [&](const auto& mech, const auto& R, const auto& Omega, const auto& x,
                                        const auto& v) {
      using Mech = std::decay_t<decltype(mech)>;
      MechanicsState<Mech> state;
      for (std::size_t i = 0; i < R.size(); ++i) state.config.R[i] = R[i];
      state.config.x = x;
      state.w = mech.velocity_state(state.config, Omega, v);
      Sample sample = sample_of<M>();
      typename M::State& record = state_of<M>(sample);
      const auto to_state = [&mech](const MechanicsState<Mech>& s, typename M::State& out) {
        struct {
          typename Mech::Config config;
          typename Mech::Rate rates;
        } decoded{s.config, {}};
        mech.rates(s.config, s.w, decoded.rates);
        Binding::from_chart(decoded, out);
      };
      return fn(mech, state, sample, record, to_state);
    });
  });
}

/// Whether Scheme::Flow<Mech> exists: a scheme may restrict its mechanics by a member
/// `template <class Mech> static constexpr bool applies` (the splittings: a separable
/// Hamiltonian), naming why in `static constexpr const char* applies_to_what`; otherwise it
/// applies to every system.
template <class Scheme, class Mech>
constexpr bool scheme_applies() {
  if constexpr (requires { Scheme::template applies<Mech>; }) {
    return Scheme::template applies<Mech>;
  } else {
    return true;
  }
}

/// Why Scheme::Flow<Mech> does not exist (Scheme::applies_to_what). A function, so that the
/// member is named only by schemes that restrict their mechanics (clang checks a non-dependent
/// name in a discarded branch).
template <class Scheme>
constexpr const char* scheme_restriction() {
  if constexpr (requires { Scheme::applies_to_what; }) {
    return Scheme::applies_to_what;
  } else {
    return "does not apply to this system";
  }
}

/// A Method running Scheme::Flow<Mech> (see the top of this file) over the continuous mechanics
/// of the scene's system (its binding's run_baseline), at the scene's h, with the scene's
/// controls inside the mechanics (the flow's Control is the time). A flow whose state carries
/// more than the MechanicsState (a cached force) provides make_state(mechanics_state, t0).
/// Takes no options. A system the scheme does not apply to is refused (InvalidInput "method").
template <class Scheme>
class MechanicsFlowMethod final : public Method {
 public:
  explicit MechanicsFlowMethod(std::string name) : name_(std::move(name)) {}

  std::string name() const override { return name_; }
  Fields settings(const Scene& /*scene*/) const override {
    Fields f = {{"state", std::string("R_i, x, w (mechanics)")}};
    if constexpr (requires { Scheme::description; }) f.push_back({"scheme", std::string(Scheme::description)});
    return f;
  }

  Stats run(const Scene& scene, Recorder& recorder) const override {
    return with_mechanics(scene, [&](const auto& mech, auto& state, Sample& sample, auto& record, const auto& to_state) {
      using Mech = std::decay_t<decltype(mech)>;
      if constexpr (scheme_applies<Scheme, Mech>()) {
        const typename Scheme::template Flow<Mech> flow(mech);
        const auto time = [](double t) { return t; };
        if constexpr (requires { flow.make_state(state, 0.0); }) {
          auto flow_state = flow.make_state(state, 0.0);
          return drive_flow(flow, flow_state, scene.horizon, time, to_state, sample, record, recorder);
        } else {
          return drive_flow(flow, state, scene.horizon, time, to_state, sample, record, recorder);
        }
      } else {
        throw InvalidInput("method", name_ + " " + scheme_restriction<Scheme>() + " (the scene's system: " +
                                         scene.system() + ")");
        return Stats{};
      }
    });
  }

 private:
  std::string name_;
};

/// The registration of a one-step scheme over the mechanics: `info` with its traits (name, order,
/// stages, legend, ...); the fields the driver fixes (fixed step, on the group, no coordinate
/// model, evaluations = steps x stages) and `make` (options refused) are set here.
template <class Scheme>
MethodInfo mechanics_flow_method_info(MethodInfo info) {
  info.step_control = baselines::StepControl::Fixed;
  info.models.clear();
  info.counts_evaluations = false;
  info.takes_form = false;
  info.make = [name = info.name](const MethodOptions& options) -> std::unique_ptr<Method> {
    refuse_options(name, options);
    return std::make_unique<MechanicsFlowMethod<Scheme>>(name);
  };
  return info;
}

}  // namespace lgvi::experiments
