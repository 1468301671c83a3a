// The yardstick of the step-cost benchmark: one classical fixed-step RK4 step of the quaternion
// model of an attitude system (free rigid body, 3D pendulum), written as a user would write it
// for speed: fixed-size Eigen types, no heap, no virtual calls, the physics from lgvi/systems.
//
//   q' = 1/2 q (x) (0, Omega)        (q = (w, v) a unit quaternion, body angular velocity Omega)
//   Omega' = J^{-1} (J Omega x Omega + M(R(q)))
//
// with M = system.moment (eq. 13; zero for the free body) and R(q) = (w^2 - |v|^2) I + 2 v v^T
// + 2 w hat(v) (the form of baselines/coordinates.hpp). Uncontrolled: the benchmark's LGVI steps
// run with a zero control, which they still evaluate, so the comparison does not favour the LGVI.
// Four right-hand sides per step, one potential evaluation each; q is not renormalized.
#pragma once

#include <Eigen/Dense>

#include "lgvi/lgvi.hpp"
#include "lgvi/so3.hpp"
#include "lgvi/types.hpp"

namespace lgvi::benchmarks {

template <AttitudeSystem S>
class QuaternionRk4 {
 public:
  using Quaternion = Eigen::Vector4d;  ///< (w, x, y, z)
  struct State {
    Quaternion q;
    Vec3 Omega;
  };

  /// Holds the system by reference (it must outlive the stepper).
  explicit QuaternionRk4(const S& system) : system_(system) {}

  /// The state (q(R), Omega); R must be a rotation.
  static State make_state(const Mat3& R, const Vec3& Omega) {
    const Eigen::Quaterniond q(R);
    return State{Quaternion(q.w(), q.x(), q.y(), q.z()), Omega};
  }

  /// R(q) = (w^2 - |v|^2) I + 2 v v^T + 2 w hat(v).
  static Mat3 rotation(const Quaternion& q) {
    const double w = q(0);
    const Vec3 v = q.tail<3>();
    return (w * w - v.squaredNorm()) * Mat3::Identity() + 2.0 * v * v.transpose() +
           2.0 * w * so3::hat(v);
  }

  /// One RK4 step of size h, in place.
  void step(State& s, double h) const {
    State k1, k2, k3, k4;
    rate(s, k1);
    rate(axpy(s, 0.5 * h, k1), k2);
    rate(axpy(s, 0.5 * h, k2), k3);
    rate(axpy(s, h, k3), k4);
    const double c = h / 6.0;
    s.q += c * (k1.q + 2.0 * (k2.q + k3.q) + k4.q);
    s.Omega += c * (k1.Omega + 2.0 * (k2.Omega + k3.Omega) + k4.Omega);
  }

  const S& system() const { return system_; }

 private:
  static State axpy(const State& s, double a, const State& k) {
    return State{s.q + a * k.q, s.Omega + a * k.Omega};
  }

  /// (q', Omega') at s.
  void rate(const State& s, State& d) const {
    const double w = s.q(0);
    const Vec3 v = s.q.template tail<3>();
    d.q(0) = -0.5 * v.dot(s.Omega);
    d.q.template tail<3>() = 0.5 * (w * s.Omega + v.cross(s.Omega));
    const Mat3& J = system_.inertia.J;
    d.Omega = system_.inertia.J_inverse *
              ((J * s.Omega).cross(s.Omega) + system_.moment(rotation(s.q)));
  }

  const S& system_;
};

}  // namespace lgvi::benchmarks
