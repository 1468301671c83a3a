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
#include "experiments/methods/method.hpp"
#include "experiments/methods/one_step.hpp"
#include "experiments/systems/systems.hpp"
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
    // The system's flow map, initial state, control and sample come from its binding; the flow
    // map itself, or its composition when a scheme is set, runs under the one-step driver.
    return visit_binding(scene.model, [&](auto binding, const auto& m) {
      using M = std::decay_t<decltype(m)>;
      Sample sample = sample_of<M>();
      typename M::State& record = state_of<M>(sample);
      return decltype(binding)::run_lgvi(m, scene.form, options_, [&](const auto& lgvi, auto& state, auto&& control,
                                                                    auto&& to_state) {
        if (scheme_) {
          const ComposedLgvi<std::decay_t<decltype(lgvi)>> composed(lgvi, *scheme_);
          return drive_flow(composed, state, scene.horizon, control, to_state, sample, record, recorder);
        }
        return drive_flow(lgvi, state, scene.horizon, control, to_state, sample, record, recorder);
      });
    });
  }

 private:
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

/// The traits every LGVI form and composition shares: a discrete variational flow on the group
/// (symmetric in its symmetric form, the composition of symmetric steps with symmetric
/// coefficients), its momentum maps kept by the discrete Noether theorem, its rotation update's
/// options and Newton iterations, and every case of the extremes suite expected to complete.
MethodInfo with_lgvi_traits(MethodInfo info) {
  info.symmetric = true;
  info.variational = true;
  info.symplectic = true;
  info.stays_on_group = true;
  info.preserves_momentum_map = true;
  info.takes_rotation_update = true;
  info.reports_step_iterations = true;
  info.must_complete_at_extremes = true;
  return info;
}

MethodInfo lgvi_method_info() {
  return with_lgvi_traits({"lgvi", MethodFamily::Lgvi, 2, 1, baselines::StepControl::Fixed, false, {}, false, true,
                           "LGVI order 2", [](const MethodOptions& options) { return make_lgvi(std::nullopt, options); }});
}

MethodInfo composed_lgvi_method_info(const char* scheme) {
  const CompositionScheme s = composition_scheme(scheme);
  return with_lgvi_traits({kComposedPrefix + std::string(s.name),
                           MethodFamily::ComposedLgvi,
                           s.order,
                           s.gammas.size(),
                           baselines::StepControl::Fixed,
                           false,
                           {},
                           false,
                           false,
                           "LGVI order " + std::to_string(s.order) + " (" + s.name + ")",
                           [s](const MethodOptions& options) { return make_lgvi(s, options); }});
}

}  // namespace lgvi::experiments
