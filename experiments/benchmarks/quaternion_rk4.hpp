// A yardstick of the step-cost benchmark: one classical fixed-step RK4 step of the quaternion
// model of an attitude system (free rigid body, 3D pendulum), written for speed as a user would
// write it: plain doubles in registers (lgvi/plain3.hpp), every call inlined (LGVI_FLATTEN and
// always_inline helpers, the flags of the LGVI step), no heap, no virtual calls, the physics
// from lgvi/systems.
//
//   q' = 1/2 q (x) (0, Omega)        (q = (w, v) a unit quaternion, body angular velocity Omega)
//   Omega' = J^{-1} (J Omega x Omega + M(R(q)))
//
// with M = system.moment (eq. 13; zero for the free body) and R(q) = (w^2 - |v|^2) I + 2 v v^T
// + 2 w hat(v) (the form of baselines/coordinates.hpp). Uncontrolled (the benchmark's LGVI steps
// evaluate a zero control, so the comparison does not favour the LGVI). Four right-hand sides
// per step, one potential evaluation each; q is not renormalized.
#pragma once

#include <Eigen/Dense>

#include "lgvi/lgvi.hpp"
#include "lgvi/types.hpp"
#include "lgvi/plain3.hpp"

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
  static Mat3 rotation(const Quaternion& q) { return rotation(Plain{q(0), {q(1), q(2), q(3)}}); }

  /// One RK4 step of size h, in place.
  LGVI_FLATTEN void step(State& s, double h) const {
    using namespace plain;
    const Rows3 J = rows3(system_.inertia.J), J_inverse = rows3(system_.inertia.J_inverse);
    const Plain q{s.q(0), {s.q(1), s.q(2), s.q(3)}};
    const V3 Omega = v3(s.Omega);
    Plain dq1, dq2, dq3, dq4;
    V3 dw1, dw2, dw3, dw4;
    rate(J, J_inverse, q, Omega, dq1, dw1);
    rate(J, J_inverse, axpy(q, 0.5 * h, dq1), Omega + (0.5 * h) * dw1, dq2, dw2);
    rate(J, J_inverse, axpy(q, 0.5 * h, dq2), Omega + (0.5 * h) * dw2, dq3, dw3);
    rate(J, J_inverse, axpy(q, h, dq3), Omega + h * dw3, dq4, dw4);
    const double c = h / 6.0;
    const Plain dq{dq1.w + 2.0 * (dq2.w + dq3.w) + dq4.w, dq1.v + 2.0 * (dq2.v + dq3.v) + dq4.v};
    const Plain q1 = axpy(q, c, dq);
    const V3 Omega1 = Omega + c * (dw1 + 2.0 * (dw2 + dw3) + dw4);
    s.q = Quaternion(q1.w, q1.v.x, q1.v.y, q1.v.z);
    s.Omega = vec3(Omega1);
  }

  const S& system() const { return system_; }

 private:
  /// A quaternion (w, v) on plain doubles.
  struct Plain {
    double w;
    plain::V3 v;
  };
  static Plain axpy(const Plain& q, double a, const Plain& d) {
    return {q.w + a * d.w, q.v + a * d.v};
  }
  static Mat3 rotation(const Plain& q) {
    const double w = q.w, x = q.v.x, y = q.v.y, z = q.v.z;
    const double d = w * w - (x * x + y * y + z * z);
    Mat3 R;
    R << d + 2.0 * x * x, 2.0 * (x * y - w * z), 2.0 * (x * z + w * y),  //
        2.0 * (y * x + w * z), d + 2.0 * y * y, 2.0 * (y * z - w * x),   //
        2.0 * (z * x - w * y), 2.0 * (z * y + w * x), d + 2.0 * z * z;
    return R;
  }

  /// (q', Omega') at (q, Omega).
  void rate(const plain::Rows3& J, const plain::Rows3& J_inverse, const Plain& q,
            const plain::V3& Omega, Plain& dq, plain::V3& dOmega) const {
    using namespace plain;
    dq.w = -0.5 * dot(q.v, Omega);
    dq.v = 0.5 * (q.w * Omega + cross(q.v, Omega));
    dOmega = J_inverse * (cross(J * Omega, Omega) + v3(system_.moment(rotation(q))));
  }

  const S& system_;
};

}  // namespace lgvi::benchmarks
