// The coordinate models: charts (round trip, kinematics against R' = R hat(Omega), Jacobians of
// R(c)), right-hand sides (energy and momentum maps of lgvi/systems are first integrals of the
// continuous flow: their derivative along f vanishes), and the full ODE Jacobian against central
// differences of the right-hand side, for every chart and system, with controls.
#include <gtest/gtest.h>

#include <random>

#include "baseline_cases.hpp"
#include "model_checks.hpp"
#include "lgvi/systems/dumbbell.hpp"

namespace lgvi::test {
namespace {

using baselines::CoordinateOde;
using baselines::EulerChart;
using baselines::MatrixChart;
using baselines::QuaternionChart;

template <class Chart>
class ChartTest : public ::testing::Test {};
using Charts = ::testing::Types<QuaternionChart, EulerChart, MatrixChart>;
TYPED_TEST_SUITE(ChartTest, Charts);

TYPED_TEST(ChartTest, RoundTripKinematicsAndRotationJacobian) {
  using Chart = TypeParam;
  auto rng = make_rng(1);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    const Mat3 R = random_attitude(rng);
    const Vec3 Omega(normal(rng), normal(rng), normal(rng));
    const typename Chart::Coords c = Chart::from_rotation(R);
    EXPECT_LT((Chart::rotation(c) - R).norm(), roundoff(1.0, 30)) << "round trip";
    // Chain rule: d/dt vec(R(c)) = dR/dc c' must be vec(R hat(Omega)).
    const Eigen::Matrix<double, 9, 1> Rdot = Chart::rotation_jacobian(c) * Chart::rate(c, Omega);
    EXPECT_LT((Rdot - baselines::vec_rows(R * so3::hat(Omega))).norm(), roundoff(Omega.norm(), 60)) << "kinematics";
    // dR/dc against central differences of R(c).
    for (int j = 0; j < Chart::size; ++j) {
      typename Chart::Coords cp = c, cm = c;
      cp(j) += kFdStep;
      cm(j) -= kFdStep;
      const Eigen::Matrix<double, 9, 1> fd = (baselines::vec_rows(Chart::rotation(cp)) - baselines::vec_rows(Chart::rotation(cm))) / (2 * kFdStep);
      EXPECT_LT((Chart::rotation_jacobian(c).col(j) - fd).norm(), kFdTolerance) << "dR/dc_" << j;
    }
  }
}

TEST(QuaternionChart, OffTheUnitSphereTheRotationScalesByTheSquaredNorm) {
  // R(q) = |q|^2 R(q/|q|), so the orthogonality error is sqrt(3) (|q|^4 - 1) (see coordinates.hpp).
  const QuaternionChart::Coords q = 1.001 * QuaternionChart::from_rotation(so3::exp(Vec3(0.3, 1.0, -2.0)));
  const Mat3 R = QuaternionChart::rotation(q);
  EXPECT_NEAR(so3::orthogonality_error(R), std::sqrt(3.0) * (std::pow(q.norm(), 4) - 1.0), 1e-14);
  EXPECT_NEAR(QuaternionChart::norm_error(q), 1e-3, 1e-15);
}

TEST(EulerChart, SequenceIsYawPitchRoll) {
  const EulerChart::Coords c(0.3, -0.7, 1.9);  // roll, pitch, yaw
  const Mat3 Rz = so3::exp(Vec3(0, 0, c(2))), Ry = so3::exp(Vec3(0, c(1), 0)), Rx = so3::exp(Vec3(c(0), 0, 0));
  EXPECT_LT((EulerChart::rotation(c) - Rz * Ry * Rx).norm(), roundoff(1.0, 20));
  EXPECT_LT((EulerChart::from_rotation(Rz * Ry * Rx) - c).norm(), roundoff(1.0, 20));
  // Omega = B c' and c' = B^{-1} Omega.
  const Vec3 Omega(0.4, -1.2, 0.8);
  EXPECT_LT((EulerChart::omega_matrix(c) * EulerChart::rate(c, Omega) - Omega).norm(), roundoff(1.0, 20));
  EXPECT_TRUE(EulerChart::singular(EulerChart::Coords(0.1, M_PI / 2, 0.2)));
  EXPECT_FALSE(EulerChart::singular(c));
  EXPECT_NEAR(EulerChart::kGimbalThreshold, std::sqrt(kEps), 1e-24);
}

template <class Chart>
class ModelTest : public ::testing::Test {};
TYPED_TEST_SUITE(ModelTest, Charts);

TYPED_TEST(ModelTest, FreeBody) {
  using Chart = TypeParam;
  const FreeRigidBody body = free_body();
  auto rng = make_rng(2);
  using Mech = baselines::AttitudeMechanics<FreeRigidBody>;
  const CoordinateOde<Chart, Mech> controlled{Mech(body, free_body_control)}, free{Mech(body)};
  for (int trial = 0; trial < 10; ++trial) {
    const Mat3 R = random_attitude(rng);
    const Vec3 Omega = 2.0 * random_vector(rng);
    expect_jacobian(controlled, 0.7, controlled.initial_state({R}, {Omega}), "free body, controlled");
    const auto y = free.initial_state({R}, {Omega});
    const auto energy = [&](const auto& d) { return body.energy(d.config.R[0], d.rates.Omega[0]); };
    const double E = energy(free.decode(y.data()));
    EXPECT_LT(std::abs(derivative_along_flow(free, y, energy)), kFdTolerance * std::max(1.0, E));
    for (int i = 0; i < 3; ++i) {
      const auto pi = [&](const auto& d) { return body.spatial_momentum(d.config.R[0], d.rates.Omega[0])(i); };
      EXPECT_LT(std::abs(derivative_along_flow(free, y, pi)), kFdTolerance * std::max(1.0, E));
    }
  }
}

TYPED_TEST(ModelTest, Pendulum) {
  using Chart = TypeParam;
  const Pendulum3D pendulum = Pendulum3D::paper();
  auto rng = make_rng(3);
  using Mech = baselines::AttitudeMechanics<Pendulum3D>;
  const CoordinateOde<Chart, Mech> controlled{Mech(pendulum, pendulum_control)}, free{Mech(pendulum)};
  for (int trial = 0; trial < 10; ++trial) {
    const Mat3 R = random_attitude(rng);
    const Vec3 Omega = 3.0 * random_vector(rng);
    expect_jacobian(controlled, 0.3, controlled.initial_state({R}, {Omega}), "pendulum, controlled");
    const auto y = free.initial_state({R}, {Omega});
    const auto energy = [&](const auto& d) { return pendulum.energy(d.config.R[0], d.rates.Omega[0]); };
    const auto vertical = [&](const auto& d) { return pendulum.vertical_momentum(d.config.R[0], d.rates.Omega[0]); };
    const double scale = std::max(1.0, std::abs(energy(free.decode(y.data()))));
    EXPECT_LT(std::abs(derivative_along_flow(free, y, energy)), kFdTolerance * scale);
    EXPECT_LT(std::abs(derivative_along_flow(free, y, vertical)), kFdTolerance * scale);
    // The control moment R^T e3 x u has no vertical component: the momentum stays conserved.
    const auto yc = controlled.initial_state({R}, {Omega});
    EXPECT_LT(std::abs(derivative_along_flow(controlled, yc, vertical)), kFdTolerance * scale);
  }
}

TYPED_TEST(ModelTest, Dumbbell) {
  using Chart = TypeParam;
  const DumbbellSpacecraft dumbbell = DumbbellSpacecraft::paper();
  auto rng = make_rng(4);
  using Mech = baselines::DumbbellMechanics;
  const auto control = [](double t) {
    DumbbellSpacecraft::Control u;
    u.force = Vec3(0.02 * std::sin(t), 0.01 * std::cos(2.0 * t), 0.015 * std::sin(0.5 * t));
    u.moment = Vec3(1e-3 * std::cos(t), 2e-3 * std::sin(1.5 * t), 1e-3 * std::sin(t + 1.0));
    return u;
  };
  const CoordinateOde<Chart, Mech> controlled{Mech(dumbbell, control)}, free{Mech(dumbbell)};
  for (int trial = 0; trial < 10; ++trial) {
    const Mat3 R = random_attitude(rng);
    const Vec3 Omega = random_vector(rng), x = Vec3(1.0, 0.2, -0.1) + 0.1 * random_vector(rng);
    const Vec3 v(0.1, 0.95, 0.05);
    expect_jacobian(controlled, 1.1, controlled.initial_state({R}, {Omega}, x, v), "dumbbell, controlled");
    const auto y = free.initial_state({R}, {Omega}, x, v);
    const auto energy = [&](const auto& d) {
      return dumbbell.energy(d.config.R[0], d.config.x, d.rates.Omega[0], d.rates.x_dot);
    };
    const double scale = std::max(1.0, std::abs(energy(free.decode(y.data()))));
    EXPECT_LT(std::abs(derivative_along_flow(free, y, energy)), kFdTolerance * scale);
    for (int i = 0; i < 3; ++i) {
      const auto h = [&](const auto& d) {
        return dumbbell.angular_momentum(d.config.R[0], d.config.x, d.rates.Omega[0], d.rates.x_dot)(i);
      };
      EXPECT_LT(std::abs(derivative_along_flow(free, y, h)), kFdTolerance * scale);
    }
  }
}

TEST(EulerModel, RightHandSideRefusesTheSingularSet) {
  const FreeRigidBody body = free_body();
  using Mech = baselines::AttitudeMechanics<FreeRigidBody>;
  const CoordinateOde<EulerChart, Mech> ode{Mech(body)};
  CoordinateOde<EulerChart, Mech>::State y;
  y << 0.1, M_PI / 2, 0.3, 1.0, 2.0, 3.0;
  using State = CoordinateOde<EulerChart, Mech>::State;
  State f = State::Constant(7.0);
  EXPECT_EQ(ode.rhs(0.0, y.data(), f.data()), baselines::RhsStatus::Singular);
  EXPECT_EQ(f, State(State::Constant(7.0)));  // untouched: no NaN produced
  EXPECT_LE(ode.singularity_function(y.data()), 0.0);
  EXPECT_NE(ode.describe_singularity(y.data()).find("gimbal lock: pitch theta = 90"), std::string::npos)
      << ode.describe_singularity(y.data());
}

}  // namespace
}  // namespace lgvi::test

namespace lgvi::test {
namespace {

// The model layer is generic in the number of bodies, the further coordinates and the form of the
// velocity state, which is what the multibody systems need (cart-pendulum: N = 1, NX = 2, momenta
// of eq. 37; connected bodies: N = 2, momenta of eq. 47). A toy system exercises that path: two
// free rigid bodies and a planar harmonic oscillator, in momentum form w = (J1 Omega1, J2 Omega2,
// m x'), so the rates need a "mass-matrix" solve and the model differentiates them numerically
// (no rates_are_velocities, no velocity_jacobian).
struct ToyMultibody {
  static constexpr int bodies = 2;
  static constexpr int positions = 2;
  static constexpr int velocities = 8;
  using Config = baselines::Configuration<2, 2>;
  using Rate = baselines::Rates<2, 2>;
  using Velocity = baselines::Vector<8>;
  const FreeRigidBody* body1;
  const FreeRigidBody* body2;
  double mass = 2.0, stiffness = 3.0;

  void rates(const Config&, const Velocity& w, Rate& r) const {
    r.Omega[0] = body1->inertia.J_inverse * w.head<3>();
    r.Omega[1] = body2->inertia.J_inverse * w.segment<3>(3);
    r.x_dot = w.tail<2>() / mass;
  }
  Velocity acceleration(double, const Config& c, const Velocity& w) const {
    Rate r;
    rates(c, w, r);
    Velocity a;
    a << Vec3(w.head<3>()).cross(r.Omega[0]), Vec3(w.segment<3>(3)).cross(r.Omega[1]), -stiffness * c.x;
    return a;
  }
  Velocity velocity_state(const Config&, const std::array<Vec3, 2>& Omega, const baselines::Vector<2>& x_dot) const {
    Velocity w;
    w << body1->inertia.J * Omega[0], body2->inertia.J * Omega[1], mass * x_dot;
    return w;
  }
  bool time_dependent() const { return false; }
};
static_assert(baselines::Mechanics<ToyMultibody>);

template <class Chart>
class MultibodyTest : public ::testing::Test {};
TYPED_TEST_SUITE(MultibodyTest, Charts);

TYPED_TEST(MultibodyTest, TwoBodiesAndCoordinatesInMomentumForm) {
  using Chart = TypeParam;
  const FreeRigidBody b1 = free_body(), b2(Vec3(0.5, 0.4, 0.3).asDiagonal());
  const ToyMultibody toy{&b1, &b2};
  const CoordinateOde<Chart, ToyMultibody> ode(toy);
  auto rng = make_rng(5);
  const std::array<Mat3, 2> R = {random_attitude(rng), random_attitude(rng)};
  const std::array<Vec3, 2> Omega = {Vec3(1.0, -0.5, 0.3), Vec3(-0.2, 0.8, 0.6)};
  const baselines::Vector<2> x(0.3, -0.1), x_dot(0.2, 0.4);
  const auto y = ode.initial_state(R, Omega, x, x_dot);
  expect_jacobian(ode, 0.0, y, "toy multibody");
  const auto d = ode.decode(y.data());
  for (int i = 0; i < 2; ++i) {
    EXPECT_LT((d.config.R[i] - R[i]).norm(), roundoff(1.0, 30));
    EXPECT_LT((d.rates.Omega[i] - Omega[i]).norm(), roundoff(1.0, 30));
  }
  EXPECT_LT((d.rates.x_dot - x_dot).norm(), roundoff(1.0, 4));
  // Integrate: each body's kinetic energy and the oscillator's energy are first integrals.
  const auto energies = [&](const double* s) {
    const auto e = ode.decode(s);
    return Vec3(b1.energy(e.config.R[0], e.rates.Omega[0]), b2.energy(e.config.R[1], e.rates.Omega[1]),
                0.5 * toy.mass * e.rates.x_dot.squaredNorm() + 0.5 * toy.stiffness * e.config.x.squaredNorm());
  };
  const Vec3 E0 = energies(y.data());
  const Stats stats = baselines::integrate("cvode-bdf", ode, std::span<const double>(y.data(), y.size()),
                                           uniform_times(2.0, 20), adaptive(1e-10),
                                           [&](std::size_t, double, const double* s) {
                                             EXPECT_LT((energies(s) - E0).norm(), 1e-6);
                                             return true;
                                           });
  EXPECT_TRUE(stats.ok()) << stats.brief();
}

}  // namespace
}  // namespace lgvi::test

namespace lgvi::test {
namespace {

// The renormalized model's record of | |q| - 1 | is the solver's state's, taken before decode
// normalizes the quaternion for R: a solver that skipped the renormalization between steps would
// otherwise be recorded at round-off (validate's quaternion-norm metric could not see it).
TEST(RenormalizedModel, DecodeRecordsTheNormOfTheStateBeforeNormalizing) {
  using Mech = baselines::AttitudeMechanics<FreeRigidBody>;
  const FreeRigidBody body = free_body();
  const Mech mech(body, {});
  const CoordinateOde<QuaternionChart, Mech> renormalized(mech, true), plain(mech);
  auto y = renormalized.initial_state({free_body_R0()}, {free_body_Omega0()});
  y.head<4>() *= 1.0 + 1e-6;  // a quaternion one un-renormalized drift away from the sphere
  const auto d = renormalized.decode(y.data());
  EXPECT_NEAR(d.quaternion_norm_error[0], 1e-6, 1e-15);
  EXPECT_EQ(d.quaternion_norm_error[0], plain.decode(y.data()).quaternion_norm_error[0]);
  // R is still the normalized quaternion's: orthogonal to round-off.
  EXPECT_LT(so3::orthogonality_error(d.config.R[0]), roundoff(1.0, 4));
}

}  // namespace
}  // namespace lgvi::test
