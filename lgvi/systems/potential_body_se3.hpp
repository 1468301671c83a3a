// A rigid body moving in space under a potential U(R, x) (scene system "potential-body-se3"): the
// kinetic energy 1/2 m |v|^2 + 1/2 Omega^T J Omega of the dumbbell (section 3.1) and one potential
// of
//
//   uniform gravity g [m/s^2] (inertial frame):
//       U(R, x) = -m g^T x,   f = m g,   M = 0;
//     the attitude is a free rigid body's and the mass centre a parabola: R J Omega and the
//     momentum across g are conserved;
//   a linear spring of stiffness k [N/m] from an inertial anchor a to the body point r (body
//   frame), the attachment, d = x + R r - a:
//       U(R, x) = k/2 |d|^2,   f = -k d,   M = r x R^T f;
//     a central force about the anchor (it acts along d at the attachment), so the angular
//     momentum about the anchor, (x - a) x m v + R J Omega, is conserved; with r != 0 it couples
//     rotation and translation (an elastic pendulum of a rigid bob);
//   a user's potential: callables U(R, x) and its wrench (f, M)(R, x) (UserPotentialSE3; Python's
//     lgvi.potential_scene with mass and force).
//
// f = -dU/dx (inertial) and M the moment of eq. 13 in the dumbbell's convention: with the force
// f^q on a point rho^q of the body, M = sum_q rho^q x R^T f^q, i.e. d/de U(R exp(hat(e)), x) at
// e = 0 is -M (tests/lgvi/test_systems.cpp checks both by central differences). The class
// satisfies RigidBodySystem (lgvi/lgvi.hpp): the LGVI on SE(3), its compositions and the SE(3)
// baselines (baselines/mechanics.hpp RigidBodyMechanics) run it unchanged.
#pragma once

#include <functional>
#include <utility>
#include <variant>

#include "lgvi/inertia.hpp"
#include "lgvi/systems/system.hpp"
#include "lgvi/types.hpp"

namespace lgvi {

struct UniformGravity {
  Vec3 gravity = Vec3::Zero();  ///< g [m/s^2], inertial frame
};

struct AnchoredSpring {
  double stiffness = 0.0;            ///< k [N/m]
  Vec3 anchor = Vec3::Zero();        ///< a, inertial frame
  Vec3 attachment = Vec3::Zero();    ///< r, body frame (from the mass centre)
};

/// A potential on SE(3) given by two callables: U(R, x) and its wrench (f = -dU/dx inertial, M of
/// eq. 13), a C++ user's or Python's. As UserPotential: they must not throw; a failure is a
/// non-finite value, which ends every method's run with its non-finite status. One wrench call
/// per potential evaluation (the LGVI: once per step).
struct UserPotentialSE3 {
  std::function<double(const Mat3&, const Vec3&)> energy;
  std::function<Wrench(const Mat3&, const Vec3&)> wrench;
};

using SE3Potential = std::variant<UniformGravity, AnchoredSpring, UserPotentialSE3>;

class PotentialBodySE3 {
 public:
  using Control = Wrench;  ///< u^f (inertial frame), u^m (body frame)
  using Forces = Wrench;   ///< -dU/dx and M(R, x)

  double mass;
  Inertia inertia;
  SE3Potential term;

  /// Throws InvalidInput naming the field: mass not finite and positive ("mass"), an inertia
  /// Inertia::from rejects ("inertia"), a non-finite gravity ("gravity"), a spring's stiffness not
  /// finite and positive ("stiffness") or a non-finite anchor or attachment ("anchor",
  /// "attachment"), a user potential's missing callable ("potential", "moment").
  PotentialBodySE3(double m, const Mat3& J, SE3Potential potential, InertiaDomain domain = InertiaDomain::Physical)
      : mass(m), inertia(Inertia::from(J, "inertia", domain)), term(std::move(potential)) {
    require_positive(mass, "mass");
    if (const auto* gravity = std::get_if<UniformGravity>(&term)) {
      require_finite(gravity->gravity, "gravity");
    } else if (const auto* spring = std::get_if<AnchoredSpring>(&term)) {
      require_positive(spring->stiffness, "stiffness");
      require_finite(spring->anchor, "anchor");
      require_finite(spring->attachment, "attachment");
    } else {
      const auto& user = std::get<UserPotentialSE3>(term);
      if (!user.energy) throw InvalidInput("potential", "is not set (a callable U(R, x))");
      if (!user.wrench) throw InvalidInput("moment", "is not set (a callable giving f(R, x) and M(R, x))");
    }
  }

  double potential(const Mat3& R, const Vec3& x) const {
    if (const auto* gravity = std::get_if<UniformGravity>(&term)) return -mass * gravity->gravity.dot(x);
    if (const auto* spring = std::get_if<AnchoredSpring>(&term)) {
      return 0.5 * spring->stiffness * (x + R * spring->attachment - spring->anchor).squaredNorm();
    }
    return std::get<UserPotentialSE3>(term).energy(R, x);
  }
  Forces forces(const Mat3& R, const Vec3& x) const {
    Forces out;
    if (const auto* gravity = std::get_if<UniformGravity>(&term)) {
      out.force = mass * gravity->gravity;
    } else if (const auto* spring = std::get_if<AnchoredSpring>(&term)) {
      out.force = -spring->stiffness * (x + R * spring->attachment - spring->anchor);
      out.moment = spring->attachment.cross(R.transpose() * out.force);
    } else {
      out = std::get<UserPotentialSE3>(term).wrench(R, x);
    }
    return out;
  }

  double energy(const Mat3& R, const Vec3& x, const Vec3& Omega, const Vec3& v) const {
    return 0.5 * mass * v.squaredNorm() + 0.5 * Omega.dot(inertia.J * Omega) + potential(R, x);
  }
  /// The angular momentum the potential conserves: about the mass centre, R J Omega (gravity);
  /// about the anchor, (x - a) x m v + R J Omega (spring); about the origin, x x m v + R J Omega,
  /// for a user's potential (conserved when U is invariant under rotations about the origin).
  Vec3 angular_momentum(const Mat3& R, const Vec3& x, const Vec3& Omega, const Vec3& v) const {
    const Vec3 spin = R * (inertia.J * Omega);
    if (std::holds_alternative<UniformGravity>(term)) return spin;
    const Vec3 centre = std::holds_alternative<AnchoredSpring>(term) ? std::get<AnchoredSpring>(term).anchor : Vec3::Zero();
    return (x - centre).cross(mass * v) + spin;
  }
};

static_assert(System<PotentialBodySE3>);

}  // namespace lgvi
