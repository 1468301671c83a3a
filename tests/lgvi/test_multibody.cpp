// Multibody LGVIs (section 4): the 3D pendulum on a cart and two connected bodies.
//  - The discrete Euler-Lagrange equations the code solves are the derivatives of the discrete
//    Lagrangians eqs. 29 and 39 (checked by central finite differences of L_d itself), which is
//    what settles the transposes and the factor the extracted text lost.
//  - Conservation over 1e5 steps, bounded energy, orthogonality, second order.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <random>
#include <vector>

#include "lgvi/integrate.hpp"
#include "lgvi/multibody_lgvi.hpp"
#include "lgvi/ocp/newton_armijo.hpp"
#include "test_support.hpp"

namespace lgvi::test {
namespace {


// --- Initial states and controls -----------------------------------------------------------------
Mat3 cart_R0() { return so3::exp(Vec3(0.5, -0.3, 0.2)); }
Vec2 cart_q0() { return Vec2(0.1, -0.2); }
Vec3 cart_Omega0() { return Vec3(1.0, -0.5, 2.0); }
Vec2 cart_qdot0() { return Vec2(0.3, 0.1); }
Vec2 cart_control(double t) { return Vec2(2.0 * std::sin(3.0 * t), 1.5 * std::cos(2.0 * t)); }

Mat3 bodies_R2_0() { return so3::exp(Vec3(0.3, 0.2, -0.1)); }
Vec3 bodies_Omega1_0() { return Vec3(0.5, -0.4, 0.3); }
Vec3 bodies_Omega2_0() { return Vec3(-0.2, 0.6, 0.1); }
/// A zero-mean internal control (inertial frame): it changes the shape but, being internal,
/// not the total angular momentum.
/// Amplitude 0.01: the control pumps energy into the chaotic relative motion. At 0.05 the
/// momenta grew 40-100x within the 1e5 steps of the test below, to |h Pi| ~ 1-3 where the
/// rotation update at h = 1e-2 has no solution: of 10 runs started 1e-15 apart (Omega1_0 x
/// shifted by k 1e-15), 5 failed, with the solver of that time as with today's, so the test
/// passed or failed by round-off. At 0.01, 80 such runs (both solvers) stayed below
/// |h Pi| = 0.2 and all completed.
Vec3 bodies_control(double t) {
  return 0.01 * Vec3(std::sin(0.7 * t), 0.5 * std::cos(1.1 * t), -0.3 * std::sin(1.9 * t + 0.5));
}

// --- The discrete Lagrangians as printed (eqs. 29, 39), for finite differences -------------------
double cart_discrete_lagrangian(const CartPendulum& S, double h, const Mat3& R0, const Vec2& q0,
                                const Mat3& R1, const Vec2& q1) {
  const Vec2 dq = q1 - q0;
  const Mat3 F = R0.transpose() * R1;
  const Vec3 c(dq.x(), dq.y(), 0.0);
  const double m = S.mass, g = S.gravity;
  return 0.5 / h * (S.cart_mass + m) * dq.squaredNorm() +
         ((Mat3::Identity() - F) * S.inertia.Jd).trace() / h +
         m / h * c.dot((R1 - R0) * S.d)  // m/h (dx e1^T + dy e2^T)(R_{k+1} - R_k) d
         + 0.5 * h * m * g * (R0.row(2).dot(S.d) + R1.row(2).dot(S.d));
}

/// Eq. 39 with the joint displacement x_{k+1} - x_k that keeps the mass centre fixed.
double bodies_discrete_lagrangian(const ConnectedBodies& S, double h, const Mat3& A1,
                                  const Mat3& A2, const Mat3& B1, const Mat3& B2) {
  const Mat3 F1 = A1.transpose() * B1, F2 = A2.transpose() * B2;
  const double m1 = S.mass1, m2 = S.mass2, total = m1 + m2;
  const Vec3 a1 = A1 * (F1 - Mat3::Identity()) * S.d1, a2 = A2 * (F2 - Mat3::Identity()) * S.d2;
  const Vec3 dx = -(m1 * a1 + m2 * a2) / total;  // (m1+m2) x + m1 R1 d1 + m2 R2 d2 = const
  const Mat3 I = Mat3::Identity();
  return total / (2.0 * h) * dx.squaredNorm() + ((I - F1) * S.inertia1.Jd).trace() / h +
         ((I - F2) * S.inertia2.Jd).trace() / h + m1 / h * (A1 * (F1 - I) * S.d1 * dx.transpose()).trace() +
         m2 / h * (A2 * (F2 - I) * S.d2 * dx.transpose()).trace();
}

/// Central difference of f(R exp(eps hat(e_i))) for i = 1..3.
template <class F>
Vec3 rotation_gradient(const Mat3& R, F&& f) {
  Vec3 g;
  for (int i = 0; i < 3; ++i) {
    const Vec3 e = kFdStep * Vec3::Unit(i);
    g(i) = (f(R * so3::exp(e)) - f(R * so3::exp(-e))) / (2.0 * kFdStep);
  }
  return g;
}

TEST(CartPendulumLgvi, SolvesTheDiscreteEulerLagrangeEquationsOfEq29) {
  const CartPendulum S = CartPendulum::paper();
  const double h = 0.01;
  for (const LgviForm form : {LgviForm::Symmetric, LgviForm::Printed}) {
    const CartPendulumLgvi lgvi(S, form);
    const auto s0 = lgvi.make_state(cart_R0(), cart_q0(), cart_Omega0(), cart_qdot0());
    const Vec2 u0 = cart_control(0.0), u1 = cart_control(h);
    CartPendulumState s1;
    ASSERT_TRUE(lgvi.step(s0, h, u0, u1, s1).converged());
    const auto [c0, c1] = impulse_weights(form, h);
    auto L = [&](const Mat3& Ra, const Vec2& qa, const Mat3& Rb, const Vec2& qb) {
      return cart_discrete_lagrangian(S, h, Ra, qa, Rb, qb);
    };
    // Pi_k = -dL_d/d eta_k, Pi_{k+1} = dL_d/d eta_{k+1} (no control on the attitude).
    const Vec3 Pi_minus = -rotation_gradient(s0.R, [&](const Mat3& R) { return L(R, s0.q, s1.R, s1.q); });
    const Vec3 Pi_plus = rotation_gradient(s1.R, [&](const Mat3& R) { return L(s0.R, s0.q, R, s1.q); });
    // p_k + c0 u_k = -dL_d/dq_k = dL_d/dq_{k+1} = p_{k+1} - c1 u_{k+1}.
    Vec2 p_minus, p_plus;
    for (int i = 0; i < 2; ++i) {
      const Vec2 e = kFdStep * Vec2::Unit(i);
      p_minus(i) = -(L(s0.R, s0.q + e, s1.R, s1.q) - L(s0.R, s0.q - e, s1.R, s1.q)) / (2 * kFdStep);
      p_plus(i) = (L(s0.R, s0.q, s1.R, s1.q + e) - L(s0.R, s0.q, s1.R, s1.q - e)) / (2 * kFdStep);
    }
    // Each derivative of L_d is O(|Pi| + |p|); FD error kFdTolerance relative to L_d's scale
    // (terms up to ~|J_d|/h ~ 1e2), so the bound scales with that.
    const double scale = S.inertia.Jd.norm() / h;
    EXPECT_LE((Pi_minus - s0.Pi).norm(), kFdTolerance * scale) << to_string(form);
    EXPECT_LE((Pi_plus - s1.Pi).norm(), kFdTolerance * scale) << to_string(form);
    EXPECT_LE((p_minus - (s0.p + c0 * u0)).norm(), kFdTolerance * scale) << to_string(form);
    EXPECT_LE((p_plus - (s1.p - c1 * u1)).norm(), kFdTolerance * scale) << to_string(form);
  }
}

TEST(ConnectedBodiesLgvi, SolvesTheDiscreteEulerLagrangeEquationsOfEq39) {
  const ConnectedBodies S = ConnectedBodies::paper();
  const double h = 0.01;
  const ConnectedBodiesLgvi lgvi(S, LgviForm::Symmetric);
  const auto s0 = lgvi.make_state(Mat3::Identity(), bodies_R2_0(), bodies_Omega1_0(), bodies_Omega2_0());
  ConnectedBodiesState s1;
  ASSERT_TRUE(lgvi.step(s0, h, Vec3::Zero(), Vec3::Zero(), s1).converged());
  auto L = [&](const Mat3& A1, const Mat3& A2, const Mat3& B1, const Mat3& B2) {
    return bodies_discrete_lagrangian(S, h, A1, A2, B1, B2);
  };
  const Vec3 Pi1_minus = -rotation_gradient(s0.R1, [&](const Mat3& R) { return L(R, s0.R2, s1.R1, s1.R2); });
  const Vec3 Pi2_minus = -rotation_gradient(s0.R2, [&](const Mat3& R) { return L(s0.R1, R, s1.R1, s1.R2); });
  const Vec3 Pi1_plus = rotation_gradient(s1.R1, [&](const Mat3& R) { return L(s0.R1, s0.R2, R, s1.R2); });
  const Vec3 Pi2_plus = rotation_gradient(s1.R2, [&](const Mat3& R) { return L(s0.R1, s0.R2, s1.R1, R); });
  const double scale = (S.inertia1.Jd.norm() + S.inertia2.Jd.norm()) / h;
  EXPECT_LE((Pi1_minus - s0.Pi1).norm(), kFdTolerance * scale);
  EXPECT_LE((Pi2_minus - s0.Pi2).norm(), kFdTolerance * scale);
  EXPECT_LE((Pi1_plus - s1.Pi1).norm(), kFdTolerance * scale);
  EXPECT_LE((Pi2_plus - s1.Pi2).norm(), kFdTolerance * scale);
}

// The momenta of eq. 47 with Jr_i = J_i + alpha_i m_i hat(d_i)^2 (the reading derived from eq.
// 39) make the energy 1/2 Pi^T M^{-1} Pi an invariant to O(h^2); the other reading of the garbled
// text, J_i - alpha_i m_i hat(d_i)^2 (i.e. J_i + alpha_i m_i hat(d_i)^T hat(d_i)), does not: its
// "energy" varies by O(1) along the same discrete trajectory.
TEST(ConnectedBodiesLgvi, Eq47MomentumMapSignTellsTheRightReadingFromTheWrongOne) {
  const ConnectedBodies S = ConnectedBodies::paper();
  const ConnectedBodiesLgvi lgvi(S);
  auto s = lgvi.make_state(Mat3::Identity(), bodies_R2_0(), bodies_Omega1_0(), bodies_Omega2_0());
  const double alpha1 = S.mass1 * S.mass1 / (S.mass1 + S.mass2), alpha2 = S.mass2 * S.mass2 / (S.mass1 + S.mass2);
  auto wrong_mass_matrix = [&](const Mat3& R1, const Mat3& R2) {
    Mat6x6 A = S.mass_matrix(R1, R2);
    const Mat3 D1 = so3::hat(S.d1), D2 = so3::hat(S.d2);
    A.topLeftCorner<3, 3>() = S.inertia1.J - alpha1 * D1 * D1;
    A.bottomRightCorner<3, 3>() = S.inertia2.J - alpha2 * D2 * D2;
    return A;
  };
  auto energy = [&](const Mat6x6& A, const ConnectedBodiesState& x) {
    Vec6 P;
    P << x.Pi1, x.Pi2;
    return 0.5 * P.dot(A.ldlt().solve(P));
  };
  const double right0 = energy(S.mass_matrix(s.R1, s.R2), s), wrong0 = energy(wrong_mass_matrix(s.R1, s.R2), s);
  double right_dev = 0.0, wrong_dev = 0.0;
  integrate(lgvi, s, 0.0, 1e-3, 20000, zero_control<Vec3>(),
            [&](std::size_t, double, const ConnectedBodiesState& x, const RotationUpdateSummary&) {
              right_dev = std::max(right_dev, std::abs(energy(S.mass_matrix(x.R1, x.R2), x) - right0));
              wrong_dev = std::max(wrong_dev, std::abs(energy(wrong_mass_matrix(x.R1, x.R2), x) - wrong0));
              return true;
            });
  std::cout << "[ measured ] relative energy deviation: eq. 47 as derived " << right_dev / right0
            << ", other sign " << wrong_dev / wrong0 << "\n";
  // O(h^2) at h = 1e-3 with O(1) constants: below 1e-4; the wrong reading is O(1): above 1e-2.
  EXPECT_LE(right_dev / right0, 1e-4);
  EXPECT_GE(wrong_dev / wrong0, 1e-2);
}

// --- Conservation over 1e5 steps -----------------------------------------------------------------

/// Mean over the last tenth inside [min, max] of the first tenth.
void expect_no_drift(const std::vector<double>& e) {
  const std::size_t tenth = e.size() / 10;
  const auto [lo, hi] = std::minmax_element(e.begin(), e.begin() + tenth);
  double mean_last = 0.0;
  for (std::size_t i = e.size() - tenth; i < e.size(); ++i) mean_last += e[i];
  mean_last /= static_cast<double>(tenth);
  std::cout << "[ measured ] energy band first tenth [" << *lo << ", " << *hi << "], mean last tenth "
            << mean_last << "\n";
  EXPECT_GE(mean_last, *lo);
  EXPECT_LE(mean_last, *hi);
}

TEST(CartPendulumLgvi, ConservesPlanarAndVerticalMomentumOverTenToTheFiveSteps) {
  const CartPendulum S = CartPendulum::paper();
  const CartPendulumLgvi lgvi(S);
  // A small linear momentum keeps the cart within ~1 m over the run, so the momentum map's terms
  // x p_y - y p_x stay of the order of the map itself (a runaway cart would measure the
  // cancellation of large terms, not the integrator).
  // The pendulum's swing is part of p (eq. 37): q' is chosen so that p = (0.002, -0.001).
  const Vec2 p_target(0.002, -0.001);
  const Vec2 p_at_rest = lgvi.make_state(cart_R0(), cart_q0(), cart_Omega0(), Vec2::Zero()).p;
  auto s = lgvi.make_state(cart_R0(), cart_q0(), cart_Omega0(),
                           (p_target - p_at_rest) / (S.cart_mass + S.mass));
  const Vec2 p0 = s.p;
  const double m0 = S.vertical_momentum(s.R, s.q, s.Pi, s.p);
  Vec3 Omega;
  Vec2 qdot;
  lgvi.velocities(s, Omega, qdot);
  const double E0 = S.energy(s.R, Omega, qdot);
  double dp = 0.0, dm = 0.0, orth = 0.0;
  std::vector<double> energy_error;
  const Stats stats = integrate(lgvi, s, 0.0, 1e-3, 100'000, zero_control<Vec2>(),
                                [&](std::size_t, double, const CartPendulumState& x, const RotationUpdateSummary&) {
                                  dp = std::max(dp, (x.p - p0).norm());
                                  dm = std::max(dm, std::abs(S.vertical_momentum(x.R, x.q, x.Pi, x.p) - m0));
                                  orth = std::max(orth, so3::orthogonality_error(x.R));
                                  Vec3 O;
                                  Vec2 v;
                                  lgvi.velocities(x, O, v);
                                  energy_error.push_back(S.energy(x.R, O, v) - E0);
                                  return true;
                                });
  ASSERT_TRUE(stats.ok()) << stats.brief();
  std::cout << "[ stats    ] " << stats.brief() << "\n[ measured ] planar momentum drift "
            << dp / p0.norm() << ", vertical momentum drift " << dm / std::abs(m0) << ", orthogonality "
            << orth << "\n";
  EXPECT_LE(dp / p0.norm(), kMomentumRelativeBound);
  EXPECT_LE(dm / std::abs(m0), kMomentumRelativeBound);
  EXPECT_LE(orth, kOrthogonalityBound);
  expect_no_drift(energy_error);
}

TEST(ConnectedBodiesLgvi, ConservesTotalAngularMomentumWithInternalControl) {
  const ConnectedBodies S = ConnectedBodies::paper();
  const ConnectedBodiesLgvi lgvi(S);
  auto s = lgvi.make_state(Mat3::Identity(), bodies_R2_0(), bodies_Omega1_0(), bodies_Omega2_0());
  const Vec3 H0 = ConnectedBodies::total_angular_momentum(s.R1, s.R2, s.Pi1, s.Pi2);
  double dH = 0.0, orth = 0.0, control_impulse = 0.0;
  const Stats stats = integrate(lgvi, s, 0.0, 1e-2, 100'000, bodies_control,
                                [&](std::size_t, double t, const ConnectedBodiesState& x, const RotationUpdateSummary&) {
                                  dH = std::max(dH, (ConnectedBodies::total_angular_momentum(x.R1, x.R2, x.Pi1, x.Pi2) - H0).norm());
                                  orth = std::max({orth, so3::orthogonality_error(x.R1), so3::orthogonality_error(x.R2)});
                                  control_impulse = std::max(control_impulse, bodies_control(t).norm());
                                  return true;
                                });
  ASSERT_TRUE(stats.ok()) << stats.brief();
  ASSERT_GT(control_impulse, 0.005);  // the control really is on
  std::cout << "[ stats    ] " << stats.brief() << "\n[ measured ] total angular momentum drift "
            << dH / H0.norm() << ", orthogonality " << orth << "\n";
  EXPECT_LE(dH / H0.norm(), kMomentumRelativeBound);
  EXPECT_LE(orth, kOrthogonalityBound);
}

TEST(ConnectedBodiesLgvi, EnergyBoundedWithoutControl) {
  const ConnectedBodies S = ConnectedBodies::paper();
  const ConnectedBodiesLgvi lgvi(S);
  auto s = lgvi.make_state(Mat3::Identity(), bodies_R2_0(), bodies_Omega1_0(), bodies_Omega2_0());
  Vec3 O1, O2;
  lgvi.velocities(s, O1, O2);
  const double E0 = S.energy(s.R1, s.R2, O1, O2);
  std::vector<double> energy_error;
  const Stats stats = integrate(lgvi, s, 0.0, 1e-2, 100'000, zero_control<Vec3>(),
                                [&](std::size_t, double, const ConnectedBodiesState& x, const RotationUpdateSummary&) {
                                  Vec3 a, b;
                                  lgvi.velocities(x, a, b);
                                  energy_error.push_back(S.energy(x.R1, x.R2, a, b) - E0);
                                  return true;
                                });
  ASSERT_TRUE(stats.ok()) << stats.brief();
  expect_no_drift(energy_error);
}

// --- Order -----------------------------------------------------------------------------------------
// Global error at T against the symmetric form at h_min/16 over h, h/2, h/4, h/8 (see
// tests/lgvi/test_lgvi_order.cpp for the argument).

template <class Lgvi, class Make, class Control, class Distance>
double fitted_order(const Lgvi& lgvi, const Lgvi& reference, Make make, Control control,
                    Distance distance, double T, double h_max) {
  auto run = [&](const Lgvi& integrator, double h) {
    auto s = make();
    const Stats st = integrate(integrator, s, 0.0, h, static_cast<std::size_t>(std::llround(T / h)), control, null_observer());
    EXPECT_TRUE(st.ok()) << st.brief();
    return s;
  };
  const auto ref = run(reference, h_max / 128.0);
  std::array<double, 4> h{}, e{};
  for (int i = 0; i < 4; ++i) {
    h[i] = h_max / (1 << i);
    e[i] = distance(run(lgvi, h[i]), ref);
  }
  const double slope = loglog_slope(h, e);
  std::cout << "[ slope    ] " << slope << " (errors " << e[0] << " .. " << e[3] << ")\n";
  return slope;
}

double cart_distance(const CartPendulumLgvi& lgvi, const CartPendulumState& a, const CartPendulumState& b) {
  Vec3 Oa, Ob;
  Vec2 va, vb;
  lgvi.velocities(a, Oa, va);
  lgvi.velocities(b, Ob, vb);
  return so3::log(a.R.transpose() * b.R).norm() + (a.q - b.q).norm() + (Oa - Ob).norm() + (va - vb).norm();
}

class MultibodyOrder : public ::testing::TestWithParam<LgviForm> {};

TEST_P(MultibodyOrder, CartPendulumWithControl) {
  const CartPendulum S = CartPendulum::paper();
  const CartPendulumLgvi lgvi(S, GetParam()), reference(S, LgviForm::Symmetric);
  const double slope = fitted_order(
      lgvi, reference, [&] { return lgvi.make_state(cart_R0(), cart_q0(), cart_Omega0(), cart_qdot0()); },
      cart_control, [&](const auto& a, const auto& b) { return cart_distance(lgvi, a, b); }, 1.0, 0.02);
  EXPECT_NEAR(slope, GetParam() == LgviForm::Symmetric ? 2.0 : 1.0, kOrderTolerance);
}

TEST_P(MultibodyOrder, ConnectedBodiesWithControl) {
  const ConnectedBodies S = ConnectedBodies::paper();
  const ConnectedBodiesLgvi lgvi(S, GetParam()), reference(S, LgviForm::Symmetric);
  // A control strong enough that the end-point impulse of the printed form dominates its error.
  auto control = [](double t) { return Vec3(0.5 * std::sin(2.0 * t), 0.4 * std::cos(3.0 * t), 0.3); };
  auto distance = [&](const ConnectedBodiesState& a, const ConnectedBodiesState& b) {
    Vec3 a1, a2, b1, b2;
    lgvi.velocities(a, a1, a2);
    lgvi.velocities(b, b1, b2);
    return so3::log(a.R1.transpose() * b.R1).norm() + so3::log(a.R2.transpose() * b.R2).norm() +
           (a1 - b1).norm() + (a2 - b2).norm();
  };
  const double slope = fitted_order(
      lgvi, reference,
      [&] { return lgvi.make_state(Mat3::Identity(), bodies_R2_0(), bodies_Omega1_0(), bodies_Omega2_0()); },
      control, distance, 0.5, 0.01);
  EXPECT_NEAR(slope, GetParam() == LgviForm::Symmetric ? 2.0 : 1.0, kOrderTolerance);
}

INSTANTIATE_TEST_SUITE_P(Forms, MultibodyOrder, ::testing::Values(LgviForm::Symmetric, LgviForm::Printed),
                         [](const auto& info) { return std::string(to_string(info.param)); });

// group_newton_detail::solve_newton_matrix_columns (the closed-form solve of the step
// linearizations) against Eigen's pivoted LU on random well-conditioned systems of the Newton
// matrices' shape (the locked inertias on the diagonal blocks, a weaker coupling off it), where
// both are stable (the LU backward stable, the block elimination for well-conditioned diagonal
// blocks), so they agree to ~n kappa eps |X|, bound roundoff(kappa |X|, n); and the
// fallback when the first diagonal block is singular (no adjugate inverse): the LU's residual,
// |DG X - B| <= roundoff(|DG| |X|, n).
template <int N, int C>
void check_closed_form_solve(const Eigen::Matrix<double, 3 * N, 3 * N>& DG, const Eigen::Matrix<double, 3 * N, C>& B) {
  const Eigen::Matrix<double, 3 * N, C> X = group_newton_detail::solve_newton_matrix_columns<N, C>(DG, B);
  const Eigen::Matrix<double, 3 * N, C> X_lu = DG.partialPivLu().solve(B);
  const double kappa = ocp::condition_number(DG);
  EXPECT_LE((X - X_lu).norm(), roundoff(kappa * X_lu.norm(), 3 * N)) << "kappa " << kappa;
  EXPECT_LE((DG * X - B).norm(), roundoff(DG.norm() * X.norm(), 3 * N));
}

TEST(GroupNewton, ClosedFormSolveOfMatrixRightHandSidesAgreesWithPivotedLu) {
  auto rng = make_rng(91);
  std::normal_distribution<double> normal;
  const auto random = [&](auto M) {
    for (Eigen::Index i = 0; i < M.size(); ++i) M.data()[i] = normal(rng);
    return M;
  };
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::Matrix<double, 6, 6> DG = 0.3 * random(Eigen::Matrix<double, 6, 6>());
    DG.topLeftCorner<3, 3>() += Vec3(2.0, 3.0, 4.0).asDiagonal();
    DG.bottomRightCorner<3, 3>() += Vec3(1.0, 1.5, 0.5).asDiagonal();
    check_closed_form_solve<2, 15>(DG, random(Eigen::Matrix<double, 6, 15>()));
    Mat3 D1 = 0.3 * random(Mat3());
    D1 += Vec3(2.0, 3.0, 4.0).asDiagonal();
    check_closed_form_solve<1, 12>(D1, random(Eigen::Matrix<double, 3, 12>()));
  }
  // P = 0: the block elimination has no P^{-1}; the pivoted LU solves the (regular) system.
  Eigen::Matrix<double, 6, 6> DG = Eigen::Matrix<double, 6, 6>::Zero();
  DG.topRightCorner<3, 3>() = Mat3::Identity();
  DG.bottomLeftCorner<3, 3>() = Vec3(1.0, 2.0, 3.0).asDiagonal();
  DG.bottomRightCorner<3, 3>() = random(Mat3());
  check_closed_form_solve<2, 15>(DG, random(Eigen::Matrix<double, 6, 15>()));
}

}  // namespace
}  // namespace lgvi::test
