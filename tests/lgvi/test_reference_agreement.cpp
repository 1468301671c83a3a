// The fast rotation update and LGVI steps (closed-form solves, lazily formed Newton
// matrices, inline hot path) against the pre-optimization reference kept verbatim in
// reference_rotation_update.hpp: the same results to round-off.
//
// 1. Solver: same status, chart, fallback and (but for |G| landing on the tolerance) iteration
//    count; F agrees to the bound set by both solves' residuals.
// 2. One step from the same state: the states agree to a few eps.
// 3. Trajectories (1e5 steps for the free body and a pendulum swing): the per-step differences
//    delta_k, and the round-off of each map, propagate through the tangent map of the flow,
//    bounded by G_N = max_{m <= N} ||D Phi^m||, measured here from perturbed reference
//    trajectories (see compare and expect_agreement in step_agreement.hpp for the bounds). For
//    the free body (an integrable discrete flow: the LGVI of the free body is the Moser-Veselov
//    map) and a regular pendulum swing G_m grows linearly in m (shear along the invariant tori);
//    for the chaotic tumbling pendulum and the dumbbell it grows exponentially and the horizon
//    is 1e4 steps.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "lgvi/lgvi.hpp"
#include "lgvi/multibody_lgvi.hpp"
#include "lgvi/so3.hpp"
#include "lgvi/systems/dumbbell.hpp"
#include "lgvi/systems/free_rigid_body.hpp"
#include "lgvi/systems/pendulum.hpp"
#include "lgvi_cases.hpp"
#include "reference_rotation_update.hpp"
#include "step_agreement.hpp"
#include "test_support.hpp"

namespace lgvi::test {
namespace {

// --- 1. The solver ---------------------------------------------------------------------------

/// Random valid inertia (as in test_rotation_update.cpp): principal moments in [0.1, 1] with the
/// triangle inequality, random principal axes.
template <class Rng>
Mat3 random_valid_inertia(Rng& rng) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double J1 = 0.1 + 0.9 * uniform(rng), J2 = 0.1 + 0.9 * uniform(rng);
  const double lo = std::max(std::abs(J1 - J2), 0.1), hi = J1 + J2;
  const double J3 = lo + (hi - lo) * uniform(rng);
  const Mat3 Q = so3::random_rotation(rng);
  const Mat3 J = Q * Vec3(J1, J2, J3).asDiagonal() * Q.transpose();
  return 0.5 * (J + J.transpose());
}

/// 1 / smallest singular value of the derivative of F -> vee(F J_d - J_d F^T) along
/// F exp(hat(d)) (see test_rotation_update.cpp): how far apart two approximate solutions with
/// given residuals can be.
double sensitivity(const Mat3& F, const Mat3& Jd) {
  Mat3 A;
  for (int j = 0; j < 3; ++j) {
    const Mat3 E = so3::hat(Vec3::Unit(j));
    A.col(j) = so3::vee(F * E * Jd + Jd * E * F.transpose());
  }
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(A.transpose() * A, Eigen::EigenvaluesOnly);
  return 1.0 / std::sqrt(std::max(eig.eigenvalues()(0), 0.0));
}

// Random inertias and momenta h p = J Omega_h, |Omega_h| log-uniform in [1e-8, 1] (the Taylor
// branches of both charts and the large rotations), both charts, the default tolerance and two
// loosened ones (1e-8 and 1e-6: the polishing step then decides more often and starts farther
// from the root; a loosened tolerance is how a regression gate is exercised). The two F solve
// the same equation to their residuals r |h p|: |F_new - F_ref|_F <= sqrt(2) |A^{-1}|
// (r_new + r_ref) |h p| plus evaluating each G (1 flop of |h p| + 3 ||J||) and forming each F
// (8 flops of 1), the bound of RandomBatch.CayleyAndExponentialAgree in test_rotation_update.cpp.
// Iteration counts: a Newton step differs by round-off, so the count differs only when an
// iterate's |G| lies within round-off of the tolerance (or of the polishing threshold): rare,
// asserted below 1% of the solves.
TEST(FastRotationUpdate, AgreesWithTheReferenceSolver) {
  auto rng = test::make_rng(1201);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> normal;
  constexpr int kSamples = 4000;
  int solves = 0, count_mismatches = 0;
  double worst_ratio = 0.0;
  for (int k = 0; k < kSamples; ++k) {
    const Inertia I = Inertia::from(random_valid_inertia(rng));
    const Vec3 n = Vec3(normal(rng), normal(rng), normal(rng)).normalized();
    const Vec3 hp = I.J * (std::pow(1e-8, uniform(rng)) * n);
    for (const Parametrization p : {Parametrization::Cayley, Parametrization::Exponential}) {
      for (const double tolerance : {RotationUpdateOptions{}.relative_tolerance, 1e-8, 1e-6}) {
        RotationUpdateOptions o;
        o.primary = p;
        o.relative_tolerance = tolerance;
        const RotationUpdateSolver fast(I, o);
        const reference::RotationUpdateSolver ref(I, o);
        Mat3 F_fast = Mat3::Zero(), F_ref = Mat3::Zero();
        const RotationUpdateSummary a = fast.solve(hp, F_fast);
        const RotationUpdateSummary b = ref.solve(hp, F_ref);
        ++solves;
        ASSERT_EQ(a.status, b.status) << a.brief() << " vs " << b.brief();
        ASSERT_TRUE(a.converged()) << a.brief();
        EXPECT_EQ(a.parametrization, b.parametrization);
        EXPECT_EQ(a.used_fallback, b.used_fallback);
        EXPECT_EQ(a.rhs_norm, b.rhs_norm);
        count_mismatches += a.iterations != b.iterations || a.polished != b.polished;
        const double h = hp.norm();
        const double dG = (a.residual() + b.residual()) * h + 2.0 * roundoff(h + 3.0 * I.J.norm());
        const double tol = std::sqrt(2.0) * sensitivity(F_ref, I.Jd) * dG + 2.0 * roundoff(1.0, 8);
        const double diff = (F_fast - F_ref).norm();
        EXPECT_LE(diff, tol) << a.brief() << " vs " << b.brief();
        worst_ratio = std::max(worst_ratio, diff / tol);
      }
    }
  }
  std::cout << "[ measured ] " << solves << " solves: iteration counts differ in "
            << count_mismatches << ", max |F_fast - F_ref| / bound " << worst_ratio << "\n";
  EXPECT_LE(count_mismatches, solves / 100);
}

// The failure paths keep their meaning: outside the domain (no iteration), no solution inside the
// bound (both charts fail, iterations of both counted), and the primary chart running out of
// iterations with and without the fallback.
TEST(FastRotationUpdate, FailuresMatchTheReference) {
  const Inertia I = Inertia::from(Vec3(0.13, 0.28, 0.17).asDiagonal());
  const double bound = RotationUpdateSolver(I).domain_bound();
  for (const bool fallback : {true, false}) {
    for (const int max_iterations : {30, 2}) {
      RotationUpdateOptions o;
      o.fallback = fallback;
      o.max_iterations = max_iterations;
      const RotationUpdateSolver fast(I, o);
      const reference::RotationUpdateSolver ref(I, o);
      for (const Vec3& hp : {Vec3(1.5 * bound, 0.0, 0.0), Vec3(0.2, 0.0, 0.0),  // J_1 < 0.2 < bound
                             Vec3(0.1, -0.05, 0.08)}) {
        Mat3 F_fast = Mat3::Constant(42.0), F_ref = Mat3::Constant(42.0);
        const RotationUpdateSummary a = fast.solve(hp, F_fast);
        const RotationUpdateSummary b = ref.solve(hp, F_ref);
        // The fast solver names a failed solve with |(h p)_i| > J_i on a principal axis
        // OutsideDomain (RotationUpdateSolver::diagnose, after the same iterations); the
        // reference predates that diagnosis.
        const bool diagnosed = !b.converged() && a.axis_ratio > 1.0;
        EXPECT_EQ(a.status, diagnosed ? RotationUpdateStatus::OutsideDomain : b.status)
            << a.brief() << " vs " << b.brief();
        EXPECT_EQ(a.iterations, b.iterations) << a.brief() << " vs " << b.brief();
        EXPECT_EQ(a.used_fallback, b.used_fallback);
        EXPECT_EQ(a.parametrization, b.parametrization);
        if (!diagnosed) {
          EXPECT_EQ(a.brief().substr(0, 20), b.brief().substr(0, 20));
        }
        if (!a.converged()) {
          EXPECT_EQ(F_fast, Mat3::Constant(42.0));
        }
      }
    }
  }
}

// --- 2, 3. Steps and trajectories (compared by step_agreement.hpp) --------------------------

template <class System>
StepCase<AttitudeState> attitude_case(const std::string& name, const System& system, double h,
                                      double pi_scale, Parametrization p) {
  RotationUpdateOptions o;
  o.primary = p;
  auto lgvi = std::make_shared<AttitudeLgvi<System>>(system, LgviForm::Symmetric, o);
  auto solver = std::make_shared<reference::RotationUpdateSolver>(system.inertia, o);
  StepCase<AttitudeState> c;
  c.name = name + " (" + to_string(p) + ")";
  const Vec3 u = Vec3::Zero();
  c.fast = [lgvi, h, u](const AttitudeState& in, AttitudeState& out) {
    return lgvi->step(in, h, u, u, out);
  };
  c.reference = [lgvi, solver, h, u](const AttitudeState& in, AttitudeState& out) {
    return reference::attitude_step(lgvi->system(), LgviForm::Symmetric, *solver, in, h, u, u, out);
  };
  set_attitude_geometry<AttitudeLgvi<System>>(c, lgvi, pi_scale);
  return c;
}

// The free body (integrable): the paper's inertia, a generic tumble, h = 1e-2, 1e5 steps
// (1000 s, ~300 periods of the body's rotation).
TEST(FastLgviStep, FreeBodyAgreesWithTheReferenceOver1e5Steps) {
  const FreeRigidBody body = free_body();
  const AttitudeLgvi lgvi(body);
  const AttitudeState s0 = lgvi.make_state(free_body_R0(), free_body_Omega0());
  for (const Parametrization p : {Parametrization::Cayley, Parametrization::Exponential}) {
    expect_agreement(attitude_case("free body", body, 1e-2, s0.Pi.norm(), p), s0, 100000);
  }
}

// The pendulum: a regular swing (moderate amplitude, on a torus: linear growth) over 1e5 steps
// of h = 1e-3 (100 s), and the paper's chaotic tumble (Omega0 = 4.14 (1, 1, 1)) over 1e4 steps.
TEST(FastLgviStep, PendulumAgreesWithTheReference) {
  const Pendulum3D pendulum = Pendulum3D::paper();
  const AttitudeLgvi lgvi(pendulum);
  const AttitudeState swing = lgvi.make_state(so3::exp(Vec3(0.4, -0.2, 0.0)), Vec3(0.3, 0.5, 0.2));
  const AttitudeState tumble = lgvi.make_state(Mat3::Identity(), pendulum_Omega0());
  for (const Parametrization p : {Parametrization::Cayley, Parametrization::Exponential}) {
    expect_agreement(attitude_case("pendulum swing", pendulum, 1e-3, swing.Pi.norm(), p), swing,
                     100000);
    expect_agreement(attitude_case("pendulum tumble", pendulum, 1e-3, tumble.Pi.norm(), p),
                     tumble, 10000);
  }
}

// The dumbbell (SE(3), the same rotation update; an orbit with a moment coupling attitude and
// position): 1e4 steps of h = 1e-2 with the tangent-growth bound.
TEST(FastLgviStep, DumbbellAgreesWithTheReference) {
  const DumbbellSpacecraft dumbbell = DumbbellSpacecraft::paper();
  const DumbbellLgvi lgvi(dumbbell);
  const RigidBodyState s0 =
      lgvi.make_state(dumbbell_R0(), dumbbell_x0(), dumbbell_Omega0(), dumbbell_v0());
  const double pi_scale = s0.Pi.norm(), v_scale = s0.v.norm(), x_scale = s0.x.norm();
  const reference::RotationUpdateSolver solver(dumbbell.inertia);
  const double h = 1e-2;
  const DumbbellSpacecraft::Control u;
  StepCase<RigidBodyState> c;
  c.name = "dumbbell (cayley)";
  c.fast = [&](const RigidBodyState& in, RigidBodyState& out) { return lgvi.step(in, h, u, u, out); };
  c.reference = [&](const RigidBodyState& in, RigidBodyState& out) {
    return reference::dumbbell_step(dumbbell, LgviForm::Symmetric, solver, in, h, u, u, out);
  };
  c.distance = [=](const RigidBodyState& a, const RigidBodyState& b) {
    const Eigen::Vector4d d((a.R - b.R).norm(), (a.x - b.x).norm() / x_scale, (a.Pi - b.Pi).norm() / pi_scale,
                 (a.v - b.v).norm() / v_scale);
    return d.norm();
  };
  c.perturb = [&](const RigidBodyState& s, int i, double eps) {
    const Vec3 e = eps * Vec3::Unit(i % 3);
    const Vec3 Omega = lgvi.omega(s);
    switch (i / 3) {
      case 0: return lgvi.make_state(s.R * so3::exp(e), s.x, Omega, s.v);
      case 1: return lgvi.make_state(s.R, s.x + x_scale * e, Omega, s.v);
      case 2: return lgvi.make_state(s.R, s.x, Omega + dumbbell.inertia.J_inverse * (pi_scale * e), s.v);
      default: return lgvi.make_state(s.R, s.x, Omega, s.v + v_scale * e);
    }
  };
  c.dimension = 12;
  expect_agreement(c, s0, 10000);
}

// The multibody steps (closed-form block solves in the group Newton): the cart-pendulum with
// h = 1e-3 and the connected bodies with h = 1e-2, 1e4 steps each.
TEST(FastLgviStep, CartPendulumAgreesWithTheReference) {
  const CartPendulum cart = CartPendulum::paper();
  const CartPendulumLgvi lgvi(cart);
  const CartPendulumState s0 = lgvi.make_state(so3::exp(Vec3(0.5, -0.3, 0.2)), Vec2(0.1, -0.2),
                                               Vec3(1.0, -0.5, 2.0), Vec2(0.3, 0.1));
  const double pi_scale = s0.Pi.norm(), p_scale = s0.p.norm(), q_scale = s0.q.norm();
  const double h = 1e-3;
  const Vec2 u = Vec2::Zero();
  StepCase<CartPendulumState> c;
  c.name = "cart-pendulum";
  c.fast = [&](const CartPendulumState& in, CartPendulumState& out) { return lgvi.step(in, h, u, u, out); };
  c.reference = [&](const CartPendulumState& in, CartPendulumState& out) {
    return reference::cart_pendulum_step(cart, LgviForm::Symmetric, {}, in, h, u, u, out);
  };
  c.distance = [=](const CartPendulumState& a, const CartPendulumState& b) {
    const Eigen::Vector4d d((a.R - b.R).norm(), (a.q - b.q).norm() / q_scale, (a.Pi - b.Pi).norm() / pi_scale,
                 (a.p - b.p).norm() / p_scale);
    return d.norm();
  };
  c.perturb = [&](const CartPendulumState& s, int i, double eps) {
    Vec3 Omega;
    Vec2 q_dot;
    lgvi.velocities(s, Omega, q_dot);
    if (i < 3) return lgvi.make_state(s.R * so3::exp(eps * Vec3::Unit(i)), s.q, Omega, q_dot);
    if (i < 5) return lgvi.make_state(s.R, s.q + q_scale * eps * Vec2::Unit(i - 3), Omega, q_dot);
    CartPendulumState t = lgvi.make_state(s.R, s.q, Omega, q_dot);
    if (i < 8) t.Pi += pi_scale * eps * Vec3::Unit(i - 5);
    else t.p += p_scale * eps * Vec2::Unit(i - 8);
    return t;
  };
  c.dimension = 10;
  expect_agreement(c, s0, 10000);
}

TEST(FastLgviStep, ConnectedBodiesAgreeWithTheReference) {
  const ConnectedBodies bodies = ConnectedBodies::paper();
  const ConnectedBodiesLgvi lgvi(bodies);
  const ConnectedBodiesState s0 = lgvi.make_state(Mat3::Identity(), so3::exp(Vec3(0.3, 0.2, -0.1)),
                                                  Vec3(0.5, -0.4, 0.3), Vec3(-0.2, 0.6, 0.1));
  const double pi_scale = std::max(s0.Pi1.norm(), s0.Pi2.norm());
  const double h = 1e-2;
  const Vec3 u = Vec3::Zero();
  StepCase<ConnectedBodiesState> c;
  c.name = "connected bodies";
  c.fast = [&](const ConnectedBodiesState& in, ConnectedBodiesState& out) {
    return lgvi.step(in, h, u, u, out);
  };
  c.reference = [&](const ConnectedBodiesState& in, ConnectedBodiesState& out) {
    return reference::connected_bodies_step(bodies, LgviForm::Symmetric, {}, in, h, u, u, out);
  };
  c.distance = [=](const ConnectedBodiesState& a, const ConnectedBodiesState& b) {
    const Eigen::Vector4d d((a.R1 - b.R1).norm(), (a.R2 - b.R2).norm(), (a.Pi1 - b.Pi1).norm() / pi_scale,
                 (a.Pi2 - b.Pi2).norm() / pi_scale);
    return d.norm();
  };
  c.perturb = [&](const ConnectedBodiesState& s, int i, double eps) {
    const Vec3 e = eps * Vec3::Unit(i % 3);
    ConnectedBodiesState t = s;
    switch (i / 3) {
      case 0: t.R1 = s.R1 * so3::exp(e); break;
      case 1: t.R2 = s.R2 * so3::exp(e); break;
      case 2: t.Pi1 += pi_scale * e; break;
      default: t.Pi2 += pi_scale * e; break;
    }
    return t;
  };
  c.dimension = 12;
  expect_agreement(c, s0, 10000);
}

}  // namespace
}  // namespace lgvi::test
