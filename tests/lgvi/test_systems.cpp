// Physical systems (lgvi/systems/): potentials against their moments and forces, the pendulum's
// symmetric control, the dumbbell's circular orbit, and parameter validation.
//
// Sign of the moment (eq. 13, hat(M) = dU/dR^T R - R^T dU/dR). With A = dU/dR^T R,
//   d/d eta U(R exp(hat eta)) at 0 = sum_ij [dU/dR]_ij [R hat(eta)]_ij = tr(A hat(eta))
//                                   = -vee(A - A^T) . eta = -M . eta,
// because tr(X hat(eta)) = -vee(X - X^T) . eta for any X. So M = -dU/d eta: the moment is minus
// the gradient of the potential along body-frame rotations, like the force -dU/dx.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "lgvi/so3.hpp"
#include "lgvi/systems/dumbbell.hpp"
#include "lgvi/systems/pendulum.hpp"
#include "lgvi/systems/potential_body.hpp"
#include "lgvi/systems/potential_body_se3.hpp"
#include "test_support.hpp"

namespace lgvi {
namespace {

using test::kFdStep;
using test::kFdTolerance;
using test::roundoff;

/// The paper's initial attitude of the dumbbell (section 3.1): body e1 (the rod) along-track.
Mat3 paper_R0() {
  Mat3 R;
  R << 0, -1, 0,  //
      1, 0, 0,    //
      0, 0, 1;
  return R;
}

/// Central-difference gradient of eta -> U(R exp(hat eta)) at 0.
template <class Potential>
Vec3 fd_rotation_gradient(const Mat3& R, Potential&& U) {
  Vec3 g;
  for (int j = 0; j < 3; ++j) {
    const Vec3 d = kFdStep * Vec3::Unit(j);
    g(j) = (U(R * so3::exp(d)) - U(R * so3::exp(-d))) / (2.0 * kFdStep);
  }
  return g;
}

/// Central-difference dU/dR, [dU/dR]_ij = dU/dR_ij, treating R as a general 3x3 matrix (both
/// potentials are defined for any matrix: they only use R rho or a row of R).
template <class Potential>
Mat3 fd_matrix_gradient(const Mat3& R, Potential&& U) {
  Mat3 G;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      Mat3 Rp = R, Rm = R;
      Rp(i, j) += kFdStep;
      Rm(i, j) -= kFdStep;
      G(i, j) = (U(Rp) - U(Rm)) / (2.0 * kFdStep);
    }
  }
  return G;
}

struct Attitude {
  std::string name;
  Mat3 R;
};
std::ostream& operator<<(std::ostream& os, const Attitude& a) { return os << a.name; }

std::vector<Attitude> attitudes() {
  std::vector<Attitude> cases = {
      {"identity", Mat3::Identity()},
      {"paper_R0", paper_R0()},
      {"inverted", so3::exp(M_PI * Vec3::UnitX())},
      {"tilted", so3::exp(Vec3(0.4, -0.3, 0.2))},
  };
  auto rng = test::make_rng(/*salt=*/701);
  for (int k = 0; k < 16; ++k)
    cases.push_back({"random_" + std::to_string(k), so3::random_rotation(rng)});
  return cases;
}
std::string attitude_name(const testing::TestParamInfo<Attitude>& i) { return i.param.name; }

// --- 3D pendulum ---------------------------------------------------------------------------------

class PendulumAt : public testing::TestWithParam<Attitude> {
 protected:
  const Pendulum3D p = Pendulum3D::paper();
  // U(R exp(eta)) = -m g e3^T R exp(eta) rho: amplitude m g |rho|, and every derivative in eta is
  // bounded by the same amplitude, so the FD error is kFdTolerance relative to it.
  double scale() const { return p.mass * p.gravity * p.rho.norm(); }
};

// M = -dU/d eta (the sign derived at the top of this file).
TEST_P(PendulumAt, MomentIsMinusRotationalGradientOfPotential) {
  const Mat3 R = GetParam().R;
  const Vec3 g = fd_rotation_gradient(R, [&](const Mat3& Q) { return p.potential(Q); });
  EXPECT_LE((p.moment(R) + g).norm(), kFdTolerance * scale())
      << "M = " << p.moment(R).transpose() << ", dU/deta = " << g.transpose();
}

// Eq. 13 as printed: hat(M) = dU/dR^T R - R^T dU/dR, with dU/dR by central differences.
TEST_P(PendulumAt, MomentSatisfiesEquation13) {
  const Mat3 R = GetParam().R;
  const Mat3 dU = fd_matrix_gradient(R, [&](const Mat3& Q) { return p.potential(Q); });
  const Mat3 hatM = dU.transpose() * R - R.transpose() * dU;
  EXPECT_LE((so3::hat(p.moment(R)) - hatM).norm(), kFdTolerance * scale());
}

// The control moment R^T e3 x u has no vertical component: e3^T R (R^T e3 x u) = 0. Forming the
// cross product (2 flops per component, |R^T e3| = 1), then the dot product (3 flops) on values of
// size |u|: 5 flops of |u|, within roundoff(|u|).
TEST_P(PendulumAt, ControlMomentHasNoVerticalComponent) {
  const Mat3 R = GetParam().R;
  auto rng = test::make_rng(702);
  std::normal_distribution<double> normal;
  for (int k = 0; k < 8; ++k) {
    const Vec3 u(normal(rng), normal(rng), normal(rng));
    const Vec3 tau = p.control_moment(R, u);
    EXPECT_LE(std::abs(Vec3::UnitZ().dot(R * tau)), roundoff(u.norm())) << "u = " << u.transpose();
    // ... and is not trivially zero: |R^T e3 x u| = |u| sin(angle(e3, R u)).
    EXPECT_NEAR(tau.norm(), (R.row(2).transpose()).cross(u).norm(), roundoff(u.norm()));
  }
}

// J_moment_eta = d(M + R^T e3 x u)/deta (the derivative the discrete linearization and the
// continuous costate equations use) against central differences of the applied moment along
// R -> R exp(hat eta); the moment's amplitude, and that of its derivatives, is m g |rho| + |u|.
TEST_P(PendulumAt, MomentJacobianMatchesDifferences) {
  const Mat3 R = GetParam().R;
  auto rng = test::make_rng(703);
  std::normal_distribution<double> normal;
  const Vec3 u(normal(rng), normal(rng), normal(rng));
  const auto applied = [&](const Mat3& Q) { return Vec3(p.moment(Q) + p.control_moment(Q, u)); };
  Mat3 fd;
  for (int j = 0; j < 3; ++j) {
    const Vec3 d = kFdStep * Vec3::Unit(j);
    fd.col(j) = (applied(R * so3::exp(d)) - applied(R * so3::exp(-d))) / (2.0 * kFdStep);
  }
  EXPECT_LE((p.J_moment_eta(R, u) - fd).norm(), kFdTolerance * (scale() + u.norm()));
}

// The vertical momentum's gradient [Pi x a; a] against central differences of e3^T R Pi in the
// tangent [eta; dPi]; the amplitude of e3^T R Pi and of its derivatives is |Pi| + 1.
TEST_P(PendulumAt, VerticalMomentumGradientMatchesDifferences) {
  const Mat3 R = GetParam().R;
  const Vec3 Pi(0.3, -1.2, 0.7);
  const auto C = [](const Mat3& Q, const Vec3& P) { return Q.row(2).dot(P); };
  Eigen::Matrix<double, 6, 1> fd;
  for (int j = 0; j < 3; ++j) {
    const Vec3 d = kFdStep * Vec3::Unit(j);
    fd(j) = (C(R * so3::exp(d), Pi) - C(R * so3::exp(-d), Pi)) / (2.0 * kFdStep);
    fd(3 + j) = (C(R, Pi + d) - C(R, Pi - d)) / (2.0 * kFdStep);
  }
  EXPECT_LE((Pendulum3D::vertical_momentum_gradient(R, Pi) - fd).norm(), kFdTolerance * (1.0 + Pi.norm()));
}

INSTANTIATE_TEST_SUITE_P(Attitudes, PendulumAt, testing::ValuesIn(attitudes()), attitude_name);

TEST(Pendulum3D, PaperParameters) {
  const Pendulum3D p = Pendulum3D::paper();
  EXPECT_EQ(p.mass, 1.0);
  EXPECT_EQ(p.inertia.J, Mat3(Vec3(0.13, 0.28, 0.17).asDiagonal()));
  EXPECT_EQ(p.rho, Vec3(0.0, 0.0, 0.3));
  // Hanging equilibrium at R = I (rho along +e3, gravity along +e3): zero moment, minimum U.
  EXPECT_EQ(p.moment(Mat3::Identity()), Vec3::Zero());
  EXPECT_LT(p.potential(Mat3::Identity()), p.potential(so3::exp(Vec3(0.1, 0.0, 0.0))));
}

struct BadPendulum {
  std::string name;
  double m;
  Mat3 J;
  Vec3 rho;
  double g;
  std::string field;
};
std::ostream& operator<<(std::ostream& os, const BadPendulum& c) { return os << c.name; }

std::vector<BadPendulum> bad_pendulums() {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Mat3 J = Vec3(0.13, 0.28, 0.17).asDiagonal();
  const Vec3 rho(0, 0, 0.3);
  return {
      {"zero_mass", 0.0, J, rho, 9.81, "mass"},
      {"negative_mass", -1.0, J, rho, 9.81, "mass"},
      {"nan_mass", nan, J, rho, 9.81, "mass"},
      {"nan_rho", 1.0, J, Vec3(0, nan, 0.3), 9.81, "rho"},
      {"negative_gravity", 1.0, J, rho, -9.81, "gravity"},
      {"nan_gravity", 1.0, J, rho, nan, "gravity"},
      {"triangle_violating_inertia", 1.0, Vec3(1.0, 1.0, 2.1).asDiagonal(), rho, 9.81, "inertia"},
  };
}

class PendulumRejects : public testing::TestWithParam<BadPendulum> {};

TEST_P(PendulumRejects, ThrowsInvalidInputNamingTheField) {
  const BadPendulum& c = GetParam();
  try {
    const Pendulum3D p(c.m, c.J, c.rho, c.g);
    ADD_FAILURE() << "accepted " << c.name;
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.field(), c.field) << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(Parameters, PendulumRejects, testing::ValuesIn(bad_pendulums()),
                         [](const testing::TestParamInfo<BadPendulum>& i) { return i.param.name; });

// --- Dumbbell spacecraft -------------------------------------------------------------------------

struct Configuration {
  std::string name;
  Mat3 R;
  Vec3 x;
};
std::ostream& operator<<(std::ostream& os, const Configuration& c) { return os << c.name; }

std::vector<Configuration> configurations() {
  std::vector<Configuration> cases = {
      {"paper_initial", paper_R0(), Vec3(1, 0, 0)},
      {"radial_rod", Mat3::Identity(), Vec3(1, 0, 0)},
      {"tilted", so3::exp(Vec3(0.3, 0.5, -0.2)), Vec3(0.6, 0.7, 0.2)},
  };
  auto rng = test::make_rng(/*salt=*/703);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> radius(0.7, 2.0);
  for (int k = 0; k < 16; ++k) {
    const Vec3 dir = Vec3(normal(rng), normal(rng), normal(rng)).normalized();
    cases.push_back({"random_" + std::to_string(k), so3::random_rotation(rng), radius(rng) * dir});
  }
  return cases;
}

class DumbbellAt : public testing::TestWithParam<Configuration> {
 protected:
  const DumbbellSpacecraft d = DumbbellSpacecraft::paper();
  // |U| <= mu m / (|x| - |rho|) and its derivatives (in x or in eta) are bounded by that scale
  // times O(1) factors for |x| >= 0.7 >> |rho| = 0.15: the FD error is kFdTolerance relative to it.
  double scale(const Vec3& x) const { return d.mu * d.mass / (x.norm() - d.rho.norm()); }
};

// force = -dU/dx (central differences in each inertial direction).
TEST_P(DumbbellAt, ForceIsMinusPositionGradientOfPotential) {
  const auto& [name, R, x] = GetParam();
  Vec3 g;
  for (int j = 0; j < 3; ++j) {
    const Vec3 dx = kFdStep * Vec3::Unit(j);
    g(j) = (d.potential(R, x + dx) - d.potential(R, x - dx)) / (2.0 * kFdStep);
  }
  const Vec3 f = d.forces(R, x).force;
  EXPECT_LE((f + g).norm(), kFdTolerance * scale(x))
      << "f = " << f.transpose() << ", dU/dx = " << g.transpose();
}

// M = -dU/d eta (the sign derived at the top of this file).
TEST_P(DumbbellAt, MomentIsMinusRotationalGradientOfPotential) {
  // Named references, not a structured binding: clang 14 (the sanitizer build) does not let a
  // lambda capture a structured binding.
  const Mat3& R = GetParam().R;
  const Vec3& x = GetParam().x;
  const Vec3 g = fd_rotation_gradient(R, [&](const Mat3& Q) { return d.potential(Q, x); });
  const Vec3 M = d.forces(R, x).moment;
  EXPECT_LE((M + g).norm(), kFdTolerance * scale(x))
      << "M = " << M.transpose() << ", dU/deta = " << g.transpose();
}

// Eq. 13 as printed, with dU/dR by central differences.
TEST_P(DumbbellAt, MomentSatisfiesEquation13) {
  const Mat3& R = GetParam().R;
  const Vec3& x = GetParam().x;
  const Mat3 dU = fd_matrix_gradient(R, [&](const Mat3& Q) { return d.potential(Q, x); });
  const Mat3 hatM = dU.transpose() * R - R.transpose() * dU;
  EXPECT_LE((so3::hat(d.forces(R, x).moment) - hatM).norm(), kFdTolerance * scale(x));
}

INSTANTIATE_TEST_SUITE_P(Configurations, DumbbellAt, testing::ValuesIn(configurations()),
                         [](const testing::TestParamInfo<Configuration>& i) {
                           return i.param.name;
                         });

// Circular speed at r = 1 with l = |rho| = 0.15: (1 + l^2)^(-3/4) = 0.98345052 (mpmath), which the
// paper prints as 0.9835. One pow and a few flops: roundoff(1, 2).
TEST(DumbbellSpacecraft, CircularSpeedMatchesThePaper) {
  const DumbbellSpacecraft d = DumbbellSpacecraft::paper();
  const double v = d.circular_speed(1.0);
  EXPECT_NEAR(v, std::pow(1.0 + 0.15 * 0.15, -0.75), roundoff(1.0, 2));
  EXPECT_NEAR(v, 0.983450515903372, roundoff(1.0, 2));
  EXPECT_EQ(std::round(v * 1e4) / 1e4, 0.9835);
}

// That speed gives a circular orbit: at x = (1, 0, 0) with the rod along-track (R0), each
// sphere is at distance sqrt(1 + l^2) and pulled with mu m/2 / (1 + l^2); the along-track parts
// cancel, the radial parts add to mu m / (1 + l^2)^(3/2) = m v^2 / r, the centripetal force of the
// circle of radius 1 at speed v. By symmetry the moment vanishes (a relative equilibrium, the
// rod rotating with Omega = v / r about e3, the paper's Omega_0 = (0, 0, 0.9835)).
TEST(DumbbellSpacecraft, CircularSpeedGivesCircularOrbit) {
  const DumbbellSpacecraft d = DumbbellSpacecraft::paper();
  const double r = 1.0;
  const double v = d.circular_speed(r);
  const DumbbellSpacecraft::Forces f = d.forces(paper_R0(), Vec3(r, 0, 0));
  const double centripetal = d.mass * v * v / r;
  // ~10 flops on O(1) values in forces(), a pow and 2 flops in v^2.
  EXPECT_NEAR(f.force.norm() * r, centripetal, roundoff(centripetal, 12));
  EXPECT_NEAR(f.force.x(), -centripetal, roundoff(centripetal, 12));  // pointing at the centre
  EXPECT_LE(f.force.tail<2>().norm(), roundoff(centripetal, 2));
  EXPECT_LE(f.moment.norm(), roundoff(f.force.norm() * d.rho.norm(), 4));
  // Rod along-track: R0 rho points along +e2, the velocity direction.
  EXPECT_LE((paper_R0() * d.rho - d.rho.norm() * Vec3::UnitY()).norm(), roundoff(d.rho.norm()));
}

// J = m (l^2 I - rho rho^T) + (2/5) m r^2 I = diag(0.001, 0.0235, 0.0235) for the paper's
// dumbbell: positive definite thanks to the spheres' own inertia.
TEST(DumbbellSpacecraft, InertiaIsPositiveDefinite) {
  const DumbbellSpacecraft d = DumbbellSpacecraft::paper();
  const Vec3 moments = Eigen::SelfAdjointEigenSolver<Mat3>(d.inertia.J).eigenvalues();
  EXPECT_GT(moments(0), 0.0);
  EXPECT_LE((d.inertia.J - Mat3(Vec3(0.001, 0.0235, 0.0235).asDiagonal())).norm(),
            roundoff(0.0235, 4));
}

struct BadDumbbell {
  std::string name;
  double m;
  double mu;
  Vec3 rho;
  double radius;
  std::string field;
};
std::ostream& operator<<(std::ostream& os, const BadDumbbell& c) { return os << c.name; }

std::vector<BadDumbbell> bad_dumbbells() {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Vec3 rho(0.15, 0, 0);
  return {
      {"zero_mass", 0.0, 1.0, rho, 0.05, "mass"},
      {"negative_mass", -1.0, 1.0, rho, 0.05, "mass"},
      {"nan_mass", nan, 1.0, rho, 0.05, "mass"},
      {"zero_mu", 1.0, 0.0, rho, 0.05, "mu"},
      {"nan_mu", 1.0, nan, rho, 0.05, "mu"},
      {"zero_rho", 1.0, 1.0, Vec3::Zero(), 0.05, "rho"},
      {"nan_rho", 1.0, 1.0, Vec3(nan, 0, 0), 0.05, "rho"},
      {"negative_radius", 1.0, 1.0, rho, -0.05, "sphere_radius"},
      {"nan_radius", 1.0, 1.0, rho, nan, "sphere_radius"},
      // A bare rod has J singular about its axis: rejected by the inertia check.
      {"zero_radius_rod", 1.0, 1.0, rho, 0.0, "inertia (from rho and sphere_radius)"},
  };
}

class DumbbellRejects : public testing::TestWithParam<BadDumbbell> {};

TEST_P(DumbbellRejects, ThrowsInvalidInputNamingTheField) {
  const BadDumbbell& c = GetParam();
  try {
    const DumbbellSpacecraft d(c.m, c.mu, c.rho, c.radius);
    ADD_FAILURE() << "accepted " << c.name;
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.field(), c.field) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind(c.field + ": ", 0), 0u) << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(Parameters, DumbbellRejects, testing::ValuesIn(bad_dumbbells()),
                         [](const testing::TestParamInfo<BadDumbbell>& i) { return i.param.name; });

}  // namespace
}  // namespace lgvi

// --- a body in a parametric potential (lgvi/systems/potential_body.hpp) -------------------------

namespace lgvi {
namespace {

/// The attitude spring (k = 0.5 toward a 90 deg turn about (1, 1, 1)) and a dipole in a field.
std::vector<PotentialBody> potential_bodies() {
  const Mat3 J = Vec3(0.13, 0.28, 0.17).asDiagonal();
  const Mat3 target = so3::exp(M_PI / 2.0 * Vec3(1.0, 1.0, 1.0).normalized());
  return {PotentialBody(J, AttitudeSpring{0.5, target}),
          PotentialBody(J, MagneticDipole{Vec3(0.0, 0.3, 2.0), Vec3(0.05, -0.02, 0.1)})};
}

/// The field an InvalidInput from make() names, "(accepted)" when make() does not throw.
template <class Make>
std::string field_of(Make&& make) {
  try {
    make();
  } catch (const InvalidInput& e) {
    return e.field();
  }
  return "(accepted)";
}

class PotentialBodyAt : public testing::TestWithParam<Attitude> {};

// M = -dU/d eta, and eq. 13 with dU/dR by differences (both potentials are defined for any 3x3
// matrix). Every derivative of U along a rotation is bounded by its amplitude (3k for the spring,
// |m||B| for the dipole): the FD error is kFdTolerance relative to it.
TEST_P(PotentialBodyAt, MomentIsMinusRotationalGradientAndSatisfiesEquation13) {
  const Mat3 R = GetParam().R;
  for (const PotentialBody& body : potential_bodies()) {
    const double scale = std::holds_alternative<AttitudeSpring>(body.term)
                             ? 3.0 * std::get<AttitudeSpring>(body.term).stiffness
                             : std::get<MagneticDipole>(body.term).dipole.norm() *
                                   std::get<MagneticDipole>(body.term).field.norm();
    const auto U = [&](const Mat3& Q) { return body.potential(Q); };
    const Vec3 g = fd_rotation_gradient(R, U);
    EXPECT_LE((body.moment(R) + g).norm(), kFdTolerance * scale) << body.term.index();
    const Mat3 dU = fd_matrix_gradient(R, U);
    EXPECT_LE((so3::hat(body.moment(R)) - (dU.transpose() * R - R.transpose() * dU)).norm(), kFdTolerance * scale)
        << body.term.index();
  }
}
INSTANTIATE_TEST_SUITE_P(Attitudes, PotentialBodyAt, testing::ValuesIn(attitudes()), attitude_name);

// About the target the spring's moment and potential have closed forms: with R = R_t exp(hat e),
// R^T R_t = exp(-hat e), so M = -2 k (sin|e| / |e|) e and U = k (3 - tr exp(hat e)) =
// 2 k (1 - cos|e|): near the target a rotational spring of stiffness 2k about every axis. Checked
// to round-off (entries of size k, tens of operations) at |e| up to 3.
TEST(PotentialBody, SpringHasItsClosedFormAboutTheTarget) {
  const PotentialBody spring = potential_bodies()[0];
  const AttitudeSpring& s = std::get<AttitudeSpring>(spring.term);
  auto rng = test::make_rng(/*salt=*/733);
  std::uniform_real_distribution<double> angle(0.01, 3.0);
  for (int k = 0; k < 20; ++k) {
    const double a = angle(rng);
    const Vec3 e = a * so3::random_rotation(rng).col(0);
    const Mat3 R = s.target * so3::exp(e);
    EXPECT_LE((spring.moment(R) + 2.0 * s.stiffness * std::sin(a) / a * e).norm(), roundoff(2.0 * s.stiffness, 32));
    EXPECT_NEAR(spring.potential(R), 2.0 * s.stiffness * (1.0 - std::cos(a)), roundoff(3.0 * s.stiffness, 32));
  }
}

TEST(PotentialBody, RejectsABadParameterNamingIt) {
  const Mat3 J = Vec3(0.13, 0.28, 0.17).asDiagonal();
  EXPECT_EQ(field_of([&] { PotentialBody(J, AttitudeSpring{0.0, Mat3::Identity()}); }), "stiffness");
  EXPECT_EQ(field_of([&] { PotentialBody(J, AttitudeSpring{-1.0, Mat3::Identity()}); }), "stiffness");
  EXPECT_EQ(field_of([&] { PotentialBody(J, AttitudeSpring{1.0, 2.0 * Mat3::Identity()}); }), "target");
  EXPECT_EQ(field_of([&] { PotentialBody(J, AttitudeSpring{1.0, -Mat3::Identity()}); }), "target");  // det -1
  EXPECT_EQ(field_of([&] { PotentialBody(J, MagneticDipole{Vec3(NAN, 0, 0), Vec3::UnitZ()}); }), "dipole");
  EXPECT_EQ(field_of([&] { PotentialBody(J, MagneticDipole{Vec3::UnitZ(), Vec3(0, INFINITY, 0)}); }), "field");
  EXPECT_EQ(field_of([&] { PotentialBody(-J, MagneticDipole{Vec3::UnitZ(), Vec3::UnitZ()}); }), "inertia");
}

}  // namespace
}  // namespace lgvi

// --- a body on SE(3) in a parametric potential (lgvi/systems/potential_body_se3.hpp) ------------

namespace lgvi {
namespace {

/// The anchored-spring.toml scene's body and a thrown body in uniform gravity.
std::vector<PotentialBodySE3> potential_bodies_se3() {
  const Mat3 J = Vec3(0.02, 0.03, 0.04).asDiagonal();
  return {PotentialBodySE3(1.0, J, AnchoredSpring{20.0, Vec3(0.1, -0.2, 0.05), Vec3(0.0, 0.03, 0.1)}),
          PotentialBodySE3(0.35, J, UniformGravity{Vec3(0.0, 0.0, -9.81)})};
}

class PotentialBodySE3At : public testing::TestWithParam<Configuration> {};

// f = -dU/dx, M = -dU/d eta and eq. 13, by central differences, as the dumbbell's. Scale: the
// potential's size at the configuration (|x| <= 2): the spring's k (|x| + |r| + |a|)^2
// and gravity's m |g| |x|; the derivatives are bounded by the same, so the FD error is
// kFdTolerance relative to it. |d| <= |x| + |r| + |a| = |x| + 0.104 + 0.229.
TEST_P(PotentialBodySE3At, ForceAndMomentAreMinusTheGradientsOfThePotential) {
  const Mat3& R = GetParam().R;
  const Vec3& x = GetParam().x;
  for (const PotentialBodySE3& body : potential_bodies_se3()) {
    const double scale = std::holds_alternative<AnchoredSpring>(body.term)
                             ? 20.0 * std::pow(x.norm() + 0.34, 2)
                             : body.mass * 9.81 * std::max(1.0, x.norm());
    Vec3 g;
    for (int j = 0; j < 3; ++j) {
      const Vec3 dx = kFdStep * Vec3::Unit(j);
      g(j) = (body.potential(R, x + dx) - body.potential(R, x - dx)) / (2.0 * kFdStep);
    }
    const Wrench w = body.forces(R, x);
    EXPECT_LE((w.force + g).norm(), kFdTolerance * scale) << body.term.index();
    const auto U = [&](const Mat3& Q) { return body.potential(Q, x); };
    EXPECT_LE((w.moment + fd_rotation_gradient(R, U)).norm(), kFdTolerance * scale) << body.term.index();
    const Mat3 dU = fd_matrix_gradient(R, U);
    EXPECT_LE((so3::hat(w.moment) - (dU.transpose() * R - R.transpose() * dU)).norm(), kFdTolerance * scale)
        << body.term.index();
  }
}
INSTANTIATE_TEST_SUITE_P(Configurations, PotentialBodySE3At, testing::ValuesIn(configurations()),
                         [](const testing::TestParamInfo<Configuration>& i) { return i.param.name; });

// The spring is a central force about its anchor: the torque of f, applied at the attachment
// x + R r, about the anchor vanishes, (x + R r - a) x f = 0, so d/dt [(x - a) x m v + R J Omega] =
// (x - a) x f + R M = (x - a) x f + (R r) x f = 0. Checked to round-off of |d| |f| (a few flops).
TEST(PotentialBodySE3, SpringExertsNoTorqueAboutItsAnchor) {
  const PotentialBodySE3 body = potential_bodies_se3()[0];
  const AnchoredSpring& s = std::get<AnchoredSpring>(body.term);
  for (const Configuration& c : configurations()) {
    const Wrench w = body.forces(c.R, c.x);
    const Vec3 about_anchor = (c.x - s.anchor).cross(w.force) + c.R * w.moment;
    const Vec3 d = c.x + c.R * s.attachment - s.anchor;
    EXPECT_LE(about_anchor.norm(), roundoff(d.norm() * w.force.norm(), 16)) << c.name;
  }
}

TEST(PotentialBodySE3, RejectsABadParameterNamingIt) {
  const Mat3 J = Vec3(0.02, 0.03, 0.04).asDiagonal();
  const Vec3 z = Vec3::Zero();
  EXPECT_EQ(field_of([&] { PotentialBodySE3(0.0, J, UniformGravity{z}); }), "mass");
  EXPECT_EQ(field_of([&] { PotentialBodySE3(NAN, J, UniformGravity{z}); }), "mass");
  EXPECT_EQ(field_of([&] { PotentialBodySE3(1.0, -J, UniformGravity{z}); }), "inertia");
  EXPECT_EQ(field_of([&] { PotentialBodySE3(1.0, J, UniformGravity{Vec3(0, NAN, 0)}); }), "gravity");
  EXPECT_EQ(field_of([&] { PotentialBodySE3(1.0, J, AnchoredSpring{0.0, z, z}); }), "stiffness");
  EXPECT_EQ(field_of([&] { PotentialBodySE3(1.0, J, AnchoredSpring{1.0, Vec3(INFINITY, 0, 0), z}); }), "anchor");
  EXPECT_EQ(field_of([&] { PotentialBodySE3(1.0, J, AnchoredSpring{1.0, z, Vec3(0, 0, NAN)}); }), "attachment");
  EXPECT_EQ(field_of([&] { PotentialBodySE3(1.0, J, UserPotentialSE3{}); }), "potential");
  EXPECT_EQ(field_of([&] {
              PotentialBodySE3(1.0, J, UserPotentialSE3{[](const Mat3&, const Vec3&) { return 0.0; }, {}});
            }),
            "moment");
}

}  // namespace
}  // namespace lgvi
