// The optimal control part of each system's binding (scene [ocp] tables, `lgvi-testbed ocp`,
// `figures`, the shooting suite): which method of lgvi/ocp solves the system, its lgvi/ocp model,
// the problem record built from a scene, and the system's columns and labels in the ocp outputs.
// A system without a specialization has no optimal control (OcpBinding<M>::indirect and ::direct
// false). The harness consults these instead of branching on the system's name.
//
// OcpBinding<M> provides:
//   indirect, direct               which methods exist (lgvi/ocp/indirect.hpp, direct.hpp)
//   nu                             number of controls (W is nu x nu)
//   IndirectModel / DirectModel    the lgvi/ocp model of the method
//   transfer(m, target, t_final)   the method's boundary-condition record (initial state = the
//                                  scene's [initial])
//   system(m)                      the physical system the solver takes
//   violation_label                axis label of the terminal violation (shooting suite)
//   figure_script                  the gnuplot script of `figures` (experiments/plots/fig_*.gp)
//   continuous                     a continuous (Pontryagin) shooting exists (baselines/pontryagin.hpp):
//                                  solve_continuous(m, problem, options) and
//                                  continuous_costate(lambda_0), the discrete multiplier on the
//                                  continuous costate's coordinates
//   collocation                    continuous Hermite-Simpson collocation of the quaternion model
//                                  exists (lgvi/ocp/collocation.hpp, `ocp --solver collocation`);
//                                  collocation_columns: the names of its state y's entries and of
//                                  its controls in the trajectory CSV, collocation_quaternions the
//                                  number of quaternions at the head of y (the attitude systems
//                                  write R, Omega, q instead)
//   violation_norm, violation_parts   the summary's terminal violation: what its norm is, and
//                                  its parts {name, offset, size} in the residual
//   state_columns(c), state_row(row, lgvi, s)   the trajectory CSV's state columns
//   indirect only: control_columns(c), multiplier_columns(c) of the trajectory CSV;
//                cost_parts(form, h, steps, u, fields), the cost split by the control's parts
//   direct only: energy(lgvi, s) of the trajectory CSV, knot_layout (summary text)
#pragma once

#include <array>
#include <string>
#include <vector>

#include "baselines/pontryagin.hpp"
#include "experiments/output/fields.hpp"
#include "experiments/systems/systems.hpp"
#include "lgvi/ocp/direct.hpp"
#include "lgvi/ocp/indirect.hpp"
#include "lgvi/ocp/models.hpp"

namespace lgvi::experiments {

template <class M>
struct OcpBinding {
  static constexpr bool indirect = false;
  static constexpr bool direct = false;
  static constexpr bool collocation = false;
  static constexpr int nu = 0;
  static constexpr const char* violation_label = "";
  static constexpr const char* figure_script = "";
};

namespace ocp_binding_detail {
inline void append_matrix(std::vector<double>& row, const Mat3& R) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) row.push_back(R(i, j));
}
inline void matrix_names(std::vector<std::string>& c, const std::string& name) {
  for (char i = '1'; i <= '3'; ++i)
    for (char j = '1'; j <= '3'; ++j) c.push_back(name + i + j);
}
inline void vector_names(std::vector<std::string>& c, const std::string& name) {
  for (char i = '1'; i <= '3'; ++i) c.push_back(name + i);
}
}  // namespace ocp_binding_detail

/// A part of the terminal residual r: the summary's `name` is |r.segment(offset, size)|.
struct ResidualPart {
  const char* name;
  int offset;
  int size;
};

/// The indirect method's part that the single-attitude systems share (free body, pendulum): the
/// transfer on SO(3) and the columns of its outputs. M is the scene model.
template <class M>
struct AttitudeOcpBinding {
  static constexpr bool indirect = true;
  static constexpr bool direct = false;
  static constexpr bool collocation = true;
  static constexpr int nu = 3;
  static ocp::TransferProblem transfer(const M& m, const AttitudeInitial& target, double t_final) {
    ocp::TransferProblem p;
    p.R0 = m.initial.R;
    p.Omega0 = m.initial.Omega;
    p.Rf = target.R;
    p.Omegaf = target.Omega;
    p.t_final = t_final;
    return p;
  }
  static constexpr const char* violation_label = "|r| = |[log(R_f^T R(T)); Ω(T) - Ω_f]| [rad, rad/s]";
  /// The pendulum's figure draws any single attitude: R e3 and R e1, u, the shooting, Ω.
  static constexpr const char* figure_script = "fig_pendulum.gp";
  static constexpr const char* violation_norm = "2-norm of [log(R_f^T R_N)^vee; Omega_N - Omega_f]";
  static constexpr std::array<ResidualPart, 2> violation_parts = {
      {{"violation_rotation", 0, 3}, {"violation_angular_velocity", 3, 3}}};
  static void state_columns(std::vector<std::string>& c) {
    ocp_binding_detail::matrix_names(c, "R");
    ocp_binding_detail::vector_names(c, "Omega");
  }
  static void control_columns(std::vector<std::string>& c) { ocp_binding_detail::vector_names(c, "u"); }
  static void multiplier_columns(std::vector<std::string>& c) {
    ocp_binding_detail::vector_names(c, "lambda_R");
    ocp_binding_detail::vector_names(c, "lambda_Pi");
  }
  template <class Lgvi, class State>
  static void state_row(std::vector<double>& row, const Lgvi& lgvi, const State& s) {
    ocp_binding_detail::append_matrix(row, s.R);
    const Vec3 Omega = lgvi.omega(s);
    for (int i = 0; i < 3; ++i) row.push_back(Omega(i));
  }
  /// One control (the moment): no split of the cost.
  template <class Controls>
  static void cost_parts(LgviForm, double, std::size_t, const Controls&, Fields&) {}
};

/// The 3D pendulum (section 3.2): indirect shooting with the symmetry decomposition.
template <>
struct OcpBinding<PendulumModel> : AttitudeOcpBinding<PendulumModel> {
  using IndirectModel = ocp::PendulumModel;
  static const Pendulum3D& system(const PendulumModel& m) { return m.system; }
  static constexpr bool continuous = true;
  static baselines::ContinuousShootingResult solve_continuous(const PendulumModel& m, const ocp::TransferProblem& p,
                                                              const baselines::ContinuousShootingOptions& o) {
    return baselines::solve_pontryagin(m.system, p, o);
  }
  static Eigen::VectorXd continuous_costate(const Eigen::VectorXd& discrete) {
    return baselines::continuous_costate_from_discrete(discrete);
  }
};

/// The free rigid body with a body-frame control moment (a spacecraft slew): indirect shooting
/// (lgvi/ocp/models.hpp FreeBodyModel).
template <>
struct OcpBinding<FreeBodyModel> : AttitudeOcpBinding<FreeBodyModel> {
  using IndirectModel = ocp::FreeBodyModel;
  static const FreeRigidBody& system(const FreeBodyModel& m) { return m.system; }
  /// The optimal control model has no gravity-gradient moment: a scene on an orbit is refused.
  static void check_scene(const SceneReader& r, const FreeBodyModel& m) {
    if (m.gravity_gradient) {
      r.fail("parameters.orbit_rate", "the free body's optimal control model has no gravity-gradient moment "
                                      "(remove orbit_rate, or [ocp])");
    }
  }
  static constexpr bool continuous = false;
};

/// The dumbbell spacecraft (section 3.1): indirect shooting on SE(3).
template <>
struct OcpBinding<DumbbellModel> {
  static constexpr bool indirect = true;
  static constexpr bool direct = false;
  static constexpr bool collocation = true;
  static constexpr int collocation_quaternions = 1;
  static constexpr std::array<const char*, 19> collocation_columns = {
      "q0", "q1", "q2", "q3", "x1", "x2", "x3", "Omega1", "Omega2", "Omega3", "v1", "v2", "v3",
      "um1", "um2", "um3", "uf1", "uf2", "uf3"};
  static constexpr int nu = 6;
  using IndirectModel = ocp::DumbbellModel;
  static const DumbbellSpacecraft& system(const DumbbellModel& m) { return m.system; }
  static ocp::TransferProblem transfer(const DumbbellModel& m, const RigidBodyInitial& target, double t_final) {
    ocp::TransferProblem p;
    p.R0 = m.initial.R;
    p.x0 = m.initial.x;
    p.Omega0 = m.initial.Omega;
    p.v0 = m.initial.v;
    p.Rf = target.R;
    p.xf = target.x;
    p.Omegaf = target.Omega;
    p.vf = target.v;
    p.t_final = t_final;
    return p;
  }
  static constexpr const char* violation_label = "|r| [normalized: rad, length, rad/time, length/time]";
  static constexpr const char* figure_script = "fig_dumbbell.gp";
  static constexpr const char* violation_norm =
      "2-norm of [log(R_f^T R_N)^vee; x_N - x_f; Omega_N - Omega_f; v_N - v_f]";
  static constexpr std::array<ResidualPart, 4> violation_parts = {{{"violation_rotation", 0, 3},
                                                                   {"violation_position", 3, 3},
                                                                   {"violation_angular_velocity", 6, 3},
                                                                   {"violation_velocity", 9, 3}}};
  static void state_columns(std::vector<std::string>& c) {
    ocp_binding_detail::matrix_names(c, "R");
    ocp_binding_detail::vector_names(c, "x");
    ocp_binding_detail::vector_names(c, "Omega");
    ocp_binding_detail::vector_names(c, "v");
  }
  static void control_columns(std::vector<std::string>& c) {
    ocp_binding_detail::vector_names(c, "um");
    ocp_binding_detail::vector_names(c, "uf");
  }
  static void multiplier_columns(std::vector<std::string>& c) {
    for (const char* block : {"lambda_R", "lambda_x", "lambda_Pi", "lambda_p"}) ocp_binding_detail::vector_names(c, block);
  }
  static void state_row(std::vector<double>& row, const DumbbellLgvi& lgvi, const RigidBodyState& s) {
    ocp_binding_detail::append_matrix(row, s.R);
    for (int i = 0; i < 3; ++i) row.push_back(s.x(i));
    const Vec3 Omega = lgvi.omega(s);
    for (int i = 0; i < 3; ++i) row.push_back(Omega(i));
    for (int i = 0; i < 3; ++i) row.push_back(s.v(i));
  }
  /// The cost split into the moment and the force controls, each sum_k c_k/2 |u_k part|^2 with
  /// the form's impulse weights (valid for W = I only: the caller checks).
  template <class Controls>
  static void cost_parts(LgviForm form, double h, std::size_t steps, const Controls& u, Fields& f) {
    double moment = 0.0, force = 0.0;
    const auto [c0, c1] = impulse_weights(form, h);
    for (std::size_t j = 0; j < u.size(); ++j) {
      const double w = j == 0 ? c0 : j == steps ? c1 : c0 + c1;
      moment += 0.5 * w * u[j].template head<3>().squaredNorm();
      force += 0.5 * w * u[j].template tail<3>().squaredNorm();
    }
    f.push_back({"cost_moment", moment});
    f.push_back({"cost_force", force});
  }
  static constexpr bool continuous = true;
  static baselines::DumbbellContinuousShootingResult solve_continuous(const DumbbellModel& m,
                                                                      const ocp::TransferProblem& p,
                                                                      const baselines::ContinuousShootingOptions& o) {
    return baselines::solve_pontryagin(m.system, p, o);
  }
  /// The discrete lambda_0 is the continuous costate's coordinates already (the identity).
  static Eigen::VectorXd continuous_costate(const Eigen::VectorXd& discrete) { return discrete; }
};

/// The pendulum on a cart (section 4.1): the direct method, controls the cart forces (u_x, u_y).
template <>
struct OcpBinding<CartPendulumModel> {
  static constexpr bool indirect = false;
  static constexpr bool direct = true;
  static constexpr bool collocation = true;
  /// the momentum form of eq. 37: Pi, p the momenta
  static constexpr int collocation_quaternions = 1;
  static constexpr std::array<const char*, 13> collocation_columns = {
      "q0", "q1", "q2", "q3", "x", "y", "Pi1", "Pi2", "Pi3", "px", "py", "ux", "uy"};
  static constexpr int nu = 2;
  using DirectModel = ocp::CartPendulumDirectModel;
  static const CartPendulum& system(const CartPendulumModel& m) { return m.system; }
  static ocp::CartPendulumTransfer transfer(const CartPendulumModel& m, const CartPendulumInitial& target,
                                            double t_final) {
    ocp::CartPendulumTransfer p;
    p.R0 = m.initial.R;
    p.q0 = m.initial.q;
    p.Omega0 = m.initial.Omega;
    p.q_dot0 = m.initial.q_dot;
    p.Rf = target.R;
    p.qf = target.q;
    p.Omegaf = target.Omega;
    p.q_dotf = target.q_dot;
    p.t_final = t_final;
    return p;
  }
  static constexpr const char* violation_label = "|terminal constraints| [rad, m, rad/s, m/s]";
  static constexpr const char* figure_script = "fig_cart_pendulum.gp";
  static constexpr bool continuous = false;
  static constexpr const char* violation_norm =
      "2-norm of [log(R_N^T R_f)^vee; q_N - q_f; Omega_N - Omega_f; qdot_N - qdot_f]";
  static constexpr const char* knot_layout = "u_x at the knots, then u_y";
  static void state_columns(std::vector<std::string>& c) {
    ocp_binding_detail::matrix_names(c, "R");
    ocp_binding_detail::vector_names(c, "Omega");
    for (const char* name : {"x", "y", "xdot", "ydot"}) c.push_back(name);
  }
  static void state_row(std::vector<double>& row, const CartPendulumLgvi& lgvi, const CartPendulumState& s) {
    Vec3 Omega;
    Vec2 q_dot;
    lgvi.velocities(s, Omega, q_dot);
    ocp_binding_detail::append_matrix(row, s.R);
    for (int i = 0; i < 3; ++i) row.push_back(Omega(i));
    row.insert(row.end(), {s.q.x(), s.q.y(), q_dot.x(), q_dot.y()});
  }
  static double energy(const CartPendulumLgvi& lgvi, const CartPendulumState& s) {
    Vec3 Omega;
    Vec2 q_dot;
    lgvi.velocities(s, Omega, q_dot);
    return lgvi.system().energy(s.R, Omega, q_dot);
  }
  static constexpr std::array<ResidualPart, 4> violation_parts = {{{"violation_rotation", 0, 3},
                                                                   {"violation_position", 3, 2},
                                                                   {"violation_angular_velocity", 5, 3},
                                                                   {"violation_velocity", 8, 2}}};
};

/// Two bodies joined by a ball joint (section 4.2): the direct method, the internal moment u.
template <>
struct OcpBinding<ConnectedBodiesModel> {
  static constexpr bool indirect = false;
  static constexpr bool direct = true;
  static constexpr bool collocation = true;
  /// the momentum form of eq. 47
  static constexpr int collocation_quaternions = 2;
  static constexpr std::array<const char*, 17> collocation_columns = {
      "q1_0", "q1_1", "q1_2", "q1_3", "q2_0", "q2_1", "q2_2", "q2_3", "Pi1_1", "Pi1_2", "Pi1_3",
      "Pi2_1", "Pi2_2", "Pi2_3", "u1", "u2", "u3"};
  static constexpr int nu = 3;
  using DirectModel = ocp::ConnectedBodiesDirectModel;
  static const ConnectedBodies& system(const ConnectedBodiesModel& m) { return m.system; }
  static ocp::ConnectedBodiesTransfer transfer(const ConnectedBodiesModel& m, const ConnectedBodiesInitial& target,
                                               double t_final) {
    ocp::ConnectedBodiesTransfer p;
    p.R1_0 = m.initial.R1;
    p.R2_0 = m.initial.R2;
    p.Omega1_0 = m.initial.Omega1;
    p.Omega2_0 = m.initial.Omega2;
    p.R1_f = target.R1;
    p.R2_f = target.R2;
    p.Omega1_f = target.Omega1;
    p.Omega2_f = target.Omega2;
    p.t_final = t_final;
    return p;
  }
  static constexpr const char* violation_label = "|terminal constraints| [rad, rad/s]";
  static constexpr const char* figure_script = "fig_connected_bodies.gp";
  static constexpr bool continuous = false;
  static constexpr const char* violation_norm =
      "2-norm of [log(R1_N^T R1_f)^vee; log(R2_N^T R2_f)^vee; Omega1_N - Omega1_f; "
      "Omega2_N - Omega2_f] (Omega2 not among the SLSQP constraints)";
  static constexpr const char* knot_layout = "u_1 at the knots, then u_2, then u_3";
  static void state_columns(std::vector<std::string>& c) {
    ocp_binding_detail::matrix_names(c, "R1_");
    ocp_binding_detail::matrix_names(c, "R2_");
    ocp_binding_detail::vector_names(c, "Omega1_");
    ocp_binding_detail::vector_names(c, "Omega2_");
  }
  static void state_row(std::vector<double>& row, const ConnectedBodiesLgvi& lgvi, const ConnectedBodiesState& s) {
    Vec3 Omega1, Omega2;
    lgvi.velocities(s, Omega1, Omega2);
    ocp_binding_detail::append_matrix(row, s.R1);
    ocp_binding_detail::append_matrix(row, s.R2);
    for (int i = 0; i < 3; ++i) row.push_back(Omega1(i));
    for (int i = 0; i < 3; ++i) row.push_back(Omega2(i));
  }
  static double energy(const ConnectedBodiesLgvi& lgvi, const ConnectedBodiesState& s) {
    Vec3 Omega1, Omega2;
    lgvi.velocities(s, Omega1, Omega2);
    return lgvi.system().energy(s.R1, s.R2, Omega1, Omega2);
  }
  static constexpr std::array<ResidualPart, 4> violation_parts = {{{"violation_rotation1", 0, 3},
                                                                   {"violation_rotation2", 3, 3},
                                                                   {"violation_angular_velocity1", 6, 3},
                                                                   {"violation_angular_velocity2", 9, 3}}};
};

}  // namespace lgvi::experiments
