// The free body's LGVI on a circular orbit: the gravity-gradient potential of
// lgvi/systems/gravity_gradient.hpp added to the free body's flow map (scenes with
// [parameters] orbit_rate).
#pragma once

#include "lgvi/flow_map.hpp"
#include "lgvi/lgvi.hpp"
#include "lgvi/systems/free_rigid_body.hpp"
#include "lgvi/systems/gravity_gradient.hpp"

namespace lgvi {

/// The control of a flow whose potential depends on time: the control moment u(t) and t itself,
/// so that a step knows the times of its ends (integrate() and the compositions sample controls
/// at the ends of each step and substep).
struct TimedMoment {
  Vec3 u = Vec3::Zero();
  double t = 0.0;
};

/// The free body's LGVI on a circular orbit. The gravity-gradient potential V(R, t)
/// (lgvi/systems/gravity_gradient.hpp) enters as a potential does in eqs. 13-14, through its
/// moment with the form's impulse weights: c0 M(R_k, t_k) and c1 M(R_{k+1}, t_{k+1}) (symmetric:
/// h/2, h/2, the discrete Lagrangian's trapezoidal V(R_k, t_k) + V(R_{k+1}, t_{k+1}); printed:
/// 0, h). The state keeps M(R_k, t_k) in AttitudeState::M, from which the base step takes its start
/// impulse; the end impulse depends on R_{k+1} alone (not on Pi_{k+1}), so it is added after the
/// rotation update, explicitly: one gravity-gradient evaluation per step. In the frame turning
/// with the orbit the discrete Lagrangian does not depend on k (R_k^T R_{k+1} = Q_k^T exp(n h
/// hat(e3)) Q_{k+1}), so the map is a variational integrator of an autonomous system there: its
/// Jacobi integral stays bounded (tests/experiments/systems/test_gravity_gradient.cpp).
class GravityGradientLgvi {
 public:
  using State = AttitudeState;
  using Control = TimedMoment;
  static constexpr int potential_evaluations_per_step = 1;

  GravityGradientLgvi(const AttitudeLgvi<FreeRigidBody>& lgvi, const GravityGradient& gravity)
      : lgvi_(lgvi), gravity_(gravity) {}

  /// The state at (R, Omega) at time t, with the gravity-gradient moment there.
  State make_state(const Mat3& R, const Vec3& Omega, double t) const {
    State s = lgvi_.make_state(R, Omega);
    s.M = gravity_.moment(lgvi_.system().inertia.J, R, t);
    return s;
  }

  /// One step from t_k = u_k.t to t_{k+1} = u_k1.t; `in.M` must be the moment at (in.R, t_k).
  RotationUpdateSummary step(const State& in, double h, const Control& u_k, const Control& u_k1, State& out) const {
    const RotationUpdateSummary summary = lgvi_.step(in, h, u_k.u, u_k1.u, out);
    if (!summary.converged()) return summary;
    out.M = gravity_.moment(lgvi_.system().inertia.J, out.R, u_k1.t);
    out.Pi += impulse_weights(lgvi_.form(), h).end * out.M;
    return summary;
  }

  LgviForm form() const { return lgvi_.form(); }
  const FreeRigidBody& system() const { return lgvi_.system(); }
  Vec3 omega(const State& s) const { return lgvi_.omega(s); }

 private:
  const AttitudeLgvi<FreeRigidBody>& lgvi_;
  GravityGradient gravity_;
};

static_assert(FlowMap<GravityGradientLgvi>);

}  // namespace lgvi
