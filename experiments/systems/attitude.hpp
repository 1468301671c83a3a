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
  static constexpr bool single_body = true;

  static void state_columns(std::vector<std::string>& c) {
    matrix_columns(c, "R");
    vector_columns(c, "Omega");
  }
  static std::size_t write_state(const Sample& s, double* row, std::size_t n) {
    n = write_matrix(s.R, row, n);
    return write_vector(s.Omega, 3, row, n);
  }
  static double orthogonality_error(const Sample& s) { return so3::orthogonality_error(s.R); }
  static double determinant_error(const Sample& s) { return so3::determinant_error(s.R); }
  static double final_state_error(const Sample& s, const Sample& ref) {
    return std::max((s.R - ref.R).norm(), relative_error(s.Omega, ref.Omega));
  }
  static double initial_rate(const M& m) { return m.initial.Omega.norm(); }
  static void drop_controls(M& m) { m.control.reset(); }

  template <class Drive>
  static Stats run_lgvi(const M& m, LgviForm form, const RotationUpdateOptions& options, Drive&& drive) {
    using System = std::decay_t<decltype(m.system)>;
    const AttitudeLgvi<System> lgvi(m.system, form, options);
    AttitudeState state = lgvi.make_state(m.initial.R, m.initial.Omega);
    const auto control = [&m](double t) -> Vec3 { return m.control ? (*m.control)(t) : Vec3::Zero(); };
    const auto to_sample = [&](const AttitudeState& s, Sample& sample) {
      sample.R = s.R;
      sample.Omega = lgvi.omega(s);
    };
    return drive(lgvi, state, control, to_sample);
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
  static void from_chart(const Decoded& d, Sample& s) {
    s.R = d.config.R[0];
    s.Omega = d.rates.Omega[0];
  }
};

}  // namespace lgvi::experiments
