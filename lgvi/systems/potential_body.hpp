// A rigid body in a parametric attitude potential (scene system "potential-body"): the free
// body's kinetic energy 1/2 Omega^T J Omega and one potential U(R) of
//
//   attitude spring toward R_t, stiffness k [J]:
//       U(R) = k (3 - tr(R_t^T R)) = k/2 ||R - R_t||_F^2,
//       M(R) = k vee(R^T R_t - R_t^T R);
//     near the target, R = R_t exp(hat(e)): U = k |e|^2 + O(|e|^4) and M = -2 k e + O(|e|^3),
//     a rotational spring of stiffness 2k about every axis (a body's "torsion pendulum");
//   magnetic dipole m [A m^2] (body frame) in a uniform field B [T] (inertial frame):
//       U(R) = -B^T R m,
//       M(R) = m x R^T B,
//     which conserves the angular momentum about the field, B^T R J Omega;
//   a user's potential: callables U(R) and M(R) (UserPotential; Python's lgvi.potential_scene).
//
// M is the moment of eq. 13, hat(M) = (dU/dR)^T R - R^T dU/dR, i.e. minus the left-trivialized
// derivative: d/de U(R exp(hat(e))) at e = 0 is -M (tests/lgvi/test_potential_body.cpp checks
// both by central differences). The class satisfies AttitudeSystem: the LGVI, its compositions
// and every attitude baseline (AttitudeMechanics) run it unchanged.
#pragma once

#include <functional>
#include <utility>
#include <variant>

#include "lgvi/inertia.hpp"
#include "lgvi/so3.hpp"
#include "lgvi/types.hpp"

namespace lgvi {

struct AttitudeSpring {
  double stiffness = 0.0;           ///< k [J] (U = k (3 - tr(R_t^T R)))
  Mat3 target = Mat3::Identity();  ///< R_t
  double potential(const Mat3& R) const { return stiffness * (3.0 - (target.transpose() * R).trace()); }
  Vec3 moment(const Mat3& R) const {
    const Mat3 A = R.transpose() * target;
    return stiffness * so3::vee(A - A.transpose());
  }
};

struct MagneticDipole {
  Vec3 dipole = Vec3::Zero();  ///< m [A m^2], body frame
  Vec3 field = Vec3::Zero();   ///< B [T], inertial frame
  double potential(const Mat3& R) const { return -field.dot(R * dipole); }
  Vec3 moment(const Mat3& R) const { return dipole.cross(R.transpose() * field); }
};

/// A potential given by two callables: U(R) [J] and its moment M(R) (eq. 13, the convention
/// above), a C++ user's or Python's (the module's potential_scene). They must not throw (the
/// integrators and the C solvers beneath the baselines cannot unwind): a failure is a non-finite
/// value, which ends every method's run with its non-finite status; the caller keeps the reason.
/// Each is called once per potential evaluation (the LGVI: once per step).
struct UserPotential {
  std::function<double(const Mat3&)> energy;
  std::function<Vec3(const Mat3&)> torque;
  double potential(const Mat3& R) const { return energy(R); }
  Vec3 moment(const Mat3& R) const { return torque(R); }
};

using AttitudePotential = std::variant<AttitudeSpring, MagneticDipole, UserPotential>;

class PotentialBody {
 public:
  using Control = Vec3;  ///< a body-frame control moment
  static constexpr bool has_potential = true;

  Inertia inertia;
  AttitudePotential term;

  /// Throws InvalidInput naming the field: an inertia Inertia::from rejects ("inertia"); a spring
  /// with a stiffness not finite and positive ("stiffness") or a target that is not a rotation to
  /// 1e-9 in ||R_t^T R_t - I||_F and det ("target"); a dipole or field with a non-finite entry
  /// ("dipole", "field").
  PotentialBody(const Mat3& J, AttitudePotential potential, InertiaDomain domain = InertiaDomain::Physical)
      : inertia(Inertia::from(J, "inertia", domain)), term(std::move(potential)) {
    if (const auto* spring = std::get_if<AttitudeSpring>(&term)) {
      require_positive(spring->stiffness, "stiffness");
      require_finite(spring->target, "target");
      const double defect = (spring->target.transpose() * spring->target - Mat3::Identity()).norm();
      if (!(defect <= 1e-9) || !(spring->target.determinant() > 0.0)) {
        throw InvalidInput("target", "must be a rotation matrix (||R^T R - I||_F <= 1e-9, det R = +1)");
      }
    } else if (const auto* dipole = std::get_if<MagneticDipole>(&term)) {
      require_finite(dipole->dipole, "dipole");
      require_finite(dipole->field, "field");
    } else {
      const auto& user = std::get<UserPotential>(term);
      if (!user.energy) throw InvalidInput("potential", "is not set (a callable U(R))");
      if (!user.torque) throw InvalidInput("moment", "is not set (a callable M(R))");
    }
  }

  double potential(const Mat3& R) const {
    return std::visit([&](const auto& u) { return u.potential(R); }, term);
  }
  Vec3 moment(const Mat3& R) const {
    return std::visit([&](const auto& u) { return u.moment(R); }, term);
  }
  Vec3 control_moment(const Mat3& /*R*/, const Control& u) const { return u; }
  double energy(const Mat3& R, const Vec3& Omega) const { return 0.5 * Omega.dot(inertia.J * Omega) + potential(R); }
  /// R J Omega, conserved only about a dipole's field.
  Vec3 spatial_momentum(const Mat3& R, const Vec3& Omega) const { return R * (inertia.J * Omega); }
};

}  // namespace lgvi
