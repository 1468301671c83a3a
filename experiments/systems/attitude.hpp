// The part of the bindings the single-attitude systems share (free body, pendulum): one rigid
// body on SO(3), the AttitudeLgvi flow map, the AttitudeMechanics continuous model.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <type_traits>

#include "baselines/mechanics.hpp"
#include "experiments/system_binding.hpp"
#include "lgvi/lgvi.hpp"

namespace lgvi::experiments {

/// The LGVI of an attitude system under state feedback u = law(R, Omega) (control_moment linear
/// in u): the discrete Lagrange-d'Alembert impulses c0 tau(x_k) + c1 tau(x_{k+1}) (symmetric:
/// h/2, h/2; printed: 0, h) with the feedback evaluated at both ends of the step, so the
/// symmetric form stays second order in the control. The end impulse is implicit, but only
/// through Pi_{k+1}: R_{k+1} solves the rotation update with the start impulse alone. So the
/// flow map steps once with u_{k+1} = u_k and then iterates
///     Pi_{k+1} <- Pi_{k+1} + c1 (tau(R_{k+1}, law(R_{k+1}, J^{-1} Pi_{k+1})) - tau applied),
/// a fixed point with contraction factor about c1 kd / J_min (kd the rate gain), to rounding
/// (|change| <= 8 eps (|Pi_{k+1}| + c1 |tau|)); after kMaxIterations the step fails (status
/// NotConverged, as a rotation update failure: h is too large for the gain).
template <class Lgvi, class Law>
class FeedbackLgvi {
 public:
  using State = typename Lgvi::State;
  using Control = typename Lgvi::Control;
  static constexpr int potential_evaluations_per_step = Lgvi::potential_evaluations_per_step;
  static constexpr int kMaxIterations = 100;

  FeedbackLgvi(const Lgvi& lgvi, Law law) : lgvi_(lgvi), law_(std::move(law)) {}

  /// The controls passed are ignored: the feedback law gives them.
  RotationUpdateSummary step(const State& in, double h, const Control& /*u_k*/, const Control& /*u_k1*/,
                             State& out) const {
    const Control u_k = law_(in.R, lgvi_.omega(in));  // before `out`, which may alias `in`, is written
    RotationUpdateSummary summary = lgvi_.step(in, h, u_k, u_k, out);
    if (!summary.converged()) return summary;
    const double c1 = impulse_weights(lgvi_.form(), h).end;
    const auto& system = lgvi_.system();
    Vec3 applied = system.control_moment(out.R, u_k);
    for (int i = 0; i < kMaxIterations; ++i) {
      const Vec3 wanted = system.control_moment(out.R, law_(out.R, lgvi_.omega(out)));
      const Vec3 change = c1 * (wanted - applied);
      out.Pi += change;
      applied = wanted;
      if (change.norm() <= 8.0 * std::numeric_limits<double>::epsilon() * (out.Pi.norm() + std::abs(c1) * wanted.norm())) {
        return summary;
      }
    }
    summary.status = RotationUpdateStatus::NotConverged;
    return summary;
  }

  LgviForm form() const { return lgvi_.form(); }
  const auto& system() const { return lgvi_.system(); }
  Vec3 omega(const State& s) const { return lgvi_.omega(s); }

 private:
  const Lgvi& lgvi_;
  Law law_;
};

/// AttitudeMechanics with a feedback control u(R, Omega) added to its moment (the baselines'
/// side of the scenes' PD feedback): Omega' = J^{-1} (J Omega x Omega + M(R) + tau(R, u(t)) +
/// tau(R, feedback(R, Omega))). The velocity Jacobian adds the feedback's derivative by central
/// differences (exact up to rounding for a feedback affine in Omega, as the PD law is).
template <AttitudeSystem S>
class FeedbackMechanics {
 public:
  using Base = baselines::AttitudeMechanics<S>;
  static constexpr int bodies = Base::bodies;
  static constexpr int positions = Base::positions;
  static constexpr int velocities = Base::velocities;
  static constexpr bool rates_are_velocities = Base::rates_are_velocities;
  using System = S;
  using Control = typename S::Control;
  using Config = typename Base::Config;
  using Rate = typename Base::Rate;
  using Velocity = typename Base::Velocity;

  FeedbackMechanics(const S& system, std::function<Control(double)> control,
                    std::function<Control(const Mat3&, const Vec3&)> feedback)
      : base_(system, std::move(control)), feedback_(std::move(feedback)) {}

  void rates(const Config& c, const Velocity& w, Rate& r) const { base_.rates(c, w, r); }
  Velocity acceleration(double t, const Config& c, const Velocity& w) const {
    return base_.acceleration(t, c, w) + feedback_acceleration(c.R[0], w);
  }
  Mat3 velocity_jacobian(double t, const Config& c, const Velocity& w) const {
    Mat3 A = base_.velocity_jacobian(t, c, w);
    for (int k = 0; k < 3; ++k) {
      const double a = 1e-6 * std::max(1.0, std::abs(w(k)));
      Vec3 plus = w, minus = w;
      plus(k) += a;
      minus(k) -= a;
      A.col(k) += (feedback_acceleration(c.R[0], plus) - feedback_acceleration(c.R[0], minus)) / (2.0 * a);
    }
    return A;
  }
  Velocity velocity_state(const Config& c, const std::array<Vec3, 1>& Omega, const baselines::Vector<0>& x_dot) const {
    return base_.velocity_state(c, Omega, x_dot);
  }
  bool time_dependent() const { return base_.time_dependent(); }
  const S& system() const { return base_.system(); }

 private:
  Vec3 feedback_acceleration(const Mat3& R, const Vec3& Omega) const {
    const S& s = base_.system();
    return s.inertia.J_inverse * s.control_moment(R, feedback_(R, Omega));
  }

  Base base_;
  std::function<Control(const Mat3&, const Vec3&)> feedback_;
};

template <class M>
struct AttitudeBinding {
  using State = typename M::State;
  static constexpr bool single_body = true;

  /// [parameters]: SystemBinding<M>::kParameterKeys; [initial]: R, quaternion or euler (default
  /// identity), Omega or omega_space;
  /// [control]: a sinusoid (the body-frame moment, or the pendulum's u of eq. 23).
  static void check_keys(const SceneReader& r, const SceneTable& parameters, const SceneTable& initial) {
    r.check_keys(parameters, SystemBinding<M>::kParameterKeys);
    r.check_keys(initial, concat_keys({SceneReader::attitude_keys("R"), SceneReader::body_rate_keys("Omega")}));
  }
  static void check_control_keys(const SceneReader& r, const SceneTable& control) {
    r.check_keys(control, SceneReader::kSinusoidKeys);
  }
  static M read(const SceneReader& r, const SceneTable& parameters, const SceneTable& initial,
                const std::optional<SceneTable>& control) {
    const Mat3 R = r.attitude(initial, "R");
    M m{SystemBinding<M>::read_parameters(r, parameters), State{R, r.body_rate(initial, "Omega", R)}};
    if (control && r.control_type(*control) == "pd") {
      m.feedback = r.feedback(*control);
    } else if (control) {
      m.control = r.sinusoid(*control);
    }
    using System = std::decay_t<decltype(m.system)>;
    r.validate_initial_state(AttitudeLgvi<System>(m.system), m.system.energy(m.initial.R, m.initial.Omega),
                             m.initial.R, m.initial.Omega);
    return m;
  }

  static void state_columns(std::vector<std::string>& c) {
    matrix_columns(c, "R");
    vector_columns(c, "Omega");
  }
  static std::size_t write_state(const State& s, double* row, std::size_t n) {
    n = write_matrix(s.R, row, n);
    return write_vector(s.Omega, row, n);
  }
  static double orthogonality_error(const State& s) { return so3::orthogonality_error(s.R); }
  static double determinant_error(const State& s) { return so3::determinant_error(s.R); }
  static double final_state_error(const State& s, const State& ref) {
    return std::max((s.R - ref.R).norm(), relative_error(s.Omega, ref.Omega));
  }
  static double distance(const State& a, const State& b) { return (a.R - b.R).norm() + (a.Omega - b.Omega).norm(); }
  static double initial_rate(const M& m) { return m.initial.Omega.norm(); }
  static void drop_controls(M& m) {
    m.control.reset();
    m.feedback.reset();
  }
  static bool controlled(const M& m) { return m.control || m.feedback; }

  /// The system's control u for the feedback moment tau(R, Omega): the free body's u is tau; the
  /// pendulum's is tau x R^T e3, whose moment R^T e3 x u is tau's part normal to the vertical.
  static Vec3 feedback_control(const M& m, const Mat3& R, const Vec3& Omega) {
    const Vec3 tau = m.feedback->moment(R, Omega);
    if constexpr (std::is_same_v<M, PendulumModel>) {
      return tau.cross(R.row(2).transpose());
    } else {
      return tau;
    }
  }
  static std::string units() { return "t [s], R [1], Omega [rad/s], energy [J], momentum [kg m^2/s]"; }

  template <class Drive>
  static Stats run_lgvi(const M& m, LgviForm form, const RotationUpdateOptions& options, Drive&& drive) {
    using System = std::decay_t<decltype(m.system)>;
    const AttitudeLgvi<System> lgvi(m.system, form, options);
    AttitudeState state = lgvi.make_state(m.initial.R, m.initial.Omega);
    const auto control = [&m](double t) -> Vec3 { return m.control ? (*m.control)(t) : Vec3::Zero(); };
    const auto to_state = [&](const AttitudeState& s, State& out) {
      out.R = s.R;
      out.Omega = lgvi.omega(s);
    };
    if (m.feedback) {
      const FeedbackLgvi feedback(lgvi, [&m](const Mat3& R, const Vec3& Omega) { return feedback_control(m, R, Omega); });
      return drive(feedback, state, control, to_state);
    }
    return drive(lgvi, state, control, to_state);
  }

  template <class Chart>
  static Stats run_baseline(const M& m, Chart&& chart) {
    using System = std::decay_t<decltype(m.system)>;
    auto control = std::function<Vec3(double)>{};
    if (m.control) control = [&m](double t) -> Vec3 { return (*m.control)(t); };
    if (m.feedback) {
      const FeedbackMechanics<System> mech(m.system, control, [&m](const Mat3& R, const Vec3& Omega) {
        return feedback_control(m, R, Omega);
      });
      return chart(mech, std::array<Mat3, 1>{m.initial.R}, std::array<Vec3, 1>{m.initial.Omega},
                   baselines::Vector<0>(), baselines::Vector<0>());
    }
    const baselines::AttitudeMechanics<System> mech(m.system, control);
    return chart(mech, std::array<Mat3, 1>{m.initial.R}, std::array<Vec3, 1>{m.initial.Omega}, baselines::Vector<0>(),
                 baselines::Vector<0>());
  }
  template <class Decoded>
  static void from_chart(const Decoded& d, State& s) {
    s.R = d.config.R[0];
    s.Omega = d.rates.Omega[0];
  }
};

}  // namespace lgvi::experiments
