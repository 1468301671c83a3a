// The continuous-time models of the multibody systems (cart-pendulum, eq. 37; connected bodies,
// eq. 47) in momentum form:
//  - the equations come from the continuous Lagrangian: the moments of lgvi/systems are its
//    left-trivialized R-derivatives and the momenta its velocity derivatives (central
//    differences of L);
//  - right-hand sides: energy rate = control power, momentum-map rates = the control's (zero
//    for the connected bodies' internal moment), p' = u; ODE Jacobians against central
//    differences, every chart, on and off the constraint set;
//  - agreement: CVODE at a tight tolerance against the LGVI at h and h/2 (the LGVI converges to
//    it at order 2 and its distance is its own Richardson-estimated h^2 error);
//  - conservation of p, the cart's vertical momentum and the bodies' total angular momentum to
//    the accuracy the solver's tolerance promises;
//  - the unit-norm error of the quaternion models grows without renormalization, and stays at
//    round-off with it.
#include <gtest/gtest.h>

#include <iostream>

#include <Eigen/Eigenvalues>

#include "baseline_cases.hpp"
#include "baselines/control.hpp"
#include "model_checks.hpp"
#include "multibody_cases.hpp"

namespace lgvi::test {
namespace {

using baselines::CartPendulumMechanics;
using baselines::ConnectedBodiesMechanics;
using baselines::CoordinateOde;

// --- the equations against the continuous Lagrangian -------------------------------------------

TEST(MultibodyLagrangian, CartMomentsAndMomentaAreDerivativesOfL) {
  const CartPendulum cart = CartPendulum::paper();
  auto rng = make_rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    const Mat3 R = so3::random_rotation(rng);
    const Vec3 Omega = 2.0 * random_vector(rng);
    const Vec2 q_dot = random_vector(rng).head<2>();
    const double scale = std::max(1.0, std::abs(cart.lagrangian(R, Omega, q_dot)));
    // X . e_j = d/da L(R exp(a hat(e_j))) at a = 0.
    const Vec3 X = cart.moment(R) + cart.coupling_moment(R, Omega, q_dot);
    Vec3 Pi;
    Vec2 p;
    cart.momenta(R, Omega, q_dot, Pi, p);
    for (int j = 0; j < 3; ++j) {
      const Vec3 e = kFdStep * Vec3::Unit(j);
      const double fd = (cart.lagrangian(R * so3::exp(e), Omega, q_dot) - cart.lagrangian(R * so3::exp(-e), Omega, q_dot)) /
                        (2 * kFdStep);
      EXPECT_NEAR(X(j), fd, kFdTolerance * scale) << "moment " << j;
      const double fd_Pi = (cart.lagrangian(R, Omega + e, q_dot) - cart.lagrangian(R, Omega - e, q_dot)) / (2 * kFdStep);
      EXPECT_NEAR(Pi(j), fd_Pi, kFdTolerance * scale) << "Pi " << j;
    }
    for (int j = 0; j < 2; ++j) {
      const Vec2 e = kFdStep * Vec2::Unit(j);
      const double fd_p = (cart.lagrangian(R, Omega, q_dot + e) - cart.lagrangian(R, Omega, q_dot - e)) / (2 * kFdStep);
      EXPECT_NEAR(p(j), fd_p, kFdTolerance * scale) << "p " << j;
    }
  }
}

TEST(MultibodyLagrangian, ConnectedBodiesMomentsAndMomentaAreDerivativesOfL) {
  const ConnectedBodies bodies = ConnectedBodies::paper();
  auto rng = make_rng(12);
  for (int trial = 0; trial < 20; ++trial) {
    const Mat3 R1 = so3::random_rotation(rng), R2 = so3::random_rotation(rng);
    const Vec3 O1 = 2.0 * random_vector(rng), O2 = 2.0 * random_vector(rng);
    const double scale = std::max(1.0, std::abs(bodies.lagrangian(R1, R2, O1, O2)));
    Vec3 X1, X2, Pi1, Pi2;
    bodies.coupling_moments(R1, R2, O1, O2, X1, X2);
    bodies.momenta(R1, R2, O1, O2, Pi1, Pi2);
    EXPECT_LT((R1 * X1 + R2 * X2).norm(), roundoff(scale, 40)) << "the coupling is internal";
    for (int j = 0; j < 3; ++j) {
      const Vec3 e = kFdStep * Vec3::Unit(j);
      const auto L = [&](const Mat3& a, const Mat3& b, const Vec3& u, const Vec3& v) { return bodies.lagrangian(a, b, u, v); };
      EXPECT_NEAR(X1(j), (L(R1 * so3::exp(e), R2, O1, O2) - L(R1 * so3::exp(-e), R2, O1, O2)) / (2 * kFdStep),
                  kFdTolerance * scale);
      EXPECT_NEAR(X2(j), (L(R1, R2 * so3::exp(e), O1, O2) - L(R1, R2 * so3::exp(-e), O1, O2)) / (2 * kFdStep),
                  kFdTolerance * scale);
      EXPECT_NEAR(Pi1(j), (L(R1, R2, O1 + e, O2) - L(R1, R2, O1 - e, O2)) / (2 * kFdStep), kFdTolerance * scale);
      EXPECT_NEAR(Pi2(j), (L(R1, R2, O1, O2 + e) - L(R1, R2, O1, O2 - e)) / (2 * kFdStep), kFdTolerance * scale);
    }
  }
}

// --- right-hand sides and Jacobians, every chart -------------------------------------------------

template <class Chart>
class MultibodyModel : public ::testing::Test {};
using Charts = ::testing::Types<baselines::QuaternionChart, baselines::EulerChart, baselines::MatrixChart>;
TYPED_TEST_SUITE(MultibodyModel, Charts);

TYPED_TEST(MultibodyModel, CartPendulum) {
  using Chart = TypeParam;
  const CartPendulum cart = CartPendulum::paper();
  using Mech = CartPendulumMechanics;
  const CoordinateOde<Chart, Mech> controlled{Mech(cart, cart_control)}, free{Mech(cart)};
  auto rng = make_rng(13);
  for (int trial = 0; trial < 10; ++trial) {
    const Mat3 R = random_attitude(rng);
    const Vec3 Omega = 2.0 * random_vector(rng);
    const Vec2 q = random_vector(rng).head<2>(), q_dot = random_vector(rng).head<2>();
    // kappa as for the connected bodies: the coupling block m hat(d) R^T E changes by at most m |d|.
    const auto kappa = [&](const auto& state) {
      const Mat5 A = cart.mass_matrix(controlled.decode(state.data()).config.R[0]);
      return cart.mass * cart.d.norm() / Eigen::SelfAdjointEigenSolver<Mat5>(A).eigenvalues()(0);
    };
    expect_jacobian(controlled, 0.7, controlled.initial_state({R}, {Omega}, q, q_dot), "cart-pendulum, controlled",
                    kappa);
    const auto y = controlled.initial_state({R}, {Omega}, q, q_dot);
    // The decoded state is the initial one (momenta -> velocities by the mass matrix of eq. 37).
    const auto d = controlled.decode(y.data());
    EXPECT_LT((d.rates.Omega[0] - Omega).norm() + (d.rates.x_dot - q_dot).norm(), roundoff(10.0, 100));
    const auto energy = [&](const auto& s) { return cart.energy(s.config.R[0], s.rates.Omega[0], s.rates.x_dot); };
    const auto vertical = [&](const auto& s) {
      Vec3 Pi;
      Vec2 p;
      cart.momenta(s.config.R[0], s.rates.Omega[0], s.rates.x_dot, Pi, p);
      return cart.vertical_momentum(s.config.R[0], s.config.x, Pi, p);
    };
    const double scale = std::max(1.0, std::abs(energy(d)));
    // derivative_along_flow evaluates the right-hand side at t = 0.
    const Vec2 u = cart_control(0.0);
    EXPECT_NEAR(derivative_along_flow(controlled, y, energy), u.dot(q_dot), kFdTolerance * scale) << "dE/dt = u . q'";
    EXPECT_NEAR(derivative_along_flow(controlled, y, vertical), q.x() * u.y() - q.y() * u.x(), kFdTolerance * scale);
    EXPECT_LT(std::abs(derivative_along_flow(free, y, energy)), kFdTolerance * scale);
    EXPECT_LT(std::abs(derivative_along_flow(free, y, vertical)), kFdTolerance * scale);
    typename CoordinateOde<Chart, Mech>::State f;
    ASSERT_EQ(controlled.rhs(0.0, y.data(), f.data()), baselines::RhsStatus::Ok);
    EXPECT_EQ(Vec2(f.template tail<2>()), u) << "p' = u exactly";
  }
}

TYPED_TEST(MultibodyModel, ConnectedBodies) {
  using Chart = TypeParam;
  const ConnectedBodies bodies = ConnectedBodies::paper();
  using Mech = ConnectedBodiesMechanics;
  const CoordinateOde<Chart, Mech> controlled{Mech(bodies, bodies_control)};
  auto rng = make_rng(14);
  for (int trial = 0; trial < 10; ++trial) {
    const std::array<Mat3, 2> R = {random_attitude(rng), random_attitude(rng)};
    const std::array<Vec3, 2> Omega = {2.0 * random_vector(rng), 2.0 * random_vector(rng)};
    const auto y = controlled.initial_state(R, Omega);
    // kappa = ||A^{-1}|| ||dA/dR_ij||: the coupling block mu hat(d1) R1^T R2 hat(d2) changes by at
    // most mu |d1| |d2| per unit change of an entry of R1 or R2.
    const auto kappa = [&](const auto& state) {
      const auto c = controlled.decode(state.data()).config;
      const Mat6x6 A = bodies.mass_matrix(c.R[0], c.R[1]);
      return bodies.mu * bodies.d1.norm() * bodies.d2.norm() / Eigen::SelfAdjointEigenSolver<Mat6x6>(A).eigenvalues()(0);
    };
    expect_jacobian(controlled, 0.3, y, "connected bodies, controlled", kappa);
    const auto d = controlled.decode(y.data());
    EXPECT_LT((d.rates.Omega[0] - Omega[0]).norm() + (d.rates.Omega[1] - Omega[1]).norm(), roundoff(10.0, 100));
    const auto energy = [&](const auto& s) {
      return bodies.energy(s.config.R[0], s.config.R[1], s.rates.Omega[0], s.rates.Omega[1]);
    };
    const double scale = std::max(1.0, std::abs(energy(d)));
    const Vec3 u = bodies_control(0.0);
    EXPECT_NEAR(derivative_along_flow(controlled, y, energy), u.dot(R[0] * Omega[0] - R[1] * Omega[1]),
                kFdTolerance * scale)
        << "dE/dt = power of the joint moment";
    for (int i = 0; i < 3; ++i) {
      const auto momentum = [&](const auto& s) {
        Vec3 Pi1, Pi2;
        bodies.momenta(s.config.R[0], s.config.R[1], s.rates.Omega[0], s.rates.Omega[1], Pi1, Pi2);
        return ConnectedBodies::total_angular_momentum(s.config.R[0], s.config.R[1], Pi1, Pi2)(i);
      };
      EXPECT_LT(std::abs(derivative_along_flow(controlled, y, momentum)), kFdTolerance * scale)
          << "total angular momentum " << i << " (internal control)";
    }
  }
}

// --- agreement with the LGVI ------------------------------------------------------------------------

// CVODE Adams at r = 1e-12 (its error N r (1 + |y|) sqrt(n) ~ 1e-8 here) against the symmetric
// LGVI at h and h/2, with controls, sampled every 0.1 s over T:
//   |Y_cvode - Y_h| <= kRichardsonSlack * 4/3 |Y_h - Y_{h/2}| + bound(cvode)   (multibody_cases.hpp)
//   log2(|Y_cvode - Y_h| / |Y_cvode - Y_{h/2}|) = 2 +- kOrderTolerance
// The second says the LGVI converges to the baseline's trajectory at its order: the two solve
// the same continuous equations. The LGVI's errors (~1e-6 .. 1e-4) dwarf the reference's.
constexpr double kReferenceTolerance = 1e-12;

void expect_agreement(const char* what, const Path& cvode, const Path& coarse, const Path& fine) {
  ASSERT_TRUE(cvode.stats.ok()) << cvode.stats.brief();
  ASSERT_TRUE(coarse.stats.ok() && fine.stats.ok());
  ASSERT_EQ(cvode.z.size(), coarse.z.size());
  ASSERT_EQ(cvode.z.size(), fine.z.size());
  const double e_coarse = max_distance(cvode, coarse), e_fine = max_distance(cvode, fine);
  const double richardson = 4.0 / 3.0 * max_distance(coarse, fine);
  const double reference = adaptive_bound(cvode, kReferenceTolerance);
  const double order = std::log2(e_coarse / e_fine);
  std::cout << "[ agree    ] " << what << ": |cvode - lgvi(h)| = " << e_coarse << ", |cvode - lgvi(h/2)| = " << e_fine
            << ", Richardson estimate of lgvi(h)'s error " << richardson << ", cvode bound " << reference
            << ", order " << order << " (" << cvode.stats.steps << " cvode steps)\n";
  EXPECT_LE(e_coarse, kRichardsonSlack * richardson + reference);
  EXPECT_NEAR(order, 2.0, kOrderTolerance);
  EXPECT_LT(reference, 0.01 * e_fine) << "the reference must be far more accurate than the LGVI";
}

TEST(MultibodyAgreement, CartPendulumCvodeMatchesTheLgvi) {
  const CartPendulum cart = CartPendulum::paper();
  constexpr double T = 3.0, h = 2e-3;
  const std::size_t steps = 1500, samples = 30;
  const baselines::CartPendulumMechanics mech(cart, cart_control);
  const Path cvode = run_model("cvode-adams", baselines::CoordinateModel::Quaternion, mech, {cart_R0()}, {cart_Omega0()},
                               cart_q0(), cart_q_dot0(), uniform_times(T, samples), adaptive(kReferenceTolerance));
  const Path coarse = run_cart_lgvi(cart, h, steps, steps / samples, cart_control);
  const Path fine = run_cart_lgvi(cart, h / 2, 2 * steps, 2 * steps / samples, cart_control);
  expect_agreement("cart-pendulum, controlled, 3 s, h = 2e-3 / 1e-3", cvode, coarse, fine);
}

TEST(MultibodyAgreement, ConnectedBodiesCvodeMatchesTheLgvi) {
  const ConnectedBodies bodies = ConnectedBodies::paper();
  constexpr double T = 3.0, h = 4e-3;
  const std::size_t steps = 750, samples = 30;
  const baselines::ConnectedBodiesMechanics mech(bodies, bodies_control);
  const Path cvode = run_model("cvode-adams", baselines::CoordinateModel::Quaternion, mech, bodies_R0(),
                               bodies_Omega0(), {}, {}, uniform_times(T, samples), adaptive(kReferenceTolerance));
  const Path coarse = run_bodies_lgvi(bodies, h, steps, steps / samples, bodies_control);
  const Path fine = run_bodies_lgvi(bodies, h / 2, 2 * steps, 2 * steps / samples, bodies_control);
  expect_agreement("connected bodies, controlled, 3 s, h = 4e-3 / 2e-3", cvode, coarse, fine);
}

TEST(MultibodyAgreement, CartControlSampledOnTheLgviGridReplaysOnCvode) {
  // An LGVI control is a sequence u_k at t_k = k h: replayed on the baseline as the piecewise-
  // linear SampledControl (the function whose trapezoidal impulses the symmetric LGVI applies).
  // Its kinks lie on the grid of h and h/2, so the LGVI stays second order and the bounds above
  // hold unchanged.
  const CartPendulum cart = CartPendulum::paper();
  constexpr double T = 3.0, h = 2e-3;
  const std::size_t steps = 1500, samples = 30;
  std::vector<double> t;
  std::vector<Vec2> u;
  for (std::size_t k = 0; k <= steps; ++k) {
    t.push_back(static_cast<double>(k) * h);
    u.push_back(cart_control(t.back()));
  }
  const baselines::SampledControl<2> replay(t, u, baselines::Interpolation::PiecewiseLinear);
  const baselines::CartPendulumMechanics mech(cart, replay);
  const Path cvode = run_model("cvode-adams", baselines::CoordinateModel::Quaternion, mech, {cart_R0()}, {cart_Omega0()},
                               cart_q0(), cart_q_dot0(), uniform_times(T, samples), adaptive(kReferenceTolerance));
  const Path coarse = run_cart_lgvi(cart, h, steps, steps / samples, replay);
  const Path fine = run_cart_lgvi(cart, h / 2, 2 * steps, 2 * steps / samples, replay);
  expect_agreement("cart-pendulum, sampled control replayed, h = 2e-3 / 1e-3", cvode, coarse, fine);
}

// --- conservation to the promised accuracy --------------------------------------------------------

/// |grad_y m| at y by central differences (steps as the model's), m a scalar of the raw state.
template <class Fn>
double gradient_norm(const Eigen::VectorXd& y, Fn&& m) {
  double g2 = 0.0;
  for (int j = 0; j < y.size(); ++j) {
    const double a = kFdStep * std::max(1.0, std::abs(y(j)));
    Eigen::VectorXd yp = y, ym = y;
    yp(j) += a;
    ym(j) -= a;
    const double g = (m(yp) - m(ym)) / (2 * a);
    g2 += g * g;
  }
  return std::sqrt(g2);
}

/// A conserved quantity m drifts by at most max|grad m| times the state error the solver
/// promises (adaptive_bound): first order in the state error, which is ~1e-5 at most here.
template <class Fn>
void expect_conserved(const char* what, const Path& p, double r, Fn&& m) {
  ASSERT_TRUE(p.stats.ok()) << p.stats.brief();
  const double m0 = m(p.raw.front());
  double drift = 0.0, grad = 0.0;
  for (const Eigen::VectorXd& y : p.raw) {
    drift = std::max(drift, std::abs(m(y) - m0));
    grad = std::max(grad, gradient_norm(y, m));
  }
  const double bound = grad * adaptive_bound(p, r);
  std::cout << "[ conserve ] " << what << ": max drift " << drift << " (|m0| = " << std::abs(m0) << "), bound " << bound
            << "\n";
  EXPECT_LE(drift, bound);
}

TEST(MultibodyConservation, CartMomentaToTheTolerance) {
  const CartPendulum cart = CartPendulum::paper();
  using Ode = CoordinateOde<baselines::QuaternionChart, CartPendulumMechanics>;
  const Ode ode{CartPendulumMechanics(cart)};
  for (const double r : {1e-6, 1e-10}) {
    const Path p = run_baseline("cvode-bdf", ode, {cart_R0()}, {cart_Omega0()}, cart_q0(), cart_q_dot0(),
                                uniform_times(10.0, 100), adaptive(r));
    const auto vertical = [&](const Eigen::VectorXd& y) {
      const auto d = ode.decode(y.data());
      return cart.vertical_momentum(d.config.R[0], d.config.x, y.segment<3>(Ode::kW), y.segment<2>(Ode::kW + 3));
    };
    expect_conserved(r == 1e-6 ? "cart vertical momentum, cvode-bdf 1e-6, 10 s"
                               : "cart vertical momentum, cvode-bdf 1e-10, 10 s",
                     p, r, vertical);
    // p' = 0 exactly: the cart's momentum stays at its initial value to round-off.
    for (const Eigen::VectorXd& y : p.raw) {
      EXPECT_LE((y.tail<2>() - p.raw.front().tail<2>()).norm(), roundoff(p.raw.front().tail<2>().norm(), 1.0));
    }
  }
}

TEST(MultibodyConservation, ConnectedBodiesAngularMomentumToTheTolerance) {
  const ConnectedBodies bodies = ConnectedBodies::paper();
  using Ode = CoordinateOde<baselines::QuaternionChart, ConnectedBodiesMechanics>;
  const Ode ode{ConnectedBodiesMechanics(bodies, bodies_control)};  // internal: conserved anyway
  for (const double r : {1e-6, 1e-10}) {
    const Path p = run_baseline("cvode-bdf", ode, bodies_R0(), bodies_Omega0(), {}, {}, uniform_times(20.0, 100),
                                adaptive(r));
    for (int i = 0; i < 3; ++i) {
      const auto momentum = [&](const Eigen::VectorXd& y) {
        const auto d = ode.decode(y.data());
        return ConnectedBodies::total_angular_momentum(d.config.R[0], d.config.R[1], y.segment<3>(Ode::kW),
                                                       y.segment<3>(Ode::kW + 3))(i);
      };
      expect_conserved("connected bodies total angular momentum component, cvode-bdf, 20 s, controlled", p, r, momentum);
    }
  }
}

// --- the quaternion models conserve nothing exactly ------------------------------------------------

// As tests/baselines/test_drift.cpp for the single bodies: without renormalization the unit-norm
// error exceeds the round-off floor 16 N eps at the end and its maximum grows by more than
// kGrowth from the first tenth of the run to the whole (a random walk grows by sqrt(10) ~ 3.2);
// with it the reported attitudes are rotations to round-off.
constexpr double kGrowth = 3.0;

template <class Mech>
void expect_quaternion_drift(const char* what, const Mech& mech, const std::array<Mat3, Mech::bodies>& R0,
                             const std::array<Vec3, Mech::bodies>& Omega0, const baselines::Vector<Mech::positions>& x0,
                             const baselines::Vector<Mech::positions>& x_dot0, double T) {
  for (const std::string method : {"cvode-bdf", "odeint-dopri5"}) {
    const Path p = run_model(method, baselines::CoordinateModel::Quaternion, mech, R0, Omega0, x0, x_dot0,
                             uniform_times(T, 100), adaptive(1e-6));
    ASSERT_TRUE(p.stats.ok()) << p.stats.brief();
    const auto& e = p.quaternion_norm_error;
    const double early = *std::max_element(e.begin(), e.begin() + 11);
    const double all = *std::max_element(e.begin(), e.end());
    const double floor = roundoff(1.0, static_cast<double>(p.stats.steps));
    std::cout << "[ drift    ] " << what << ", " << method << "/quaternion, rtol 1e-6: max | |q| - 1 | to T/10: " << early
              << ", to T: " << all << ", at T: " << e.back() << " (floor " << floor << ", " << p.stats.steps
              << " steps)\n";
    EXPECT_GT(e.back(), floor);
    EXPECT_GT(all, kGrowth * early);

    const Path r = run_model(method, baselines::CoordinateModel::QuaternionRenormalized, mech, R0, Omega0, x0, x_dot0,
                             uniform_times(T, 100), adaptive(1e-6));
    ASSERT_TRUE(r.stats.ok()) << r.stats.brief();
    double worst = 0.0;
    for (const Eigen::VectorXd& z : r.z) {
      for (int i = 0; i < Mech::bodies; ++i) {
        Mat3 R;
        for (int k = 0; k < 9; ++k) R(k / 3, k % 3) = z(9 * i + k);
        worst = std::max(worst, so3::orthogonality_error(R));
      }
    }
    std::cout << "[ drift    ] " << what << ", " << method << "/quaternion-renormalized: max ||R^T R - I|| " << worst << "\n";
    EXPECT_LE(worst, roundoff(1.0, 10));
  }
}

TEST(MultibodyDrift, CartPendulumQuaternionNormGrows) {
  const CartPendulum cart = CartPendulum::paper();
  // 1000 s: over the first 100 s cvode-bdf's |q| error is still dominated by its early steps.
  expect_quaternion_drift("cart-pendulum 1000 s", CartPendulumMechanics(cart), {cart_R0()}, {cart_Omega0()}, cart_q0(),
                          cart_q_dot0(), 1000.0);
}

TEST(MultibodyDrift, ConnectedBodiesQuaternionNormGrows) {
  const ConnectedBodies bodies = ConnectedBodies::paper();
  expect_quaternion_drift("connected bodies 200 s", ConnectedBodiesMechanics(bodies), bodies_R0(), bodies_Omega0(), {},
                          {}, 200.0);
}

}  // namespace
}  // namespace lgvi::test
