// "sensitivity": how accurate are the transition matrices that the optimal-control solvers
// differentiate with? The discrete one is the product of the LGVI's linearized steps A_k
// (lgvi/ocp/linearization.hpp, symmetric form, zero control); the continuous one comes from
// CVODES forward sensitivities (baselines/sensitivity.hpp) on the quaternion model, converted to
// the same tangent coordinates z = [eta; dOmega] (dR = R hat(eta), rad and rad/s).
//
// Cases: system (pendulum, free body: parameters and initial state of the named scene, its
// controls dropped: the flow is the uncontrolled one) x horizon T x method (LGVI at a few h,
// CVODES at a few rtol). Each case reports, as relative Frobenius norms,
//   fd_error               |Phi - Phi_fd| / |Phi_fd| against central differences of the method's
//                          own flow (LGVI: the LGVI at the same h, so the linearization is
//                          exact and the error is the differences' own; CVODES: the continuous
//                          flow integrated at kFdRtol, so the error is CVODES's at its rtol, down
//                          to the differences' floor);
//   fd_tolerance           the differences' error estimate (below), the bound the LGVI's
//                          fd_error must meet: a larger one is status "fd-mismatch";
//   continuous_difference  |Phi - Phi_ref| / |Phi_ref| against the CVODES transition matrix at
//                          kReferenceRtol (LGVI: the discretization error of the linearization,
//                          O(h^2) for the symmetric form; CVODES: its error at rtol);
// and the cost of computing Phi alone (wall time, steps, right-hand-side evaluations).
//
// Central differences. Column j of Phi_fd is (z(+a_j e_j) - z(-a_j e_j)) / (2 a_j), the initial
// state perturbed as R0 exp(a eta), Omega0 + a dOmega and the final one read back as
// z = [log(R_nom^T R)^vee; Omega - Omega_nom]. Step a = cbrt(eps) (rad) and
// cbrt(eps) max(1, |Omega0|) (rad/s), which balances the truncation a^2 |z'''| / 6 against the
// flow's round-off / a for an O(1) third derivative. Neither term is O(1) over long horizons
// (|z'''| grows with the sensitivities), so the tolerance is estimated, not assumed: with
// Phi_2a the differences at twice the step, truncation(a) = (Phi_2a - Phi_a) / 3 (the error is
// c a^2 + O(a^4)), and the noise (round-off / a) enters the same difference at full size;
// fd_tolerance = kFdSafety |Phi_2a - Phi_a| / |Phi_a| + kFdFloor, a factor kFdSafety over the
// estimate because a single difference samples the noise once.
// Where the differences cannot decide. When the sensitivities are large the perturbed final
// states leave the linear regime (a |Phi| is not small) and round-off amplified by Phi swamps
// what is left: if the third derivative grows like |Phi|^3, balancing eps sqrt(N) |Phi| / a
// against a^2 |Phi|^3 gives a relative error of ~(eps sqrt(N))^(2/3) |Phi|^(4/3) whatever the
// step. Measured on the tumbling pendulum: estimate 5e-3 at |Phi| = 2.2e4 (T = 8 s), O(1) at
// |Phi| = 4.6e6 (T = 16 s). Where the estimate exceeds kFdConclusive (not even two digits
// resolved) the case records fd_conclusive = false and the comparison gates nothing; the
// numbers are still reported.
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>

#include "baselines/coordinates.hpp"
#include "baselines/mechanics.hpp"
#include "baselines/model.hpp"
#include "baselines/sensitivity.hpp"
#include "baselines/solver.hpp"
#include "experiments/output/csv_writer.hpp"
#include "experiments/scene/scene.hpp"
#include "experiments/methods/simulate.hpp"
#include "experiments/suites/common.hpp"
#include "lgvi/lgvi.hpp"
#include "lgvi/ocp/linearization.hpp"
#include "lgvi/ocp/models.hpp"
#include "lgvi/so3.hpp"
#include "lgvi/systems/pendulum.hpp"

namespace lgvi::experiments::suites {

namespace fs = std::filesystem;

namespace {

using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Clock = std::chrono::steady_clock;

/// cbrt(eps): the balanced central-difference step.
const double kFdStep = std::cbrt(kEps);
/// Factor over the differences' own error estimate (header comment).
constexpr double kFdSafety = 10.0;
/// Below this the estimate is itself round-off: 1e3 eps^(2/3), the tests' central-difference
/// tolerance (tests/test_support.hpp kFdTolerance).
const double kFdFloor = 1e3 * std::pow(kEps, 2.0 / 3.0);
/// Differences whose own error estimate exceeds this resolve less than two digits: inconclusive.
constexpr double kFdConclusive = 1e-2;
/// The continuous flow differenced for the CVODES cases, and the reference transition matrix:
/// tighter than any swept rtol, looser than where CVODES's local error test breaks down.
constexpr double kFdRtol = 1e-13;
constexpr double kReferenceRtol = 1e-12;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// Final attitude and rate of a flow from (R0, Omega0); message says why not ok.
struct EndState {
  bool ok = false;
  Mat3 R = Mat3::Identity();
  Vec3 Omega = Vec3::Zero();
  std::string message;
};
using Flow = std::function<EndState(const Mat3&, const Vec3&)>;

/// Tangent of `end` at `nominal`: [log(R_nom^T R)^vee; Omega - Omega_nom].
Vec6 tangent_at(const EndState& nominal, const EndState& end) {
  Vec6 z;
  z << so3::log(nominal.R.transpose() * end.R), end.Omega - nominal.Omega;
  return z;
}

struct Differences {
  bool ok = false;
  std::string message;
  Mat6 Phi = Mat6::Zero();  ///< at the step a
  double estimate = 0.0;    ///< |Phi_2a - Phi_a| / |Phi_a|
  double tolerance = 0.0;   ///< kFdSafety estimate + kFdFloor
  int flows = 0;
};

/// Central differences of `flow` in z0 = [eta; dOmega] at steps a and 2a (header comment).
Differences central_differences(const Flow& flow, const Mat3& R0, const Vec3& Omega0) {
  Differences d;
  const EndState nominal = flow(R0, Omega0);
  ++d.flows;
  if (!nominal.ok) {
    d.message = "nominal flow: " + nominal.message;
    return d;
  }
  Mat6 by_step[2];
  for (int s = 0; s < 2; ++s) {
    for (int j = 0; j < 6; ++j) {
      const double a = (s + 1) * kFdStep * (j < 3 ? 1.0 : std::max(1.0, Omega0.norm()));
      Vec6 col = Vec6::Zero();
      for (const double sign : {1.0, -1.0}) {
        Vec6 dz = Vec6::Zero();
        dz(j) = sign * a;
        const EndState e = flow(R0 * so3::exp(Vec3(dz.head<3>())), Omega0 + dz.tail<3>());
        ++d.flows;
        if (!e.ok) {
          d.message = "perturbed flow (column " + std::to_string(j) + "): " + e.message;
          return d;
        }
        col += sign * tangent_at(nominal, e);
      }
      by_step[s].col(j) = col / (2.0 * a);
    }
  }
  d.ok = true;
  d.Phi = by_step[0];
  d.estimate = (by_step[1] - by_step[0]).norm() / by_step[0].norm();
  d.tolerance = kFdSafety * d.estimate + kFdFloor;
  return d;
}

// --- the LGVI --------------------------------------------------------------------------------

Flow lgvi_flow(const Pendulum3D& system, double h, std::size_t steps) {
  return [&system, h, steps](const Mat3& R0, const Vec3& Omega0) {
    const AttitudeLgvi<Pendulum3D> lgvi(system, LgviForm::Symmetric);
    AttitudeState s = lgvi.make_state(R0, Omega0);
    AttitudeState next;
    const Vec3 zero = Vec3::Zero();
    EndState e;
    for (std::size_t k = 0; k < steps; ++k) {
      const RotationUpdateSummary r = lgvi.step(s, h, zero, zero, next);
      if (!r.converged()) {
        e.message = "rotation update failed at step " + std::to_string(k) + " (t = " + shortest(k * h) + ")";
        return e;
      }
      s = next;
    }
    e.ok = true;
    e.R = s.R;
    e.Omega = system.inertia.J_inverse * s.Pi;
    return e;
  };
}

/// Phi of the LGVI: T^{-1} (A_{N-1} ... A_0) T in z coordinates, T = blockdiag(I, J).
struct Linearization {
  bool ok = false;
  std::string message;
  Mat6 Phi = Mat6::Identity();
  std::int64_t newton_iterations = 0;
};

Linearization lgvi_linearization(const Pendulum3D& system, const Mat3& R0, const Vec3& Omega0, double h,
                                 std::size_t steps) {
  const AttitudeLgvi<Pendulum3D> lgvi(system, LgviForm::Symmetric);
  const ocp::PendulumModel model(system);
  AttitudeState s = lgvi.make_state(R0, Omega0);
  AttitudeState next;
  const Vec3 zero = Vec3::Zero();
  Mat6 A = Mat6::Identity();
  Linearization out;
  for (std::size_t k = 0; k < steps; ++k) {
    ocp::StepJacobians<ocp::PendulumModel> jac;
    const RotationUpdateSummary r = ocp::linearize_step(model, lgvi, s, h, zero, zero, jac, &next);
    if (!r.converged()) {
      out.message = "rotation update failed at step " + std::to_string(k) + " (t = " + shortest(k * h) + ")";
      return out;
    }
    out.newton_iterations += r.iterations;
    A = jac.A * A;
    s = next;
  }
  Mat6 T = Mat6::Identity();
  T.bottomRightCorner<3, 3>() = system.inertia.J;
  Mat6 T_inverse = Mat6::Identity();
  T_inverse.bottomRightCorner<3, 3>() = system.inertia.J_inverse;
  out.Phi = T_inverse * A * T;
  out.ok = true;
  return out;
}

// --- CVODES ----------------------------------------------------------------------------------

/// CVODES's transition matrix from (R0, Omega0) over [0, t1], and its cost.
struct Transition {
  bool ok = false;
  std::string message;
  Mat6 Phi = Mat6::Zero();
  Stats stats;
};

/// The continuous system of a problem on the quaternion model: its flow and transition matrix.
class ContinuousSystem {
 public:
  virtual ~ContinuousSystem() = default;
  /// The flow over [0, t1] at rtol (valid while this object lives).
  virtual Flow flow(double t1, double rtol) const = 0;
  virtual Transition transition(const Mat3& R0, const Vec3& Omega0, double t1, double rtol) const = 0;
};

template <class S>
class Continuous final : public ContinuousSystem {
 public:
  using Ode = baselines::CoordinateOde<baselines::QuaternionChart, baselines::AttitudeMechanics<S>>;
  /// Keeps a copy of the system (the mechanics refer to it).
  explicit Continuous(const S& system) : system_(system), ode_(baselines::AttitudeMechanics<S>(system_)) {}
  Continuous(const Continuous&) = delete;
  Continuous& operator=(const Continuous&) = delete;

  Flow flow(double t1, double rtol) const override {
    return [this, t1, rtol](const Mat3& R0, const Vec3& Omega0) {
      const Eigen::VectorXd y0 = ode_.initial_state({R0}, {Omega0});
      const std::array<double, 2> times = {0.0, t1};
      Eigen::VectorXd y1 = y0;
      baselines::SolverSettings settings;
      settings.rtol = rtol;
      settings.atol = rtol;
      const Stats st = baselines::integrate("cvode-adams", ode_, std::span<const double>(y0.data(), y0.size()), times, settings,
                                            [&](std::size_t, double, const double* v) {
                                              y1 = Eigen::Map<const Eigen::VectorXd>(v, y0.size());
                                              return true;
                                            });
      EndState e;
      if (!st.ok()) {
        e.message = st.brief();
        return e;
      }
      e.ok = true;
      e.R = baselines::QuaternionChart::rotation(y1.head<4>().normalized());
      e.Omega = y1.tail<3>();
      return e;
    };
  }

  Transition transition(const Mat3& R0, const Vec3& Omega0, double t1, double rtol) const override {
    const Eigen::VectorXd y0 = ode_.initial_state({R0}, {Omega0});
    baselines::SensitivitySettings settings;
    settings.rtol = rtol;
    const auto r = baselines::integrate_sensitivities(ode_, y0, Eigen::MatrixXd::Identity(y0.size(), y0.size()), 0.0,
                                                      t1, settings);
    Transition out;
    out.stats = r.stats;
    if (!r.ok()) {
      out.message = r.stats.brief();
      return out;
    }
    out.ok = true;
    out.Phi = baselines::tangent_transition(ode_, y0, r.y, r.S);
    return out;
  }

 private:
  S system_;
  Ode ode_;
};

// The continuous systems of the two systems whose bindings have as_pendulum, made outside
// load_problem's generic lambda: clang 14 does not emit the templates first instantiated inside
// its `if constexpr (requires ...)` branch (Continuous's virtual members, make_shared's control
// block), and the ASan build's link failed on them.
std::shared_ptr<const ContinuousSystem> make_continuous(const FreeRigidBody& system) {
  return std::make_shared<const Continuous<FreeRigidBody>>(system);
}
std::shared_ptr<const ContinuousSystem> make_continuous(const Pendulum3D& system) {
  return std::make_shared<const Continuous<Pendulum3D>>(system);
}

/// The attitude system of a case: the scene's parameters and initial state. The LGVI side is
/// written for the pendulum model of lgvi/ocp/models.hpp: the binding gives the system as a
/// pendulum (SystemBinding::as_pendulum; the free body's has rho = 0 and g = 0, so its LGVI and
/// linearization are the free body's). The continuous side is the scene's own system.
struct AttitudeProblem {
  std::string system;  ///< the scene's system, "pendulum" or "free-body"
  Pendulum3D pendulum;
  std::shared_ptr<const ContinuousSystem> continuous;
  Mat3 R0 = Mat3::Identity();
  Vec3 Omega0 = Vec3::Zero();
};

AttitudeProblem load_problem(const std::string& scene_name, const fs::path& scenes_dir) {
  const Scene scene = load_scene(resolve_scene(scene_name, scenes_dir));
  return visit_binding(scene.model, [&](auto binding, const auto& m) -> AttitudeProblem {
    if constexpr (requires { decltype(binding)::as_pendulum(m); }) {
      return {scene.system(), decltype(binding)::as_pendulum(m), make_continuous(m.system), m.initial.R,
              m.initial.Omega};
    } else {
      throw InvalidInput("scene", scene_name + ": the sensitivity suite needs a pendulum or free-body scene (got " +
                                      scene.system() + ")");
    }
  });
}

/// The continuous reference of one (scene, T), computed once on first use (thread-safe) and
/// shared by the cases of that horizon: the CVODES transition matrix at kReferenceRtol and the
/// central differences of the continuous flow at kFdRtol.
class ContinuousReference {
 public:
  ContinuousReference(std::string scene, double T) : scene_(std::move(scene)), T_(T) {}
  std::string description() const {
    return "cvodes-adams (quaternion), rtol = " + shortest(kReferenceRtol) + "; differences of cvode-adams at rtol " +
           shortest(kFdRtol);
  }
  struct Data {
    Mat6 Phi;
    Differences fd;
    double seconds = 0.0;
  };
  /// Throws std::runtime_error when an integration failed.
  const Data& get(const fs::path& scenes_dir) const {
    std::call_once(once_, [&] {
      try {
        const auto t0 = Clock::now();
        const AttitudeProblem p = load_problem(scene_, scenes_dir);
        const Transition tr = p.continuous->transition(p.R0, p.Omega0, T_, kReferenceRtol);
        if (!tr.ok) {
          error_ = "reference transition (" + description() + "): " + tr.message;
        } else {
          data_.Phi = tr.Phi;
          data_.fd = central_differences(p.continuous->flow(T_, kFdRtol), p.R0, p.Omega0);
          if (!data_.fd.ok) error_ = "reference differences: " + data_.fd.message;
        }
        data_.seconds = seconds_since(t0);
      } catch (const std::exception& e) {
        error_ = std::string("continuous reference: ") + e.what();
      }
    });
    if (!error_.empty()) throw std::runtime_error(error_);
    return data_;
  }

 private:
  std::string scene_;
  double T_;
  mutable std::once_flag once_;
  mutable Data data_;
  mutable std::string error_;
};

struct SensitivityMethod {
  std::string kind;  ///< "lgvi" or "cvodes"
  double value;      ///< h or rtol
  std::string label() const {
    // No commas: labels are summary.csv cells.
    return kind == "lgvi" ? "LGVI linearization h = " + shortest(value) + " s"
                          : "CVODES Adams (quaternion) rtol = " + shortest(value);
  }
  std::string id() const {
    char buf[32];
    std::snprintf(buf, sizeof buf, kind == "lgvi" ? "h%g" : "rtol%.0e", value);
    return kind + "-" + buf;
  }
};

class SensitivityJob final : public Job {
 public:
  SensitivityJob(std::string scene, double T, SensitivityMethod method, std::shared_ptr<const ContinuousReference> ref)
      : scene_(std::move(scene)), T_(T), method_(std::move(method)), reference_(std::move(ref)) {}

  void validate(const fs::path& scenes_dir) const override {
    (void)load_problem(scene_, scenes_dir);
    if (!(T_ > 0.0) || !(method_.value > 0.0)) throw InvalidInput("sensitivity", "T, h and rtol must be positive");
    if (method_.kind == "lgvi") (void)lgvi_steps();
  }

  JobResult run(const JobContext& ctx) const override {
    const AttitudeProblem p = load_problem(scene_, ctx.scenes_dir);
    const ContinuousReference::Data& ref = reference_->get(ctx.scenes_dir);
    JobResult out;
    Fields f = {{"scene", scene_}, {"system", p.system}, {"label", method_.label()}, {"method", method_.kind},
                {"T", T_}};
    Mat6 Phi;
    Differences fd;
    double seconds = 0.0;
    if (method_.kind == "lgvi") {
      const std::size_t steps = lgvi_steps();
      f.push_back({"h", method_.value});
      const auto t0 = Clock::now();
      const Linearization lin = lgvi_linearization(p.pendulum, p.R0, p.Omega0, method_.value, steps);
      seconds = seconds_since(t0);
      f.push_back({"steps", static_cast<std::int64_t>(steps)});
      f.push_back({"newton_iterations", lin.newton_iterations});
      if (!lin.ok) return {false, "rotation-update-failed", lin.message, f};
      Phi = lin.Phi;
      fd = central_differences(lgvi_flow(p.pendulum, method_.value, steps), p.R0, p.Omega0);
    } else {
      f.push_back({"rtol", method_.value});
      const Transition tr = p.continuous->transition(p.R0, p.Omega0, T_, method_.value);
      seconds = tr.stats.wall_seconds;
      f.push_back({"steps", static_cast<std::int64_t>(tr.stats.steps)});
      f.push_back({"rhs_evaluations", static_cast<std::int64_t>(tr.stats.rhs_evaluations)});
      f.push_back({"jacobian_evaluations", static_cast<std::int64_t>(tr.stats.jacobian_evaluations)});
      if (!tr.ok) return {false, "solver-failed", tr.message, f};
      Phi = tr.Phi;
      fd = ref.fd;
    }
    f.push_back({"seconds", seconds});
    if (!fd.ok) return {false, "fd-failed", fd.message, f};
    const double fd_error = (Phi - fd.Phi).norm() / fd.Phi.norm();
    const double cont = (Phi - ref.Phi).norm() / ref.Phi.norm();
    const double phi_norm = ref.Phi.operatorNorm();
    f.push_back({"phi_norm", phi_norm});
    f.push_back({"fd_step", kFdStep});
    f.push_back({"fd_estimate", fd.estimate});
    f.push_back({"fd_tolerance", fd.tolerance});
    const bool conclusive = fd.estimate <= kFdConclusive;
    f.push_back({"fd_conclusive", conclusive});
    f.push_back({"fd_error", fd_error});
    f.push_back({"continuous_difference", cont});
    f.push_back({"reference", reference_->description()});
    f.push_back({"csv_path", ctx.case_id + ".csv"});

    // The matrices, entry by entry.
    CsvWriter csv(ctx.out_dir / (ctx.case_id + ".csv"), {"row", "col", "phi", "phi_fd", "phi_reference"});
    for (int i = 0; i < 6; ++i) {
      for (int j = 0; j < 6; ++j) {
        const double row[] = {double(i), double(j), Phi(i, j), fd.Phi(i, j), ref.Phi(i, j)};
        csv.write_row(row);
      }
    }
    Fields meta = {{"suite", std::string("sensitivity")},
                   {"coordinates", std::string("z = [eta; dOmega], dR = R hat(eta): rad, rad/s")},
                   {"phi", std::string("transition matrix d z(T) / d z(0) of the method")},
                   {"phi_fd", std::string("central differences of the method's own flow (CVODES: cvode-adams at "
                                          "rtol ") +
                                  shortest(kFdRtol) + ")"},
                   {"phi_reference", reference_->description()}};
    meta.insert(meta.end(), f.begin(), f.end());
    meta.push_back({"git_describe", std::string(git_describe())});
    meta.push_back({"command_line", ctx.command_line});

    // The linearization is the exact derivative of the LGVI flow: it must agree with the
    // differences to their own accuracy, wherever they have any.
    const bool mismatch = method_.kind == "lgvi" && conclusive && !(fd_error <= fd.tolerance);
    out.completed = !mismatch;
    out.status = mismatch ? "fd-mismatch" : "completed";
    meta.push_back({"status", out.status});
    csv.commit(meta);
    out.detail = method_.label() + ", T = " + shortest(T_) + " s: |Phi - Phi_fd|/|Phi_fd| = " + fmt(fd_error) +
                 " (tolerance " + fmt(fd.tolerance) +
                 (conclusive ? "" : ", differences inconclusive") + "), vs continuous " + fmt(cont) + ", |Phi| = " + fmt(phi_norm) +
                 ", " + fmt(seconds) + " s";
    out.fields = std::move(f);
    return out;
  }

 private:
  std::size_t lgvi_steps() const {
    const double n = T_ / method_.value;
    const double rounded = std::round(n);
    if (rounded < 1.0 || std::abs(n - rounded) > 1e-9 * n) {
      throw InvalidInput("h", "T = " + shortest(T_) + " is not a multiple of h = " + shortest(method_.value));
    }
    return static_cast<std::size_t>(rounded);
  }

  std::string scene_;
  double T_;
  SensitivityMethod method_;
  std::shared_ptr<const ContinuousReference> reference_;
};

std::string horizon_tag(double T) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "T%g", T);
  return buf;
}

}  // namespace

const std::vector<std::string>& sensitivity_columns() {
  static const std::vector<std::string> columns = {
      "scene",        "system",        "label",       "method",      "T",           "h",
      "rtol",         "steps",         "rhs_evaluations", "jacobian_evaluations", "newton_iterations", "seconds",
      "phi_norm",     "fd_step",       "fd_estimate", "fd_tolerance", "fd_error",   "continuous_difference",
      "fd_conclusive", "reference", "csv_path"};
  return columns;
}

Suite sensitivity_suite(const SuiteParams& params) {
  Suite s;
  s.name = "sensitivity";
  s.description = "transition matrices: LGVI linearization and CVODES vs finite differences and each other, over T";
  s.columns = sensitivity_columns();
  const bool quick = params.quick;
  const std::vector<std::string> scenes = {"pendulum", "free-body"};
  const std::vector<double> horizons =
      quick ? std::vector<double>{0.5, 2.0, 8.0} : std::vector<double>{0.25, 0.5, 1, 2, 4, 8, 16, 32};
  std::vector<SensitivityMethod> methods;
  for (const double h : quick ? std::vector<double>{0.01, 0.005, 0.0025} : std::vector<double>{0.01, 0.005, 0.0025, 0.00125}) {
    methods.push_back({"lgvi", h});
  }
  for (const double rtol : quick ? std::vector<double>{1e-6, 1e-9} : std::vector<double>{1e-6, 1e-8, 1e-10}) {
    methods.push_back({"cvodes", rtol});
  }
  for (const std::string& scene : scenes) {
    for (const double T : horizons) {
      const auto ref = std::make_shared<const ContinuousReference>(scene, T);
      for (const SensitivityMethod& m : methods) {
        SuiteCase c;
        c.id = scene + "-" + horizon_tag(T) + "-" + m.id();
        c.group = scene;
        c.labels = {{"scene", scene}, {"label", m.label()}, {"method", m.kind}, {"T", T}};
        c.labels.push_back({m.kind == "lgvi" ? "h" : "rtol", m.value});
        c.expect = Expectation::Complete;
        c.job = std::make_shared<SensitivityJob>(scene, T, m, ref);
        s.cases.push_back(std::move(c));
      }
    }
  }

  s.render = [](const RenderContext& ctx, const std::vector<SummaryRow>& rows) {
    std::vector<fs::path> files;
    for (const auto& group : by_group(rows)) {
      // Named references, not a structured binding: clang 14 (the sanitizer build) does not let
      // a lambda capture one.
      const std::string& scene = group.first;
      const auto& members = group.second;
      const auto curves_of = [&](const char* column) {
        std::vector<XyCurve> curves;
        std::map<std::string, std::size_t> where;
        for (const SummaryRow* r : members) {
          if (r->text("status") != "completed") continue;
          const auto [it, inserted] = where.emplace(r->text("label"), curves.size());
          // One method at several steps or tolerances: each curve takes its label's style.
          if (inserted) curves.push_back({r->text("label"), {}});
          if (r->number("T") && r->number(column)) curves[it->second].points.emplace_back(*r->number("T"), *r->number(column));
        }
        return curves;
      };
      const std::string system = members.front()->text("system");
      files.push_back(plot_xy(ctx, scene + "-fd-error",
                              system + ": transition matrix vs central differences of the method's own flow",
                              "horizon T [s]", "|Φ - Φ_{FD}|_F / |Φ_{FD}|_F", curves_of("fd_error")));
      files.push_back(plot_xy(ctx, scene + "-continuous-difference",
                              system + ": transition matrix vs CVODES at rtol " + shortest(kReferenceRtol),
                              "horizon T [s]", "|Φ - Φ_{ref}|_F / |Φ_{ref}|_F", curves_of("continuous_difference")));
      // Growth of the sensitivities themselves, once per horizon.
      XyCurve growth{system + ": |Φ|_2 of the continuous flow", {}};
      std::map<double, double> by_T;
      for (const SummaryRow* r : members) {
        if (r->number("T") && r->number("phi_norm")) by_T[*r->number("T")] = *r->number("phi_norm");
      }
      for (const auto& [T, n] : by_T) growth.points.emplace_back(T, n);
      files.push_back(plot_xy(ctx, scene + "-growth", system + ": size of the transition matrix d z(T) / d z(0)",
                              "horizon T [s]", "|Φ|_2 (z = [η; δΩ]: rad, rad/s)", {growth}));
    }
    // Observed order of the LGVI's continuous difference between successive h at each T.
    std::string table =
        "# Sensitivity: LGVI linearization and CVODES against finite differences and each other\n\n"
        "Relative Frobenius norms in z = [eta; dOmega]. fd: central differences of the method's own flow "
        "(LGVI at the same h; CVODES: the continuous flow at rtol " +
        shortest(kFdRtol) + "), tolerance = " + shortest(kFdSafety) +
        " x the differences' own error estimate; where that estimate exceeds " + shortest(kFdConclusive) +
        " the differences are inconclusive (marked *: the sensitivities are too large for them). continuous: against CVODES at rtol " + shortest(kReferenceRtol) +
        ". order: log2 of the ratio of continuous differences of successive LGVI steps (h halved).\n\n"
        "| scene | T [s] | method | \\|Phi\\| | fd error | fd tolerance | continuous difference | order | steps | "
        "RHS | seconds | status |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    std::map<std::pair<std::string, double>, double> previous;  // (scene, T) -> continuous difference at 2h
    for (const SummaryRow& r : rows) {
      const auto num = [&](const char* c) { return r.number(c) ? fmt(*r.number(c)) : std::string(); };
      std::string order;
      const auto T = r.number("T");
      const auto cont = r.number("continuous_difference");
      if (r.text("method") == "lgvi" && T && cont) {
        const auto key = std::make_pair(r.text("group"), *T);
        const auto it = previous.find(key);
        if (it != previous.end() && *cont > 0.0) order = fmt(std::log2(it->second / *cont));
        previous[key] = *cont;
      }
      table += "| " + r.text("group") + " | " + num("T") + " | " + r.text("label") + " | " + num("phi_norm") + " | " +
               num("fd_error") + (r.text("fd_conclusive") == "false" ? "*" : "") + " | " + num("fd_tolerance") + " | " + num("continuous_difference") + " | " + order +
               " | " + r.text("steps") + " | " + r.text("rhs_evaluations") + " | " + num("seconds") + " | " +
               r.text("status") + " |\n";
    }
    files.push_back(write_text_file(ctx, "sensitivity-table.md", table));
    return files;
  };
  return s;
}

}  // namespace lgvi::experiments::suites
