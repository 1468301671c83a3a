// The LGVI as a Method: the flow map of the scene's system (its binding's run_lgvi,
// experiments/systems/: AttitudeLgvi, DumbbellLgvi, CartPendulumLgvi, ConnectedBodiesLgvi), in
// the scene's form (symmetric or printed).
// The composed LGVIs of order 4 and 6 (lgvi/composition.hpp) are the methods "lgvi-SCHEME"
// (lgvi-yoshida4, lgvi-suzuki4, lgvi-yoshida6, lgvi-kahan-li6): the same flow map in its
// symmetric form, composed with the scheme's substeps; they need a symmetric scene form.
#include <optional>
#include <type_traits>
#include <utility>

#include "baselines/solver.hpp"
#include "experiments/method.hpp"
#include "experiments/system_bindings.hpp"
#include "lgvi/composition.hpp"
#include "lgvi/lgvi.hpp"
#include "lgvi/multibody_lgvi.hpp"

namespace lgvi::experiments {

namespace {

constexpr const char* kComposedPrefix = "lgvi-";

class LgviMethod final : public Method {
 public:
  explicit LgviMethod(RotationUpdateOptions options, std::optional<CompositionScheme> scheme = std::nullopt)
      : options_(options), scheme_(scheme) {}

  std::string name() const override { return scheme_ ? kComposedPrefix + std::string(scheme_->name) : "lgvi"; }

  Fields settings(const Scene& scene) const override {
    Fields f = {{"form", std::string(to_string(scene.form))},
                {"rotation_update_tolerance", options_.relative_tolerance}};
    if (scheme_) {
      f.push_back({"composition", std::string(scheme_->name)});
      f.push_back({"order", std::int64_t{scheme_->order}});
      f.push_back({"stages", static_cast<std::int64_t>(scheme_->gammas.size())});
    }
    return f;
  }

  Stats run(const Scene& scene, Recorder& recorder) const override {
    if (scheme_ && scene.form != LgviForm::Symmetric) {
      throw InvalidInput("form", name() + " composes the symmetric LGVI: scene '" + scene.name +
                                     "' asks for the " + to_string(scene.form) + " form");
    }
    // The system's flow map, initial state, control and sample come from its binding.
    return visit_binding(scene.model, [&](auto binding, const auto& m) {
      using M = std::decay_t<decltype(m)>;
      Sample sample = sample_of<M>();
      typename M::State& record = state_of<M>(sample);
      return decltype(binding)::run_lgvi(m, scene.form, options_, [&](const auto& lgvi, auto& state, auto&& control,
                                                                    auto&& to_state) {
        return drive(lgvi, state, scene.horizon, control, to_state, sample, record, recorder);
      });
    });
  }

 private:
  /// integrate() with the flow map itself, or with its composition when a scheme is set, handing
  /// the recorder only the steps it writes: k = 0, output_every, 2 output_every, ..., and the last
  /// step computed (t_final, or the last good step of a failed run). Other steps cost a
  /// comparison and two stores: no sample, no conserved quantities, no clock. `to_state(state,
  /// record)` writes the flow's state into the system's record, `record`, the state of `sample`.
  template <class Base, class State, class ControlFn, class ToState, class Record>
  Stats drive(const Base& base, State& state, const Horizon& hz, ControlFn&& control, ToState&& to_state,
              Sample& sample, Record& record, Recorder& recorder) const {
    std::size_t next_written = 0;  // the next k a row is written for
    int iterations_last = 0;       // Newton iterations of the last step (a row if the run stops there)
    const auto observer = [&](std::size_t k, double t, const State& s, const RotationUpdateSummary& r) {
      if (k == next_written || k == hz.steps) {
        to_state(s, record);
        sample.t = t;
        sample.newton_iterations = r.iterations;
        if (!recorder.record(k, sample)) return false;  // a non-finite value: stop_on_non_finite below
        next_written += hz.output_every;
      }
      iterations_last = r.iterations;
      return true;
    };
    Stats stats;
    // A shorter last step ends exactly on t_final (integrate's t_end).
    const double* t_end = hz.shorter_last_step ? &hz.t_final : nullptr;
    if (scheme_) {
      const ComposedLgvi<Base> composed(base, *scheme_);
      stats = integrate(composed, state, 0.0, hz.h, hz.whole_steps(), control, observer, t_end);
    } else {
      stats = integrate(base, state, 0.0, hz.h, hz.whole_steps(), control, observer, t_end);
    }
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

  RotationUpdateOptions options_;
  std::optional<CompositionScheme> scheme_;
};

/// The LGVI, composed with `scheme` when set. It takes no coordinate model and no tolerances (h
/// comes from the scene).
std::unique_ptr<Method> make_lgvi(std::optional<CompositionScheme> scheme, const MethodOptions& options) {
  if (options.model) throw InvalidInput("model", "the LGVI works on SO(3) itself: it takes no coordinate model");
  if (options.rtol || options.atol) {
    throw InvalidInput(options.rtol ? "rtol" : "atol", "the LGVI is a fixed-step method (h from the scene)");
  }
  return std::make_unique<LgviMethod>(options.rotation_update.value_or(RotationUpdateOptions{}), scheme);
}

}  // namespace

MethodInfo lgvi_method_info() {
  return {"lgvi", MethodFamily::Lgvi, 2, 1, baselines::StepControl::Fixed, false, {}, false, true, "LGVI order 2",
          [](const MethodOptions& options) { return make_lgvi(std::nullopt, options); }};
}

MethodInfo composed_lgvi_method_info(const char* scheme) {
  const CompositionScheme s = composition_scheme(scheme);
  return {kComposedPrefix + std::string(s.name),
          MethodFamily::ComposedLgvi,
          s.order,
          s.gammas.size(),
          baselines::StepControl::Fixed,
          false,
          {},
          false,
          false,
          "LGVI order " + std::to_string(s.order) + " (" + s.name + ")",
          [s](const MethodOptions& options) { return make_lgvi(s, options); }};
}

}  // namespace lgvi::experiments
