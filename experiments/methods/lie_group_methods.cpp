// The Lie group methods of baselines/lie_group.hpp as Methods: the fixed-step ones run by the
// one-step driver (one_step.hpp) at the scene's h, rkmk45 with error control (rtol/atol like
// the adaptive baselines), its rows read off its continuous extension so that the output grid
// does not change its steps. They integrate each system's continuous mechanics (the binding's
// run_baseline), so they apply to every system.
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "baselines/lie_group.hpp"
#include "experiments/methods/one_step.hpp"

namespace lgvi::experiments {

namespace {

namespace lg = baselines::lie_group;

template <class Tableau>
struct Rkmk {
  template <baselines::Mechanics Mech>
  using Flow = lg::RkmkFlow<Mech, Tableau>;
};

template <class Tableau>
struct CrouchGrossman {
  template <baselines::Mechanics Mech>
  using Flow = lg::CrouchGrossmanFlow<Mech, Tableau>;
};

struct CommutatorFree4 {
  template <baselines::Mechanics Mech>
  using Flow = lg::CommutatorFree4Flow<Mech>;
};

template <class Scheme>
MethodInfo fixed_step(const char* name, int order, int stages, const char* legend) {
  MethodInfo info{name, MethodFamily::OneStep, order, static_cast<std::size_t>(stages), baselines::StepControl::Fixed,
                  false, {}, false, false, legend, {}};
  info.stays_on_group = true;
  return mechanics_flow_method_info<Scheme>(std::move(info));
}

class Rkmk45Method final : public Method {
 public:
  explicit Rkmk45Method(lg::Rkmk45Settings settings) : settings_(settings) {}

  std::string name() const override { return "rkmk45"; }
  Fields settings(const Scene& /*scene*/) const override {
    return {{"state", std::string("R_i, x, w (mechanics)")},
            {"rtol", settings_.rtol},
            {"atol", settings_.atol},
            {"sampling", std::string("output grid interpolated by the Dormand-Prince continuous extension in the "
                                     "chart; the steps do not depend on it")}};
  }

  Stats run(const Scene& scene, Recorder& recorder) const override {
    return with_mechanics(scene, [&](const auto& mech, auto& state, Sample& sample, auto& record, const auto& to_state) {
      const std::vector<std::size_t> ks = scene.horizon.output_steps();
      std::vector<double> times;
      times.reserve(ks.size());
      for (const std::size_t k : ks) times.push_back(scene.horizon.time(k));
      const auto observer = [&](std::size_t i, double t, const auto& y) {
        to_state(y, record);
        sample.t = t;
        sample.newton_iterations = 0;
        return recorder.record(ks[i], sample);  // false on a non-finite value: stop_on_non_finite below
      };
      Stats stats = lg::integrate_rkmk45(mech, state, times, settings_, observer);
      recorder.stop_on_non_finite(stats);
      return stats;
    });
  }

 private:
  lg::Rkmk45Settings settings_;
};

/// rkmk45 takes rtol and atol (default baselines::kDefaultRtol, atol = rtol), as the adaptive
/// baselines do, and no model or rotation update.
std::unique_ptr<Method> make_rkmk45(const MethodOptions& options) {
  if (options.model) throw InvalidInput("model", "rkmk45 works on the Lie group itself: it takes no coordinate model");
  if (options.rotation_update) throw InvalidInput("rotation_update", "rkmk45 has no rotation update (LGVI only)");
  lg::Rkmk45Settings s;
  s.rtol = options.rtol.value_or(baselines::kDefaultRtol);
  s.atol = options.atol.value_or(s.rtol);
  baselines::check_tolerance(s.rtol, "rtol");  // the adaptive baselines' range (baselines/tolerance.hpp)
  baselines::check_tolerance(s.atol, "atol");
  return std::make_unique<Rkmk45Method>(s);
}

}  // namespace

MethodInfo lie_group_method_info(const std::string& name) {
  if (name == "lie-euler") return fixed_step<Rkmk<lg::EulerTableau>>("lie-euler", 1, 1, "Lie-Euler");
  if (name == "rkmk2") return fixed_step<Rkmk<lg::HeunTableau>>("rkmk2", 2, 2, "RKMK order 2 (Heun)");
  if (name == "rkmk4") return fixed_step<Rkmk<lg::ClassicalRk4Tableau>>("rkmk4", 4, 4, "RKMK order 4");
  if (name == "cg3") return fixed_step<CrouchGrossman<lg::CrouchGrossman3Tableau>>("cg3", 3, 3, "Crouch-Grossman order 3");
  if (name == "cg4") {
    return fixed_step<CrouchGrossman<lg::CrouchGrossman4aTableau>>("cg4", 4, 5, "Crouch-Grossman order 4 (CG4a)");
  }
  if (name == "cf4") return fixed_step<CommutatorFree4>("cf4", 4, 4, "commutator-free order 4");
  if (name == "rkmk45") {
    MethodInfo info{"rkmk45", MethodFamily::OneStep, 0, 0, baselines::StepControl::Adaptive, false, {}, true, false,
                    "RKMK 5(4) (Dormand-Prince)", make_rkmk45};
    info.stays_on_group = true;
    return info;
  }
  throw std::logic_error("lie_group_method_info: no Lie group method '" + name + "'");
}

}  // namespace lgvi::experiments
