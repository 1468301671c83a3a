// The continuous-time baselines as Methods: a solver (baselines/solver.hpp) on a coordinate model
// (baselines/model.hpp) of the scene's system, sampled on the scene's output grid
// (t_k = k h for k = 0, output_every, 2 output_every, ..., steps), so that the CSV rows line up
// with the LGVI's. Fixed-step solvers step with the scene's h; adaptive ones with rtol/atol, over
// the whole horizon whatever the grid, interpolating the grid's times (solver.hpp): the output
// grid does not change their steps. Controls are the scene's functions of time, evaluated
// wherever the solver asks.
#include <algorithm>
#include <cstdint>
#include <type_traits>
#include <variant>

#include "baselines/mechanics.hpp"
#include "baselines/model.hpp"
#include "baselines/solver.hpp"
#include "experiments/methods/method.hpp"
#include "experiments/systems/systems.hpp"

namespace lgvi::experiments {

namespace {

using baselines::CoordinateModel;
using baselines::CoordinateOde;
using baselines::SolverSettings;
using baselines::StepControl;

class BaselineMethod final : public Method {
 public:
  BaselineMethod(const baselines::SolverInfo& info, CoordinateModel model, SolverSettings settings)
      : info_(info), model_(model), settings_(std::move(settings)) {}

  std::string name() const override { return info_.name; }

  Fields settings(const Scene& scene) const override {
    Fields f = {{"model", std::string(baselines::to_string(model_))}};
    if (info_.step_control == StepControl::Fixed) {
      f.push_back({"step", scene.horizon.h});
    } else {
      f.push_back({"rtol", *settings_.rtol});
      f.push_back({"atol", *settings_.atol});
    }
    if (info_.uses_jacobian) {
      const bool single_body =
          visit_binding(scene.model, [](auto binding, const auto&) { return decltype(binding)::single_body; });
      f.push_back({"jacobian", single_body
                                   ? std::string("analytic kinematics, central differences of the potential terms")
                                   : std::string("analytic chart kinematics, central differences of the momentum-form "
                                                 "rates and accelerations")});
    }
    // The fixed-step implicit method iterates to newton_tolerance; the adaptive ones to their rtol.
    if (info_.uses_jacobian && info_.step_control == StepControl::Fixed) {
      f.push_back({"newton_tolerance", settings_.newton_tolerance});
    }
    f.push_back({"sampling", sampling()});
    return f;
  }

  bool records_quaternion_norm() const override {
    return model_ == CoordinateModel::Quaternion || model_ == CoordinateModel::QuaternionRenormalized;
  }

  Stats run(const Scene& scene, Recorder& recorder) const override {
    // The system's continuous mechanics and initial state come from its binding.
    return visit_binding(scene.model, [&](auto binding, const auto& m) {
      return decltype(binding)::run_baseline(m, [&](const auto& mech, const auto& R, const auto& Omega, const auto& x,
                                                   const auto& v) {
        return run_chart<decltype(binding), std::decay_t<decltype(m)>>(scene, mech, R, Omega, x, v, recorder);
      });
    });
  }

 private:
  template <class Binding, class M, class Mech>
  Stats run_chart(const Scene& scene, const Mech& mech, const std::array<Mat3, Mech::bodies>& R,
                  const std::array<Vec3, Mech::bodies>& Omega,
                  const baselines::Vector<Mech::positions>& x, const baselines::Vector<Mech::positions>& v,
                  Recorder& recorder) const {
    switch (model_) {
      case CoordinateModel::Quaternion:
        return run_model<Binding, M>(scene, CoordinateOde<baselines::QuaternionChart, Mech>(mech), R, Omega, x, v, recorder);
      case CoordinateModel::QuaternionRenormalized:
        return run_model<Binding, M>(scene, CoordinateOde<baselines::QuaternionChart, Mech>(mech, true), R, Omega, x, v,
                                  recorder);
      case CoordinateModel::Euler:
        return run_model<Binding, M>(scene, CoordinateOde<baselines::EulerChart, Mech>(mech), R, Omega, x, v, recorder);
      case CoordinateModel::Matrix:
        return run_model<Binding, M>(scene, CoordinateOde<baselines::MatrixChart, Mech>(mech), R, Omega, x, v, recorder);
    }
    throw InvalidInput("model", "unknown model");
  }

  template <class Binding, class M, class Ode, std::size_t N, int NX>
  Stats run_model(const Scene& scene, const Ode& ode, const std::array<Mat3, N>& R, const std::array<Vec3, N>& Omega,
                  const baselines::Vector<NX>& x, const baselines::Vector<NX>& v, Recorder& recorder) const {
    const Horizon& hz = scene.horizon;
    const auto y0 = ode.initial_state(R, Omega, x, v);
    std::vector<std::size_t> ks = hz.output_steps();
    // A fixed-step solver ends a shorter last step exactly on t_final: an output time at the end
    // of the whole steps, not recorded (kUnrecorded), makes it step h up to there and then
    // t_final - (steps - 1) h (fixed_step_loop); adaptive ones just integrate to t_final.
    constexpr std::size_t kUnrecorded = static_cast<std::size_t>(-1);
    const bool fixed = info_.step_control == StepControl::Fixed;
    if (fixed && hz.shorter_last_step && ks[ks.size() - 2] != hz.whole_steps()) {
      ks.insert(ks.end() - 1, kUnrecorded);
    }
    std::vector<double> times;
    times.reserve(ks.size());
    for (const std::size_t k : ks) times.push_back(hz.time(k == kUnrecorded ? hz.whole_steps() : k));

    SolverSettings s = settings_;
    if (fixed) s.h = hz.h;
    if (fixed && hz.shorter_last_step) s.shorter_last_step = true;
    Sample sample = sample_of<M>();
    typename M::State& record = state_of<M>(sample);
    const auto observer = [&](std::size_t i, double t, const double* y) {
      const auto d = ode.decode(y);
      sample.t = t;
      Binding::from_chart(d, record);
      // The worse of the bodies' quaternions.
      sample.quaternion_norm_error = *std::max_element(d.quaternion_norm_error.begin(), d.quaternion_norm_error.end());
      sample.newton_iterations = 0;
      // A hidden output time (kUnrecorded: the grid point before a shorter last step) records nothing;
      // a non-finite value stops the run (stop_on_non_finite below).
      return ks[i] == kUnrecorded || recorder.record(ks[i], sample);
    };
    Stats stats = baselines::integrate(info_.name, ode, std::span<const double>(y0.data(), y0.size()), times, s, observer);
    recorder.stop_on_non_finite(stats);
    return stats;
  }

  /// How the output grid is sampled (CSV metadata "sampling").
  std::string sampling() const {
    const char* how = "";
    switch (info_.output) {
      case baselines::OutputInterpolation::FixedGrid:
        return "every output_every-th step of h";
      case baselines::OutputInterpolation::Cvode:
        how = "CVODE's interpolating polynomial (CVodeGetDky)";
        break;
      case baselines::OutputInterpolation::DenseOutput:
        how = "odeint's dense output";
        break;
      case baselines::OutputInterpolation::Arkode:
        how = "ARKODE's degree-5 Hermite interpolant (ERKStepGetDky / ARKStepGetDky)";
        break;
      case baselines::OutputInterpolation::Hermite:
        how = "the quintic Hermite interpolant of the accepted steps (y, f, y'' at their ends)";
        break;
    }
    return std::string("output grid interpolated by ") + how + "; the steps do not depend on it";
  }

  baselines::SolverInfo info_;
  CoordinateModel model_;
  SolverSettings settings_;
};

/// A trivially valid ODE of each model kind, only to check settings against a model at
/// construction (renormalization needs a post-step hook).
class ModelProbe final : public baselines::Ode {
 public:
  explicit ModelProbe(bool renormalizes) : renormalizes_(renormalizes) {}
  int dimension() const override { return 1; }
  std::string model_name() const override { return "probe"; }
  baselines::RhsStatus rhs(double, const double*, double* f) const override {
    f[0] = 0.0;
    return baselines::RhsStatus::Ok;
  }
  baselines::RhsStatus jacobian(double, const double*, double* J) const override {
    J[0] = 0.0;
    return baselines::RhsStatus::Ok;
  }
  bool time_dependent() const override { return false; }
  bool renormalizes() const override { return renormalizes_; }

 private:
  bool renormalizes_;
};

/// The baseline `info` with options: a coordinate model (default kDefaultCoordinateModel),
/// tolerances (adaptive only).
std::unique_ptr<Method> make_baseline(const baselines::SolverInfo& info, const MethodOptions& options) {
  const std::string& name = info.name;
  if (options.rotation_update) throw InvalidInput("rotation_update", name + " has no rotation update (LGVI only)");
  const CoordinateModel model = baselines::parse_coordinate_model(options.model.value_or(kDefaultCoordinateModel));
  SolverSettings settings;
  settings.rtol = options.rtol;
  settings.atol = options.atol;
  if (info.step_control == StepControl::Fixed) settings.h = 1.0;  // the scene's h replaces it in run()
  const ModelProbe probe(model == CoordinateModel::QuaternionRenormalized);
  settings = baselines::resolve_settings(info, settings, probe);
  if (info.step_control == StepControl::Fixed) settings.h.reset();
  return std::make_unique<BaselineMethod>(info, model, settings);
}

}  // namespace

MethodInfo baseline_method_info(const baselines::SolverInfo& solver) {
  std::vector<CoordinateModel> models;
  for (const std::string& m : baselines::coordinate_model_names()) {
    const CoordinateModel model = baselines::parse_coordinate_model(m);
    // Renormalizing between steps needs a post-step hook (resolve_settings rejects it otherwise).
    if (model == CoordinateModel::QuaternionRenormalized && !solver.post_step_hook) continue;
    models.push_back(model);
  }
  MethodInfo info{solver.name,
                  MethodFamily::Baseline,
                  solver.order,
                  static_cast<std::size_t>(solver.stages),
                  solver.step_control,
                  solver.uses_jacobian,
                  models,
                  true,
                  false,
                  solver.name,
                  [&solver](const MethodOptions& options) { return make_baseline(solver, options); }};
  // The systems whose mechanics give their invariants (baselines/mechanics.hpp invariants());
  // the others are refused at run time (Ode::projection_refusal).
  if (solver.projects_onto_invariants) info.systems = {"free-body", "pendulum", "dumbbell", "potential-body", "potential-body-se3"};
  return info;
}

}  // namespace lgvi::experiments
