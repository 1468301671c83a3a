// Symplectic methods for a rigid body with a separable Hamiltonian
//     H = 1/2 Pi . J^{-1} Pi (+ 1/2 m |v|^2) + U(R, x, t)
// (SeparableMechanics, baselines/mechanics.hpp: the free body, the 3D pendulum and Lagrange top,
// the dumbbell), over the same continuous mechanics the other baselines integrate. Each is a
// Strang splitting, kick (h/2) - free flow (h) - kick (h/2), with the kick
//     Pi += h/2 F_rot(t, R, x),   m v += h/2 F_trans(t, R, x)     (generalized_force())
// at the step's ends, R and x fixed; the flows differ in how they take the free rigid body
// (and x += h v) over the step:
//
//   DlmFlow           the free body split into its principal axes' rotations, T = sum_i
//                     Pi_i^2 / (2 I_i), each flow exact and explicit (a rotation of R and of Pi
//                     about e_i by h Pi_i / I_i), composed symmetrically: axes 3, 2, 1, 2, 3 with
//                     steps h/2, h/2, h, h/2, h/2 (McLachlan, Phys. Rev. Lett. 71 (1993);
//                     Dullweber, Leimkuhler, McLachlan, J. Chem. Phys. 107 (1997)). Order 2,
//                     symplectic, time reversible; |Pi| is conserved to round-off (each substep
//                     rotates Pi).
//   ExactFreeFlow     the exact free-body flow for h (baselines/exact/free_rigid_body_exact.hpp;
//                     Celledoni, Fasso, Safstrom, Zanna, SIAM J. Sci. Comput. 30 (2008)): exact
//                     for the free body, order 2 with a potential.
//   NoSquishFlow      NO_SQUISH (Miller, Eleftheriou, Pattnaik, Ndirango, Newns, Martyna, J.
//                     Chem. Phys. 116 (2002)): the DLM composition in the quaternion q of the
//                     attitude and its conjugate momentum p = 2 S(q) (0, Pi), each axis' flow the
//                     rotation q, p <- cos(z) (q, p) + sin(z) (P_k q, P_k p), z = tau p.P_k q /
//                     (4 I_k); the kick p += h S(q) (0, F_rot). It is the DLM map in other
//                     variables (tests/baselines/test_splitting.cpp checks that to round-off).
//   RattleFlow        RATTLE for the rotation matrix as a constrained particle, L = 1/2
//                     tr(R' J_d R'^T) - U, R^T R = I (McLachlan, Scovel, J. Nonlinear Sci. 5
//                     (1995)): P_{k+1/2} = P_k - h/2 grad U(R_k) - h/2 R_k L,
//                     R_{k+1} = R_k + h P_{k+1/2} J_d^{-1} with R_{k+1}^T R_{k+1} = I solved for
//                     the symmetric multiplier L by Newton (6 unknowns), then the velocity
//                     multiplier making R^T P J_d^{-1} skew. For the free body it is the
//                     Moser-Veselov map and with a potential the symmetric LGVI of lgvi/lgvi.hpp
//                     (McLachlan, Zanna, Found. Comput. Math. 5 (2005)): an independent
//                     implementation of the same map (test_splitting.cpp checks the two agree).
//
// The body frame of these flows is the principal frame: J = Q diag(I_1, I_2, I_3) Q^T with
// I_1 <= I_2 <= I_3 (PrincipalFrame; for a diagonal J, Q is a signed permutation and the change
// of frame is exact). The composition's order of the axes is a choice the papers leave open
// (Fasso, J. Comput. Phys. 189 (2003), shows the energy error's constant depends on it): here
// the smallest moment's axis takes the full step in the middle, as NO_SQUISH prints it with
// axis 1 in the middle (docs/symplectic.md; the other orders are not measured here).
//
// The flows take any Mech and assert SeparableMechanics<Mech> (a constrained class template
// would not pass through the harness's scheme aliases with GCC 12).
//
// The state caches the generalized force at its configuration (SplittingState), so a step
// evaluates the potential once: the kick at a step's end is the next step's first kick.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Eigenvalues>

#include "baselines/coordinates.hpp"
#include "baselines/exact/free_rigid_body_exact.hpp"
#include "baselines/mechanics.hpp"
#include "lgvi/flow_map.hpp"
#include "lgvi/so3.hpp"

namespace lgvi::baselines::splitting {

/// J = Q diag(moments) Q^T, Q a rotation whose columns are principal axes, moments ascending.
struct PrincipalFrame {
  Mat3 Q;
  Vec3 moments;
  /// Q a signed permutation (exact) when J is diagonal, else the symmetric eigendecomposition.
  static PrincipalFrame of(const Mat3& J) {
    PrincipalFrame f;
    if (J.isDiagonal(0.0)) {
      std::array<int, 3> axis = {0, 1, 2};
      std::stable_sort(axis.begin(), axis.end(), [&](int a, int b) { return J(a, a) < J(b, b); });
      f.Q.setZero();
      for (int i = 0; i < 3; ++i) {
        f.Q(axis[i], i) = 1.0;
        f.moments(i) = J(axis[i], axis[i]);
      }
    } else {
      const Eigen::SelfAdjointEigenSolver<Mat3> eig(J);
      f.Q = eig.eigenvectors();
      f.moments = eig.eigenvalues();
    }
    if (f.Q.determinant() < 0.0) f.Q.col(0) = -f.Q.col(0);
    return f;
  }
};

/// The state of the splittings and RATTLE: the attitude and body momentum in the principal
/// frame, R Q and Q^T Pi, carried from step to step (so that no change of frame, and no J or
/// J^{-1}, rounds them every step: |Pi| then stays a random walk of the rotations' roundings),
/// the generalized force at the configuration and time (the next kick), and the MechanicsState
/// (R, x, w) written after every step for the output and the force evaluation (x and v carried
/// there).
template <class Mech>
struct SplittingState : MechanicsState<Mech> {
  Mat3 R_principal = Mat3::Identity();
  Vec3 Pi_principal = Vec3::Zero();
  typename Mech::Velocity force = Mech::Velocity::Zero();
};

/// What every splitting flow shares: the mechanics, the principal frame, the kicks, the
/// translation's drift and the step's close. Throws InvalidInput("method", ...) for mechanics
/// that are not separable (separable() false: a rate-dependent moment).
template <class Mech>
class Splitting {
  static_assert(SeparableMechanics<Mech>);

 public:
  using State = SplittingState<Mech>;
  using Control = double;  ///< the step's start and end times
  using Velocity = typename Mech::Velocity;
  static constexpr int potential_evaluations_per_step = 1;

  Splitting(const Mech& mech, const char* method) : mech_(mech), frame_(PrincipalFrame::of(mech.system().inertia.J)) {
    if (!mech.separable()) {
      throw InvalidInput("method", std::string(method) +
                                       " needs a separable Hamiltonian: the scene's feedback moment depends on the "
                                       "angular velocity, which no kick can carry");
    }
  }

  /// `s` in the principal frame, with its generalized force at time t0.
  State make_state(const MechanicsState<Mech>& s, double t0) const {
    State out;
    out.config = s.config;
    out.w = s.w;
    out.R_principal = s.config.R[0] * frame_.Q;
    out.Pi_principal = frame_.Q.transpose() * (mech_.system().inertia.J * s.w.template head<3>());
    out.force = mech_.generalized_force(t0, s.config);
    return out;
  }

  const PrincipalFrame& frame() const { return frame_; }

 protected:
  /// The rotational part of a generalized force in the principal frame.
  Vec3 principal_moment(const Velocity& force) const { return frame_.Q.transpose() * force.template head<3>(); }
  /// The translation's kick and drift (x += h v+); its closing kick in close_step.
  void drift_translation(const State& in, double h, State& out, Vector<Mech::positions>& v_kicked) const {
    if constexpr (Mech::positions > 0) {
      v_kicked = in.w.template tail<Mech::positions>() +
                 (0.5 * h / mech_.system().mass) * in.force.template tail<Mech::positions>();
      out.config.x = in.config.x + h * v_kicked;
    }
  }
  /// Ends a step from the drifted principal attitude R and momentum Pi: the configuration, the
  /// force at the step's end (t_k1), the closing half kick, and the velocity state for output.
  void close_step(double h, double t_k1, const Mat3& R, const Vec3& Pi, const Vector<Mech::positions>& v_kicked,
                  State& out) const {
    out.R_principal = R;
    out.config.R[0] = R * frame_.Q.transpose();
    out.force = mech_.generalized_force(t_k1, out.config);
    out.Pi_principal = Pi + (0.5 * h) * principal_moment(out.force);
    out.w.template head<3>() = frame_.Q * out.Pi_principal.cwiseQuotient(frame_.moments);
    if constexpr (Mech::positions > 0) {
      out.w.template tail<Mech::positions>() =
          v_kicked + (0.5 * h / mech_.system().mass) * out.force.template tail<Mech::positions>();
    }
  }

  const Mech& mech_;
  PrincipalFrame frame_;
};

/// The DLM composition's axes (principal, moments ascending) and step fractions.
inline constexpr std::array<int, 5> kAxes = {2, 1, 0, 1, 2};
inline constexpr std::array<double, 5> kFractions = {0.5, 0.5, 1.0, 0.5, 0.5};

/// Rotates R by exp(phi hat(e_i)) on the right and Pi by exp(-phi hat(e_i)): the exact flow of
/// T_i = Pi_i^2 / (2 I_i) for the time with phi = time Pi_i / I_i.
inline void rotate_about_axis(int i, double phi, Mat3& R, Vec3& Pi) {
  const int j = (i + 1) % 3, k = (i + 2) % 3;
  const double c = std::cos(phi), s = std::sin(phi);
  const Vec3 Rj = R.col(j), Rk = R.col(k);
  R.col(j) = c * Rj + s * Rk;
  R.col(k) = c * Rk - s * Rj;
  const double Pj = Pi(j), Pk = Pi(k);
  Pi(j) = c * Pj + s * Pk;
  Pi(k) = c * Pk - s * Pj;
}

template <class Mech>
class DlmFlow : public Splitting<Mech> {
  using Base = Splitting<Mech>;

 public:
  using typename Base::State;
  explicit DlmFlow(const Mech& mech) : Base(mech, "splitting-dlm") {}

  StepSummary step(const State& in, double h, double /*t_k*/, double t_k1, State& out) const {
    const Vec3& I = this->frame_.moments;
    Vec3 Pi = in.Pi_principal + (0.5 * h) * this->principal_moment(in.force);
    Mat3 R = in.R_principal;
    Vector<Mech::positions> v_kicked;
    this->drift_translation(in, h, out, v_kicked);
    for (std::size_t n = 0; n < kAxes.size(); ++n) {
      const int i = kAxes[n];
      rotate_about_axis(i, kFractions[n] * h * Pi(i) / I(i), R, Pi);
    }
    this->close_step(h, t_k1, R, Pi, v_kicked, out);
    return {};
  }
};

template <class Mech>
class ExactFreeFlow : public Splitting<Mech> {
  using Base = Splitting<Mech>;

 public:
  using typename Base::State;
  explicit ExactFreeFlow(const Mech& mech) : Base(mech, "splitting-exact"), principal_J_(this->frame_.moments.asDiagonal()) {}

  /// Fails (converged() false) where the closed form rejects the kicked state: on or within
  /// 1 - k = 1e-8 of a separatrix (FreeRigidBodyExact).
  StepSummary step(const State& in, double h, double /*t_k*/, double t_k1, State& out) const {
    const Vec3 Pi = in.Pi_principal + (0.5 * h) * this->principal_moment(in.force);
    ExactState free;
    try {
      // The mechanics validated the inertia (a nonphysical one only where its scene asked).
      free = FreeRigidBodyExact(principal_J_, in.R_principal, Pi.cwiseQuotient(this->frame_.moments),
                                InertiaDomain::PositiveDefinite)
                 .state(h);
    } catch (const InvalidInput&) {
      StepSummary failed;
      failed.ok = false;
      failed.failure = "the exact free flow rejected the kicked state (on or next to a separatrix)";
      return failed;
    }
    Vector<Mech::positions> v_kicked;
    this->drift_translation(in, h, out, v_kicked);
    this->close_step(h, t_k1, free.R, this->frame_.moments.cwiseProduct(free.Omega), v_kicked, out);
    return {};
  }

 private:
  Mat3 principal_J_;
};

/// The state of NO_SQUISH: a SplittingState (its principal attitude and momentum written from q
/// and p after every step) with the quaternion q of the principal attitude R Q and its
/// conjugate momentum p = 2 S(q) (0, Pi), which the steps carry.
template <class Mech>
struct NoSquishState : SplittingState<Mech> {
  Eigen::Vector4d q = Eigen::Vector4d(1.0, 0.0, 0.0, 0.0);
  Eigen::Vector4d p = Eigen::Vector4d::Zero();
};

/// P_k q = q (x) e_k, the quaternion product with the k-th unit imaginary quaternion
/// (k = 0, 1, 2 for i, j, k), q = (w, x, y, z).
inline Eigen::Vector4d times_unit(int k, const Eigen::Vector4d& q) {
  switch (k) {
    case 0: return {-q(1), q(0), q(3), -q(2)};
    case 1: return {-q(2), -q(3), q(0), q(1)};
    default: return {-q(3), q(2), -q(1), q(0)};
  }
}

/// S(q) (0, v) = q (x) (0, v) = sum_k v_k P_k q.
inline Eigen::Vector4d quaternion_times_vector(const Eigen::Vector4d& q, const Vec3& v) {
  return v(0) * times_unit(0, q) + v(1) * times_unit(1, q) + v(2) * times_unit(2, q);
}

template <class Mech>
class NoSquishFlow : public Splitting<Mech> {
  using Base = Splitting<Mech>;

 public:
  using State = NoSquishState<Mech>;
  explicit NoSquishFlow(const Mech& mech) : Base(mech, "nosquish") {}

  State make_state(const MechanicsState<Mech>& s, double t0) const {
    State out;
    static_cast<SplittingState<Mech>&>(out) = Base::make_state(s, t0);
    out.q = QuaternionChart::from_rotation(out.R_principal);
    out.p = 2.0 * quaternion_times_vector(out.q, out.Pi_principal);
    return out;
  }

  StepSummary step(const State& in, double h, double /*t_k*/, double t_k1, State& out) const {
    const Vec3& I = this->frame_.moments;
    Eigen::Vector4d q = in.q;
    // Kick: p += 2 S(q) (0, h/2 F), F in the principal frame.
    Eigen::Vector4d p = in.p + h * quaternion_times_vector(q, this->principal_moment(in.force));
    Vector<Mech::positions> v_kicked;
    this->drift_translation(in, h, out, v_kicked);
    for (std::size_t n = 0; n < kAxes.size(); ++n) {
      const int k = kAxes[n];
      const Eigen::Vector4d Pq = times_unit(k, q), Pp = times_unit(k, p);
      const double zeta = kFractions[n] * h * p.dot(Pq) / (4.0 * I(k));
      const double c = std::cos(zeta), s = std::sin(zeta);
      q = c * q + s * Pq;
      p = c * p + s * Pp;
    }
    // Pi_k = p . P_k q / 2 before the closing kick, which close_step applies to Pi; p gets the
    // same kick in its own variables.
    Vec3 Pi;
    for (int k = 0; k < 3; ++k) Pi(k) = 0.5 * p.dot(times_unit(k, q));
    this->close_step(h, t_k1, QuaternionChart::rotation(q), Pi, v_kicked, out);
    out.p = p + h * quaternion_times_vector(q, this->principal_moment(out.force));
    out.q = q;
    return {};
  }
};

/// RATTLE's settings: the multiplier's Newton iteration stops when |F^T F - I|_max <= tolerance
/// (F = R_k^T R_{k+1}), or when it stops decreasing below round_off_floor (the residual's own
/// rounding: Newton's quadratic convergence leaves nothing else), failing after max_iterations.
/// Stopping at a looser tolerance leaves a residual of one sign step after step: R^T R - I then
/// grows linearly (measured: 5e-12 after 10^4 steps of the Lagrange top with 4 eps).
struct RattleOptions {
  double tolerance = std::numeric_limits<double>::epsilon();
  double round_off_floor = 64.0 * std::numeric_limits<double>::epsilon();
  int max_iterations = 30;
};

template <class Mech>
class RattleFlow : public Splitting<Mech> {
  using Base = Splitting<Mech>;
  using Vec6 = Eigen::Matrix<double, 6, 1>;
  using Mat6 = Eigen::Matrix<double, 6, 6>;

 public:
  using typename Base::State;

  /// Throws InvalidInput("inertia", ...) for a flat body (J_d singular: the constrained
  /// particle's mass matrix has no inverse).
  explicit RattleFlow(const Mech& mech, RattleOptions options = {}) : Base(mech, "rattle"), options_(options) {
    const Vec3& I = this->frame_.moments;
    const double trace = I.sum();
    for (int i = 0; i < 3; ++i) Jd_(i) = 0.5 * trace - I(i);
    if (!(Jd_.minCoeff() > 16.0 * std::numeric_limits<double>::epsilon() * trace)) {  // flat to rounding
      throw InvalidInput("inertia", "rattle needs J_d = tr(J)/2 I - J positive definite (a flat body has a singular J_d)");
    }
  }

  StepSummary step(const State& in, double h, double /*t_k*/, double t_k1, State& out) const {
    const Vec3& I = this->frame_.moments;
    const Mat3& R = in.R_principal;
    const Vec3 Omega = in.Pi_principal.cwiseQuotient(I);
    const Vec3 Jd_inverse = Jd_.cwiseInverse();
    // Y = R^T P+ = hat(Omega) J_d + h/4 hat(M): the half kick P -= h/2 grad U, whose tangent
    // part is h/4 R hat(M) (-1/2 R hat(M) is a gradient of U giving the moment M, eq. 13).
    const Mat3 Y = so3::hat(Omega) * Jd_.asDiagonal() + (0.25 * h) * so3::hat(this->principal_moment(in.force));
    const Mat3 C = Mat3::Identity() + h * Y * Jd_inverse.asDiagonal();
    // Newton on S = h^2/2 L (symmetric): F = C - S J_d^{-1}, g(S) = F^T F - I = 0.
    Mat3 S = Mat3::Zero();
    Mat3 F = C;
    StepSummary summary;
    double previous = std::numeric_limits<double>::infinity();
    for (int it = 0;; ++it) {
      const Mat3 g = F.transpose() * F - Mat3::Identity();
      summary.solve_residual = g.cwiseAbs().maxCoeff();
      if (summary.solve_residual <= options_.tolerance) break;
      if (summary.solve_residual >= previous && summary.solve_residual <= options_.round_off_floor) break;
      previous = summary.solve_residual;
      if (it == options_.max_iterations || !std::isfinite(summary.solve_residual)) {
        summary.ok = false;
        summary.failure = "rattle: the multiplier's Newton iteration did not converge";
        return summary;
      }
      // dg = -(J_d^{-1} dS F + F^T dS J_d^{-1}) for the six symmetric unit directions dS.
      Mat6 A;
      for (int col = 0; col < 6; ++col) {
        Mat3 E = Mat3::Zero();
        E(kRow[col], kCol[col]) = E(kCol[col], kRow[col]) = 1.0;
        A.col(col) = symmetric_part_vector(-(Jd_inverse.asDiagonal() * E * F + F.transpose() * E * Jd_inverse.asDiagonal()));
      }
      const Vec6 dS = A.partialPivLu().solve(-symmetric_part_vector(g));
      for (int col = 0; col < 6; ++col) {
        S(kRow[col], kCol[col]) += dS(col);
        if (kRow[col] != kCol[col]) S(kCol[col], kRow[col]) += dS(col);
      }
      F = C - S * Jd_inverse.asDiagonal();
      summary.iterations = it + 1;
    }
    // R_{k+1}^T P_{k+1/2} = F^T (Y - S/h), then the velocity multiplier T = h/2 L' (symmetric)
    // making X = (Z - T) J_d^{-1} = hat(Omega) skew: T_ij = (Z_ij d_i + Z_ji d_j)/(d_i + d_j).
    // The map Z -> Omega is linear and takes the closing kick's h/4 hat(M) to h/2 M / I (d_i + d_j
    // = I_k), so close_step applies that kick to Pi = I Omega.
    const Mat3 Z = F.transpose() * (Y - S / h);
    Mat3 X;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        const double T = (Z(i, j) * Jd_(i) + Z(j, i) * Jd_(j)) / (Jd_(i) + Jd_(j));
        X(i, j) = (Z(i, j) - T) / Jd_(j);
      }
    }
    Vector<Mech::positions> v_kicked;
    this->drift_translation(in, h, out, v_kicked);
    this->close_step(h, t_k1, R * F, I.cwiseProduct(so3::vee(0.5 * (X - X.transpose()))), v_kicked, out);
    return summary;
  }

 private:
  static constexpr std::array<int, 6> kRow = {0, 1, 2, 0, 0, 1};
  static constexpr std::array<int, 6> kCol = {0, 1, 2, 1, 2, 2};
  static Vec6 symmetric_part_vector(const Mat3& A) {
    Vec6 v;
    for (int n = 0; n < 6; ++n) v(n) = 0.5 * (A(kRow[n], kCol[n]) + A(kCol[n], kRow[n]));
    return v;
  }

  RattleOptions options_;
  Vec3 Jd_;
};

}  // namespace lgvi::baselines::splitting
