// The free rigid body in closed form: Omega(t) by Jacobi elliptic functions, R(t) by a rotation
// about the conserved spatial angular momentum whose angle is an elliptic integral of the third
// kind (Celledoni, Fasso, Safstrom, Zanna, "The exact computation of the free rigid body motion
// and its use in splitting methods", SIAM J. Sci. Comput. 30(4), 2008, section 2).
//
// Conventions (lgvi/systems/free_rigid_body.hpp): R maps body to inertial frame, Pi = J Omega,
// Pi' = Pi x Omega, R' = R hat(Omega); conserved 2E = Pi . Omega and m = R Pi.
//
// Construction. J = Q diag(I1, I2, I3) Q^T with Q a rotation whose columns are principal axes,
// ordered so that I2 is the intermediate moment and the angular momentum circulates around the
// third axis: G^2 - 2 E I2 > 0 (energy below the separatrix's level for G: the third axis is the
// largest-moment one) or < 0 (the smallest-moment one, listed third). In that frame
// (Landau-Lifshitz, Mechanics, section 37, with signed amplitudes)
//     Omega = (a cn w, b sn w, c dn w),  w = lambda t + w0,
//     a^2 = Omega1^2 + Omega2^2 I2 (I3 - I2) / (I1 (I3 - I1)),
//     b^2 = Omega2^2 + Omega1^2 I1 (I3 - I1) / (I2 (I3 - I2)),
//     c^2 = Omega3^2 + Omega2^2 I2 (I2 - I1) / (I3 (I3 - I1)),
//     k^2 = (I2 - I1) I1 a^2 / ((I3 - I2) I3 c^2),
//     lambda = sign(I3 - I2) c sqrt((I3 - I2)(I3 - I1) / (I1 I2)),
// a, b >= 0, c with the sign of Omega3 (dn > 0 never changes it); every amplitude is a sum of
// squares from the initial Omega, so none cancels near a principal axis. Attitude:
//     R(t) Q = R0 Q B(0)^T Rz(phi(t)) B(t),
// B(t) the rotation with rows b1 = (m2, -m1, 0) / rho, b2 = b3 x b1, b3 = m / |m| (m = Pi in the
// principal frame, rho^2 = m1^2 + m2^2, never 0 off the steady rotations), so B m = |m| e3 and
// Y = R0 Q B(0)^T maps e3 to the spatial momentum. R' = R hat(Omega) gives
//     phi' = G (m1^2/I1 + m2^2/I2) / rho^2 = G/I3 + G (I3 - I1) / (I1 I3) / (1 - n sn^2 w),
//     n = -I3 (I2 - I1) / (I1 (I3 - I2)) <= 0,
// integrated in closed form by Pi(n; am w | k) (baselines/exact/elliptic.hpp).
//
// Special cases: a rotation about a principal axis (|Pi x Omega| <= 16 eps |Pi| |Omega|, which
// includes Omega = 0 and the sphere) is steady, R = R0 exp(t hat Omega0); two equal moments give
// k = 0 and n = 0 (the trigonometric solution, the same formulas). A state on the separatrix
// (G^2 = 2 E I2 within 16 eps of its terms, not a steady rotation) is rejected (InvalidInput
// "Omega0"): its motion is the hyperbolic limit k = 1. So is a state closer to it than
// 1 - k = 1e-8 (exact_detail::kMinimumDistanceToSeparatrix), where Boost's elliptic integrals
// lose digits (the scene free-body.toml, spun 0.05 rad/s off the intermediate axis, has
// 1 - k = 7e-4).
//
// Accuracy. Every special function sees an argument reduced to a half-period; the rest of a long
// horizon is the rounding of the phases lambda t and the mean precession rate times t, an error
// of eps |Omega| t, which is how well t itself determines the state (3e-10 at |Omega| = 3 rad/s,
// t = 1e6 s). Near the separatrix the motion itself amplifies its data: for the scene
// free-body.toml a 1-ulp change of Omega0 moves the state at t = 30 s by 1.6e-12, the floor any
// method meets there (gsl-rk8pd at rtol 1e-13 and 1e-14: 4e-12 and 7e-12 from this solution).
#pragma once

#include "baselines/exact/elliptic.hpp"
#include "lgvi/inertia.hpp"
#include "lgvi/types.hpp"

namespace lgvi::baselines {

/// The state of an exact solution at one time: attitude (body to inertial) and body angular
/// velocity.
struct ExactState {
  Mat3 R;
  Vec3 Omega;
};

class FreeRigidBodyExact {
 public:
  enum class Regime {
    SteadyRotation,        ///< about a principal axis (or at rest)
    AroundLargestAxis,     ///< G^2 > 2 E I2: the momentum circulates about the largest-moment axis
    AroundSmallestAxis,    ///< G^2 < 2 E I2: about the smallest-moment axis
  };

  /// Validates J (lgvi::Inertia: symmetric positive definite, in `domain`: the triangle
  /// inequality unless PositiveDefinite, since the closed form solves the Euler equations of any
  /// positive definite J; field "inertia"), R0 a rotation to 1e-10 ("R0"), Omega0 finite
  /// ("Omega0"), and rejects a state on the separatrix ("Omega0"). Throws InvalidInput.
  FreeRigidBodyExact(const Mat3& J, const Mat3& R0, const Vec3& Omega0,
                     InertiaDomain domain = InertiaDomain::Physical);

  /// R(t), Omega(t) for any finite t (negative too); throws InvalidInput("t") otherwise.
  /// Allocation-free.
  ExactState state(double t) const;

  Regime regime() const { return regime_; }
  /// Modulus k of the Jacobi functions (0 for steady and axisymmetric motions).
  double modulus() const { return jacobi_.k(); }
  /// Period of Omega(t) (4K / |lambda|; dn alone has half of it); infinity when steady.
  double period() const;

 private:
  Mat3 R0_ = Mat3::Identity();
  Vec3 Omega0_ = Vec3::Zero();
  Regime regime_ = Regime::SteadyRotation;
  Mat3 Q_ = Mat3::Identity();  ///< principal axes in the solver's order, det +1
  Mat3 Y_ = Mat3::Identity();  ///< R0 Q B(0)^T
  Vec3 moments_ = Vec3::Ones();  ///< I1, I2, I3 in the solver's order
  double a_ = 0.0, b_ = 0.0, c_ = 0.0;  ///< signed amplitudes of Omega in the principal frame
  double lambda_ = 0.0, w0_ = 0.0;
  double momentum_ = 0.0;       ///< G = |Pi|
  double precession_rate_ = 0.0;  ///< mean of phi': G/I3 + coefficient * mean of 1/(1 - n sn^2)
  double precession_coefficient_ = 0.0;  ///< G (I3 - I1) / (I1 I3 lambda)
  double periodic0_ = 0.0;      ///< the periodic part of the phase integral at w0
  exact_detail::Jacobi jacobi_{0.0};
  exact_detail::SnSquaredIntegral phase_{exact_detail::Jacobi(0.0), 1.0, 0.0};
};

}  // namespace lgvi::baselines
