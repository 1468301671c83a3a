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
#include "experiments/systems/binding.hpp"
#include "lgvi/feedback_lgvi.hpp"
#include "lgvi/lgvi.hpp"

namespace lgvi::experiments {

// The state records in the paper's variables, one per kind of configuration space: a scene's
// initial state and the recorder's samples (Sample::state) of its system. Each model names its
// record State.
struct AttitudeInitial {
  Mat3 R = Mat3::Identity();
  Vec3 Omega = Vec3::Zero();
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
  static void delay_controls(M& m, double dt) {
    if (m.control) m.control->delay += dt;
  }
  static bool controlled(const M& m) { return m.control || m.feedback; }

  /// The system's control u for the feedback moment tau(t, R, Omega): the free body's u is tau (a
  /// binding whose control is not the moment itself hides this one, as the pendulum's does).
  static Vec3 feedback_control(const M& m, double t, const Mat3& R, const Vec3& Omega) {
    return m.feedback->moment(t, R, Omega);
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
      const FeedbackLgvi feedback(lgvi, [&m](double t, const Mat3& R, const Vec3& Omega) {
        return SystemBinding<M>::feedback_control(m, t, R, Omega);
      });
      return drive(feedback, state, [](double t) { return t; }, to_state);  // its control: the times
    }
    return drive(lgvi, state, control, to_state);
  }

  template <class Chart>
  static Stats run_baseline(const M& m, Chart&& chart) {
    using System = std::decay_t<decltype(m.system)>;
    auto control = std::function<Vec3(double)>{};
    if (m.control) control = [&m](double t) -> Vec3 { return (*m.control)(t); };
    if (m.feedback) {
      const baselines::AttitudeMechanicsWithMoment<System> mech(
          m.system, control,
          [&m](double t, const Mat3& R, const Vec3& Omega) {
            return m.system.control_moment(R, SystemBinding<M>::feedback_control(m, t, R, Omega));
          },
          {.time = m.feedback->depends_on_time(), .rate = true});
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
