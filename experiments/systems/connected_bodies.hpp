// The two connected rigid bodies in the harness (scene system "connected-bodies"): SO(3) x
// SO(3); its state record carries both bodies' R1, R2, Omega1, Omega2.
#pragma once

#include <algorithm>
#include <array>
#include <functional>

#include "baselines/mechanics.hpp"
#include "experiments/systems/binding.hpp"
#include "lgvi/multibody_lgvi.hpp"

namespace lgvi::experiments {

struct ConnectedBodiesInitial {
  Mat3 R1 = Mat3::Identity(), R2 = Mat3::Identity();
  Vec3 Omega1 = Vec3::Zero(), Omega2 = Vec3::Zero();
};

struct ConnectedBodiesModel {
  using State = ConnectedBodiesInitial;
  static constexpr const char* name = "connected-bodies";
  ConnectedBodies system;
  State initial;
  std::optional<TimeControl> control;  ///< internal moment u (inertial frame): +u on body 1, -u on body 2
};

template <std::same_as<ConnectedBodiesModel> BoundModel>
struct SystemBinding<BoundModel> {
  using M = ConnectedBodiesModel;
  using State = M::State;
  static constexpr bool single_body = false;

  /// [parameters]: mass1, inertia1, d1, mass2, inertia2, d2; [initial]: R1, R2 or quaternion1/2, euler1/2 (default
  /// identity), Omega1, Omega2; [control]: a sinusoid (the internal moment, inertial frame).
  static void check_keys(const SceneReader& r, const SceneTable& parameters, const SceneTable& initial) {
    r.check_keys(parameters, {"mass1", "inertia1", "d1", "mass2", "inertia2", "d2"});
    r.check_keys(initial,
                 concat_keys({SceneReader::attitude_keys("R1"), SceneReader::attitude_keys("R2"),
                              SceneReader::body_rate_keys("Omega1"), SceneReader::body_rate_keys("Omega2")}));
  }
  static void check_control_keys(const SceneReader& r, const SceneTable& control) {
    r.check_keys(control, SceneReader::kSinusoidKeys);
  }
  static M read(const SceneReader& r, const SceneTable& parameters, const SceneTable& initial,
                const std::optional<SceneTable>& control) {
    const double m1 = r.number(parameters, "mass1");
    const Mat3 J1 = r.inertia(parameters, "inertia1");
    const Vec3 d1 = r.vec3(parameters, "d1");
    const double m2 = r.number(parameters, "mass2");
    const Mat3 J2 = r.inertia(parameters, "inertia2");
    const Vec3 d2 = r.vec3(parameters, "d2");
    State init;
    init.R1 = r.attitude(initial, "R1");
    init.R2 = r.attitude(initial, "R2");
    init.Omega1 = r.body_rate(initial, "Omega1", init.R1);
    init.Omega2 = r.body_rate(initial, "Omega2", init.R2);
    M m{r.physics("parameters.", [&] { return ConnectedBodies(m1, J1, d1, m2, J2, d2); }), init, {}};
    if (control) m.control = r.sinusoid(*control);
    r.validate_initial_state(ConnectedBodiesLgvi(m.system), m.system.energy(init.R1, init.R2, init.Omega1, init.Omega2),
                             init.R1, init.R2, init.Omega1, init.Omega2);
    return m;
  }

  static void state_columns(std::vector<std::string>& c) {
    matrix_columns(c, "R1_");
    matrix_columns(c, "R2_");
    vector_columns(c, "Omega1_");
    vector_columns(c, "Omega2_");
  }
  static std::size_t write_state(const State& s, double* row, std::size_t n) {
    n = write_matrix(s.R1, row, n);
    n = write_matrix(s.R2, row, n);
    n = write_vector(s.Omega1, row, n);
    return write_vector(s.Omega2, row, n);
  }
  static Conserved conserved(const M& m, const State& s, double /*t*/) {
    Vec3 Pi1, Pi2;
    m.system.momenta(s.R1, s.R2, s.Omega1, s.Omega2, Pi1, Pi2);
    return {m.system.energy(s.R1, s.R2, s.Omega1, s.Omega2), ConnectedBodies::total_angular_momentum(s.R1, s.R2, Pi1, Pi2),
            3};
  }
  static MomentumMap momentum_map() {
    return {"total angular momentum R1 Pi1 + R2 Pi2 (momenta of eq. 47)",
            {"angular_momentum1", "angular_momentum2", "angular_momentum3"}};
  }
  /// The worse of the two attitudes.
  static double orthogonality_error(const State& s) {
    return std::max(so3::orthogonality_error(s.R1), so3::orthogonality_error(s.R2));
  }
  static double determinant_error(const State& s) {
    return std::max(so3::determinant_error(s.R1), so3::determinant_error(s.R2));
  }
  static double final_state_error(const State& s, const State& ref) {
    const double e = std::max((s.R1 - ref.R1).norm(), relative_error(s.Omega1, ref.Omega1));
    return std::max({e, (s.R2 - ref.R2).norm(), relative_error(s.Omega2, ref.Omega2)});
  }
  static double distance(const State& a, const State& b) {
    return (a.R1 - b.R1).norm() + (a.Omega1 - b.Omega1).norm() + (a.R2 - b.R2).norm() + (a.Omega2 - b.Omega2).norm();
  }
  static double initial_rate(const M& m) { return std::max(m.initial.Omega1.norm(), m.initial.Omega2.norm()); }
  /// No potential (eq. 39): the printed form is first order only through a control at the step's
  /// end.
  static int printed_order(const M& m) { return m.control ? 1 : 2; }
  static void drop_controls(M& m) { m.control.reset(); }
  static void delay_controls(M& m, double dt) {
    if (m.control) m.control->delay += dt;
  }
  static std::string units() { return "t [s], R [1], Omega [rad/s], energy [J], momentum [kg m^2/s]"; }
  static SystemLabels labels() { return {"time [s]", "|E - E_0| [J]", "|R_1 Π_1 + R_2 Π_2 - (...)_0| [kg m^2/s]", " s"}; }

  template <class Drive>
  static Stats run_lgvi(const M& m, LgviForm form, const RotationUpdateOptions& /*options*/, Drive&& drive) {
    const ConnectedBodiesLgvi lgvi(m.system, form);
    ConnectedBodiesState state = lgvi.make_state(m.initial.R1, m.initial.R2, m.initial.Omega1, m.initial.Omega2);
    const auto control = [&m](double t) -> Vec3 { return m.control ? (*m.control)(t) : Vec3::Zero(); };
    const auto to_state = [&](const ConnectedBodiesState& s, State& out) {
      out.R1 = s.R1;
      out.R2 = s.R2;
      lgvi.velocities(s, out.Omega1, out.Omega2);
    };
    return drive(lgvi, state, control, to_state);
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
  static void from_chart(const Decoded& d, State& s) {
    s.R1 = d.config.R[0];
    s.Omega1 = d.rates.Omega[0];
    s.R2 = d.config.R[1];
    s.Omega2 = d.rates.Omega[1];
  }
};

}  // namespace lgvi::experiments
