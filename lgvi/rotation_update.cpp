#include "lgvi/rotation_update.hpp"

#include <cmath>
#include <cstdio>
#include <limits>

#include <Eigen/LU>

#include "lgvi/so3.hpp"

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
  if (status == RotationUpdateStatus::OutsideDomain) {
    std::snprintf(buf, sizeof buf,
                  "%s: no rotation solves the update for |h p| = %.6g (bound sqrt(2) ||J_d||_F)",
                  to_string(status), rhs_norm);
    return buf;
  }
  std::snprintf(buf, sizeof buf, "%s in %d Newton iterations (%s%s), residual %.3g, |h p| = %.6g",
                to_string(status), iterations, to_string(parametrization),
                used_fallback ? ", after fallback" : "", residual, rhs_norm);
  return buf;
}

RotationUpdateSolver::RotationUpdateSolver(const Inertia& inertia, RotationUpdateOptions options)
    : inertia_(inertia), options_(options), domain_bound_(std::sqrt(2.0) * inertia.Jd.norm()) {}

Mat3 rotation_from(Parametrization p, const Vec3& f) {
  return p == Parametrization::Cayley ? so3::cayley(f) : so3::exp(f);
}

Vec3 RotationUpdateSolver::matrix_residual(const Mat3& F, const Vec3& hp) const {
  const Mat3& Jd = inertia_.Jd;
  return so3::vee(F * Jd - Jd * F.transpose()) - hp;
}

namespace {

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();

// Residual G(f) and Newton Jacobian for each parametrization. For Cayley the Newton map uses
// the polynomial H = (1 + |f|^2)/2 G (same roots, Jacobian J + hat(f) J - hat(J f) - h p f^T).
// `size` = a |f| + b |f|^2 = sin(theta) + 1 - cos(theta) in both charts: the terms a J f and
// b f x J f of G are at most ||J|| size in norm (used for the round-off floor of G, see newton).
struct CayleyModel {
  static Vec3 warm_start(const Inertia& I, const Vec3& hp) { return 0.5 * (I.J_inverse * hp); }
  static void evaluate(const Mat3& J, const Vec3& hp, const Vec3& f, Vec3& G, Vec3& H, Mat3& dH,
                       double& size) {
    const Vec3 Jf = J * f;
    const double s = 1.0 + f.squaredNorm();
    H = Jf + f.cross(Jf) - 0.5 * s * hp;
    G = (2.0 / s) * H;
    size = (2.0 / s) * (f.norm() + f.squaredNorm());
    dH = J + so3::hat(f) * J - so3::hat(Jf) - hp * f.transpose();
  }
};

struct ExponentialModel {
  static Vec3 warm_start(const Inertia& I, const Vec3& hp) { return I.J_inverse * hp; }
  static void evaluate(const Mat3& J, const Vec3& hp, const Vec3& f, Vec3& G, Vec3& H, Mat3& dH,
                       double& size) {
    const double t = f.norm();
    const auto [a, b] = so3::rodrigues(t);
    size = a * t + b * t * t;
    // da/dt / t and db/dt / t; Taylor branch for t < 1e-2 (truncation t^6/45360 < 1e-16).
    double da_t, db_t;
    if (t < 1e-2) {
      const double t2 = t * t;
      da_t = -1.0 / 3.0 + t2 / 30.0 - t2 * t2 / 840.0;
      db_t = -1.0 / 12.0 + t2 / 180.0 - t2 * t2 / 6720.0;
    } else {
      const double t3 = t * t * t;
      da_t = (t * std::cos(t) - std::sin(t)) / t3;
      db_t = (t * std::sin(t) - 2.0 * (1.0 - std::cos(t))) / (t3 * t);
    }
    const Vec3 Jf = J * f;
    const Vec3 fxJf = f.cross(Jf);
    G = a * Jf + b * fxJf - hp;
    H = G;
    dH = a * J + b * (so3::hat(f) * J - so3::hat(Jf)) + da_t * Jf * f.transpose() +
         db_t * fxJf * f.transpose();
  }
};

template <class Model>
RotationUpdateSummary newton(const Inertia& I, const RotationUpdateOptions& o, const Vec3& hp,
                             Vec3& f_out) {
  RotationUpdateSummary s;
  s.rhs_norm = hp.norm();
  const double scale = s.rhs_norm > 0.0 ? s.rhs_norm : 1.0;
  const double J_norm = I.J.norm();
  Vec3 f = Model::warm_start(I, hp);
  Vec3 G, H;
  Mat3 dH;
  double size = 0.0;
  for (;;) {
    Model::evaluate(I.J, hp, f, G, H, dH, size);
    const double g = G.norm();
    s.residual = g / scale;
    if (!std::isfinite(g)) break;
    // Round-off floor of G: its terms a J f, b f x J f and h p are each formed to a few eps of
    // their size, and f itself is only representable to eps |f| (dG/df ~ a J), so |G| cannot be
    // pushed below ~eps (|h p| + ||J|| size). A tolerance relative to |h p| alone is unreachable
    // when J is ill-conditioned and h p lies near a weak principal axis in a non-principal body
    // frame (|h p| << ||J|| |f|): Newton then stalls at a few 1e-15 and reported NotConverged for
    // a solved problem (e.g. a dumbbell with rho along (1,1,1), ~1e-4 of random momenta).
    const double tol =
        o.relative_tolerance * (s.rhs_norm + J_norm * size) + o.absolute_tolerance;
    if (g <= tol) {
      // Polish: one more Newton step when |G| is still above 4 eps |h p| (the floor for a
      // well-conditioned J); kept only if it lowers |G|. Ill-conditioned J and h p near a weak
      // axis leave |G| / |h p| at ~1e-14 after the test above; one step usually halves it.
      if (o.polish && g > 4.0 * kEpsilon * s.rhs_norm && s.iterations < o.max_iterations) {
        const Vec3 polished = f - Eigen::PartialPivLU<Mat3>(dH).solve(H);
        Vec3 G2, H2;
        Mat3 dH2;
        double size2 = 0.0;
        Model::evaluate(I.J, hp, polished, G2, H2, dH2, size2);
        ++s.iterations;
        s.polished = true;
        if (G2.norm() < g) {
          f = polished;
          s.residual = G2.norm() / scale;
        }
      }
      s.status = RotationUpdateStatus::Converged;
      f_out = f;
      return s;
    }
    if (s.iterations >= o.max_iterations) break;
    const Eigen::PartialPivLU<Mat3> lu(dH);
    const Vec3 step = lu.solve(H);
    if (!step.allFinite()) break;
    f -= step;
    ++s.iterations;
  }
  s.status = RotationUpdateStatus::NotConverged;
  return s;
}

}  // namespace

RotationUpdateSummary RotationUpdateSolver::solve_in(Parametrization p, const Vec3& hp,
                                                     Vec3& f) const {
  RotationUpdateSummary s = p == Parametrization::Cayley
                                ? newton<CayleyModel>(inertia_, options_, hp, f)
                                : newton<ExponentialModel>(inertia_, options_, hp, f);
  s.parametrization = p;
  return s;
}

RotationUpdateSummary RotationUpdateSolver::solve(const Vec3& hp, Mat3& F) const {
  const double rhs_norm = hp.norm();
  if (!(rhs_norm <= domain_bound_)) {  // also catches NaN
    RotationUpdateSummary s;
    s.status = RotationUpdateStatus::OutsideDomain;
    s.parametrization = options_.primary;
    s.rhs_norm = rhs_norm;
    s.residual = std::numeric_limits<double>::quiet_NaN();
    return s;
  }
  Vec3 f;
  RotationUpdateSummary s = solve_in(options_.primary, hp, f);
  if (!s.converged() && options_.fallback) {
    const Parametrization other = options_.primary == Parametrization::Cayley
                                      ? Parametrization::Exponential
                                      : Parametrization::Cayley;
    const int first_iterations = s.iterations;
    s = solve_in(other, hp, f);
    s.iterations += first_iterations;
    s.used_fallback = true;
  }
  if (s.converged()) F = rotation_from(s.parametrization, f);
  return s;
}

}  // namespace lgvi
