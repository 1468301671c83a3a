// The part of the bindings the single-attitude systems share (free body, pendulum): one rigid
// body on SO(3), the AttitudeLgvi flow map, the AttitudeMechanics continuous model.
#pragma once

#include <array>
#include <functional>

#include "baselines/mechanics.hpp"
#include "experiments/system_binding.hpp"
#include "lgvi/lgvi.hpp"

namespace lgvi::experiments {

template <class M>
struct AttitudeBinding {
  using State = typename M::State;
  static constexpr bool single_body = true;

  /// [parameters]: SystemBinding<M>::kParameterKeys; [initial]: R (default identity), Omega;
  /// [control]: a sinusoid (the body-frame moment, or the pendulum's u of eq. 23).
  static void check_keys(const SceneReader& r, const SceneTable& parameters, const SceneTable& initial) {
    r.check_keys(parameters, SystemBinding<M>::kParameterKeys);
    r.check_keys(initial, concat_keys({SceneReader::attitude_keys("R"), {"Omega"}}));
  }
  static void check_control_keys(const SceneReader& r, const SceneTable& control) {
    r.check_keys(control, SceneReader::kSinusoidKeys);
  }
  static M read(const SceneReader& r, const SceneTable& parameters, const SceneTable& initial,
                const std::optional<SceneTable>& control) {
    M m{SystemBinding<M>::read_parameters(r, parameters), State{r.attitude(initial, "R"), r.vec3(initial, "Omega")}, {}};
    if (control) m.control = r.sinusoid(*control);
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
  static void drop_controls(M& m) { m.control.reset(); }
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
    return drive(lgvi, state, control, to_state);
  }

  template <class Chart>
  static Stats run_baseline(const M& m, Chart&& chart) {
    using System = std::decay_t<decltype(m.system)>;
    auto control = std::function<Vec3(double)>{};
    if (m.control) control = [&m](double t) -> Vec3 { return (*m.control)(t); };
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
