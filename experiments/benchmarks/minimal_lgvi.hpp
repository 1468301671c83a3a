// The floor reference of the step-cost benchmark: the LGVI step of an attitude system (free
// rigid body, 3D pendulum) written as small as it goes, to show what the project's step
// (AttitudeLgvi, lgvi/lgvi.hpp) could cost. Lee, Leok, McClamroch, "Computational geometric
// optimal control of rigid bodies", eqs. 8, 9, 11 (free body) and 21-23 (3D pendulum), in the
// symmetric form the project uses (LgviForm::Symmetric), uncontrolled:
//
//   h hat(Pi_k + h/2 M_k) = F_k J_d - J_d F_k^T,   R_{k+1} = R_k F_k,
//   Pi_{k+1} = F_k^T (Pi_k + h/2 M_k) + h/2 M_{k+1},          Pi = J Omega, M = M(R) (eq. 13).
//
// The rotation update is solved as the project's Cayley chart solves it (lgvi/rotation_update.hpp):
// with F = cay(f) = I + 2/(1 + |f|^2) (hat(f) + hat(f)^2) and h p = h (Pi_k + h/2 M_k), the
// matrix equation is the polynomial H(f) = J f + f x J f - (1 + |f|^2)/2 h p = 0, whose Newton
// matrix is dH = J + hat(f) J - hat(J f) - h p f^T, from the warm start f = J^{-1} h p / 2, with
// the same convergence test |G| <= 16 eps (|h p| + ||J||_F (a |f| + b |f|^2)),
// G = 2 H / (1 + |f|^2), a = b = 2 / (1 + |f|^2).
// Unlike the project's solver: no domain check, no polishing step, no fallback chart, no pivoted
// solve of a nearly singular Newton matrix (the adjugate only), no summary beyond the iteration
// count, no control. Then R_{k+1} row by row (r F = r + a (r x f + (r x f) x f)) and
// F^T k = k + a (f x (f x k) - f x k), a = 2/(1 + |f|^2), with no 3x3 product formed.
// tests/lgvi/test_minimal_lgvi.cpp checks that it steps as AttitudeLgvi does, to round-off.
#pragma once

#include <cmath>

#include "lgvi/lgvi.hpp"
#include "lgvi/types.hpp"
#include "lgvi/plain3.hpp"

namespace lgvi::benchmarks {

template <AttitudeSystem S>
class MinimalLgvi {
 public:
  using State = AttitudeState;  ///< (R, Pi = J Omega, M(R)), as AttitudeLgvi's
  static constexpr int max_iterations = 30;
  static constexpr double relative_tolerance = 16.0 * kEps;

  /// Holds the system by reference (it must outlive the stepper).
  explicit MinimalLgvi(const S& system) : system_(system), J_norm_(system.inertia.J.norm()) {}

  State make_state(const Mat3& R, const Vec3& Omega) const {
    return State{R, system_.inertia.J * Omega, system_.moment(R)};
  }

  /// One step in place. Returns the Newton iterations, or -1 (the state unchanged) when Newton
  /// has not converged in max_iterations.
  LGVI_FLATTEN int step(State& s, double h) const {
    using namespace plain;
    const Rows3 J = rows3(system_.inertia.J);
    const Rows3 J_columns = rows3(system_.inertia.J.transpose());
    const V3 kick = v3(s.Pi) + (0.5 * h) * v3(s.M);
    const V3 hp = h * kick;
    const double hp_norm = std::sqrt(dot(hp, hp));
    V3 f = 0.5 * (rows3(system_.inertia.J_inverse) * hp);
    double f2;
    int iterations = 0;
    for (;;) {
      const V3 Jf = J * f;
      f2 = dot(f, f);
      const double half_norm = 0.5 * (1.0 + f2);  // H = half_norm G
      const V3 H = Jf + cross(f, Jf) - half_norm * hp;
      const double tolerance =
          relative_tolerance * (half_norm * hp_norm + J_norm_ * (std::sqrt(f2) + f2));
      if (dot(H, H) <= tolerance * tolerance) break;
      if (iterations == max_iterations) return -1;
      // Columns of dH: J e_j + f x J e_j - (J f) x e_j - f_j h p; solved by the adjugate.
      const V3 c0 = J_columns.r0 + cross(f, J_columns.r0) + V3{0.0, -Jf.z, Jf.y} - f.x * hp;
      const V3 c1 = J_columns.r1 + cross(f, J_columns.r1) + V3{Jf.z, 0.0, -Jf.x} - f.y * hp;
      const V3 c2 = J_columns.r2 + cross(f, J_columns.r2) + V3{-Jf.y, Jf.x, 0.0} - f.z * hp;
      const V3 k0 = cross(c1, c2), k1 = cross(c2, c0), k2 = cross(c0, c1);
      const double inverse_det = 1.0 / dot(c0, k0);
      f = f - inverse_det * V3{dot(H, k0), dot(H, k1), dot(H, k2)};
      ++iterations;
    }
    const double a = 2.0 / (1.0 + f2);
    const Rows3 R = rows3(s.R);
    const V3 x0 = cross(R.r0, f), x1 = cross(R.r1, f), x2 = cross(R.r2, f);
    const Rows3 R1{R.r0 + a * (x0 + cross(x0, f)), R.r1 + a * (x1 + cross(x1, f)),
                   R.r2 + a * (x2 + cross(x2, f))};
    const V3 fxk = cross(f, kick);
    const Mat3 R_next = mat3(R1);
    const Vec3 M_next = system_.moment(R_next);
    s.Pi = vec3(kick + a * (cross(f, fxk) - fxk) + (0.5 * h) * v3(M_next));
    s.R = R_next;
    s.M = M_next;
    return iterations;
  }

  Vec3 omega(const State& s) const { return system_.inertia.J_inverse * s.Pi; }
  const S& system() const { return system_; }

 private:
  const S& system_;
  double J_norm_;  ///< ||J||_F, the scale of G's terms in the convergence test
};

}  // namespace lgvi::benchmarks
