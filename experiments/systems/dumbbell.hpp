// The dumbbell spacecraft in the harness (scene system "dumbbell"): one rigid body on SE(3).
#pragma once

#include <array>
#include <functional>

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

struct DumbbellModel {
  using State = RigidBodyInitial;
  static constexpr const char* name = "dumbbell";
  DumbbellSpacecraft system;
  State initial;
  std::optional<TimeControl> force_control;   ///< u^f, inertial frame
  std::optional<TimeControl> moment_control;  ///< u^m, body frame
};

template <std::same_as<DumbbellModel> BoundModel>
struct SystemBinding<BoundModel> {
  using M = DumbbellModel;
  using State = M::State;
  static constexpr bool single_body = true;

  /// [parameters]: mass, mu, rho, sphere_radius (J follows); [initial]: R/quaternion/euler (default identity),
  /// Omega, x, v; [control]: sub-tables force (inertial frame) and moment (body frame), each a
  /// sinusoid.
  static void check_keys(const SceneReader& r, const SceneTable& parameters, const SceneTable& initial) {
    r.check_keys(parameters, {"mass", "mu", "rho", "sphere_radius"});
    r.check_keys(initial, concat_keys({SceneReader::attitude_keys("R"), SceneReader::body_rate_keys("Omega"), {"x", "v"}}));
  }
  static void check_control_keys(const SceneReader& r, const SceneTable& control) {
    r.check_keys(control, {"force", "moment"});
    for (const char* key : {"force", "moment"}) {
      if (const std::optional<SceneTable> sub = r.table(control, key, false)) {
        r.check_keys(*sub, SceneReader::kSinusoidKeys);
      }
    }
  }
  static M read(const SceneReader& r, const SceneTable& parameters, const SceneTable& initial,
                const std::optional<SceneTable>& control) {
    const double mass = r.number(parameters, "mass");
    const double mu = r.number(parameters, "mu");
    const Vec3 rho = r.vec3(parameters, "rho");
    const double radius = r.number(parameters, "sphere_radius");
    State init;
    init.R = r.attitude(initial, "R");
    init.Omega = r.body_rate(initial, "Omega", init.R);
    init.x = r.vec3(initial, "x");
    init.v = r.vec3(initial, "v");
    M m{r.physics("parameters.", [&] { return DumbbellSpacecraft(mass, mu, rho, radius); }), init, {}, {}};
    if (control) {
      if (const std::optional<SceneTable> f = r.table(*control, "force", false)) m.force_control = r.sinusoid(*f);
      if (const std::optional<SceneTable> mo = r.table(*control, "moment", false)) m.moment_control = r.sinusoid(*mo);
    }
    r.validate_initial_state(DumbbellLgvi(m.system), m.system.energy(init.R, init.x, init.Omega, init.v), init.R,
                             init.x, init.Omega, init.v);
    return m;
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
  static MomentumMap momentum_map() {
    return {"total angular momentum x cross m v + R J Omega",
            {"angular_momentum1", "angular_momentum2", "angular_momentum3"}};
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
  /// The gravity force and moment act at the printed step's end: first order.
  static int printed_order(const M&) { return 1; }
  static void drop_controls(M& m) {
    m.force_control.reset();
    m.moment_control.reset();
  }
  static void delay_controls(M& m, double dt) {
    if (m.force_control) m.force_control->delay += dt;
    if (m.moment_control) m.moment_control->delay += dt;
  }
  static std::string units() {
    return "normalized: mass 1, reference orbit radius 1, mu = 1 (period 2 pi); t, x, v, Omega, energy, "
           "momentum in these units";
  }
  static SystemLabels labels() {
    return {"time [normalized: orbit period 2π]", "|E - E_0| [normalized]",
            "|H - H_0| [normalized],  H = x × m v + R J Ω", " (orbit period 2π)"};
  }

  template <class Drive>
  static Stats run_lgvi(const M& m, LgviForm form, const RotationUpdateOptions& options, Drive&& drive) {
    const DumbbellLgvi lgvi(m.system, form, options);
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
    auto control = std::function<DumbbellSpacecraft::Control(double)>{};
    if (m.force_control || m.moment_control) control = [&m](double t) { return control_at(m, t); };
    const baselines::DumbbellMechanics mech(m.system, control);
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
  static DumbbellSpacecraft::Control control_at(const M& m, double t) {
    DumbbellSpacecraft::Control u;
    if (m.force_control) u.force = (*m.force_control)(t);
    if (m.moment_control) u.moment = (*m.moment_control)(t);
    return u;
  }
};

}  // namespace lgvi::experiments
