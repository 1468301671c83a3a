// The Poisson-structure defect of a one-step map (structure_defect.hpp: the coordinates, the
// tensors, the finite differences and their floor).
#include "experiments/methods/structure_defect.hpp"

#include <Eigen/SVD>

#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>
#include <variant>

#include "experiments/methods/recorder.hpp"
#include "experiments/systems/systems.hpp"
#include "lgvi/so3.hpp"

namespace lgvi::experiments {

namespace {

/// The scene's attitude state and inertia, for the systems measured here (uncontrolled free body
/// without orbit, uncontrolled pendulum); InvalidInput("system", ...) for any other scene.
AttitudeInitial& probed_initial(Model& model) {
  if (auto* m = std::get_if<FreeBodyModel>(&model)) {
    if (m->control || m->feedback) {
      throw InvalidInput("system", "the free body is controlled: a moment given as a function of time or state is "
                                   "not Hamiltonian, no Poisson structure to measure");
    }
    if (m->gravity_gradient) {
      throw InvalidInput("system", "the free body on an orbit (orbit_rate) has a time-dependent potential: not measured");
    }
    return m->initial;
  }
  if (auto* m = std::get_if<PendulumModel>(&model)) {
    if (m->control || m->feedback) {
      throw InvalidInput("system", "the pendulum is controlled: a moment given as a function of time or state is not "
                                   "Hamiltonian, no Poisson structure to measure");
    }
    return m->initial;
  }
  throw InvalidInput("system", std::string("the structure defect is measured on the free-body and the pendulum only "
                                           "(the scene's system: ") + system_name(model) + ")");
}

const Inertia& probed_inertia(const Model& model) {
  if (const auto* m = std::get_if<FreeBodyModel>(&model)) return m->system.inertia;
  return std::get<PendulumModel>(model).system.inertia;
}

/// The rotation nearest a near-rotation X (its polar factor), by Newton's X <- (X + X^-T) / 2,
/// which converges quadratically from ||X^T X - I|| < 1: a quaternion baseline's attitude
/// |q|^2 Q(q / |q|) (baselines/coordinates.hpp) becomes Q(q / |q|), so that its output chart reads
/// the rotation and not the quaternion's norm drift. Four steps take an orthogonality error of
/// 1e-3 below round-off; on a rotation they change it by round-off only.
Mat3 nearest_rotation(Mat3 X) {
  for (int i = 0; i < 4; ++i) X = 0.5 * (X + X.inverse().transpose());
  return X;
}

/// B(p) = [[0, I], [-I, hat(p)]], the canonical Poisson tensor of T*SO(3) at a chart centre,
/// momentum in units of s.
Mat6 canonical_tensor(const Vec3& p) {
  Mat6 B = Mat6::Zero();
  B.block<3, 3>(0, 3) = Mat3::Identity();
  B.block<3, 3>(3, 0) = -Mat3::Identity();
  B.block<3, 3>(3, 3) = so3::hat(p);
  return B;
}

/// One step of `method` from the perturbed states of a scene: y(z) of structure_defect.hpp.
class StepProbe {
 public:
  StepProbe(const Scene& scene, const Method& method, const StructureDefectOptions& options)
      : scene_(scene), method_(method), initial_(probed_initial(scene_.model)), inertia_(probed_inertia(scene_.model)) {
    scene_.horizon = make_horizon(scene.horizon.h, scene.horizon.h, 1);
    R0_ = initial_.R;
    Pi0_ = inertia_.J * initial_.Omega;
    s_ = options.momentum_scale > 0.0 ? options.momentum_scale : Pi0_.norm();
    if (!(s_ > 0.0)) s_ = inertia_.J.norm() / scene.horizon.h;  // at rest: one radian per step
    run(Vec6::Zero(), R_nominal_, Pi_nominal_);
  }

  /// The output chart's coordinates y = (log(R_nom^T R), (Pi - Pi_nom) / s) of the step from
  /// z = (xi, dPi / s) about the scene's initial state.
  Vec6 operator()(const Vec6& z) {
    Mat3 R;
    Vec3 Pi;
    run(z, R, Pi);
    Vec6 y;
    y.head<3>() = so3::log(R_nominal_.transpose() * R);
    y.tail<3>() = (Pi - Pi_nominal_) / s_;
    return y;
  }

  double momentum_scale() const { return s_; }
  Vec3 p_in() const { return Pi0_ / s_; }
  Vec3 p_out() const { return Pi_nominal_ / s_; }
  std::size_t evaluations() const { return evaluations_; }

 private:
  void run(const Vec6& z, Mat3& R, Vec3& Pi) {
    initial_.R = R0_ * so3::exp(Vec3(z.head<3>()));
    initial_.Omega = inertia_.J_inverse * (Pi0_ + s_ * z.tail<3>());
    Recorder recorder(scene_.model, 1, nullptr, method_.records_quaternion_norm());
    const Stats stats = method_.run(scene_, recorder);
    ++evaluations_;
    if (!stats.ok() || recorder.samples() != 2) {
      throw std::runtime_error("structure_defect: " + method_.name() + " on " + scene_.system() +
                               ", one step of h = " + std::to_string(scene_.horizon.h) + ": " + stats.brief());
    }
    const AttitudeInitial& out = std::holds_alternative<FreeBodyModel>(scene_.model)
                                     ? state_of<FreeBodyModel>(recorder.last())
                                     : state_of<PendulumModel>(recorder.last());
    R = nearest_rotation(out.R);
    Pi = inertia_.J * out.Omega;
  }

  Scene scene_;  // the scene over one step; its initial state is the probe's input
  const Method& method_;
  AttitudeInitial& initial_;
  const Inertia& inertia_;
  Mat3 R0_;
  Vec3 Pi0_;
  double s_ = 1.0;
  Mat3 R_nominal_;
  Vec3 Pi_nominal_;
  std::size_t evaluations_ = 0;
};

double spectral_norm(const Mat6& A) { return Eigen::JacobiSVD<Mat6>(A).singularValues()(0); }

}  // namespace

void StructureDefectOptions::validate() const {
  if (!(std::isfinite(evaluation_error) && evaluation_error > 0.0)) {
    throw InvalidInput("evaluation_error", "must be finite and > 0");
  }
  if (!(std::isfinite(increment) && increment >= 0.0)) throw InvalidInput("increment", "must be finite and >= 0");
  if (!(std::isfinite(momentum_scale) && momentum_scale >= 0.0)) {
    throw InvalidInput("momentum_scale", "must be finite and >= 0");
  }
}

std::string StructureDefect::brief() const {
  char line[400];
  std::snprintf(line, sizeof line,
                "%s on %s, h = %g: %s defect %.2e (floor %.2e, %s; canonical %.2e, floor %.2e), d = %.2e, s = %.3g, "
                "||D|| = %.3g, cond %.3g, %zu steps",
                method.c_str(), system.c_str(), h, structure.c_str(), defect, floor,
                round_off() ? "round-off" : "above", canonical_defect, canonical_floor, increment, momentum_scale, jacobian_norm,
                jacobian_condition, evaluations);
  return line;
}

StructureDefect structure_defect(const Scene& scene, const Method& method, const StructureDefectOptions& options,
                                 const std::string& name) {
  options.validate();
  StepProbe y(scene, method, options);
  const double d = options.increment > 0.0 ? options.increment : std::pow(360.0 * options.evaluation_error, 0.2);

  // Central differences at d and d/2, Richardson-extrapolated (fourth order).
  Mat6 D;
  for (int j = 0; j < 6; ++j) {
    const Vec6 e = Vec6::Unit(j);
    const Vec6 wide = (y(d * e) - y(-d * e)) / (2.0 * d);
    const Vec6 narrow = (y(0.5 * d * e) - y(-0.5 * d * e)) / d;
    D.col(j) = (4.0 * narrow - wide) / 3.0;
  }

  StructureDefect r;
  r.method = name.empty() ? method.name() : name;
  r.system = scene.system();
  r.h = scene.horizon.h;
  r.increment = d;
  r.momentum_scale = y.momentum_scale();
  r.evaluations = y.evaluations();
  r.jacobian = D;
  const Eigen::JacobiSVD<Mat6> svd(D);
  r.jacobian_norm = svd.singularValues()(0);
  r.jacobian_condition = svd.singularValues()(0) / svd.singularValues()(5);

  // The Jacobian's entry error (round-off 3 eps_y / d, truncation d^4 / 480) and the floors.
  const double entry_error = 3.0 * options.evaluation_error / d + std::pow(d, 4) / 480.0;
  const Vec3 p_in = y.p_in();
  const Vec3 p_out = y.p_out();
  const Mat6 B_in = canonical_tensor(p_in);
  const Mat6 B_out = canonical_tensor(p_out);
  r.canonical_defect = (D * B_in * D.transpose() - B_out).norm() / B_out.norm();
  r.canonical_floor = 2.0 * 6.0 * entry_error * spectral_norm(B_in) * r.jacobian_norm / B_out.norm();

  if (std::holds_alternative<FreeBodyModel>(scene.model)) {
    const Mat3 D_pi = D.block<3, 3>(3, 3);
    const Mat3 P_out = so3::hat(p_out);
    r.lie_poisson_defect = (D_pi * so3::hat(p_in) * D_pi.transpose() - P_out).norm() / P_out.norm();
    const double D_pi_norm = Eigen::JacobiSVD<Mat3>(D_pi).singularValues()(0);
    r.structure = "Lie-Poisson so(3)*";
    r.defect = r.lie_poisson_defect;
    r.lie_poisson_floor = 2.0 * 3.0 * entry_error * p_in.norm() * D_pi_norm / (std::sqrt(2.0) * p_out.norm());
    r.floor = r.lie_poisson_floor;
  } else {
    r.lie_poisson_defect = std::numeric_limits<double>::quiet_NaN();
    r.lie_poisson_floor = std::numeric_limits<double>::quiet_NaN();
    r.structure = "canonical T*SO(3)";
    r.defect = r.canonical_defect;
    r.floor = r.canonical_floor;
  }
  return r;
}

StructureDefect structure_defect(const Scene& scene, const MethodInfo& info, const StructureDefectOptions& options) {
  if (info.adaptive()) {
    throw InvalidInput("method", info.name + " is error-controlled: its step is not a one-step map at a fixed h");
  }
  if (!info.applies_to(scene.system())) {
    throw InvalidInput("method", info.name + " does not apply to the " + scene.system());
  }
  MethodOptions method_options;
  if (!info.on_group()) method_options.model = options.model;
  const std::unique_ptr<Method> method = info.make(method_options);
  return structure_defect(scene, *method, options, info.name);
}

Scene structure_probe_scene(const std::string& system, double h) {
  // h and t_final are replaced by the overrides below.
  static constexpr const char* kFreeBody = R"(system = "free-body"
description = "structure probe: free body, generic attitude and rate"
[parameters]
inertia = [0.13, 0.28, 0.17]
[initial]
euler = { sequence = "ZYX", angles = [0.4, -0.3, 0.7] }
Omega = [1.2, -0.8, 2.0]
[integration]
h = 0.01
t_final = 0.01
)";
  static constexpr const char* kPendulum = R"(system = "pendulum"
description = "structure probe: the paper's pendulum, tilted, generic rate"
[parameters]
mass = 1.0
inertia = [0.13, 0.28, 0.17]
rho = [0.0, 0.0, 0.3]
gravity = 9.81
[initial]
euler = { sequence = "ZYX", angles = [0.3, 0.5, -0.4] }
Omega = [1.0, -1.5, 2.0]
[integration]
h = 0.01
t_final = 0.01
)";
  const char* text = system == "free-body" ? kFreeBody : system == "pendulum" ? kPendulum : nullptr;
  if (text == nullptr) {
    throw InvalidInput("system", "structure probe scenes: free-body or pendulum (not '" + system + "')");
  }
  SceneOverrides overrides;
  overrides.h = h;
  overrides.t_final = h;
  overrides.output_every = 1;
  overrides.form = LgviForm::Symmetric;
  return parse_scene(text, "structure-probe-" + system + ".toml", overrides);
}

}  // namespace lgvi::experiments
