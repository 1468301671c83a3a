// The two connected rigid bodies in the harness (scene system "connected-bodies"): SO(3) x
// SO(3). The sample's R, Omega are body 1's, R2, Omega2 body 2's.
#pragma once

#include <algorithm>
#include <array>
#include <functional>

#include "baselines/mechanics.hpp"
#include "experiments/system_binding.hpp"
#include "lgvi/multibody_lgvi.hpp"

namespace lgvi::experiments {

template <>
struct SystemBinding<ConnectedBodiesModel> {
  using M = ConnectedBodiesModel;
  static constexpr bool single_body = false;

  static void state_columns(std::vector<std::string>& c) {
    matrix_columns(c, "R1_");
    matrix_columns(c, "R2_");
    vector_columns(c, "Omega1_");
    vector_columns(c, "Omega2_");
  }
  static std::size_t write_state(const Sample& s, double* row, std::size_t n) {
    n = write_matrix(s.R, row, n);
    n = write_matrix(s.R2, row, n);
    n = write_vector(s.Omega, 3, row, n);
    return write_vector(s.Omega2, 3, row, n);
  }
  static Conserved conserved(const M& m, const Sample& s) {
    Vec3 Pi1, Pi2;
    m.system.momenta(s.R, s.R2, s.Omega, s.Omega2, Pi1, Pi2);
    return {m.system.energy(s.R, s.R2, s.Omega, s.Omega2), ConnectedBodies::total_angular_momentum(s.R, s.R2, Pi1, Pi2),
            3};
  }
  static MomentumMap momentum_map() {
    return {"total angular momentum R1 Pi1 + R2 Pi2 (momenta of eq. 47)",
            {"angular_momentum1", "angular_momentum2", "angular_momentum3"}};
  }
  /// The worse of the two attitudes.
  static double orthogonality_error(const Sample& s) {
    return std::max(so3::orthogonality_error(s.R), so3::orthogonality_error(s.R2));
  }
  static double determinant_error(const Sample& s) {
    return std::max(so3::determinant_error(s.R), so3::determinant_error(s.R2));
  }
  static double final_state_error(const Sample& s, const Sample& ref) {
    const double e = std::max((s.R - ref.R).norm(), relative_error(s.Omega, ref.Omega));
    return std::max({e, (s.R2 - ref.R2).norm(), relative_error(s.Omega2, ref.Omega2)});
  }
  static double initial_rate(const M& m) { return std::max(m.initial.Omega1.norm(), m.initial.Omega2.norm()); }
  static void drop_controls(M& m) { m.control.reset(); }
  static SystemLabels labels() { return {"time [s]", "|E - E_0| [J]", "|R_1 Π_1 + R_2 Π_2 - (...)_0| [kg m^2/s]"}; }

  template <class Drive>
  static Stats run_lgvi(const M& m, LgviForm form, const RotationUpdateOptions& /*options*/, Drive&& drive) {
    const ConnectedBodiesLgvi lgvi(m.system, form);
    ConnectedBodiesState state = lgvi.make_state(m.initial.R1, m.initial.R2, m.initial.Omega1, m.initial.Omega2);
    const auto control = [&m](double t) -> Vec3 { return m.control ? (*m.control)(t) : Vec3::Zero(); };
    const auto to_sample = [&](const ConnectedBodiesState& s, Sample& sample) {
      sample.R = s.R1;
      sample.R2 = s.R2;
      lgvi.velocities(s, sample.Omega, sample.Omega2);
    };
    return drive(lgvi, state, control, to_sample);
  }

  template <class Chart>
  static Stats run_baseline(const M& m, Chart&& chart) {
    auto control = std::function<Vec3(double)>{};
    if (m.control) control = [&m](double t) -> Vec3 { return (*m.control)(t); };
    const baselines::ConnectedBodiesMechanics mech(m.system, control);
    return chart(mech, std::array<Mat3, 2>{m.initial.R1, m.initial.R2},
                 std::array<Vec3, 2>{m.initial.Omega1, m.initial.Omega2}, baselines::Vector<0>(),
                 baselines::Vector<0>());
  }
  template <class Decoded>
  static void from_chart(const Decoded& d, Sample& s) {
    s.R = d.config.R[0];
    s.Omega = d.rates.Omega[0];
    s.R2 = d.config.R[1];
    s.Omega2 = d.rates.Omega[1];
  }
};

}  // namespace lgvi::experiments
