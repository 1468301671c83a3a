// The 3D pendulum on a cart in the harness (scene system "cart-pendulum"): SO(3) x R^2; its
// state record carries the cart's q = (x, y) and q_dot = (x', y').
#pragma once

#include <array>
#include <functional>

#include "baselines/mechanics.hpp"
#include "experiments/systems/binding.hpp"
#include "lgvi/multibody_lgvi.hpp"

namespace lgvi::experiments {

struct CartPendulumInitial {
  Mat3 R = Mat3::Identity();
  Vec3 Omega = Vec3::Zero();
  Vec2 q = Vec2::Zero();      ///< cart position (x, y)
  Vec2 q_dot = Vec2::Zero();  ///< cart velocity
};

struct CartPendulumModel {
  using State = CartPendulumInitial;
  static constexpr const char* name = "cart-pendulum";
  CartPendulum system;
  State initial;
  std::optional<TimeControl> control;  ///< cart forces (u_x, u_y) in components 1, 2; component 3 is 0
};

template <std::same_as<CartPendulumModel> BoundModel>
struct SystemBinding<BoundModel> {
  using M = CartPendulumModel;
  using State = M::State;
  static constexpr bool single_body = false;
  /// Its LGVI forms R_{k+1} = R_k + R_k (F - I) by a compensated sum: R stays on SO(3) to a
  /// bounded few eps, not a random walk (validate's orthogonality floor).
  static constexpr bool lgvi_attitude_compensated = true;

  /// [parameters]: cart_mass, mass, inertia, d, gravity; [initial]: R/quaternion/euler (default identity),
  /// Omega, q, q_dot; [control]: a 2-component sinusoid (the cart's forces u_x, u_y).
  static void check_keys(const SceneReader& r, const SceneTable& parameters, const SceneTable& initial) {
    r.check_keys(parameters, {"cart_mass", "mass", "inertia", "d", "gravity"});
    r.check_keys(initial, concat_keys({SceneReader::attitude_keys("R"), SceneReader::body_rate_keys("Omega"), {"q", "q_dot"}}));
  }
  static void check_control_keys(const SceneReader& r, const SceneTable& control) {
    r.check_keys(control, SceneReader::kSinusoidKeys);
  }
  static M read(const SceneReader& r, const SceneTable& parameters, const SceneTable& initial,
                const std::optional<SceneTable>& control) {
    const double cart_mass = r.number(parameters, "cart_mass");
    const double mass = r.number(parameters, "mass");
    const Mat3 J = r.inertia(parameters, "inertia");
    const Vec3 d = r.vec3(parameters, "d");
    const double g = r.number(parameters, "gravity");
    State init;
    init.R = r.attitude(initial, "R");
    init.Omega = r.body_rate(initial, "Omega", init.R);
    init.q = r.vec2(initial, "q");
    init.q_dot = r.vec2(initial, "q_dot");
    M m{r.physics("parameters.", [&] { return CartPendulum(cart_mass, mass, J, d, g); }), init, {}};
    if (control) m.control = r.sinusoid2(*control);
    r.validate_initial_state(CartPendulumLgvi(m.system), m.system.energy(init.R, init.Omega, init.q_dot), init.R,
                             init.q, init.Omega, init.q_dot);
    return m;
  }

  static void state_columns(std::vector<std::string>& c) {
    matrix_columns(c, "R");
    vector_columns(c, "Omega");
    for (const char* name : {"x", "y", "xdot", "ydot"}) c.push_back(name);
  }
  static std::size_t write_state(const State& s, double* row, std::size_t n) {
    n = write_matrix(s.R, row, n);
    n = write_vector(s.Omega, row, n);
    n = write_vector(s.q, row, n);
    return write_vector(s.q_dot, row, n);
  }
  static Conserved conserved(const M& m, const State& s, double /*t*/) {
    Vec3 Pi;
    Vec2 p;
    m.system.momenta(s.R, s.Omega, s.q_dot, Pi, p);
    return {m.system.energy(s.R, s.Omega, s.q_dot), Vec3(m.system.vertical_momentum(s.R, s.q, Pi, p), 0.0, 0.0), 1};
  }
  static MomentumMap momentum_map() {
    return {"vertical angular momentum e3^T R Pi + x p_y - y p_x (momenta of eq. 37)", {"vertical_momentum"}};
  }
  static double orthogonality_error(const State& s) { return so3::orthogonality_error(s.R); }
  static double determinant_error(const State& s) { return so3::determinant_error(s.R); }
  static double final_state_error(const State& s, const State& ref) {
    const double e = std::max((s.R - ref.R).norm(), relative_error(s.Omega, ref.Omega));
    return std::max({e, relative_error(s.q, ref.q), relative_error(s.q_dot, ref.q_dot)});
  }
  static double distance(const State& a, const State& b) {
    return (a.R - b.R).norm() + (a.Omega - b.Omega).norm() + (a.q - b.q).norm() + (a.q_dot - b.q_dot).norm();
  }
  static double initial_rate(const M& m) { return m.initial.Omega.norm(); }
  /// Eq. 29 splits the potential symmetrically in both forms: the printed form is first order
  /// only through a control at the step's end.
  static int printed_order(const M& m) { return m.control ? 1 : 2; }
  static void drop_controls(M& m) { m.control.reset(); }
  static void delay_controls(M& m, double dt) {
    if (m.control) m.control->delay += dt;
  }
  static std::string units() {
    return "t [s], R [1], Omega [rad/s], energy [J], momentum [kg m^2/s], x y [m], xdot ydot [m/s]";
  }
  static SystemLabels labels() {
    return {"time [s]", "|E - E_0| [J]", "|e_3^T R Π + x p_y - y p_x - (...)_0| [kg m^2/s]", " s"};
  }

  template <class Drive>
  static Stats run_lgvi(const M& m, LgviForm form, const RotationUpdateOptions& options, Drive&& drive) {
    // Its Newton solver has its own options (GroupNewtonOptions); of the rotation update's it
    // takes only how the attitude sum is formed.
    const CartPendulumLgvi lgvi(m.system, form, GroupNewtonOptions{}, options.compensated_attitude);
    CartPendulumState state = lgvi.make_state(m.initial.R, m.initial.q, m.initial.Omega, m.initial.q_dot);
    const auto control = [&m](double t) -> Vec2 {
      if (!m.control) return Vec2::Zero();
      const Vec3 u = (*m.control)(t);
      return Vec2(u.x(), u.y());
    };
    const auto to_state = [&](const CartPendulumState& s, State& out) {
      out.R = s.R;
      out.q = s.q;
      lgvi.velocities(s, out.Omega, out.q_dot);
    };
    return drive(lgvi, state, control, to_state);
  }

  template <class Chart>
  static Stats run_baseline(const M& m, Chart&& chart) {
    auto control = std::function<CartPendulum::Control(double)>{};
    if (m.control) control = [&m](double t) -> Vec2 { return (*m.control)(t).template head<2>(); };
    const baselines::CartPendulumMechanics mech(m.system, control);
    return chart(mech, std::array<Mat3, 1>{m.initial.R}, std::array<Vec3, 1>{m.initial.Omega}, m.initial.q,
                 m.initial.q_dot);
  }
  template <class Decoded>
  static void from_chart(const Decoded& d, State& s) {
    s.R = d.config.R[0];
    s.Omega = d.rates.Omega[0];
    s.q = d.config.x;
    s.q_dot = d.rates.x_dot;
  }
};

}  // namespace lgvi::experiments
