// THE PRE-OPTIMIZATION REFERENCE of the rotation update and of the LGVI steps: verbatim copies,
// as they were before the closed-form fast path, of
//   lgvi/rotation_update.cpp   Newton with a generic Newton matrix and PartialPivLU solves;
//   lgvi/lgvi.hpp              AttitudeLgvi::step and DumbbellLgvi::step;
//   lgvi/group_newton.hpp      solve_on_rotations and J_G_xi;
//   lgvi/multibody_lgvi.cpp    CartPendulumLgvi::step and ConnectedBodiesLgvi::step.
// Only the wrapping differs: namespace lgvi::reference, `inline`, and the steps as free
// functions taking the integrator's members as arguments (same parameter names, so the bodies
// are unchanged). Used by test_reference_agreement.cpp to show that the fast path gives the same
// results to round-off, and by lgvi-benchmarks to time before and after in one run. Do not
// optimize this file.
#pragma once

#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include <Eigen/LU>

#include "lgvi/group_newton.hpp"
#include "lgvi/lgvi.hpp"
#include "lgvi/multibody_lgvi.hpp"
#include "lgvi/rotation_update.hpp"
#include "lgvi/so3.hpp"

namespace lgvi::reference {

// --- lgvi/rotation_update.cpp ---------------------------------------------------------------


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
inline RotationUpdateSummary newton(const Inertia& I, const RotationUpdateOptions& o, const Vec3& hp,
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
    s.set_residual(g / scale);
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
      if (g > 4.0 * kEps * s.rhs_norm && s.iterations < o.max_iterations) {
        const Vec3 polished = f - Eigen::PartialPivLU<Mat3>(dH).solve(H);
        Vec3 G2, H2;
        Mat3 dH2;
        double size2 = 0.0;
        Model::evaluate(I.J, hp, polished, G2, H2, dH2, size2);
        ++s.iterations;
        s.polished = true;
        if (G2.norm() < g) {
          f = polished;
          s.set_residual(G2.norm() / scale);
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

/// The rotation-update solver as it was (same interface as lgvi::RotationUpdateSolver).
class RotationUpdateSolver {
 public:
  explicit RotationUpdateSolver(const Inertia& inertia, RotationUpdateOptions options = {})
      : inertia_(inertia), options_(options), domain_bound_(std::sqrt(2.0) * inertia.Jd.norm()) {}
  RotationUpdateSummary solve(const Vec3& hp, Mat3& F) const;
  RotationUpdateSummary solve_in(Parametrization p, const Vec3& hp, Vec3& f) const;
  const Inertia& inertia() const { return inertia_; }
  const RotationUpdateOptions& options() const { return options_; }

 private:
  Inertia inertia_;
  RotationUpdateOptions options_;
  double domain_bound_;
};

inline RotationUpdateSummary RotationUpdateSolver::solve_in(Parametrization p, const Vec3& hp,
                                                     Vec3& f) const {
  RotationUpdateSummary s = p == Parametrization::Cayley
                                ? newton<CayleyModel>(inertia_, options_, hp, f)
                                : newton<ExponentialModel>(inertia_, options_, hp, f);
  s.parametrization = p;
  return s;
}

inline RotationUpdateSummary RotationUpdateSolver::solve(const Vec3& hp, Mat3& F) const {
  const double rhs_norm = hp.norm();
  if (!(rhs_norm <= domain_bound_)) {  // also catches NaN
    RotationUpdateSummary s;
    s.status = RotationUpdateStatus::OutsideDomain;
    s.parametrization = options_.primary;
    s.rhs_norm = rhs_norm;
    s.set_residual(std::numeric_limits<double>::quiet_NaN());
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

// --- lgvi/lgvi.hpp ----------------------------------------------------------------------------

template <AttitudeSystem S>
inline RotationUpdateSummary attitude_step(const S& system_, LgviForm form_,
                                           const RotationUpdateSolver& solver_,
                                           const AttitudeState& in, double h,
                                           const typename S::Control& u_k,
                                           const typename S::Control& u_k1, AttitudeState& out) {
  const auto [c0, c1] = impulse_weights(form_, h);
  Vec3 kick = in.Pi;
  if (c0 != 0.0) kick += c0 * (in.M + system_.control_moment(in.R, u_k));
  Mat3 F;
  const RotationUpdateSummary summary = solver_.solve(h * kick, F);
  if (!summary.converged()) return summary;
  const Mat3 R1 = in.R * F;
  const Vec3 M1 = system_.moment(R1);
  out.Pi = F.transpose() * kick + c1 * (M1 + system_.control_moment(R1, u_k1));
  out.R = R1;
  out.M = M1;
  return summary;
}

inline RotationUpdateSummary dumbbell_step(const DumbbellSpacecraft& system_, LgviForm form_,
                                           const RotationUpdateSolver& solver_,
                                           const RigidBodyState& in, double h,
                                           const DumbbellSpacecraft::Control& u_k,
                                           const DumbbellSpacecraft::Control& u_k1,
                                           RigidBodyState& out) {
  const auto [c0, c1] = impulse_weights(form_, h);
  const double m = system_.mass;
  Vec3 kick = in.Pi;
  Vec3 p = m * in.v;
  if (c0 != 0.0) {
    kick += c0 * (in.forces.moment + u_k.moment);
    p += c0 * (in.forces.force + u_k.force);
  }
  Mat3 F;
  const RotationUpdateSummary summary = solver_.solve(h * kick, F);
  if (!summary.converged()) return summary;
  const Mat3 R1 = in.R * F;
  const Vec3 x1 = in.x + (h / m) * p;
  const DumbbellSpacecraft::Forces f1 = system_.forces(R1, x1);
  out.Pi = F.transpose() * kick + c1 * (f1.moment + u_k1.moment);
  out.v = (p + c1 * (f1.force + u_k1.force)) / m;
  out.R = R1;
  out.x = x1;
  out.forces = f1;
  return summary;
}

// --- lgvi/group_newton.hpp --------------------------------------------------------------------

/// Solves G = 0 from the initial guess A (A_i = F_i - I, updated in place on success only). The
/// residual callable is residual(const std::array<Mat3, N>& A, Vector& G, Matrix& DG) -> double
/// scale.
/// Returns a RotationUpdateSummary (parametrization: exponential, the update's retraction).
template <int N, class Residual>
inline RotationUpdateSummary solve_on_rotations(std::array<Mat3, N>& A, Residual&& residual,
                                         const GroupNewtonOptions& o = {}) {
  using Vector = Eigen::Matrix<double, 3 * N, 1>;
  using Matrix = Eigen::Matrix<double, 3 * N, 3 * N>;
  RotationUpdateSummary s;
  s.parametrization = Parametrization::Exponential;
  std::array<Mat3, N> iterate = A;
  const auto update = [](std::array<Mat3, N>& X, const Vector& xi) {
    for (int i = 0; i < N; ++i) {
      const Mat3 E = so3::exp_minus_identity(xi.template segment<3>(3 * i));
      X[i] += E + X[i] * E;
    }
  };
  Vector G;
  Matrix DG;
  for (;;) {
    const double scale = residual(std::as_const(iterate), G, DG);
    const double g = G.norm();
    s.rhs_norm = scale;
    s.set_residual(scale > 0.0 ? g / scale : g);
    if (!std::isfinite(g)) break;
    if (g <= o.relative_tolerance * scale + o.absolute_tolerance) {
      // Polish: one more Newton step, kept if it lowers |G|. The tolerance test is relative to
      // the largest terms of G; a conserved momentum along a weak inertia axis is far smaller and
      // would accumulate the leftover residual step after step.
      if (s.iterations < o.max_iterations && g > 0.0) {
        const Vector xi = Eigen::PartialPivLU<Matrix>(DG).solve(-G);
        std::array<Mat3, N> polished = iterate;
        update(polished, xi);
        Vector G2;
        Matrix DG2;
        residual(std::as_const(polished), G2, DG2);
        ++s.iterations;
        s.polished = true;
        if (G2.norm() < g) {
          iterate = polished;
          s.set_residual(scale > 0.0 ? G2.norm() / scale : G2.norm());
        }
      }
      s.status = RotationUpdateStatus::Converged;
      A = iterate;
      return s;
    }
    if (s.iterations >= o.max_iterations) break;
    const Vector xi = Eigen::PartialPivLU<Matrix>(DG).solve(-G);
    if (!xi.allFinite()) break;
    update(iterate, xi);
    ++s.iterations;
  }
  s.status = RotationUpdateStatus::NotConverged;
  return s;
}

/// d/dxi vee(F exp(hat xi) K - K exp(hat xi)^T F^T) at xi = 0 for symmetric K (F = I + A):
/// F (tr(K F) I - K F) (from hat(xi) B + B^T hat(xi) = hat((tr B I - B) xi), B = K F).
inline Mat3 J_G_xi(const Mat3& F, const Mat3& K) {
  const Mat3 KF = K * F;
  return F * (KF.trace() * Mat3::Identity() - KF);
}

// --- lgvi/multibody_lgvi.cpp ------------------------------------------------------------------

inline RotationUpdateSummary cart_pendulum_step(const CartPendulum& system_, LgviForm form_,
                                                const GroupNewtonOptions& options_,
                                                const CartPendulumState& in, double h,
                                                const Vec2& u_k, const Vec2& u_k1,
                                                CartPendulumState& out) {
  const auto [c0, c1] = impulse_weights(form_, h);
  const CartPendulum& S = system_;
  const double m = S.mass, total = S.cart_mass + S.mass, kappa = m * m / total;
  const Mat3& Jd = S.inertia.Jd;
  const Vec3& d = S.d;
  const Mat3 D = so3::hat(d);
  const Vec2 p_minus = in.p + c0 * u_k;
  const Eigen::Matrix<double, 3, 2> RtE = in.R.transpose().leftCols<2>();  // R_k^T E
  const Vec3 n = in.R.row(2).transpose();                                  // R_k^T e3
  const Mat3 P = Mat3::Identity() - n * n.transpose();
  const Vec3 coupling = (m * h / total) * d.cross(RtE * p_minus);
  const Vec3 b = h * in.Pi + (0.5 * h * h) * in.M - coupling;
  const double b_scale = (h * in.Pi).norm() + (0.5 * h * h * in.M).norm() + coupling.norm();

  // In terms of A = F - I (see group_newton.hpp): F J_d - J_d F^T = A J_d - J_d A^T.
  auto residual = [&](const std::array<Mat3, 1>& A, Vec3& G, Mat3& DG) {
    const Vec3 t1 = so3::vee(A[0] * Jd - Jd * A[0].transpose());
    const Vec3 t2 = kappa * d.cross(P * (A[0] * d));
    G = t1 - t2 - b;
    const Mat3 F = Mat3::Identity() + A[0];
    DG = J_G_xi(F, Jd) + kappa * D * P * F * D;
    return t1.norm() + t2.norm() + b_scale;
  };
  // Warm start from the linearization (J + kappa hat(d) P hat(d)) f = b at F = I.
  const Mat3 J0 = S.inertia.J + kappa * D * P * D;
  std::array<Mat3, 1> A{so3::exp_minus_identity(J0.partialPivLu().solve(b))};
  const RotationUpdateSummary summary = reference::solve_on_rotations<1>(A, residual, options_);
  if (!summary.converged()) return summary;

  const Vec2 dq = (h * p_minus - m * RtE.transpose() * (A[0] * d)) / total;
  // R_{k+1} = R_k + R_k (F - I) with compensated (Kahan) summation: the increment R_k A is
  // O(h) and formed to eps of its own size, and the compensation keeps the rounding of the sum
  // from accumulating. Plain R_k F lets R drift off SO(3) by ~eps per step, and the vertical
  // momentum map of this system (unlike the single bodies') is sensitive to that drift: its
  // pendulum and cart parts cancel only through R (a x b) = R a x R b.
  const Mat3 increment = in.R * A[0] - in.R_compensation;
  const Mat3 R1 = in.R + increment;
  out.R_compensation = (R1 - in.R) - increment;
  const Vec3 M1 = S.moment(R1);
  out.Pi = so3::vee(Jd * A[0] - A[0].transpose() * Jd) / h +
           (m / h) * d.cross(R1.transpose().leftCols<2>() * dq) + (0.5 * h) * M1;
  out.p = p_minus + c1 * u_k1;
  out.q = in.q + dq;
  out.R = R1;
  out.M = M1;
  return summary;
}

inline RotationUpdateSummary connected_bodies_step(const ConnectedBodies& system_, LgviForm form_,
                                                   const GroupNewtonOptions& options_,
                                                   const ConnectedBodiesState& in, double h,
                                                   const Vec3& u_k, const Vec3& u_k1,
                                                   ConnectedBodiesState& out) {
  const auto [c0, c1] = impulse_weights(form_, h);
  const ConnectedBodies& S = system_;
  const double mu = S.mu;
  const Mat3& K1 = S.reduced1.Jd;
  const Mat3& K2 = S.reduced2.Jd;
  const Vec3 &d1 = S.d1, &d2 = S.d2;
  const Mat3 D1 = so3::hat(d1), D2 = so3::hat(d2);
  const Mat3 R12 = in.R1.transpose() * in.R2;
  Vec3 hPi1 = h * in.Pi1, hPi2 = h * in.Pi2;
  if (c0 != 0.0) {
    hPi1 += (h * c0) * (in.R1.transpose() * u_k);
    hPi2 -= (h * c0) * (in.R2.transpose() * u_k);
  }
  const double rhs_scale = hPi1.norm() + hPi2.norm();

  // In terms of A_i = F_i - I (see group_newton.hpp): a_i = R_i A_i d_i.
  auto residual = [&](const std::array<Mat3, 2>& A, Vec6& G, Mat6x6& DG) {
    const Vec3 t1 = so3::vee(A[0] * K1 - K1 * A[0].transpose());
    const Vec3 t2 = so3::vee(A[1] * K2 - K2 * A[1].transpose());
    const Vec3 x1 = mu * d1.cross(R12 * (A[1] * d2));              // mu d1 x R1^T a2
    const Vec3 x2 = mu * d2.cross(R12.transpose() * (A[0] * d1));  // mu d2 x R2^T a1
    G << t1 - x1 - hPi1, t2 - x2 - hPi2;
    const Mat3 F1 = Mat3::Identity() + A[0], F2 = Mat3::Identity() + A[1];
    DG.topLeftCorner<3, 3>() = J_G_xi(F1, K1);
    DG.topRightCorner<3, 3>() = mu * D1 * R12 * F2 * D2;
    DG.bottomLeftCorner<3, 3>() = mu * D2 * R12.transpose() * F1 * D1;
    DG.bottomRightCorner<3, 3>() = J_G_xi(F2, K2);
    return t1.norm() + t2.norm() + x1.norm() + x2.norm() + rhs_scale;
  };
  // Warm start: at F = I the equations linearize to the mass matrix of eq. 47 times xi = h Omega.
  Vec3 xi1, xi2;
  S.velocities(in.R1, in.R2, hPi1, hPi2, xi1, xi2);
  std::array<Mat3, 2> A{so3::exp_minus_identity(xi1), so3::exp_minus_identity(xi2)};
  const RotationUpdateSummary summary = reference::solve_on_rotations<2>(A, residual, options_);
  if (!summary.converged()) return summary;

  const Mat3 R1 = in.R1 * (Mat3::Identity() + A[0]), R2 = in.R2 * (Mat3::Identity() + A[1]);
  const Vec3 a1 = in.R1 * (A[0] * d1), a2 = in.R2 * (A[1] * d2);
  out.Pi1 = so3::vee(K1 * A[0] - A[0].transpose() * K1) / h - (mu / h) * d1.cross(R1.transpose() * a2) +
            c1 * (R1.transpose() * u_k1);
  out.Pi2 = so3::vee(K2 * A[1] - A[1].transpose() * K2) / h - (mu / h) * d2.cross(R2.transpose() * a1) -
            c1 * (R2.transpose() * u_k1);
  out.R1 = R1;
  out.R2 = R2;
  return summary;
}

}  // namespace lgvi::reference
