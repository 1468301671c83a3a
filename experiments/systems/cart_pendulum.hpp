// The 3D pendulum on a cart in the harness (scene system "cart-pendulum"): SO(3) x R^2. The
// sample carries the cart's (x, y) and (x', y') in the first two components of x and v.
#pragma once

#include <array>
#include <functional>

#include "baselines/mechanics.hpp"
#include "experiments/system_binding.hpp"
#include "lgvi/multibody_lgvi.hpp"

namespace lgvi::experiments {

template <>
struct SystemBinding<CartPendulumModel> {
  using M = CartPendulumModel;
  static constexpr bool single_body = false;

  static void state_columns(std::vector<std::string>& c) {
    matrix_columns(c, "R");
    vector_columns(c, "Omega");
    for (const char* name : {"x", "y", "xdot", "ydot"}) c.push_back(name);
  }
  static std::size_t write_state(const Sample& s, double* row, std::size_t n) {
    n = write_matrix(s.R, row, n);
    n = write_vector(s.Omega, 3, row, n);
    n = write_vector(s.x, 2, row, n);
    return write_vector(s.v, 2, row, n);
  }
  static Conserved conserved(const M& m, const Sample& s) {
    const Vec2 q = s.x.head<2>(), q_dot = s.v.head<2>();
    Vec3 Pi;
    Vec2 p;
    m.system.momenta(s.R, s.Omega, q_dot, Pi, p);
    return {m.system.energy(s.R, s.Omega, q_dot), Vec3(m.system.vertical_momentum(s.R, q, Pi, p), 0.0, 0.0), 1};
  }
  static MomentumMap momentum_map() {
    return {"vertical angular momentum e3^T R Pi + x p_y - y p_x (momenta of eq. 37)", {"vertical_momentum"}};
  }
  static double orthogonality_error(const Sample& s) { return so3::orthogonality_error(s.R); }
  static double determinant_error(const Sample& s) { return so3::determinant_error(s.R); }
  static double final_state_error(const Sample& s, const Sample& ref) {
    const double e = std::max((s.R - ref.R).norm(), relative_error(s.Omega, ref.Omega));
    return std::max({e, relative_error(s.x, ref.x), relative_error(s.v, ref.v)});
  }
  static double initial_rate(const M& m) { return m.initial.Omega.norm(); }
  static void drop_controls(M& m) { m.control.reset(); }
  static SystemLabels labels() {
    return {"time [s]", "|E - E_0| [J]", "|e_3^T R Π + x p_y - y p_x - (...)_0| [kg m^2/s]"};
  }

  template <class Drive>
  static Stats run_lgvi(const M& m, LgviForm form, const RotationUpdateOptions& /*options*/, Drive&& drive) {
    const CartPendulumLgvi lgvi(m.system, form);
    CartPendulumState state = lgvi.make_state(m.initial.R, m.initial.q, m.initial.Omega, m.initial.q_dot);
    const auto control = [&m](double t) -> Vec2 {
      if (!m.control) return Vec2::Zero();
      const Vec3 u = (*m.control)(t);
      return Vec2(u.x(), u.y());
    };
    const auto to_sample = [&](const CartPendulumState& s, Sample& sample) {
      Vec2 q_dot;
      sample.R = s.R;
      lgvi.velocities(s, sample.Omega, q_dot);
      sample.x << s.q, 0.0;
      sample.v << q_dot, 0.0;
    };
    return drive(lgvi, state, control, to_sample);
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
  static void from_chart(const Decoded& d, Sample& s) {
    s.R = d.config.R[0];
    s.Omega = d.rates.Omega[0];
    s.x << d.config.x, 0.0;  // (x, y, 0) and (x', y', 0), as the LGVI records them
    s.v << d.rates.x_dot, 0.0;
  }
};

}  // namespace lgvi::experiments
