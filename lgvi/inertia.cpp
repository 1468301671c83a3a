#include "lgvi/inertia.hpp"

#include <cmath>
#include <sstream>

#include <Eigen/Eigenvalues>

namespace lgvi {

void require_positive(double value, const std::string& field) {
  if (!std::isfinite(value)) throw InvalidInput(field, "is not finite");
  if (value <= 0.0) {
    std::ostringstream s;
    s << "must be > 0 (got " << value << ")";
    throw InvalidInput(field, s.str());
  }
}

Inertia Inertia::from(const Mat3& J, const std::string& field, InertiaDomain domain) {
  require_finite(J, field);
  const double scale = J.cwiseAbs().maxCoeff();
  if (scale == 0.0) throw InvalidInput(field, "is zero");
  if ((J - J.transpose()).cwiseAbs().maxCoeff() > 1e-12 * scale) {
    throw InvalidInput(field, "is not symmetric");
  }
  const Mat3 Js = 0.5 * (J + J.transpose());
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(Js, Eigen::EigenvaluesOnly);
  const Vec3 moments = eig.eigenvalues();  // ascending
  if (moments(0) <= 0.0) {
    std::ostringstream s;
    s << "is not positive definite (smallest principal moment " << moments(0) << ")";
    throw InvalidInput(field, s.str());
  }
  // Triangle inequality on the principal moments: J_min + J_mid >= J_max, with a round-off
  // allowance of 64 eps * J_max so that an exactly flat body is accepted.
  const double slack = moments(0) + moments(1) - moments(2);
  const bool physical = slack >= -64.0 * std::numeric_limits<double>::epsilon() * moments(2);
  if (!physical && domain == InertiaDomain::Physical) {
    std::ostringstream s;
    s << "violates the triangle inequality J1 + J2 >= J3 (principal moments " << moments(0)
      << ", " << moments(1) << ", " << moments(2) << ")";
    throw InvalidInput(field, s.str());
  }
  Inertia I;
  I.J = Js;
  I.Jd = 0.5 * Js.trace() * Mat3::Identity() - Js;
  I.J_inverse = Js.inverse();
  I.physical = physical;
  return I;
}

}  // namespace lgvi
