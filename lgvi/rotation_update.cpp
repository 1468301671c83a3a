#include "lgvi/rotation_update.hpp"

#include <cmath>
#include <cstdio>
#include <limits>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

namespace lgvi {

const char* to_string(Parametrization p) {
  return p == Parametrization::Cayley ? "cayley" : "exponential";
}

const char* to_string(RotationUpdateStatus s) {
  switch (s) {
    case RotationUpdateStatus::Converged: return "converged";
    case RotationUpdateStatus::OutsideDomain: return "outside the rotation update's domain";
    case RotationUpdateStatus::NotConverged: return "not converged";
  }
  return "unknown";
}

std::string RotationUpdateSummary::brief() const {
  char buf[256];
  if (status == RotationUpdateStatus::OutsideDomain && axis_ratio > 1.0) {
    // The axis named by its moment: "axis 2" read as the body's e2 (it is not, unless J is
    // diagonal with increasing moments).
    static constexpr const char* kMoment[] = {"smallest", "middle", "largest"};
    std::snprintf(buf, sizeof buf,
                  "%s: no rotation solves the update: |(h p)_i| / J_i = %.6g > 1 about the principal axis of the "
                  "%s moment of inertia (h |Omega_i| too large; the step must shrink by this factor at least)",
                  to_string(status), axis_ratio, axis >= 0 && axis < 3 ? kMoment[axis] : "unknown");
    return buf;
  }
  if (status == RotationUpdateStatus::OutsideDomain) {
    std::snprintf(buf, sizeof buf,
                  "%s: no rotation solves the update for |h p| = %.6g (bound sqrt(2) ||J_d||_F)",
                  to_string(status), rhs_norm);
    return buf;
  }
  std::snprintf(buf, sizeof buf, "%s in %d Newton iterations (%s%s), residual %.3g, |h p| = %.6g",
                to_string(status), iterations, to_string(parametrization),
                used_fallback ? ", after fallback" : "", residual(), rhs_norm);
  return buf;
}

RotationUpdateSolver::RotationUpdateSolver(const Inertia& inertia, RotationUpdateOptions options)
    : inertia_(inertia),
      options_(options),
      domain_bound_(std::sqrt(2.0) * inertia.Jd.norm()),
      J_norm_(inertia.J.norm()),
      cayley_det2_floor_(rotation_update_detail::cayley_det2_floor(J_norm_)) {
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(inertia.J);
  const Vec3 moments = eig.eigenvalues();  // increasing
  const Vec3 d = Vec3::Constant(0.5 * moments.sum()) - moments;  // J_d in the principal frame
  Vec3 inverse_bound;
  for (int i = 0; i < 3; ++i) inverse_bound(i) = 1.0 / (std::abs(d((i + 1) % 3)) + std::abs(d((i + 2) % 3)));
  axis_map_ = inverse_bound.asDiagonal() * eig.eigenvectors().transpose();
}

void RotationUpdateSolver::diagnose(const Vec3& hp, RotationUpdateSummary& s) const {
  const Vec3 ratios = (axis_map_ * hp).cwiseAbs();
  Eigen::Index axis = 0;
  s.axis_ratio = ratios.maxCoeff(&axis);
  s.axis = static_cast<int>(axis);
  if (s.axis_ratio > 1.0 && !s.converged()) s.status = RotationUpdateStatus::OutsideDomain;
}

Vec3 RotationUpdateSolver::matrix_residual(const Mat3& F, const Vec3& hp) const {
  const Mat3& Jd = inertia_.Jd;
  return so3::vee(F * Jd - Jd * F.transpose()) - hp;
}

RotationUpdateSummary RotationUpdateSolver::outside_domain(const Vec3& hp, double rhs_norm) const {
  RotationUpdateSummary s;
  s.status = RotationUpdateStatus::OutsideDomain;
  s.parametrization = options_.primary;
  s.rhs_norm = rhs_norm;
  s.set_residual(std::numeric_limits<double>::quiet_NaN());
  diagnose(hp, s);
  return s;
}

RotationUpdateSummary RotationUpdateSolver::newton_in(Parametrization p, const Vec3& hp,
                                                      double rhs_norm,
                                                      const rotation_update_detail::FastNewton* from,
                                                      RotationStep& step) const {
  namespace d = rotation_update_detail;
  const d::V3 b = d::v3(hp);
  RotationUpdateSummary s =
      p == Parametrization::Cayley
          ? d::newton<d::CayleyChart>(inertia_, J_norm_, options_, hp, rhs_norm,
                                      from ? from->f : d::CayleyChart::warm_start(inertia_, b),
                                      from ? from->iterations : 0, step)
          : d::newton<d::ExponentialChart>(inertia_, J_norm_, options_, hp, rhs_norm,
                                           from ? from->f : d::ExponentialChart::warm_start(inertia_, b),
                                           from ? from->iterations : 0, step);
  s.parametrization = p;
  if (s.converged()) step.chart = p;
  return s;
}

RotationUpdateSummary RotationUpdateSolver::slow_path(const Vec3& hp, double rhs_norm,
                                                      const rotation_update_detail::FastNewton& at,
                                                      RotationStep& step) const {
  const Parametrization primary = options_.primary;
  RotationUpdateSummary s = newton_in(primary, hp, rhs_norm, &at, step);
  if (s.converged()) return s;
  if (options_.fallback) {
    // The other chart from its own warm start, its iterations counted on top.
    const Parametrization other =
        primary == Parametrization::Cayley ? Parametrization::Exponential : Parametrization::Cayley;
    RotationStep candidate;
    const int primary_iterations = s.iterations;
    s = newton_in(other, hp, rhs_norm, nullptr, candidate);
    s.iterations += primary_iterations;
    s.used_fallback = true;
    if (s.converged()) {
      step = candidate;
      return s;
    }
  }
  diagnose(hp, s);
  return s;
}

namespace rotation_update_detail {

Vec3 solve_pivoted(const Vec3& c0, const Vec3& c1, const Vec3& c2, const Vec3& b) {
  Mat3 A;
  A << c0, c1, c2;
  return Eigen::PartialPivLU<Mat3>(A).solve(b);
}

}  // namespace rotation_update_detail

}  // namespace lgvi
