// A yardstick of the step-cost benchmark: one classical fixed-step RK4 step of the rotation-
// matrix model of an attitude system (free rigid body, 3D pendulum), written like
// quaternion_rk4.hpp: plain doubles (lgvi/plain3.hpp), every call inlined (LGVI_FLATTEN), no heap.
//
//   R' = R hat(Omega),   Omega' = J^{-1} (J Omega x Omega + M(R))
//
// (the continuous equations of lgvi/systems, with M = system.moment, eq. 13; zero for the free
// body). Uncontrolled; four right-hand sides per step, one potential evaluation each; R is
// not re-orthogonalized, so it drifts off SO(3) by the method's O(h^4) local error.
#pragma once

#include "lgvi/lgvi.hpp"
#include "lgvi/types.hpp"
#include "lgvi/plain3.hpp"

namespace lgvi::benchmarks {

template <AttitudeSystem S>
class MatrixRk4 {
 public:
  struct State {
    Mat3 R;
    Vec3 Omega;
  };

  /// Holds the system by reference (it must outlive the stepper).
  explicit MatrixRk4(const S& system) : system_(system) {}

  static State make_state(const Mat3& R, const Vec3& Omega) { return State{R, Omega}; }

  /// One RK4 step of size h, in place.
  LGVI_FLATTEN void step(State& s, double h) const {
    using namespace plain;
    const Rows3 J = rows3(system_.inertia.J), J_inverse = rows3(system_.inertia.J_inverse);
    const Rows3 R = rows3(s.R);
    const V3 Omega = v3(s.Omega);
    Rows3 dR1, dR2, dR3, dR4;
    V3 dw1, dw2, dw3, dw4;
    rate(J, J_inverse, R, Omega, dR1, dw1);
    rate(J, J_inverse, R + (0.5 * h) * dR1, Omega + (0.5 * h) * dw1, dR2, dw2);
    rate(J, J_inverse, R + (0.5 * h) * dR2, Omega + (0.5 * h) * dw2, dR3, dw3);
    rate(J, J_inverse, R + h * dR3, Omega + h * dw3, dR4, dw4);
    const double c = h / 6.0;
    s.R = mat3(R + c * (dR1 + 2.0 * (dR2 + dR3) + dR4));
    s.Omega = vec3(Omega + c * (dw1 + 2.0 * (dw2 + dw3) + dw4));
  }

  const S& system() const { return system_; }

 private:
  /// (R', Omega') at (R, Omega).
  void rate(const plain::Rows3& J, const plain::Rows3& J_inverse, const plain::Rows3& R,
            const plain::V3& Omega, plain::Rows3& dR, plain::V3& dOmega) const {
    using namespace plain;
    dR = times_hat(R, Omega);
    dOmega = J_inverse * (cross(J * Omega, Omega) + v3(system_.moment(mat3(R))));
  }

  const S& system_;
};

}  // namespace lgvi::benchmarks
