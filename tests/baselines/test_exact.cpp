// The exact solutions (baselines/exact/): the free rigid body in closed form and the Lagrange top,
// each checked against what defines it and against the integrators it is meant to grade:
//  (a) conservation of energy and the momentum map (spatial momentum R J Omega; the pendulum's
//      vertical momentum e3^T R J Omega) and orthonormality of R, to round-off, up to t = 1e6;
//  (b) central differences of state(t) satisfy Euler's equation (J Omega' = J Omega x Omega + M(R))
//      and R' = R hat(Omega);
//  (c) agreement with gsl-rk8pd (Prince-Dormand 8(9)) at rtol = atol = 1e-13 over several periods;
//  (d) the LGVI converges to them at order 2, the composed yoshida4 at order 4;
// over the regimes: both sides of the intermediate-axis separatrix, near it, axisymmetric,
// near a principal axis, steady, non-diagonal J, random (seeded); for the top: looping and cusped
// nutation, released from rest (a planar swing through the bottom), spinning from the hanging
// position (through the pole), over the top, 1e-7 from the pole, non-diagonal J, random.
#include <gtest/gtest.h>

#include <iomanip>
#include <optional>
#include <sstream>
#include <variant>

#include <boost/math/quadrature/gauss.hpp>

#include "baseline_cases.hpp"
#include "baselines/exact/elliptic.hpp"
#include "baselines/exact/free_rigid_body_exact.hpp"
#include "baselines/exact/lagrange_top.hpp"
#include "lgvi/composition.hpp"
#include "lgvi/integrate.hpp"
#include "lgvi/lgvi.hpp"
#include "allocation_counter.hpp"

namespace lgvi::test {
namespace {

using baselines::ExactState;
using baselines::FreeRigidBodyExact;
using baselines::LagrangeTopExact;

// --- The cases ------------------------------------------------------------------------------------

struct ExactCase {
  std::string name;
  std::optional<FreeRigidBody> body;  ///< exactly one of body, pendulum
  std::optional<Pendulum3D> pendulum;
  Mat3 R0;
  Vec3 Omega0;
};
std::ostream& operator<<(std::ostream& os, const ExactCase& c) { return os << c.name; }

/// Calls f with the case's system (FreeRigidBody or Pendulum3D).
template <class F>
decltype(auto) with_system(const ExactCase& c, F&& f) {
  return c.body ? f(*c.body) : f(*c.pendulum);
}

Mat3 rotation_x(double angle) { return so3::exp(Vec3(angle, 0.0, 0.0)); }

ExactCase free_case(std::string name, const Mat3& J, const Mat3& R0, const Vec3& Omega0) {
  return {std::move(name), FreeRigidBody(J), std::nullopt, R0, Omega0};
}
ExactCase top_case(std::string name, const Mat3& J, const Vec3& rho, const Mat3& R0, const Vec3& Omega0) {
  return {std::move(name), std::nullopt, Pendulum3D(1.0, J, rho, 9.81), R0, Omega0};
}

std::vector<ExactCase> exact_cases() {
  const Mat3 J = Vec3(0.13, 0.28, 0.17).asDiagonal();  // principal moments: e1 smallest, e2 largest
  const Mat3 R0 = so3::exp(Vec3(0.3, -0.2, 0.5));
  const Mat3 Q = so3::exp(Vec3(0.4, -1.1, 0.7));
  const Mat3 J_top = Vec3(0.14, 0.14, 0.08).asDiagonal();
  const Vec3 rho(0.0, 0.0, 0.3);
  const Mat3 tilted = rotation_x(150.0 * M_PI / 180.0);  // symmetry axis 30 deg from upright
  const Vec3 d = Vec3(0.3, -0.5, 0.8).normalized();
  const Mat3 J_top_rotated = 0.14 * Mat3::Identity() + (0.08 - 0.14) * d * d.transpose();

  std::vector<ExactCase> c = {
      free_case("free_around_largest_axis", J, R0, Vec3(0.5, 3.0, 0.4)),    // G^2 > 2 E I2
      free_case("free_around_smallest_axis", J, R0, Vec3(3.0, 0.4, 0.5)),   // G^2 < 2 E I2
      free_case("free_near_separatrix", J, Mat3::Identity(), Vec3(0.05, 0.05, 3.0)),  // the scene: k = 0.9993
      free_case("free_axisymmetric_prolate", Vec3(0.2, 0.2, 0.3).asDiagonal(), R0, Vec3(1.0, 2.0, 3.0)),
      free_case("free_axisymmetric_oblate", Vec3(0.3, 0.3, 0.2).asDiagonal(), R0, Vec3(1.0, 2.0, 3.0)),
      free_case("free_near_principal_axis", J, R0, Vec3(1e-5, 3.0, 2e-5)),
      free_case("free_steady_spin", J, R0, Vec3(0.0, 0.0, 3.0)),
      free_case("free_nondiagonal_inertia", Q * J * Q.transpose(), R0, Vec3(1.0, -2.0, 0.5)),
      top_case("top_looping", J_top, rho, tilted, Vec3(0.5, 0.0, 40.0)),
      top_case("top_cusps", J_top, rho, tilted, Vec3(0.0, 0.0, 40.0)),
      top_case("top_from_rest", J_top, rho, rotation_x(1.0), Vec3::Zero()),
      top_case("top_spin_from_hanging", J_top, rho, Mat3::Identity(), Vec3(1.0, 2.0, 5.0)),
      top_case("top_over_the_top", J_top, rho, Mat3::Identity(), Vec3(20.0, 0.0, 3.0)),
      top_case("top_near_pole", J_top, rho, rotation_x(1e-7), Vec3(1.0, 2.0, 5.0)),
      top_case("top_sleeping", J_top, rho, Mat3::Identity(), Vec3(0.0, 0.0, 5.0)),
      top_case("top_nondiagonal_inertia", J_top_rotated, 0.3 * d, so3::exp(Vec3(0.4, 1.2, -0.3)), Vec3(1.0, -2.0, 3.0)),
  };
  // Random (seeded) bodies: principal moments in [1, 2] kg m^2 (the triangle inequality holds),
  // random axes, attitude and rates; the top with J3 in [0.3, 1.9] J1 (J3 <= 2 J1).
  std::mt19937_64 rng = make_rng(7);
  std::uniform_real_distribution<double> moment(1.0, 2.0), unit(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  const auto random_vector = [&](double scale) -> Vec3 {
    const double x = normal(rng), y = normal(rng), z = normal(rng);  // in this order, for the seed
    return scale * Vec3(x, y, z);
  };
  for (int i = 0; i < 2; ++i) {
    const Mat3 V = so3::random_rotation(rng);
    const Mat3 Jr = V * Vec3(moment(rng), moment(rng), moment(rng)).asDiagonal() * V.transpose();
    c.push_back(free_case("free_random_" + std::to_string(i), Jr, so3::random_rotation(rng), random_vector(2.0)));
  }
  for (int i = 0; i < 2; ++i) {
    const Vec3 axis = random_vector(1.0).normalized();
    const double J1 = 0.1 + 0.2 * unit(rng), J3 = J1 * (0.3 + 1.6 * unit(rng));
    const Mat3 Jr = J1 * Mat3::Identity() + (J3 - J1) * axis * axis.transpose();
    c.push_back(top_case("top_random_" + std::to_string(i), Jr, (0.1 + 0.4 * unit(rng)) * axis,
                         so3::random_rotation(rng), random_vector(3.0)));
  }
  return c;
}

// --- The exact solution of a case and its physics -------------------------------------------------

using ExactSolution = std::variant<FreeRigidBodyExact, LagrangeTopExact>;

ExactSolution make_exact(const ExactCase& c) {
  if (c.body) return FreeRigidBodyExact(c.body->inertia.J, c.R0, c.Omega0);
  return LagrangeTopExact(*c.pendulum, c.R0, c.Omega0);
}
ExactState state_at(const ExactSolution& e, double t) {
  return std::visit([t](const auto& x) { return x.state(t); }, e);
}
/// Period of the motion (of Omega for the free body, of the nutation for the top); for a steady
/// motion the period of the spin, 2 pi / |Omega0|.
double period(const ExactCase& c, const ExactSolution& e) {
  const double p = std::holds_alternative<FreeRigidBodyExact>(e) ? std::get<FreeRigidBodyExact>(e).period()
                                                                 : std::get<LagrangeTopExact>(e).nutation_period();
  return std::isfinite(p) ? p : 2.0 * M_PI / std::max(c.Omega0.norm(), 1.0);
}
/// The fastest rate of the motion w [1/s]: max |Omega| over a period and, for the pendulum, the
/// small-oscillation rate sqrt(m g |rho| / J_min).
double fastest_rate(const ExactCase& c, const ExactSolution& e) {
  double w = 0.0;
  const double T = period(c, e);
  for (int i = 0; i <= 64; ++i) w = std::max(w, state_at(e, T * i / 64.0).Omega.norm());
  if (c.pendulum) {
    const Pendulum3D& p = *c.pendulum;
    w = std::max(w, std::sqrt(p.mass * p.gravity * p.rho.norm() / p.inertia.J.eigenvalues().real().minCoeff()));
  }
  return w;
}
/// The conserved momentum map: R J Omega (free body), (0, 0, e3^T R J Omega) (pendulum).
Vec3 momentum(const ExactCase& c, const ExactState& s) {
  if (c.body) return c.body->spatial_momentum(s.R, s.Omega);
  return Vec3(0.0, 0.0, c.pendulum->vertical_momentum(s.R, s.Omega));
}
/// Omega' from Euler's equation J Omega' = J Omega x Omega + M(R) (M = 0 for the free body).
Vec3 angular_acceleration(const ExactCase& c, const ExactState& s) {
  return with_system(c, [&](const auto& sys) -> Vec3 {
    return sys.inertia.J_inverse * ((sys.inertia.J * s.Omega).cross(s.Omega) + sys.moment(s.R));
  });
}

std::string fmt(double x) {
  std::ostringstream os;
  os << std::setprecision(3) << x;
  return os.str();
}

class Exact : public ::testing::TestWithParam<ExactCase> {};

// (a) Conservation and orthonormality. state(t) costs a fixed number of operations whatever t is
// (the Jacobi argument is reduced to a half-period): Boost's special functions to a few ulp, then
// at most four 3x3 products; so each conserved quantity is a round-off, kOperations rounding steps
// deep, of its scale: energy 1/2 Omega^T J Omega + m g |rho|, momentum |J Omega|. The long times
// test that nothing grows with t.
constexpr double kOperations = 16.0;

TEST_P(Exact, ConservesEnergyMomentumAndOrthonormalityToRoundOffUpToAMillionSeconds) {
  const ExactCase& c = GetParam();
  const ExactSolution e = make_exact(c);
  const double T = period(c, e);
  const ExactState s0 = state_at(e, 0.0);
  EXPECT_LE((s0.R - c.R0).norm(), roundoff(1.0, kOperations));
  EXPECT_LE((s0.Omega - c.Omega0).norm(), roundoff(fastest_rate(c, e), kOperations));  // Omega0 may be 0
  const double E0 = with_system(c, [&](const auto& sys) { return sys.energy(s0.R, s0.Omega); });
  const double potential_scale = c.pendulum ? c.pendulum->mass * c.pendulum->gravity * c.pendulum->rho.norm() : 0.0;
  const Vec3 m0 = momentum(c, s0);
  double worst_energy = 0.0, worst_momentum = 0.0, worst_orthogonality = 0.0;
  for (const double t : {0.37 * T, 3.1 * T, 1e3 + 0.3, 1e4 + 0.7, 1e6 + 0.1, -2.3 * T}) {
    const ExactState s = state_at(e, t);
    const double kinetic = 0.5 * s.Omega.dot(with_system(c, [](const auto& sys) { return sys.inertia.J; }) * s.Omega);
    const double E = with_system(c, [&](const auto& sys) { return sys.energy(s.R, s.Omega); });
    const double p_scale = with_system(c, [&](const auto& sys) { return (sys.inertia.J * s.Omega).norm(); });
    const double de = std::abs(E - E0) / (kinetic + potential_scale);
    const double dm = (momentum(c, s) - m0).norm() / std::max(p_scale, 1e-300);
    const double orth = (s.R.transpose() * s.R - Mat3::Identity()).norm();
    worst_energy = std::max(worst_energy, de);
    worst_momentum = std::max(worst_momentum, dm);
    worst_orthogonality = std::max(worst_orthogonality, orth);
    EXPECT_LE(de, roundoff(1.0, kOperations)) << "t = " << t;
    EXPECT_LE(dm, roundoff(1.0, kOperations)) << "t = " << t;
    EXPECT_LE(orth, roundoff(1.0, kOperations)) << "t = " << t;
  }
  std::cout << "[ conserve ] " << c.name << ": energy " << fmt(worst_energy) << ", momentum " << fmt(worst_momentum)
            << ", ||R^T R - I|| " << fmt(worst_orthogonality) << " (relative, t up to 1e6; bound "
            << fmt(roundoff(1.0, kOperations)) << ")\n";
}

// (b) The time derivative. The state at t carries a rounding error ~eps (1 + w |t|) (its phases
// are rounded); central differences with step a then err by a^2 w^3 / 6 (truncation) plus
// eps (1 + w |t|) / a (rounding), balanced at a = cbrt(eps (1 + w |t|)) / w; the error is then
// ~eps^(2/3) (1 + w |t|)^(2/3) w for R' (scale w) and w^2 for Omega', asserted with the project's
// 1e3 safety factor (kFdTolerance).
TEST_P(Exact, SatisfiesEulersEquationAndTheKinematicsByCentralDifferences) {
  const ExactCase& c = GetParam();
  const ExactSolution e = make_exact(c);
  const double T = period(c, e);
  const double w = fastest_rate(c, e);
  double worst_R = 0.0, worst_Omega = 0.0;
  for (const double t : {0.1 * T, 0.77 * T, 2.3 * T, 1e3 + 0.3, 1e4 + 0.7}) {
    const double growth = 1.0 + w * std::abs(t);
    const double a = kFdStep * std::cbrt(growth) / w;
    const double tp = t + a, tm = t - a;  // the step as represented
    const ExactState s = state_at(e, t), sp = state_at(e, tp), sm = state_at(e, tm);
    const Mat3 R_dot = (sp.R - sm.R) / (tp - tm);
    const Vec3 Omega_dot = (sp.Omega - sm.Omega) / (tp - tm);
    const double tolerance = kFdTolerance * std::pow(growth, 2.0 / 3.0);
    const double eR = (R_dot - s.R * so3::hat(s.Omega)).norm() / w;
    const double eO = (Omega_dot - angular_acceleration(c, s)).norm() / (w * w);
    worst_R = std::max(worst_R, eR / tolerance);
    worst_Omega = std::max(worst_Omega, eO / tolerance);
    EXPECT_LE(eR, tolerance) << "R' = R hat(Omega) at t = " << t;
    EXPECT_LE(eO, tolerance) << "Euler's equation at t = " << t;
  }
  std::cout << "[ fd       ] " << c.name << ": w = " << fmt(w) << " 1/s, worst error / tolerance: R' " << fmt(worst_R)
            << ", Omega' " << fmt(worst_Omega) << "\n";
}

// (c) Agreement with gsl-rk8pd at rtol = atol = 1e-13 on the quaternion model over three periods
// (at most 30 s), sampled 30 times. What the solver promises (test_agreement.cpp): its local
// errors stay below rtol (1 + |y_i|) per component, so after N accepted steps the distance
// ||R - R_ref||_F + |Omega - Omega_ref| is below N rtol (1 + max |y_i|) sqrt(n), n = 7. The exact
// solution is far more accurate than that (a), so the bound is the solver's own.
constexpr double kExactReferenceRtol = 1e-13;

TEST_P(Exact, AgreesWithRk8pdToItsTolerance) {
  const ExactCase& c = GetParam();
  const ExactSolution e = make_exact(c);
  const double horizon = std::min(3.0 * period(c, e), 30.0);
  const std::vector<double> times = uniform_times(horizon, 30);
  const Trajectory tr = with_system(c, [&](const auto& sys) {
    return run_attitude("gsl-rk8pd", CoordinateModel::Quaternion, sys, nullptr, c.R0, c.Omega0, times,
                        adaptive(kExactReferenceRtol));
  });
  ASSERT_TRUE(tr.stats.ok()) << tr.stats.brief();
  double distance = 0.0, y_max = 1.0;
  for (std::size_t k = 0; k < times.size(); ++k) {
    const ExactState s = state_at(e, times[k]);
    distance = std::max(distance, state_distance(tr.R[k], tr.Omega[k], s.R, s.Omega));
    y_max = std::max(y_max, s.Omega.cwiseAbs().maxCoeff());
  }
  const double bound = static_cast<double>(tr.stats.steps) * kExactReferenceRtol * (1.0 + y_max) * std::sqrt(7.0);
  std::cout << "[ rk8pd    ] " << c.name << ": distance " << fmt(distance) << " over " << fmt(horizon) << " s ("
            << tr.stats.steps << " steps; bound " << fmt(bound) << ", ratio " << fmt(distance / bound) << ")\n";
  EXPECT_LT(distance, bound);
}

// (d) Order of the LGVI against the exact solution: the final-state error (final_error) at one
// period (at most 10 s) for h = h_max / 2^i, i = 0..3, h_max w = 0.05 (the asymptotic regime: the
// error constants are O(1) in h w), fitted by a log-log regression: 2 +- 0.1 for the symmetric
// LGVI, 4 +- 0.15 for yoshida4 (the project's bands, tests/lgvi). On the steady rotations (one
// spin period) the error is the phase of that rotation, whose per-step angle asin(h |Omega|)
// errs at the same orders.
constexpr double kOrderTolerance2 = 0.1;
constexpr double kOrderTolerance4 = 0.15;

/// max(||R - R_exact||_F, |Omega - Omega_exact| / w): Omega relative to the motion's rate w, since
/// the top released from rest is at rest again after a period.
template <class Flow, class System>
double final_error(const Flow& flow, const AttitudeLgvi<System>& base, const ExactCase& c,
                   const ExactState& exact, double w, double T, double h) {
  AttitudeState s = base.make_state(c.R0, c.Omega0);
  const auto steps = static_cast<std::size_t>(std::llround(T / h));
  const Stats st = integrate(flow, s, 0.0, T / static_cast<double>(steps), steps,
                             zero_control<typename Flow::Control>(), null_observer());
  EXPECT_TRUE(st.ok()) << st.brief();
  const Vec3 Omega = base.omega(s);
  return std::max((s.R - exact.R).norm(), (Omega - exact.Omega).norm() / w);
}

TEST_P(Exact, LgviConvergesToItAtOrderTwoAndComposedAtOrderFour) {
  const ExactCase& c = GetParam();
  const ExactSolution e = make_exact(c);
  const double T = std::min(period(c, e), 10.0);
  const double w = fastest_rate(c, e);
  const double h_max = 0.05 / w;
  const ExactState exact = state_at(e, T);
  with_system(c, [&](const auto& sys) {
    using System = std::decay_t<decltype(sys)>;
    const AttitudeLgvi<System> lgvi(sys);
    const ComposedLgvi<AttitudeLgvi<System>> yoshida4(lgvi, composition_scheme("yoshida4"));
    std::array<double, 4> h{}, e2{}, e4{};
    for (int i = 0; i < 4; ++i) {
      h[i] = h_max / (1 << i);
      e2[i] = final_error(lgvi, lgvi, c, exact, w, T, h[i]);
      e4[i] = final_error(yoshida4, lgvi, c, exact, w, T, h[i]);
    }
    const double p2 = loglog_slope(h, e2), p4 = loglog_slope(h, e4);
    std::cout << "[ order    ] " << c.name << ": lgvi " << fmt(p2) << " (errors " << fmt(e2[0]) << " .. " << fmt(e2[3])
              << "), yoshida4 " << fmt(p4) << " (" << fmt(e4[0]) << " .. " << fmt(e4[3]) << "), T = " << fmt(T)
              << " s, h w = 0.05 .. 0.00625\n";
    EXPECT_NEAR(p2, 2.0, kOrderTolerance2);
    EXPECT_NEAR(p4, 4.0, kOrderTolerance4);
  });
}

INSTANTIATE_TEST_SUITE_P(Regimes, Exact, ::testing::ValuesIn(exact_cases()),
                         [](const auto& info) { return info.param.name; });

// --- Structure and bad input ---------------------------------------------------------------------

TEST(ExactFreeBody, ClassifiesTheRegimesAndTheAxisymmetricModulus) {
  const Mat3 J = Vec3(0.13, 0.28, 0.17).asDiagonal();
  EXPECT_EQ(FreeRigidBodyExact(J, Mat3::Identity(), Vec3(0.5, 3.0, 0.4)).regime(),
            FreeRigidBodyExact::Regime::AroundLargestAxis);
  EXPECT_EQ(FreeRigidBodyExact(J, Mat3::Identity(), Vec3(3.0, 0.4, 0.5)).regime(),
            FreeRigidBodyExact::Regime::AroundSmallestAxis);
  EXPECT_EQ(FreeRigidBodyExact(J, Mat3::Identity(), Vec3(0.0, 0.0, 3.0)).regime(),
            FreeRigidBodyExact::Regime::SteadyRotation);  // the intermediate axis: unstable, but steady
  EXPECT_EQ(FreeRigidBodyExact(Vec3(0.2, 0.2, 0.3).asDiagonal(), Mat3::Identity(), Vec3(1, 2, 3)).modulus(), 0.0);
}

TEST(ExactFreeBody, RejectsTheSeparatrixAndBadInputNamingTheField) {
  const Mat3 J = Vec3(1.0, 2.0, 3.0).asDiagonal();
  // On the separatrix G^2 = 2 E I2: I3 (I3 - I2) w3^2 = I1 (I2 - I1) w1^2, i.e. 3 w3^2 = w1^2; with
  // w3 = 1 and w1 = sqrt(3) rounded the two sides agree to 1 ulp, within the 16 eps it rejects.
  const auto field = [](auto&& make) {
    try {
      make();
    } catch (const InvalidInput& e) {
      return e.field();
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(field([&] { FreeRigidBodyExact(J, Mat3::Identity(), Vec3(std::sqrt(3.0), 1.0, 1.0)); }), "Omega0");
  EXPECT_EQ(field([&] { FreeRigidBodyExact(J, 2.0 * Mat3::Identity(), Vec3(1, 2, 3)); }), "R0");
  EXPECT_EQ(field([&] { FreeRigidBodyExact(J, Mat3::Identity(), Vec3(1, NAN, 3)); }), "Omega0");
  EXPECT_EQ(field([&] { FreeRigidBodyExact(Vec3(1.0, 1.0, 3.0).asDiagonal(), Mat3::Identity(), Vec3(1, 2, 3)); }),
            "inertia");  // triangle inequality
  const FreeRigidBodyExact ok(J, Mat3::Identity(), Vec3(1, 2, 3));
  EXPECT_EQ(field([&] { (void)ok.state(INFINITY); }), "t");
}

TEST(ExactFreeBody, RejectsStatesCloserToTheSeparatrixThanItsElliptics) {
  // 1e-5 rad/s off the intermediate axis: 1 - k = 1.1e-11 < 1e-8.
  const Mat3 J = Vec3(0.13, 0.17, 0.28).asDiagonal();
  try {
    FreeRigidBodyExact(J, Mat3::Identity(), Vec3(1e-5, 3.0, 0.7e-5));
    ADD_FAILURE() << "accepted";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.field(), "Omega0");
    EXPECT_NE(std::string(e.what()).find("separatrix"), std::string::npos) << e.what();
  }
  // 1e-3 rad/s off: 1 - k = 1.1e-7, accepted.
  EXPECT_NO_THROW(FreeRigidBodyExact(J, Mat3::Identity(), Vec3(1e-3, 3.0, 0.7e-3)));
}

// The elliptic building blocks against independent computations: the integral of
// 1/(p + q sn^2) over [0, r], |r| <= K, against 30-point Gauss-Legendre quadrature on intervals
// doubling in length away from the integrand's peak at 0 (sharp for large q/p), in each of
// SnSquaredIntegral's three branches (Carlson's R_J for |q/p| <= 0.5, Boost's Pi, the peak
// asymptotics beyond q/p = 1e16); beyond K the integral's half-period property
// int_0^{r + 2K} = int_0^r + 2 int_0^K. (Quadrature around the next peak, at 2K, cannot resolve
// offsets below ulp(2K): measured 3e-13 off.) Tolerance: 64 eps relative to the scale
// 1/sqrt(p (p + q)) of the integral over the peak.
TEST(ExactElliptic, SnSquaredIntegralMatchesQuadrature) {
  using baselines::exact_detail::Jacobi;
  using baselines::exact_detail::SnSquaredIntegral;
  for (const double k : {0.0, 0.5, 0.95}) {
    const Jacobi jacobi(k);
    const double K = jacobi.quarter_period();
    for (const double ratio : {0.3, -0.3, 0.9, -0.9, 40.0, 1e10, 1e18}) {  // q / p
      const double p = 0.7, q = ratio * p;
      const SnSquaredIntegral integral(jacobi, p, q);
      const auto value = [&](double r) { return integral.mean() * r + integral.periodic(jacobi.at(r)); };
      const auto integrand = [&](double v) {
        const double sn = jacobi.at(v).sn;
        return 1.0 / (p + q * sn * sn);
      };
      const auto quadrature = [&](double r) {  // int_0^r, 0 <= r <= K
        double sum = 0.0, near = 0.0;
        for (double far = 1e-12 * r; near < r; far = std::min(r, 2.0 * far)) {
          sum += boost::math::quadrature::gauss<double, 30>::integrate(integrand, near, far);
          near = far;
        }
        return sum;
      };
      const double tolerance = 64.0 * kEps / std::sqrt(p * std::max(p + q, p)) * K;
      for (const double r : {0.3 * K, 0.999 * K, K}) {
        const double expected = quadrature(r);
        EXPECT_NEAR(value(r), expected, tolerance) << "k = " << k << ", q/p = " << ratio << ", r = " << r;
        EXPECT_NEAR(value(-r), -expected, tolerance) << "k = " << k << ", q/p = " << ratio << ", r = " << -r;
        EXPECT_NEAR(value(r + 2.0 * K), expected + 2.0 * value(K), 4.0 * tolerance) << "k = " << k << ", q/p = " << ratio;
        EXPECT_NEAR(value(r - 6.0 * K), expected - 6.0 * value(K), 8.0 * tolerance) << "k = " << k << ", q/p = " << ratio;
      }
    }
  }
}

TEST(ExactElliptic, QuarterPeriodShiftMatchesDirectEvaluation) {
  using baselines::exact_detail::Jacobi;
  for (const double k : {0.0, 0.5, 0.95}) {
    const Jacobi jacobi(k);
    const double K = jacobi.quarter_period();
    for (const double w : {0.0, 0.3, -0.4 * K, 0.999 * K, 1.3 * K, 7.7 * K, -5.2 * K}) {
      for (const int direction : {+1, -1}) {
        const auto direct = jacobi.at(w + direction * K);
        const auto shifted = jacobi.shifted(jacobi.at(w), direction);
        EXPECT_NEAR(shifted.sn, direct.sn, 8.0 * kEps) << k << " " << w << " " << direction;
        EXPECT_NEAR(shifted.cn, direct.cn, 8.0 * kEps) << k << " " << w << " " << direction;
        EXPECT_NEAR(shifted.dn, direct.dn, 8.0 * kEps) << k << " " << w << " " << direction;
        EXPECT_NEAR(shifted.r, direct.r, 8.0 * kEps * K) << k << " " << w << " " << direction;
        EXPECT_EQ(shifted.j, direct.j) << k << " " << w << " " << direction;
      }
    }
    // dn at the quarter period is k' (Boost 1.74's own dn is 4e-4 off there).
    EXPECT_NEAR(jacobi.at(K).dn, std::sqrt(1.0 - k * k), 4.0 * kEps);
  }
}

TEST(ExactLagrangeTop, RejectsAPendulumThatIsNotALagrangeTop) {
  const Pendulum3D paper = Pendulum3D::paper();  // J = diag(0.13, 0.28, 0.17): not axisymmetric
  EXPECT_FALSE(baselines::is_lagrange_top(paper));
  try {
    LagrangeTopExact(paper, Mat3::Identity(), Vec3(1, 2, 3));
    ADD_FAILURE() << "accepted the paper's pendulum";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.field(), "inertia");
    EXPECT_NE(std::string(e.what()).find("not a Lagrange top"), std::string::npos) << e.what();
  }
  // Axisymmetric about a different axis than rho: not a Lagrange top either.
  EXPECT_FALSE(baselines::is_lagrange_top(Pendulum3D(1.0, Vec3(0.14, 0.14, 0.08).asDiagonal(), Vec3(0.3, 0, 0), 9.81)));
  // Within the stated tolerance: accepted.
  const double J1 = 0.14 * (1.0 + 0.1 * baselines::kLagrangeTopTolerance);
  EXPECT_TRUE(baselines::is_lagrange_top(Pendulum3D(1.0, Vec3(J1, 0.14, 0.08).asDiagonal(), Vec3(0, 0, 0.3), 9.81)));
}

TEST(ExactLagrangeTop, WithoutGravityTorqueIsTheFreeBodyForAnyInertia) {
  const Mat3 J = Vec3(0.13, 0.28, 0.17).asDiagonal();
  const Pendulum3D weightless(1.0, J, Vec3(0, 0, 0.3), 0.0);
  EXPECT_TRUE(baselines::is_lagrange_top(weightless));
  const LagrangeTopExact top(weightless, so3::exp(Vec3(0.1, 0.2, 0.3)), Vec3(1, 2, 3));
  const FreeRigidBodyExact body(J, so3::exp(Vec3(0.1, 0.2, 0.3)), Vec3(1, 2, 3));
  EXPECT_TRUE(top.is_free_body());
  for (const double t : {0.5, 7.0}) {
    EXPECT_EQ((top.state(t).R - body.state(t).R).norm(), 0.0);
    EXPECT_EQ((top.state(t).Omega - body.state(t).Omega).norm(), 0.0);
  }
}

TEST(ExactLagrangeTop, TurningPointsBoundTheNutation) {
  // Released at rest 1 rad from the bottom: a planar pendulum between u = cos 1 and u = 1 (the
  // other side of the swing, where the axis passes under the pivot and up to cos 1 again).
  const Pendulum3D top(1.0, Vec3(0.14, 0.14, 0.08).asDiagonal(), Vec3(0, 0, 0.3), 9.81);
  const LagrangeTopExact rest(top, rotation_x(1.0), Vec3::Zero());
  EXPECT_NEAR(rest.u_min(), std::cos(1.0), 1e-15);
  EXPECT_EQ(rest.u_max(), 1.0);
  // The planar pendulum's period is 4 K(sin(1/2)) sqrt(J1 / (m g |rho|)), and the nutation period
  // half of it (u = cos(theta) repeats when theta changes sign). K by the arithmetic-geometric
  // mean, K(k) = pi / (2 agm(1, sqrt(1 - k^2))), independently of Boost.
  double a = 1.0, b = std::cos(0.5);
  for (int i = 0; i < 8; ++i) {  // quadratic convergence: 8 steps reach round-off
    const double mean = 0.5 * (a + b);
    b = std::sqrt(a * b);
    a = mean;
  }
  const double K = M_PI / (2.0 * a);
  EXPECT_NEAR(rest.nutation_period(), 2.0 * K * std::sqrt(0.14 / (9.81 * 0.3)), 1e-13);
}

TEST(ExactSolutions, EvaluateWithoutAllocating) {
  const FreeRigidBodyExact body(Vec3(0.13, 0.28, 0.17).asDiagonal(), Mat3::Identity(), Vec3(0.5, 3.0, 0.4));
  const LagrangeTopExact top(Pendulum3D(1.0, Vec3(0.14, 0.14, 0.08).asDiagonal(), Vec3(0, 0, 0.3), 9.81),
                             rotation_x(2.6), Vec3(0.5, 0.0, 40.0));
  double sink = 0.0;
  const std::size_t before = allocation_count();
  for (int i = 0; i < 100; ++i) {
    sink += body.state(0.37 * i).R(0, 0) + top.state(0.37 * i).R(0, 0);
  }
  EXPECT_EQ(allocation_count() - before, 0u) << sink;
}

}  // namespace
}  // namespace lgvi::test
