// A continuous-time model: a coordinate chart (baselines/coordinates.hpp) for each attitude
// combined with a system's equations of motion (baselines/mechanics.hpp) into one first-order
// ODE behind the Ode interface.
//
// State layout: y = [c_1 .. c_N | x | w]: the chart coordinates of each attitude, the further
// configuration variables, the velocity state. Dimension N * Chart::size + NX + NW, known at
// compile time, so the right-hand side and Jacobian use fixed-size Eigen types only.
//
// Jacobian: the kinematics part (chart rates and their dependence on Omega, dR/dc) is analytic;
// the equations of motion contribute
//   d(acceleration)/dw         analytic when the mechanics provides velocity_jacobian
//                              (Euler's gyroscopic term), else central differences;
//   d(acceleration)/d(R, x)    central differences of the system's own functions (moment,
//                              control moment, forces) in the 9 entries of each R and in x, so
//                              no physics is restated; valid off SO(3) too, where the quaternion
//                              and matrix models wander. Cost: 2 (9N + NX) acceleration
//                              evaluations per Jacobian; accuracy ~eps^(2/3) relative, ample for
//                              the Newton iterations of implicit solvers.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>
#include <type_traits>
#include <vector>

#include "baselines/coordinates.hpp"
#include "baselines/mechanics.hpp"
#include "baselines/ode.hpp"
#include "baselines/projection.hpp"
#include "lgvi/inertia.hpp"
#include "lgvi/systems/free_rigid_body.hpp"
#include "lgvi/systems/pendulum.hpp"

namespace lgvi::baselines {

/// The coordinate models of the baselines (CLI --model).
enum class CoordinateModel { Quaternion, QuaternionRenormalized, Euler, Matrix };

/// "quaternion", "quaternion-renormalized", "euler", "matrix".
const char* to_string(CoordinateModel model);
/// Parses a model name; throws InvalidInput("model", ...) naming the known ones.
CoordinateModel parse_coordinate_model(const std::string& name);
/// Every model name, in the order above.
std::vector<std::string> coordinate_model_names();

/// Central-difference step for a variable of magnitude v: cbrt(eps) max(1, |v|) balances the
/// O(a^2) truncation against the O(eps / a) round-off.
inline double fd_step(double v) {
  return 6.0554544523933395e-06 * std::max(1.0, std::abs(v));
}

template <class Chart, Mechanics M>
class CoordinateOde final : public Ode {
 public:
  static constexpr int N = M::bodies;
  static constexpr int NX = M::positions;
  static constexpr int NW = M::velocities;
  static constexpr int C = Chart::size;
  static constexpr int kDim = N * C + NX + NW;
  static constexpr int kX = N * C;       ///< offset of x
  static constexpr int kW = N * C + NX;  ///< offset of w
  static constexpr int NR = 3 * N + NX;  ///< size of the rates (Omega_1..N, x')

  using State = Vector<kDim>;
  using Jacobian = Eigen::Matrix<double, kDim, kDim, Eigen::RowMajor>;
  using Config = typename M::Config;
  using Velocity = typename M::Velocity;
  using Rate = typename M::Rate;

  /// `renormalize` makes the quaternion-renormalized model (QuaternionChart only).
  explicit CoordinateOde(M mechanics, bool renormalize = false)
      : mechanics_(std::move(mechanics)), renormalize_(renormalize) {
    if (renormalize && !std::is_same_v<Chart, QuaternionChart>) {
      throw InvalidInput("model", "only the quaternion model can be renormalized");
    }
  }

  /// The state of the paper's variables: attitudes, angular velocities, x and x'. Validates
  /// finiteness and that each R is a rotation (1e-10).
  State initial_state(const std::array<Mat3, N>& R, const std::array<Vec3, N>& Omega,
                      const Vector<NX>& x = Vector<NX>::Zero(), const Vector<NX>& x_dot = Vector<NX>::Zero()) const;

  /// The paper's variables at y: R_i = Chart::rotation(c_i) (for the renormalized model, of the
  /// normalized quaternion: between two steps an interpolant is off the unit sphere by the local
  /// error, and that model's promise is a unit quaternion), Omega_i, x, x', and per body the
  /// unit-norm error | |q| - 1 | of the quaternion in y as the solver holds it, before that
  /// normalization (0 for the other charts).
  struct Decoded {
    Config config;
    Rate rates;
    std::array<double, N> quaternion_norm_error{};
  };
  Decoded decode(const double* y_ptr) const;

  int dimension() const override { return kDim; }
  std::string model_name() const override {
    if (renormalize_) return "quaternion-renormalized";
    return Chart::name;
  }
  bool time_dependent() const override { return mechanics_.time_dependent(); }

  RhsStatus rhs(double t, const double* y_ptr, double* ydot_ptr) const override;

  RhsStatus jacobian(double t, const double* y_ptr, double* J_ptr) const override;

  bool has_singular_set() const override { return std::is_same_v<Chart, EulerChart>; }
  double singularity_function(const double* y_ptr) const override {
    if constexpr (std::is_same_v<Chart, EulerChart>) {
      const Eigen::Map<const State> y(y_ptr);
      double g = std::numeric_limits<double>::infinity();
      for (int i = 0; i < N; ++i) g = std::min(g, Chart::singularity_function(y.template segment<C>(C * i)));
      return g;
    } else {
      return 1.0;
    }
  }
  std::string describe_singularity(const double* y_ptr) const override {
    if constexpr (std::is_same_v<Chart, EulerChart>) {
      const Eigen::Map<const State> y(y_ptr);
      int worst = 0;
      for (int i = 1; i < N; ++i) {
        if (Chart::singularity_function(y.template segment<C>(C * i)) <
            Chart::singularity_function(y.template segment<C>(C * worst))) {
          worst = i;
        }
      }
      const double theta = y(C * worst + 1);
      char buf[256];
      std::snprintf(buf, sizeof buf,
                    "gimbal lock%s: pitch theta = %.10g deg (|cos theta| = %.3g, threshold sqrt(eps) = %.3g)",
                    N > 1 ? (" of body " + std::to_string(worst + 1)).c_str() : "", theta * 180.0 / std::numbers::pi,
                    std::abs(std::cos(theta)), EulerChart::kGimbalThreshold);
      return buf;
    } else {
      return {};
    }
  }

  bool renormalizes() const override { return renormalize_; }
  void renormalize(double* y_ptr) const override {
    if constexpr (std::is_same_v<Chart, QuaternionChart>) {
      Eigen::Map<State> y(y_ptr);
      for (int i = 0; i < N; ++i) y.template segment<C>(C * i).normalize();
    }
  }
  void project_error(const double* y_ptr, double* err_ptr) const override {
    if constexpr (std::is_same_v<Chart, QuaternionChart>) {
      const Eigen::Map<const State> y(y_ptr);
      Eigen::Map<State> err(err_ptr);
      for (int i = 0; i < N; ++i) {
        const Vector<4> q = y.template segment<4>(4 * i).normalized();
        err.template segment<4>(4 * i) -= q * q.dot(err.template segment<4>(4 * i));
      }
    }
  }

  // Manifold projection (cvode-bdf-projected; baselines/projection.hpp): the chart's constraints
  // of each body, then the mechanics' invariants (mechanics.hpp invariants(), where it has them).
  static constexpr bool has_invariants = requires(const M& m, const Config& c, const Velocity& w, double* g) {
    { m.invariants(c, w, g) } -> std::convertible_to<int>;
  };
  static constexpr int kChartConstraints = N * ChartConstraints<Chart>::count;
  static constexpr int kMaxConstraints = kChartConstraints + [] {
    if constexpr (has_invariants) {
      return M::max_invariants;
    } else {
      return 0;
    }
  }();
  static_assert(kMaxConstraints <= kMaxProjectionConstraints);
  static_assert(kDim <= kMaxProjectionDim, "raise kMaxProjectionDim (projection.hpp)");

  std::string projection_refusal() const override;
  std::string projection_constraints() const override;
  ProjectionTarget projection_target(const double* y0_ptr) const override;
  int project(const ProjectionTarget& target, double* y_ptr, double* err_ptr) const override;

  const M& mechanics() const { return mechanics_; }

 private:
  /// g(y) into out (kMaxConstraints entries at most); returns how many.
  int constraint_values(const State& y, double* out) const {
    int k = 0;
    Config config;
    for (int i = 0; i < N; ++i) {
      const typename Chart::Coords c = y.template segment<C>(C * i);
      ChartConstraints<Chart>::values(c, out + k);
      k += ChartConstraints<Chart>::count;
      config.R[i] = Chart::rotation(c);
    }
    if constexpr (has_invariants) {
      config.x = y.template segment<NX>(kX);
      const Velocity w = y.template segment<NW>(kW);
      k += mechanics_.invariants(config, w, out + k);
    }
    return k;
  }

  static bool singular(const Eigen::Map<const State>& y) {
    if constexpr (std::is_same_v<Chart, EulerChart>) {
      for (int i = 0; i < N; ++i) {
        if (Chart::singular(y.template segment<C>(C * i))) return true;
      }
    }
    return false;
  }

  M mechanics_;
  bool renormalize_;
};

// The members that instantiate most code are defined below the class, outside it (so not
// inline), and compiled once for the library's systems (the explicit instantiation declarations
// at the end; baselines/model_instances_*.cpp define them): a file that runs a model of these
// systems does not compile them again (test_baselines' files spent about half their compile time
// instantiating them). A model of another mechanics (a user's, a harness wrapper) instantiates them where
// it is used, as any template.

template <class Chart, Mechanics M>
auto CoordinateOde<Chart, M>::initial_state(const std::array<Mat3, N>& R, const std::array<Vec3, N>& Omega,
                                            const Vector<NX>& x, const Vector<NX>& x_dot) const -> State {
  State y;
  Config config;
  for (int i = 0; i < N; ++i) {
    require_finite(R[i], "R0");
    if (!so3::is_rotation(R[i], 1e-10)) throw InvalidInput("R0", "is not a rotation matrix (R^T R != I or det R != 1)");
    require_finite(Omega[i], "Omega0");
    y.template segment<C>(C * i) = Chart::from_rotation(R[i]);
    config.R[i] = R[i];
  }
  require_finite(x, "x0");
  require_finite(x_dot, "v0");
  config.x = x;
  y.template segment<NX>(kX) = x;
  y.template segment<NW>(kW) = mechanics_.velocity_state(config, Omega, x_dot);
  return y;
}

template <class Chart, Mechanics M>
auto CoordinateOde<Chart, M>::decode(const double* y_ptr) const -> Decoded {
  const Eigen::Map<const State> y(y_ptr);
  Decoded d;
  for (int i = 0; i < N; ++i) {
    typename Chart::Coords c = y.template segment<C>(C * i);
    if constexpr (std::is_same_v<Chart, QuaternionChart>) {
      // The norm of the solver's own state, before the renormalized model normalizes it here:
      // a missing renormalization between steps must show in this record.
      d.quaternion_norm_error[i] = Chart::norm_error(c);
      if (renormalize_) c.normalize();
    }
    d.config.R[i] = Chart::rotation(c);
  }
  d.config.x = y.template segment<NX>(kX);
  mechanics_.rates(d.config, y.template segment<NW>(kW), d.rates);
  return d;
}

template <class Chart, Mechanics M>
RhsStatus CoordinateOde<Chart, M>::rhs(double t, const double* y_ptr, double* ydot_ptr) const {
  const Eigen::Map<const State> y(y_ptr);
  Eigen::Map<State> ydot(ydot_ptr);
  if (singular(y)) return RhsStatus::Singular;
  Config config;
  for (int i = 0; i < N; ++i) config.R[i] = Chart::rotation(y.template segment<C>(C * i));
  config.x = y.template segment<NX>(kX);
  const Velocity w = y.template segment<NW>(kW);
  Rate r;
  mechanics_.rates(config, w, r);
  for (int i = 0; i < N; ++i) ydot.template segment<C>(C * i) = Chart::rate(y.template segment<C>(C * i), r.Omega[i]);
  ydot.template segment<NX>(kX) = r.x_dot;
  ydot.template segment<NW>(kW) = acceleration_given_rates(mechanics_, t, config, w, r);
  return RhsStatus::Ok;
}

template <class Chart, Mechanics M>
RhsStatus CoordinateOde<Chart, M>::jacobian(double t, const double* y_ptr, double* J_ptr) const {
  const Eigen::Map<const State> y(y_ptr);
  Eigen::Map<Jacobian> J(J_ptr);
  if (singular(y)) return RhsStatus::Singular;
  J.setZero();
  Config config;
  std::array<typename Chart::Coords, N> c;
  // D = d vec(R_1..R_N) / d(c_1..c_N), block diagonal 9N x NC.
  Eigen::Matrix<double, 9 * N, N * C> D = Eigen::Matrix<double, 9 * N, N * C>::Zero();
  for (int i = 0; i < N; ++i) {
    c[i] = y.template segment<C>(C * i);
    config.R[i] = Chart::rotation(c[i]);
    D.template block<9, C>(9 * i, C * i) = Chart::rotation_jacobian(c[i]);
  }
  config.x = y.template segment<NX>(kX);
  const Velocity w = y.template segment<NW>(kW);

  // Jacobians of the rates (Omega_i, x') and of the acceleration w.r.t. (vec R, x, w).
  Eigen::Matrix<double, NR, 9 * N> G_R = Eigen::Matrix<double, NR, 9 * N>::Zero();
  Eigen::Matrix<double, NR, NX> G_x = Eigen::Matrix<double, NR, NX>::Zero();
  Eigen::Matrix<double, NR, NW> G_w = Eigen::Matrix<double, NR, NW>::Zero();
  Eigen::Matrix<double, NW, 9 * N> A_R;
  Eigen::Matrix<double, NW, NX> A_x;
  Eigen::Matrix<double, NW, NW> A_w;
  const auto rates_vector = [&](const Config& cfg, const Velocity& v) {
    Rate r;
    mechanics_.rates(cfg, v, r);
    Vector<NR> out;
    for (int i = 0; i < N; ++i) out.template segment<3>(3 * i) = r.Omega[i];
    if constexpr (NX > 0) out.template tail<NX>() = r.x_dot;
    return out;
  };
  constexpr bool analytic_rates = requires { requires M::rates_are_velocities; };
  if constexpr (analytic_rates) {
    static_assert(NR == NW, "rates_are_velocities needs w = (Omega_1..N, x')");
    G_w.setIdentity();
  }
  for (int i = 0; i < N; ++i) {
    for (int e = 0; e < 9; ++e) {
      const double a = fd_step(config.R[i](e / 3, e % 3));
      Config plus = config, minus = config;
      plus.R[i](e / 3, e % 3) += a;
      minus.R[i](e / 3, e % 3) -= a;
      A_R.col(9 * i + e) = (mechanics_.acceleration(t, plus, w) - mechanics_.acceleration(t, minus, w)) / (2.0 * a);
      if constexpr (!analytic_rates) {
        G_R.col(9 * i + e) = (rates_vector(plus, w) - rates_vector(minus, w)) / (2.0 * a);
      }
    }
  }
  if constexpr (NX > 0) {  // (Eigen's products of fixed zero-size blocks do not compile)
    for (int k = 0; k < NX; ++k) {
      const double a = fd_step(config.x(k));
      Config plus = config, minus = config;
      plus.x(k) += a;
      minus.x(k) -= a;
      A_x.col(k) = (mechanics_.acceleration(t, plus, w) - mechanics_.acceleration(t, minus, w)) / (2.0 * a);
      if constexpr (!analytic_rates) G_x.col(k) = (rates_vector(plus, w) - rates_vector(minus, w)) / (2.0 * a);
    }
  }
  constexpr bool analytic_velocity = requires(const M& m) { m.velocity_jacobian(t, config, w); };
  if constexpr (analytic_velocity) {
    A_w = mechanics_.velocity_jacobian(t, config, w);
  }
  if constexpr (!analytic_velocity || !analytic_rates) {
    for (int k = 0; k < NW; ++k) {
      const double a = fd_step(w(k));
      Velocity plus = w, minus = w;
      plus(k) += a;
      minus(k) -= a;
      if constexpr (!analytic_velocity) {
        A_w.col(k) = (mechanics_.acceleration(t, config, plus) - mechanics_.acceleration(t, config, minus)) / (2.0 * a);
      }
      if constexpr (!analytic_rates) G_w.col(k) = (rates_vector(config, plus) - rates_vector(config, minus)) / (2.0 * a);
    }
  }

  // Rows of w: [A_R D, A_x, A_w].
  J.template block<NW, N * C>(kW, 0) = A_R * D;
  J.template block<NW, NW>(kW, kW) = A_w;
  if constexpr (NX > 0) {
    J.template block<NW, NX>(kW, kX) = A_x;
    // Rows of x: the x' part of the rates.
    J.template block<NX, N * C>(kX, 0) = G_R.template bottomRows<NX>() * D;
    J.template block<NX, NX>(kX, kX) = G_x.template bottomRows<NX>();
    J.template block<NX, NW>(kX, kW) = G_w.template bottomRows<NX>();
  }
  // Rows of c_i: d rate / dc_i + d rate / dOmega_i * dOmega_i / d(c, x, w).
  const Vector<NR> r = rates_vector(config, w);
  for (int i = 0; i < N; ++i) {
    const Vec3 Omega = r.template segment<3>(3 * i);
    const auto K_O = Chart::rate_omega_jacobian(c[i]);
    J.template block<C, C>(C * i, C * i) = Chart::rate_jacobian(c[i], Omega);
    J.template block<C, N * C>(C * i, 0) += K_O * (G_R.template middleRows<3>(3 * i) * D);
    if constexpr (NX > 0) J.template block<C, NX>(C * i, kX) = K_O * G_x.template middleRows<3>(3 * i);
    J.template block<C, NW>(C * i, kW) = K_O * G_w.template middleRows<3>(3 * i);
  }
  return RhsStatus::Ok;
}

template <class Chart, Mechanics M>
std::string CoordinateOde<Chart, M>::projection_refusal() const {
  if (renormalize_) {
    return "the quaternion-renormalized model renormalizes through its own post-step hook; the projection keeps "
           "|q| = 1 on the quaternion model itself (use --model quaternion)";
  }
  if constexpr (!has_invariants) {
    // Projecting the chart's constraints alone is the renormalized model under another name.
    return "the system gives no invariant to project onto (the cart-pendulum's and the connected bodies' energies "
           "sit behind a configuration-dependent mass matrix; a PD feedback or orbit moment conserves none): use "
           "cvode-bdf with --model quaternion-renormalized for |q| = 1";
  }
  return {};
}

template <class Chart, Mechanics M>
std::string CoordinateOde<Chart, M>::projection_constraints() const {
  std::string out = ChartConstraints<Chart>::count > 0
                        ? std::string(ChartConstraints<Chart>::name) + (N > 1 ? " (each body)" : "")
                        : std::string();
  std::string invariants;
  if constexpr (has_invariants) {
    invariants = mechanics_.invariant_names();
  } else {
    // The cart-pendulum, the connected bodies, an attitude system with an extra moment:
    // baselines/mechanics.hpp says why they have no invariants here.
    invariants = "no invariant of this system";
  }
  out += (out.empty() ? "" : ", ") + invariants;
  return out + " (Euclidean in the " + std::string(Chart::name) + " model's state)";
}

template <class Chart, Mechanics M>
ProjectionTarget CoordinateOde<Chart, M>::projection_target(const double* y0_ptr) const {
  ProjectionTarget target;
  if (renormalize_) return target;
  const State y0 = Eigen::Map<const State>(y0_ptr);
  target.count = constraint_values(y0, target.value.data());
  for (int i = 0; i < N; ++i) ChartConstraints<Chart>::targets(target.value.data() + i * ChartConstraints<Chart>::count);
  return target;
}

template <class Chart, Mechanics M>
int CoordinateOde<Chart, M>::project(const ProjectionTarget& target, double* y_ptr, double* err_ptr) const {
  const int m = target.count;
  if (m == 0) return 0;
  const State y = Eigen::Map<const State>(y_ptr);
  // G = g'(y) by central differences in each entry of the state (exact up to rounding for the
  // polynomial constraints; projection.hpp), m rows of kDim entries.
  using Values = Eigen::Matrix<double, std::max(kMaxConstraints, 1), 1>;
  Eigen::Matrix<double, std::max(kMaxConstraints, 1), kDim, Eigen::RowMajor> G;
  Values plus = Values::Zero(), minus = Values::Zero();
  State s = y;
  for (int j = 0; j < kDim; ++j) {
    const double a = fd_step(y(j));
    const double up = y(j) + a, down = y(j) - a;
    s(j) = up;
    constraint_values(s, plus.data());
    s(j) = down;
    constraint_values(s, minus.data());
    s(j) = y(j);
    G.col(j) = (plus - minus) / (up - down);
  }
  const ConstraintFunction g{this, [](const void* self, const double* at, double* out) {
                               static_cast<const CoordinateOde*>(self)->constraint_values(
                                   Eigen::Map<const State>(at), out);
                             }};
  return project_onto_constraints(g, kDim, m, G.data(), target.value.data(), y_ptr, err_ptr);
}

extern template class CoordinateOde<QuaternionChart, AttitudeMechanics<FreeRigidBody>>;
extern template class CoordinateOde<EulerChart, AttitudeMechanics<FreeRigidBody>>;
extern template class CoordinateOde<MatrixChart, AttitudeMechanics<FreeRigidBody>>;
extern template class CoordinateOde<QuaternionChart, AttitudeMechanics<Pendulum3D>>;
extern template class CoordinateOde<EulerChart, AttitudeMechanics<Pendulum3D>>;
extern template class CoordinateOde<MatrixChart, AttitudeMechanics<Pendulum3D>>;
extern template class CoordinateOde<QuaternionChart, DumbbellMechanics>;
extern template class CoordinateOde<EulerChart, DumbbellMechanics>;
extern template class CoordinateOde<MatrixChart, DumbbellMechanics>;
extern template class CoordinateOde<QuaternionChart, CartPendulumMechanics>;
extern template class CoordinateOde<EulerChart, CartPendulumMechanics>;
extern template class CoordinateOde<MatrixChart, CartPendulumMechanics>;
extern template class CoordinateOde<QuaternionChart, ConnectedBodiesMechanics>;
extern template class CoordinateOde<EulerChart, ConnectedBodiesMechanics>;
extern template class CoordinateOde<MatrixChart, ConnectedBodiesMechanics>;

}  // namespace lgvi::baselines
