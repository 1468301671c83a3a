// The implicit rotation update of every LGVI of the project (eqs. 8, 21, 32):
//
//     h hat(p) = F J_d - J_d F^T,   F in SO(3),   J_d = tr(J)/2 I - J.
//
// With F = I + a hat(f) + b hat(f)^2 (a parametrization of SO(3) by f in R^3) the matrix
// equation is equivalent to the vector equation
//
//     G(f) = a J f + b f x (J f) - h p = 0
//
// because hat(f) J_d + J_d hat(f) = hat(J f) and hat(f)^2 J_d - J_d hat(f)^2 = hat(f x J f).
//   Cayley:       a = b = 2 / (1 + |f|^2), f = tan(theta/2) n; solved as the polynomial
//                 H(f) = J f + f x J f - (1 + |f|^2) h p / 2 = (1 + |f|^2)/2 G(f).
//   Exponential:  a = sin(t)/t, b = (1 - cos t)/t^2, t = |f|, f = theta n.
// Newton's method with the analytic Jacobian of H (or G), from the linearized warm start
// J f = h p (exponential) or J f = h p / 2 (Cayley). Converged when
// |G(f)| <= relative_tolerance (|h p| + ||J||_F (a |f| + b |f|^2)) + absolute_tolerance, i.e.
// relative to the size of the terms of G (a |f| + b |f|^2 = sin(theta) + 1 - cos(theta) in both
// charts), which is the round-off floor of evaluating G. If the primary parametrization fails,
// the other one is tried from its own warm start.
//
// A solution exists only for |h p| <= max_F |vee(F J_d - J_d F^T)| <= sqrt(2) ||J_d||_F; beyond
// that bound the solver reports OutsideDomain without iterating. A sharper necessary condition,
// checked only after Newton failed (no cost per step): in the principal frame of J (J_d =
// diag(d), d_i = (J_j + J_k - J_i)/2 >= 0), component i of vee(F J_d - J_d F^T) is
// F_kj d_j - F_jk d_k, at most d_j + d_k = J_i in size since |F_jk| <= 1. So
// |(h p)_i| <= J_i on every principal axis, i.e. h |Omega_i| <= 1 for a free body: a fast spin
// about a symmetry axis with h |Omega| > 1 has no solution although |h p| is far inside the
// first bound. Such a failure is reported as OutsideDomain with that ratio (axis_ratio), from
// which the largest admissible step follows (h / axis_ratio).
//
// Cost: solve() is a fast path inline, and everything else out of line (slow_path). The fast
// path is the primary chart's Newton iteration from its warm start with nothing else in the loop:
// the Newton matrix written column by column from cross products and solved in closed form
// (adjugate), the iteration on plain doubles (lgvi/plain3.hpp), convergence tested on |H|^2 (no
// division or square root of G per iteration), the summary's residual stored as |H|^2 and
// evaluated only when read. It stops at the first thing it does not handle: a nearly singular
// Newton matrix (by a cheaper, more cautious guard than newton()'s, see newton_fast), a
// non-finite value, the iteration cap, or a converged |G| that wants the polishing step;
// slow_path() then continues newton() from where it stopped (pivoted LU, polishing, failure
// summary), then the fallback chart, then the diagnosis, so a solve gives the
// iterates and iteration counts of newton() alone. The steps that call it are flattened
// (LGVI_FLATTEN) and apply F without forming it (RotationStep). The exponential chart takes one
// sin/cos pair of the half angle per evaluation, and F reuses the last one. All this changes the
// Newton steps by round-off only: the converged f is that of the previous, generic implementation
// (kept in tests/lgvi/reference_rotation_update.hpp) to round-off, with the same iteration counts
// except where |G| lands within round-off of the tolerance.
#pragma once

#include <cmath>
#include <limits>
#include <string>
#include <type_traits>

#include "lgvi/inertia.hpp"
#include "lgvi/plain3.hpp"
#include "lgvi/so3.hpp"
#include "lgvi/types.hpp"

namespace lgvi {

enum class Parametrization { Cayley, Exponential };
const char* to_string(Parametrization p);

enum class RotationUpdateStatus {
  Converged,
  OutsideDomain,  ///< |h p| exceeds the bound above: no rotation solves the equation.
  NotConverged,   ///< Newton hit the iteration cap or left the finite numbers in both charts.
};
const char* to_string(RotationUpdateStatus s);

struct RotationUpdateOptions {
  Parametrization primary = Parametrization::Cayley;
  bool fallback = true;  ///< try the other parametrization when the primary fails
  /// 16 eps, relative to the size of G's terms |h p| + ||J||_F (a |f| + b |f|^2) (see the
  /// convergence test above). Evaluating G costs <= 8 unit round-offs (4 eps) of that size (the
  /// 3-term products of J f, the cross product, the scalings and sums); near the root Newton's
  /// computed residual is the previous step's evaluation error plus the current one, so it
  /// settles at <= 8 eps and may oscillate there (observed: +-5.5 eps). 16 eps leaves a factor 2.
  double relative_tolerance = 16.0 * 2.220446049250313e-16;
  double absolute_tolerance = 1e-300;
  int max_iterations = 30;  ///< per parametrization
  /// One extra Newton step when |G| is still above 4 eps |h p| after the test above (see
  /// the solver below). Switched off only to demonstrate that the regression gate catches a
  /// degraded solver (`validate --degraded-rotation-update`).
  bool polish = true;
  /// The multibody LGVI whose attitude update is a sum, the cart-pendulum's R_{k+1} = R_k +
  /// R_k (F - I), forms it by compensated summation (multibody_lgvi.cpp). Switched off only to
  /// demonstrate that the gate catches it (`validate --degrade uncompensated-attitude`): R then
  /// random-walks off SO(3) by ~eps per step.
  bool compensated_attitude = true;
};

struct RotationUpdateSummary {
  RotationUpdateStatus status = RotationUpdateStatus::NotConverged;
  Parametrization parametrization = Parametrization::Cayley;  ///< the one that produced F
  int iterations = 0;          ///< Newton iterations over all attempts
  bool used_fallback = false;
  bool polished = false;       ///< the last of `iterations` was the optional polishing step
  double rhs_norm = 0.0;       ///< |h p|
  /// Set on failure only: max_i |(h p)_i| / J_i over the principal axes (above); > 1 means no
  /// rotation solves the update, and the step must shrink by at least this factor.
  double axis_ratio = 0.0;
  int axis = -1;               ///< the principal axis (0, 1, 2 by increasing J_i) of axis_ratio

  bool converged() const { return status == RotationUpdateStatus::Converged; }
  /// |G(f)| / |h p| at return (absolute when h p = 0; NaN outside the domain).
  double residual() const {
    return h_per_g_ > 0.0 ? std::sqrt(h2_) / h_per_g_ / scale_ : h2_;
  }
  /// residual() = r.
  void set_residual(double r) {
    h2_ = r;
    h_per_g_ = 0.0;
  }
  /// residual() = sqrt(h2) / h_per_g / scale, |H|^2 = h2 and |H| = h_per_g |G| (a chart's
  /// evaluation), scale = |h p| (1 when h p = 0), evaluated only when read: a square root and
  /// two divisions at the end of the Newton iteration, which the step would otherwise wait on
  /// (10 of a free-body step's ~100 ns, measured).
  void set_residual(double h2, double h_per_g, double scale) {
    h2_ = h2;
    h_per_g_ = h_per_g;
    scale_ = scale;
  }
  /// One line: "converged in 3 Newton iterations (cayley), residual 1.2e-16".
  std::string brief() const;

 private:
  double h2_ = 0.0;       ///< |H|^2, or residual() itself when h_per_g_ == 0
  double h_per_g_ = 0.0;
  double scale_ = 1.0;
};

/// The solution F = I + a hat(f) + b hat(f)^2 of the rotation update as its parameter f and the
/// chart's coefficients (Cayley: a = b = 2 / (1 + |f|^2); exponential: a = sin|f| / |f|,
/// b = (1 - cos|f|) / |f|^2), applied without forming F. Row i of R F is
/// r_i + a m_i + b m_i x f with m_i = r_i x f (r^T hat(f) = (r x f)^T), and
/// F^T k = k - a f x k + b f x (f x k) (hat(f)^T = -hat(f), hat(f)^2 symmetric): on plain
/// doubles, no 3x3 temporary and no generic product. Both agree with the products by
/// rotation_from(chart, f) to a few ulp; matrix() is rotation_from(chart, f) to the last bit.
struct RotationStep {
  Parametrization chart = Parametrization::Cayley;
  Vec3 f = Vec3::Zero();
  double a = 0.0;
  double b = 0.0;

  Mat3 matrix() const;                         ///< F
  Mat3 right_multiply(const Mat3& R) const;    ///< R F
  Vec3 transpose_times(const Vec3& k) const;   ///< F^T k
};

namespace rotation_update_detail {
struct FastNewton;
}  // namespace rotation_update_detail

/// Solves h hat(p) = F J_d - J_d F^T for F. Immutable after construction; `solve` allocates
/// nothing and may be called concurrently.
class RotationUpdateSolver {
 public:
  explicit RotationUpdateSolver(const Inertia& inertia, RotationUpdateOptions options = {});

  /// Finds F for the right-hand side hp = h p. On success F is orthonormal to round-off; on
  /// failure F is left unchanged and the summary says why.
  RotationUpdateSummary solve(const Vec3& hp, Mat3& F) const;
  /// The same solution as its parameter (F = step.matrix()), for steps that apply F without
  /// forming it. On failure `step` is left unchanged.
  RotationUpdateSummary solve(const Vec3& hp, RotationStep& step) const;

  /// Solves in one given parametrization, without fallback; f is the converged parameter.
  RotationUpdateSummary solve_in(Parametrization p, const Vec3& hp, Vec3& f) const;

  /// Residual vee(F J_d - J_d F^T) - h p of the matrix equation (diagnostic).
  Vec3 matrix_residual(const Mat3& F, const Vec3& hp) const;

  /// Upper bound on |h p| for which a solution can exist: sqrt(2) ||J_d||_F.
  double domain_bound() const { return domain_bound_; }

  /// Fills s.axis_ratio and s.axis for the right-hand side hp (see the top of this file) and
  /// turns a failure with axis_ratio > 1 into OutsideDomain.
  void diagnose(const Vec3& hp, RotationUpdateSummary& s) const;

  const Inertia& inertia() const { return inertia_; }
  const RotationUpdateOptions& options() const { return options_; }

 private:
  /// The summary of a right-hand side outside the domain (or not finite), diagnosed.
  RotationUpdateSummary outside_domain(const Vec3& hp, double rhs_norm) const;
  /// Newton in chart p (rotation_update_detail::newton) from the iterate `from` where the fast
  /// path stopped, or from the chart's warm start when `from` is null.
  RotationUpdateSummary newton_in(Parametrization p, const Vec3& hp, double rhs_norm,
                                  const rotation_update_detail::FastNewton* from,
                                  RotationStep& step) const;
  /// solve() after the fast path stopped at `at` without converging: newton() continued from
  /// there in the primary chart, then the other chart (options.fallback), then diagnose().
  RotationUpdateSummary slow_path(const Vec3& hp, double rhs_norm,
                                  const rotation_update_detail::FastNewton& at,
                                  RotationStep& step) const;

  Inertia inertia_;
  RotationUpdateOptions options_;
  double domain_bound_;
  double J_norm_;  ///< ||J||_F, the scale of G's terms in the convergence test
  double cayley_det2_floor_;  ///< 64 eps ||J||_F^6: newton_fast's guard of the Cayley chart
  Mat3 axis_map_;  ///< diag(1 / (|d_j| + |d_k|)) Q^T: hp -> (h p)_i / J_i in the principal frame
};

/// F = I + a hat(f) + b hat(f)^2 for the given parametrization: so3::cayley(f), or exp(hat f)
/// with the solver's coefficients (ExponentialChart::rodrigues, equal to so3::exp to an ulp).
/// The F that `solve` returns is rotation_from(parametrization, f) to the last bit.
Mat3 rotation_from(Parametrization p, const Vec3& f);

// --- Implementation: the inline hot path ---------------------------------------------------------

namespace rotation_update_detail {

// The Newton iteration runs on plain doubles (lgvi/plain3.hpp).
using namespace plain;

/// Solves A x = b for A = [c0 c1 c2] (columns) by the adjugate (Cramer's rule):
/// x_i = b . (c_{i+1} x c_{i+2}) / det A, det A = c0 . (c1 x c2). Returns false, leaving x
/// untouched, when det A^2 <= eps ||A||_F^6 (also for non-finite or underflowing entries).
/// Why that guard: each cofactor carries an absolute error ~eps ||A||^2, so x's relative error
/// is ~eps ||A||^3 / |det A| <= sqrt(eps) past the guard, harmless in a Newton correction, and
/// ||A||_F^3 / |det A| >= cond_2(A) (s1 <= ||A||_F, s1 s2 <= ||A||_F^2), so the guard trips
/// before cond(A) reaches 1 / sqrt(eps) ~ 7e7. Below it the caller uses a pivoted LU.
/// The adjugate solve with the guard det A^2 > det2_floor: solve_adjugate with det2_floor =
/// eps ||A||_F^6, and newton_fast with a floor at least that, known without forming ||A||_F
/// (the same arithmetic, so wherever the latter solves, solve_adjugate gives the same x).
inline bool solve_adjugate_above(const M3& A, const V3& b, double det2_floor, V3& x) {
  const V3 k0 = cross(A.c1, A.c2), k1 = cross(A.c2, A.c0), k2 = cross(A.c0, A.c1);
  const double det = dot(A.c0, k0);
  if (!(det * det > det2_floor)) return false;
  const double inverse = 1.0 / det;
  x = {dot(b, k0) * inverse, dot(b, k1) * inverse, dot(b, k2) * inverse};
  return true;
}
inline bool solve_adjugate(const M3& A, const V3& b, V3& x) {
  const double frobenius2 = dot(A.c0, A.c0) + dot(A.c1, A.c1) + dot(A.c2, A.c2);
  return solve_adjugate_above(A, b, kEps * (frobenius2 * frobenius2 * frobenius2), x);
}
inline bool solve_adjugate(const Vec3& c0, const Vec3& c1, const Vec3& c2, const Vec3& b,
                           Vec3& x) {
  V3 y;
  if (!solve_adjugate(M3{v3(c0), v3(c1), v3(c2)}, v3(b), y)) return false;
  x = vec3(y);
  return true;
}

/// A x = b by PartialPivLU (out of line): the nearly singular case of solve_adjugate. A singular
/// A gives a non-finite x, which the Newton iteration reports.
Vec3 solve_pivoted(const Vec3& c0, const Vec3& c1, const Vec3& c2, const Vec3& b);

/// A x = b for A = [c0 c1 c2]: closed form, pivoted LU when nearly singular.
inline V3 solve3(const M3& A, const V3& b) {
  V3 x;
  if (solve_adjugate(A, b, x)) return x;
  return v3(solve_pivoted(vec3(A.c0), vec3(A.c1), vec3(A.c2), vec3(b)));
}
inline Vec3 solve3(const Vec3& c0, const Vec3& c1, const Vec3& c2, const Vec3& b) {
  return vec3(solve3(M3{v3(c0), v3(c1), v3(c2)}, v3(b)));
}

// A chart provides the Newton function H (a multiple of G with the same roots), its Newton
// matrix dH, the coefficients a, b of F at the evaluated f, and, for the convergence test
// without a division or square root per iteration, h_per_g = |H| / |G| and size_h =
// h_per_g size, where size = a |f| + b |f|^2 = sin(theta) + 1 - cos(theta) in both charts (the
// terms a J f and b f x J f of G are at most ||J|| size in norm: the round-off floor of G, see
// newton).

/// Cayley chart: H = (1 + |f|^2)/2 G = J f + f x J f - (1 + |f|^2) h p / 2 (polynomial), with
///   dH = J + hat(f) J - hat(J f) - h p f^T,
/// column j: J e_j + f x (J e_j) - (J f) x e_j - f_j h p.
struct CayleyChart {
  struct Evaluation {
    V3 H, Jf;
    double t, h_per_g, size_h;  ///< t = |f|
  };
  static V3 warm_start(const Inertia& I, const V3& hp) { return 0.5 * (m3(I.J_inverse) * hp); }
  /// a = b = 2 / (1 + |f|^2) of F = I + a hat(f) + b hat(f)^2 at the evaluated f.
  static void coefficients(const Evaluation& e, double& a, double& b) { a = b = 1.0 / e.h_per_g; }
  static void evaluate(const M3& J, const V3& hp, const V3& f, Evaluation& e) {
    e.Jf = J * f;
    const double f2 = dot(f, f);
    e.h_per_g = 0.5 * (1.0 + f2);
    e.H = e.Jf + cross(f, e.Jf) - e.h_per_g * hp;
    e.t = std::sqrt(f2);
    e.size_h = e.t + f2;
  }
  static M3 newton_matrix(const M3& J, const V3& hp, const V3& f, const Evaluation& e) {
    const V3& w = e.Jf;
    return {J.c0 + cross(f, J.c0) + V3{0.0, -w.z, w.y} - f.x * hp,
            J.c1 + cross(f, J.c1) + V3{w.z, 0.0, -w.x} - f.y * hp,
            J.c2 + cross(f, J.c2) + V3{-w.y, w.x, 0.0} - f.z * hp};
  }
};

/// Exponential chart: H = G = a J f + b f x J f - h p, with Jacobian
///   dG = a J + b (hat(f) J - hat(J f)) + (a'/t J f + b'/t f x J f) f^T   (t = |f|),
/// column j: a J e_j + b (f x J e_j - (J f) x e_j) + f_j (a'/t J f + b'/t f x J f).
struct ExponentialChart {
  struct Evaluation {
    V3 H, Jf, fxJf;
    double t, a, b, h_per_g, size_h;
  };
  /// The coefficients of so3::rodrigues in its half-angle form (one sin/cos pair of t/2: with
  /// q = sin(t/2) / (t/2), a = q cos(t/2), b = q^2 / 2; no cancellation) down to t = 1e-4, and
  /// so3::rodrigues (its series) below. so3::rodrigues switches to its series below t = 1/2; the
  /// rotation update keeps the sin/cos form there, so the LGVI's exponential chart steps as
  /// measured and accepted (the two agree to a few ulp, below G's evaluation floor of 8 eps of
  /// its term size, rotation_update test).
  static so3::RodriguesCoefficients rodrigues(double t) {
    return t < 1e-4 ? so3::rodrigues(t) : so3::rodrigues_half_angle(t);
  }
  /// The coefficients of the evaluation at f (those rotation_from recomputes).
  static void coefficients(const Evaluation& e, double& a, double& b) {
    a = e.a;
    b = e.b;
  }
  /// F = exp(hat f) = I + a hat(f) + b hat(f)^2.
  static Mat3 rotation(const V3& f, double a, double b) {
    const Vec3 w = vec3(f);
    return Mat3::Identity() + a * so3::hat(w) + b * so3::hat_squared(w);
  }
  static V3 warm_start(const Inertia& I, const V3& hp) { return m3(I.J_inverse) * hp; }
  static void evaluate(const M3& J, const V3& hp, const V3& f, Evaluation& e) {
    e.t = std::sqrt(dot(f, f));
    const auto [a, b] = rodrigues(e.t);
    e.a = a;
    e.b = b;
    e.Jf = J * f;
    e.fxJf = cross(f, e.Jf);
    e.H = a * e.Jf + b * e.fxJf - hp;
    e.h_per_g = 1.0;
    e.size_h = a * e.t + b * e.t * e.t;
  }
  static M3 newton_matrix(const M3& J, const V3& /*hp*/, const V3& f, const Evaluation& e) {
    // a'/t and b'/t. With cos t = 1 - b t^2: a'/t = (t cos t - sin t)/t^3 = (1 - b t^2 - a)/t^2,
    // b'/t = (t sin t - 2(1 - cos t))/t^4 = (a - 2 b)/t^2. Both cancel to ~eps/t^2 relative, so
    // the Taylor branch below t = 1e-2 (truncation t^6/45360 < 1e-16; cancellation <= 1e-12
    // above): an error in the Newton matrix changes the convergence rate, not the root.
    const double t2 = e.t * e.t;
    double da_t, db_t;
    if (e.t < 1e-2) {
      da_t = -1.0 / 3.0 + t2 / 30.0 - t2 * t2 / 840.0;
      db_t = -1.0 / 12.0 + t2 / 180.0 - t2 * t2 / 6720.0;
    } else {
      da_t = (1.0 - e.b * t2 - e.a) / t2;
      db_t = (e.a - 2.0 * e.b) / t2;
    }
    const V3& w = e.Jf;
    const V3 r = da_t * w + db_t * e.fxJf;
    return {e.a * J.c0 + e.b * (cross(f, J.c0) + V3{0.0, -w.z, w.y}) + f.x * r,
            e.a * J.c1 + e.b * (cross(f, J.c1) + V3{w.z, 0.0, -w.x}) + f.y * r,
            e.a * J.c2 + e.b * (cross(f, J.c2) + V3{-w.y, w.x, 0.0}) + f.z * r};
  }
};

/// The convergence test's bound on |H| (see newton): |G| <= relative_tolerance (|h p| +
/// ||J|| size) + absolute_tolerance, multiplied by h_per_g.
template <class Evaluation>
inline double converged_bound(const RotationUpdateOptions& o, double rhs_norm, double J_norm,
                              const Evaluation& e) {
  return e.h_per_g * (o.relative_tolerance * rhs_norm + o.absolute_tolerance) +
         o.relative_tolerance * J_norm * e.size_h;
}

/// Polishing wanted after convergence: |G| still above 4 eps |h p| (see newton).
template <class Evaluation>
inline bool wants_polish(const RotationUpdateOptions& o, double rhs_norm, double h2,
                         const Evaluation& e) {
  const double polish_threshold = 4.0 * kEps * rhs_norm * e.h_per_g;
  return o.polish && h2 > polish_threshold * polish_threshold;
}

/// Newton's method in one chart, from the iterate f after `iterations` iterations (the warm
/// start and 0 for a fresh solve). On convergence only, `out` holds the parameter and the
/// coefficients of F (from the last evaluation). The whole method: the Newton systems by
/// solve3 (pivoted LU when nearly singular), the polishing step, the failure summaries.
template <class Chart>
inline RotationUpdateSummary newton(const Inertia& I, double J_norm, const RotationUpdateOptions& o,
                                    const Vec3& hp_in, double rhs_norm, V3 f, int iterations,
                                    RotationStep& out) {
  RotationUpdateSummary s;
  s.rhs_norm = rhs_norm;
  s.iterations = iterations;
  const double scale = rhs_norm > 0.0 ? rhs_norm : 1.0;
  const M3 J = m3(I.J);
  const V3 hp = v3(hp_in);
  // |G| = |H| / h_per_g, reported relative to |h p| (absolute when h p = 0).
  const auto set_residual = [scale, &s](const typename Chart::Evaluation& e) {
    s.set_residual(dot(e.H, e.H), e.h_per_g, scale);
  };
  typename Chart::Evaluation e;
  for (;;) {
    Chart::evaluate(J, hp, f, e);
    const double h2 = dot(e.H, e.H);
    if (!std::isfinite(h2)) break;  // as |G| = inf or NaN: Eigen's norm() overflows alike
    // Round-off floor of G: its terms a J f, b f x J f and h p are each formed to a few eps of
    // their size, and f itself is only representable to eps |f| (dG/df ~ a J), so |G| cannot be
    // pushed below ~eps (|h p| + ||J|| size). A tolerance relative to |h p| alone is unreachable
    // when J is ill-conditioned and h p lies near a weak principal axis in a non-principal body
    // frame (|h p| << ||J|| |f|): Newton then stalls at a few 1e-15 and reported NotConverged for
    // a solved problem (e.g. a dumbbell with rho along (1,1,1), ~1e-4 of random momenta).
    // |G| <= relative_tolerance (|h p| + ||J|| size) + absolute_tolerance, multiplied by h_per_g
    // and squared:
    const double tol_h = converged_bound(o, rhs_norm, J_norm, e);
    if (h2 <= tol_h * tol_h) {
      // Polish: one more Newton step when |G| is still above 4 eps |h p| (the floor for a
      // well-conditioned J); kept only if it lowers |G|. Ill-conditioned J and h p near a weak
      // axis leave |G| / |h p| at ~1e-14 after the test above; one step usually halves it.
      set_residual(e);
      if (wants_polish(o, rhs_norm, h2, e) && s.iterations < o.max_iterations) {
        const V3 polished = f - solve3(Chart::newton_matrix(J, hp, f, e), e.H);
        typename Chart::Evaluation e2;
        Chart::evaluate(J, hp, polished, e2);
        ++s.iterations;
        s.polished = true;
        RotationUpdateSummary p;
        p.set_residual(dot(e2.H, e2.H), e2.h_per_g, scale);
        if (p.residual() < s.residual()) {
          f = polished;
          e = e2;
          set_residual(e);
        }
      }
      s.status = RotationUpdateStatus::Converged;
      out.f = vec3(f);
      Chart::coefficients(e, out.a, out.b);
      return s;
    }
    if (s.iterations >= o.max_iterations) break;
    const V3 step = solve3(Chart::newton_matrix(J, hp, f, e), e.H);
    if (!all_finite(step)) break;
    f = f - step;
    ++s.iterations;
  }
  set_residual(e);
  s.status = RotationUpdateStatus::NotConverged;
  return s;
}

/// The Cayley fast guard's limit on t = |f| and its floor on det(dH)^2 (see newton_fast).
inline double cayley_fast_t_limit(double J_norm, double rhs_norm) {
  return 0.9 * J_norm / ((1.0 + std::sqrt(2.0)) * J_norm + rhs_norm);
}
inline double cayley_det2_floor(double J_norm) { return 64.0 * kEps * std::pow(J_norm, 6); }

/// Where newton_fast stopped: the iterate and the iterations taken to reach it.
struct FastNewton {
  V3 f;
  int iterations;
};

/// The common case of newton() from the warm start, as the LGVI steps meet it: every Newton
/// matrix well conditioned (solve_adjugate's guard passes), every value finite, convergence
/// within the cap, no polishing wanted. The same iterates, test and summary as newton(), with
/// nothing else in the loop: no pivoted solve, no polishing step, no failure summary. Returns
/// true on convergence (summary and `out` written); otherwise false with the iterate where it
/// stopped in `at`, from which newton() continues (the slow path) to the result newton() alone
/// would have given, iteration counts included.
///
/// It may stop earlier than newton() would fail, never later: newton() then re-takes the same
/// steps. Two tests are cheaper than newton()'s for that reason (measured by instruction counts,
/// docs/validate.md#step-cost):
///  - Cayley chart: the conditioning guard without ||dH||_F. With t = |f|, ||dH||_F <= ||J||_F +
///    t ||J||_F + sqrt(2) |J f| + |h p| t <= ||J||_F + t ((1 + sqrt 2) ||J||_F + |h p|), so while
///    t ((1 + sqrt 2) ||J||_F + |h p|) <= 0.9 ||J||_F, ||dH||_F <= 1.9 ||J||_F and
///    det^2 > 64 eps ||J||_F^6 = `cayley_det2_floor` implies solve_adjugate's guard (the margin
///    covers the rounding of its computed norm). Otherwise (a step's rotation over 30-40 degrees,
///    t = tan(theta / 2) > 0.26-0.37, or cond(dH) above ~1e7) the fast path stops and newton()
///    decides.
///  - Finiteness: newton() stops on a non-finite residual or Newton step; here the step is not
///    tested, a non-finite one shows as a non-finite residual at the next iterate, and the fast
///    path then hands back the iterate before that step, from which newton() re-takes it and
///    stops where it would have.
template <class Chart>
inline bool newton_fast(const Inertia& I, double J_norm, const RotationUpdateOptions& o,
                        const V3& hp, double rhs_norm, double cayley_det2_floor,
                        RotationStep& out, RotationUpdateSummary& s, FastNewton& at) {
  const M3 J = m3(I.J);
  V3 f = Chart::warm_start(I, hp);
  V3 f_before = f;  // the iterate before the last Newton step
  typename Chart::Evaluation e;
  int iterations = 0;
  [[maybe_unused]] const double t_limit = cayley_fast_t_limit(J_norm, rhs_norm);
  for (;;) {
    Chart::evaluate(J, hp, f, e);
    const double h2 = dot(e.H, e.H);
    if (!std::isfinite(h2)) [[unlikely]] {
      if (iterations > 0) {
        f = f_before;
        --iterations;
      }
      break;
    }
    const double tol_h = converged_bound(o, rhs_norm, J_norm, e);
    if (h2 <= tol_h * tol_h) {
      if (wants_polish(o, rhs_norm, h2, e)) break;
      s.status = RotationUpdateStatus::Converged;
      s.iterations = iterations;
      s.rhs_norm = rhs_norm;
      s.set_residual(h2, e.h_per_g, rhs_norm > 0.0 ? rhs_norm : 1.0);
      out.f = vec3(f);
      Chart::coefficients(e, out.a, out.b);
      return true;
    }
    if (iterations >= o.max_iterations) break;
    V3 step;
    if constexpr (std::is_same_v<Chart, CayleyChart>) {
      if (!(e.t <= t_limit) ||
          !solve_adjugate_above(Chart::newton_matrix(J, hp, f, e), e.H, cayley_det2_floor, step))
        break;
    } else {
      if (!solve_adjugate(Chart::newton_matrix(J, hp, f, e), e.H, step)) break;
    }
    f_before = f;
    f = f - step;
    ++iterations;
  }
  at = {f, iterations};
  return false;
}

}  // namespace rotation_update_detail

inline Mat3 rotation_from(Parametrization p, const Vec3& f) {
  namespace d = rotation_update_detail;
  if (p == Parametrization::Cayley) return so3::cayley(f);
  const d::V3 v = d::v3(f);
  const auto [a, b] = d::ExponentialChart::rodrigues(std::sqrt(d::dot(v, v)));
  return d::ExponentialChart::rotation(v, a, b);
}

inline Mat3 RotationStep::matrix() const {
  namespace d = rotation_update_detail;
  return chart == Parametrization::Cayley ? so3::cayley(f)
                                          : d::ExponentialChart::rotation(d::v3(f), a, b);
}

inline Mat3 RotationStep::right_multiply(const Mat3& R) const {
  namespace d = rotation_update_detail;
  const d::V3 w = d::v3(f);
  Mat3 out;
  for (int i = 0; i < 3; ++i) {
    const d::V3 r{R(i, 0), R(i, 1), R(i, 2)};
    const d::V3 m = d::cross(r, w);
    const d::V3 row = r + a * m + b * d::cross(m, w);
    out(i, 0) = row.x;
    out(i, 1) = row.y;
    out(i, 2) = row.z;
  }
  return out;
}

inline Vec3 RotationStep::transpose_times(const Vec3& k_in) const {
  namespace d = rotation_update_detail;
  const d::V3 w = d::v3(f), k = d::v3(k_in);
  const d::V3 fxk = d::cross(w, k);
  return d::vec3(k - a * fxk + b * d::cross(w, fxk));
}

inline RotationUpdateSummary RotationUpdateSolver::solve_in(Parametrization p, const Vec3& hp,
                                                           Vec3& f) const {
  RotationStep step;
  RotationUpdateSummary s = newton_in(p, hp, hp.norm(), nullptr, step);
  if (s.converged()) f = step.f;
  return s;
}

// The fast path inline, everything else (newton() continued, the fallback chart, the diagnosis
// of a failure) out of line in slow_path().
LGVI_FLATTEN inline RotationUpdateSummary RotationUpdateSolver::solve(const Vec3& hp,
                                                                   RotationStep& step) const {
  namespace d = rotation_update_detail;
  const d::V3 b = d::v3(hp);
  const double rhs_norm = std::sqrt(d::dot(b, b));
  if (!(rhs_norm <= domain_bound_)) [[unlikely]] return outside_domain(hp, rhs_norm);  // also NaN
  RotationUpdateSummary s;
  s.parametrization = options_.primary;
  d::FastNewton at;
  const bool converged =
      options_.primary == Parametrization::Cayley
          ? d::newton_fast<d::CayleyChart>(inertia_, J_norm_, options_, b, rhs_norm,
                                           cayley_det2_floor_, step, s, at)
          : d::newton_fast<d::ExponentialChart>(inertia_, J_norm_, options_, b, rhs_norm,
                                                cayley_det2_floor_, step, s, at);
  if (converged) [[likely]] {
    step.chart = options_.primary;
    return s;
  }
  return slow_path(hp, rhs_norm, at, step);
}

LGVI_FLATTEN inline RotationUpdateSummary RotationUpdateSolver::solve(const Vec3& hp,
                                                                   Mat3& F) const {
  RotationStep step;
  const RotationUpdateSummary s = solve(hp, step);
  if (s.converged()) F = step.matrix();
  return s;
}

}  // namespace lgvi
