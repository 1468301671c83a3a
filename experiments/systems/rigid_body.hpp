// The part of the bindings the single rigid bodies on SE(3) share (the dumbbell, the potential
// body on SE(3)): the state record (R, Omega, x, v), the RigidBodyLgvi flow map, the
// RigidBodyMechanics continuous model, and the time-dependent force and moment controls.
#pragma once

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "baselines/mechanics.hpp"
#include "experiments/systems/binding.hpp"
#include "lgvi/lgvi.hpp"

namespace lgvi::experiments {

struct RigidBodyInitial {
  Mat3 R = Mat3::Identity();
  Vec3 Omega = Vec3::Zero();
  Vec3 x = Vec3::Zero();
  Vec3 v = Vec3::Zero();
};

/// The shared part of SystemBinding<M> for a model M with members `system` (a RigidBodySystem),
/// `initial` (RigidBodyInitial) and the optional controls `force_control` (inertial frame) and
/// `moment_control` (body frame). The system's binding adds its scene tables, its conserved
/// momentum, printed order, units and labels.
template <class M>
struct RigidBodyBinding {
  using State = RigidBodyInitial;
  using System = std::decay_t<decltype(M::system)>;
  static constexpr bool single_body = true;

  /// [initial]: R/quaternion/euler (default identity), Omega, x, v.
  static void check_initial_keys(const SceneReader& r, const SceneTable& initial) {
    r.check_keys(initial, concat_keys({SceneReader::attitude_keys("R"), SceneReader::body_rate_keys("Omega"), {"x", "v"}}));
  }
  /// [control]: sub-tables force (inertial frame) and moment (body frame), each a sinusoid.
  static void check_control_keys(const SceneReader& r, const SceneTable& control) {
    r.check_keys(control, {"force", "moment"});
    for (const char* key : {"force", "moment"}) {
      if (const std::optional<SceneTable> sub = r.table(control, key, false)) {
        r.check_keys(*sub, SceneReader::kSinusoidKeys);
      }
    }
  }
  static State read_initial(const SceneReader& r, const SceneTable& initial) {
    State init;
    init.R = r.attitude(initial, "R");
    init.Omega = r.body_rate(initial, "Omega", init.R);
    init.x = r.vec3(initial, "x");
    init.v = r.vec3(initial, "v");
    return init;
  }
  /// Reads the optional [control] sub-tables into m and validates the initial state.
  static void read_controls_and_check(const SceneReader& r, M& m, const std::optional<SceneTable>& control) {
    if (control) {
      if (const std::optional<SceneTable> f = r.table(*control, "force", false)) m.force_control = r.sinusoid(*f);
      if (const std::optional<SceneTable> mo = r.table(*control, "moment", false)) m.moment_control = r.sinusoid(*mo);
    }
    const State& init = m.initial;
    r.validate_initial_state(RigidBodyLgvi<System>(m.system), m.system.energy(init.R, init.x, init.Omega, init.v),
                             init.R, init.x, init.Omega, init.v);
  }

  static void state_columns(std::vector<std::string>& c) {
    matrix_columns(c, "R");
    vector_columns(c, "Omega");
    vector_columns(c, "x");
    vector_columns(c, "v");
  }
  static std::size_t write_state(const State& s, double* row, std::size_t n) {
    n = write_matrix(s.R, row, n);
    n = write_vector(s.Omega, row, n);
    n = write_vector(s.x, row, n);
    return write_vector(s.v, row, n);
  }
  static Conserved conserved(const M& m, const State& s, double /*t*/) {
    return {m.system.energy(s.R, s.x, s.Omega, s.v), m.system.angular_momentum(s.R, s.x, s.Omega, s.v), 3};
  }
  /// The columns of the angular momentum the system conserves (its binding's momentum_map names it).
  static std::vector<std::string> momentum_columns() {
    return {"angular_momentum1", "angular_momentum2", "angular_momentum3"};
  }
  static double orthogonality_error(const State& s) { return so3::orthogonality_error(s.R); }
  static double determinant_error(const State& s) { return so3::determinant_error(s.R); }
  static double final_state_error(const State& s, const State& ref) {
    const double e = std::max((s.R - ref.R).norm(), relative_error(s.Omega, ref.Omega));
    return std::max({e, relative_error(s.x, ref.x), relative_error(s.v, ref.v)});
  }
  static double distance(const State& a, const State& b) {
    return (a.R - b.R).norm() + (a.Omega - b.Omega).norm() + (a.x - b.x).norm() + (a.v - b.v).norm();
  }
  static double initial_rate(const M& m) { return m.initial.Omega.norm(); }
  static void drop_controls(M& m) {
    m.force_control.reset();
    m.moment_control.reset();
  }
  static void delay_controls(M& m, double dt) {
    if (m.force_control) m.force_control->delay += dt;
    if (m.moment_control) m.moment_control->delay += dt;
  }
  template <class Drive>
  static Stats run_lgvi(const M& m, LgviForm form, const RotationUpdateOptions& options, Drive&& drive) {
    const RigidBodyLgvi<System> lgvi(m.system, form, options);
    RigidBodyState state = lgvi.make_state(m.initial.R, m.initial.x, m.initial.Omega, m.initial.v);
    const auto control = [&m](double t) { return control_at(m, t); };
    const auto to_state = [&](const RigidBodyState& s, State& out) {
      out.R = s.R;
      out.Omega = lgvi.omega(s);
      out.x = s.x;
      out.v = s.v;
    };
    return drive(lgvi, state, control, to_state);
  }

  template <class Chart>
  static Stats run_baseline(const M& m, Chart&& chart) {
    auto control = std::function<Wrench(double)>{};
    if (m.force_control || m.moment_control) control = [&m](double t) { return control_at(m, t); };
    const baselines::RigidBodyMechanics<System> mech(m.system, control);
    return chart(mech, std::array<Mat3, 1>{m.initial.R}, std::array<Vec3, 1>{m.initial.Omega}, m.initial.x,
                 m.initial.v);
  }
  template <class Decoded>
  static void from_chart(const Decoded& d, State& s) {
    s.R = d.config.R[0];
    s.Omega = d.rates.Omega[0];
    s.x = d.config.x;
    s.v = d.rates.x_dot;
  }

 private:
  static Wrench control_at(const M& m, double t) {
    Wrench u;
    if (m.force_control) u.force = (*m.force_control)(t);
    if (m.moment_control) u.moment = (*m.moment_control)(t);
    return u;
  }
};

}  // namespace lgvi::experiments
