// The Lie group methods (baselines/lie_group.hpp) against what their papers state:
// - reduction: on R^n with the additive action each method is its classical Runge-Kutta
//   tableau (RKMK and Crouch-Grossman: their own; the commutator-free method: RK4), to round-off;
// - order: the global error against the exact free-body and Lagrange-top solutions
//   (baselines/exact/) falls as h^p, p = 1, 2, 4, 3, 4, 4 (lie-euler, rkmk2, rkmk4, cg3, cg4, cf4),
//   the fitted slope within kOrderTolerance (0.1) of p;
// - the attitude stays on SO(3): ||R^T R - I|| <= 1e-13 after 10^5 steps;
// - rkmk45: its error follows rtol over 6 decades, its continuous extension is of order 4 (the
//   interpolation error of one step falls as h^5), and the output times do not change its steps.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <iostream>
#include <string>
#include <type_traits>
#include <vector>

#include "allocation_counter.hpp"
#include "baselines/exact/free_rigid_body_exact.hpp"
#include "baselines/exact/lagrange_top.hpp"
#include "baselines/lie_group.hpp"
#include "baselines/mechanics.hpp"
#include "lgvi/so3.hpp"
#include "lgvi/systems/free_rigid_body.hpp"
#include "lgvi/systems/pendulum.hpp"
#include "exact_cases.hpp"
#include "test_support.hpp"

namespace lgvi::test::lie_group_tests {
namespace {

namespace lg = baselines::lie_group;
using baselines::MechanicsState;

// --- Reduction to the classical tableau on R^n -----------------------------------------------

/// A mechanics with no attitude: x in R^2, w = x', a nonlinear, time-dependent, damped
/// oscillator pair: x0'' = -sin x0 + 0.3 cos t - 0.1 x0',  x1'' = -x1^3 + x0 x1'.
struct PlanarMechanics {
  static constexpr int bodies = 0;
  static constexpr int positions = 2;
  static constexpr int velocities = 2;
  using Config = baselines::Configuration<0, 2>;
  using Rate = baselines::Rates<0, 2>;
  using Velocity = baselines::Vector<2>;
  void rates(const Config& /*c*/, const Velocity& w, Rate& r) const { r.x_dot = w; }
  Velocity acceleration(double t, const Config& c, const Velocity& w) const {
    return Velocity(-std::sin(c.x(0)) + 0.3 * std::cos(t) - 0.1 * w(0), -c.x(1) * c.x(1) * c.x(1) + c.x(0) * w(1));
  }
  Velocity velocity_state(const Config& /*c*/, const std::array<Vec3, 0>& /*Omega*/, const baselines::Vector<2>& x_dot) const {
    return x_dot;
  }
  bool time_dependent() const { return true; }
};
static_assert(baselines::Mechanics<PlanarMechanics>);

using Vec4 = Eigen::Matrix<double, 4, 1>;

Vec4 planar_field(const PlanarMechanics& m, double t, const Vec4& z) {
  PlanarMechanics::Config c;
  c.x = z.head<2>();
  const PlanarMechanics::Velocity a = m.acceleration(t, c, z.tail<2>());
  Vec4 f;
  f << z.tail<2>(), a;
  return f;
}

/// One step of the classical explicit Runge-Kutta method of `Tableau` on z = (x, w).
template <class Tableau>
Vec4 classical_step(const PlanarMechanics& m, double t, double h, const Vec4& z) {
  std::array<Vec4, Tableau::stages> k;
  for (int i = 0; i < Tableau::stages; ++i) {
    Vec4 zi = z;
    for (int j = 0; j < i; ++j) zi += h * Tableau::a[i][j] * k[j];
    k[i] = planar_field(m, t + Tableau::c[i] * h, zi);
  }
  Vec4 out = z;
  for (int i = 0; i < Tableau::stages; ++i) out += h * Tableau::b[i] * k[i];
  return out;
}

template <class Flow, class Tableau>
void expect_reduces_to_classical(const char* name) {
  const PlanarMechanics mech;
  const Flow flow(mech);
  MechanicsState<PlanarMechanics> y;
  y.config.x = baselines::Vector<2>(0.7, -0.4);
  y.w = baselines::Vector<2>(0.2, 0.9);
  Vec4 z;
  z << y.config.x, y.w;
  const double h = 0.05;
  const int steps = 40;
  for (int k = 0; k < steps; ++k) {
    flow.step(y, h, k * h, (k + 1) * h, y);
    z = classical_step<Tableau>(mech, k * h, h, z);
  }
  Vec4 lie;
  lie << y.config.x, y.w;
  // Both sum the same terms in different orders: a few eps per stage term per step, on a state of
  // size <= 2 (roundoff() counts 16 eps per operation).
  const double bound = roundoff(2.0, 2.0 * Tableau::stages * steps);
  EXPECT_LE((lie - z).norm(), bound) << name << ": |lie - classical| = " << (lie - z).norm();
}

TEST(LieGroupReduction, EachMethodIsItsClassicalTableauOnRn) {
  expect_reduces_to_classical<lg::RkmkFlow<PlanarMechanics, lg::EulerTableau>, lg::EulerTableau>("lie-euler");
  expect_reduces_to_classical<lg::RkmkFlow<PlanarMechanics, lg::HeunTableau>, lg::HeunTableau>("rkmk2");
  expect_reduces_to_classical<lg::RkmkFlow<PlanarMechanics, lg::ClassicalRk4Tableau>, lg::ClassicalRk4Tableau>("rkmk4");
  expect_reduces_to_classical<lg::CrouchGrossmanFlow<PlanarMechanics, lg::CrouchGrossman3Tableau>,
                              lg::CrouchGrossman3Tableau>("cg3");
  expect_reduces_to_classical<lg::CrouchGrossmanFlow<PlanarMechanics, lg::CrouchGrossman4aTableau>,
                              lg::CrouchGrossman4aTableau>("cg4");
  expect_reduces_to_classical<lg::CommutatorFree4Flow<PlanarMechanics>, lg::ClassicalRk4Tableau>("cf4");
}

TEST(LieGroupTableaus, RowSumsAreTheNodes) {
  const auto check = [](auto tableau, const char* name) {
    using T = decltype(tableau);
    for (int i = 0; i < T::stages; ++i) {
      double sum = 0.0;
      for (int j = 0; j < i; ++j) sum += T::a[i][j];
      EXPECT_NEAR(sum, T::c[i], 2.0 * kEps) << name << " row " << i;
    }
  };
  check(lg::HeunTableau{}, "heun");
  check(lg::ClassicalRk4Tableau{}, "rk4");
  check(lg::CrouchGrossman3Tableau{}, "cg3");
  check(lg::CrouchGrossman4aTableau{}, "cg4a");
  check(lg::DormandPrince54Tableau{}, "dopri5");
}

// --- Order against exact solutions -------------------------------------------------------------

using namespace exact_cases;  // free_J, free_R0, kFreeOmega0, top, kTopOmega0 (exact_cases.hpp)

using FreeMech = baselines::AttitudeMechanics<FreeRigidBody>;
using TopMech = baselines::AttitudeMechanics<Pendulum3D>;

template <class Mech>
MechanicsState<Mech> initial_state(const Mat3& R0, const Vec3& Omega0) {
  MechanicsState<Mech> y;
  y.config.R[0] = R0;
  y.w = Omega0;
  return y;
}

template <class Mech>
double distance(const MechanicsState<Mech>& y, const baselines::ExactState& e) {
  return (y.config.R[0] - e.R).norm() + (y.w - e.Omega).norm();
}

template <template <class> class FlowOf, class Mech>
double error_at(const Mech& mech, const MechanicsState<Mech>& y0, const baselines::ExactState& exact, double T,
                int steps) {
  const FlowOf<Mech> flow(mech);
  MechanicsState<Mech> y = y0;
  const double h = T / steps;
  for (int k = 0; k < steps; ++k) flow.step(y, h, k * h, (k + 1) * h, y);
  return distance(y, exact);
}

template <class Mech> using LieEuler = lg::RkmkFlow<Mech, lg::EulerTableau>;
template <class Mech> using Rkmk2 = lg::RkmkFlow<Mech, lg::HeunTableau>;
template <class Mech> using Rkmk4 = lg::RkmkFlow<Mech, lg::ClassicalRk4Tableau>;
template <class Mech> using Cg3 = lg::CrouchGrossmanFlow<Mech, lg::CrouchGrossman3Tableau>;
template <class Mech> using Cg4 = lg::CrouchGrossmanFlow<Mech, lg::CrouchGrossman4aTableau>;
template <class Mech> using Cf4 = lg::CommutatorFree4Flow<Mech>;

/// The fitted slope of the error at T = 1 s over N, 2N, 4N, 8N steps. N is chosen per order so
/// that the finest error stays above round-off (>= 1e-11) and the coarsest in the asymptotic
/// range (h |Omega| <= 0.2).
template <template <class> class FlowOf>
void expect_order(const char* name, int order, int coarse_steps) {
  const ExactErrors e = exact_errors(
      [](const auto& mech, const Mat3& R0, const Vec3& Omega0, const baselines::ExactState& exact, double T, int n) {
        using Mech = std::decay_t<decltype(mech)>;
        return error_at<FlowOf>(mech, initial_state<Mech>(R0, Omega0), exact, T, n);
      },
      coarse_steps);
  const auto& [h, e_free, e_top] = e;
  const double s_free = loglog_slope(h, e_free), s_top = loglog_slope(h, e_top);
  std::cout << "[ slope    ] " << name << ": free body " << s_free << " (errors " << e_free[0] << " .. " << e_free[3]
            << "), Lagrange top " << s_top << " (errors " << e_top[0] << " .. " << e_top[3] << ")\n";
  EXPECT_NEAR(s_free, order, kOrderTolerance) << name << " on the free body";
  EXPECT_NEAR(s_top, order, kOrderTolerance) << name << " on the Lagrange top";
  EXPECT_GE(std::min(e_free[3], e_top[3]), 1e-11) << name << ": the finest error is too close to round-off";
}

TEST(LieGroupOrder, LieEulerIsFirstOrder) { expect_order<LieEuler>("lie-euler", 1, 400); }
TEST(LieGroupOrder, Rkmk2IsSecondOrder) { expect_order<Rkmk2>("rkmk2", 2, 100); }
TEST(LieGroupOrder, CrouchGrossman3IsThirdOrder) { expect_order<Cg3>("cg3", 3, 50); }
TEST(LieGroupOrder, Rkmk4IsFourthOrder) { expect_order<Rkmk4>("rkmk4", 4, 25); }
TEST(LieGroupOrder, CrouchGrossman4aIsFourthOrder) { expect_order<Cg4>("cg4", 4, 25); }
TEST(LieGroupOrder, CommutatorFree4IsFourthOrder) { expect_order<Cf4>("cf4", 4, 25); }

// --- On the group ------------------------------------------------------------------------------

template <template <class> class FlowOf>
double orthogonality_after(int steps, double h) {
  const FreeRigidBody body(free_J());
  const FreeMech mech(body);
  const FlowOf<FreeMech> flow(mech);
  auto y = initial_state<FreeMech>(free_R0(), kFreeOmega0);
  for (int k = 0; k < steps; ++k) flow.step(y, h, k * h, (k + 1) * h, y);
  return so3::orthogonality_error(y.config.R[0]);
}

// Each step updates R once (RKMK: R exp(theta); Crouch-Grossman and commutator-free: R + R D, their
// product of exponentials accumulated as I + D), a rounding of ~eps per entry that keeps R
// orthogonal to that rounding: a random walk over 10^5 steps predicts ~sqrt(1e5) eps ~ 7e-14 for
// ||R^T R - I||_F, which the bound 1e-13 holds. h = 1e-3 (100 s): Lie-Euler's energy grows
// by a factor (1 + h^2 |Omega|^2)^(N/2) (exp(0.45) here; at h = 1e-2 it overflows).
TEST(LieGroupGeometry, AttitudeStaysOnSO3For1e5Steps) {
  const int steps = 100000;
  const double h = 1e-3;
  const std::vector<std::pair<const char*, double>> measured = {
      {"lie-euler", orthogonality_after<LieEuler>(steps, h)}, {"rkmk2", orthogonality_after<Rkmk2>(steps, h)},
      {"rkmk4", orthogonality_after<Rkmk4>(steps, h)},        {"cg3", orthogonality_after<Cg3>(steps, h)},
      {"cg4", orthogonality_after<Cg4>(steps, h)},            {"cf4", orthogonality_after<Cf4>(steps, h)}};
  for (const auto& [name, err] : measured) {
    std::cout << "[ ortho    ] " << name << ": ||R^T R - I|| = " << err << " after 1e5 steps\n";
    EXPECT_LE(err, 1e-13) << name;
  }
}

// The free body's field reads no attitude (AttitudeMechanics::attitude_unread), so its stages
// form none (baselines/lie_group.hpp, field_reads_attitudes). The same mechanics told that its
// field reads them forms every stage attitude: the steps must agree to the bit (the skipped
// attitudes are never read), over 200 steps of each method.
struct FreeMechFormingStageAttitudes : FreeMech {
  using FreeMech::FreeMech;
  bool attitude_unread() const { return false; }
};

template <template <class> class FlowOf>
void expect_same_steps_with_and_without_stage_attitudes(const char* name) {
  const FreeRigidBody body(free_J());
  const FreeMech skipping(body);
  const FreeMechFormingStageAttitudes forming(body);
  ASSERT_FALSE(lg::field_reads_attitudes(skipping));
  ASSERT_TRUE(lg::field_reads_attitudes(forming));
  auto a = initial_state<FreeMech>(free_R0(), kFreeOmega0);
  auto b = initial_state<FreeMechFormingStageAttitudes>(free_R0(), kFreeOmega0);
  const FlowOf<FreeMech> fa(skipping);
  const FlowOf<FreeMechFormingStageAttitudes> fb(forming);
  const double h = 0.05;
  for (int k = 0; k < 200; ++k) {
    fa.step(a, h, k * h, (k + 1) * h, a);
    fb.step(b, h, k * h, (k + 1) * h, b);
  }
  EXPECT_TRUE(a.config.R[0] == b.config.R[0]) << name;
  EXPECT_TRUE(a.w == b.w) << name;
}

TEST(LieGroupGeometry, StagesWithoutAttitudesGiveTheSameSteps) {
  expect_same_steps_with_and_without_stage_attitudes<Rkmk4>("rkmk4");
  expect_same_steps_with_and_without_stage_attitudes<Rkmk2>("rkmk2");
  expect_same_steps_with_and_without_stage_attitudes<Cg3>("cg3");
  expect_same_steps_with_and_without_stage_attitudes<Cg4>("cg4");
  expect_same_steps_with_and_without_stage_attitudes<Cf4>("cf4");
  // The Lagrange top's gravity moment reads R: its stages form their attitudes.
  EXPECT_TRUE(lg::field_reads_attitudes(TopMech(top())));
}

// A step allocates nothing (std::array and fixed-size Eigen only): the global operator new is not
// called over 100 steps of each method on the Lagrange top.
TEST(LieGroupGeometry, AStepAllocatesNothing) {
  const TopMech mech(top());
  const auto count_for = [&](auto flow) {
    auto y = initial_state<TopMech>(Mat3::Identity(), kTopOmega0);
    const std::size_t before = allocation_count();
    for (int k = 0; k < 100; ++k) flow.step(y, 0.01, k * 0.01, (k + 1) * 0.01, y);
    return allocation_count() - before;
  };
  EXPECT_EQ(count_for(LieEuler<TopMech>(mech)), 0u);
  EXPECT_EQ(count_for(Rkmk4<TopMech>(mech)), 0u);
  EXPECT_EQ(count_for(Cg4<TopMech>(mech)), 0u);
  EXPECT_EQ(count_for(Cf4<TopMech>(mech)), 0u);
}

// --- rkmk45 ------------------------------------------------------------------------------------

struct AdaptiveRun {
  Stats stats;
  std::vector<MechanicsState<FreeMech>> samples;
};

AdaptiveRun run_rkmk45(const std::vector<double>& times, double rtol, double initial_step = 0.0) {
  static const FreeRigidBody body(free_J());
  static const FreeMech mech(body);
  lg::Rkmk45Settings s;
  s.rtol = rtol;
  s.atol = rtol;
  s.initial_step = initial_step;
  AdaptiveRun r;
  r.stats = lg::integrate_rkmk45(mech, initial_state<FreeMech>(free_R0(), kFreeOmega0), times, s,
                                 [&](std::size_t, double, const auto& y) {
                                   r.samples.push_back(y);
                                   return true;
                                 });
  return r;
}

// Global error with the error per step controlled to rtol (local extrapolation: the fifth-order
// solution is kept) is proportional to rtol (HNW II.4): over rtol = 1e-4 .. 1e-10 the fitted
// slope of log error against log rtol is 1 within 0.15, and every error is within
// [1e-2, kSensGlobalErrorPerRtol] rtol (the global-error range test_support.hpp states).
TEST(Rkmk45, ErrorFollowsRtolOverSixDecades) {
  const double T = 10.0;
  const baselines::FreeRigidBodyExact exact(free_J(), free_R0(), kFreeOmega0);
  const baselines::ExactState at_T = exact.state(T);
  std::vector<double> rtols, errors;
  for (int p = 4; p <= 10; ++p) {
    const double rtol = std::pow(10.0, -p);
    const AdaptiveRun r = run_rkmk45({0.0, T}, rtol);
    ASSERT_TRUE(r.stats.ok()) << r.stats.brief();
    const double e = distance(r.samples.back(), at_T);
    std::cout << "[ rtol     ] rkmk45 rtol " << rtol << ": error " << e << ", " << r.stats.steps << " steps, "
              << r.stats.rejected_steps << " rejected, " << r.stats.rhs_evaluations << " evaluations\n";
    EXPECT_GE(e, 1e-2 * rtol);
    EXPECT_LE(e, kSensGlobalErrorPerRtol * rtol);
    rtols.push_back(rtol);
    errors.push_back(e);
  }
  EXPECT_NEAR(loglog_slope(rtols, errors), 1.0, 0.15);
}

TEST(Rkmk45, OutputTimesDoNotChangeTheSteps) {
  std::vector<double> fine, coarse;
  for (int i = 0; i <= 100; ++i) fine.push_back(0.1 * i);
  for (int i = 0; i <= 10; ++i) coarse.push_back(1.0 * i);
  coarse.back() = fine.back();
  const AdaptiveRun a = run_rkmk45(fine, 1e-8), b = run_rkmk45(coarse, 1e-8);
  ASSERT_TRUE(a.stats.ok() && b.stats.ok());
  EXPECT_EQ(a.stats.steps, b.stats.steps);
  EXPECT_EQ(a.stats.rejected_steps, b.stats.rejected_steps);
  EXPECT_EQ(a.stats.rhs_evaluations, b.stats.rhs_evaluations);
  for (int i = 0; i <= 10; ++i) {  // the shared times: the same interpolant, the same sample
    EXPECT_EQ(a.samples[10 * i].config.R[0], b.samples[i].config.R[0]) << "t = " << coarse[i];
    EXPECT_EQ(a.samples[10 * i].w, b.samples[i].w) << "t = " << coarse[i];
  }
}

// One accepted step of size h from t = 0 (tolerances loose enough that it is accepted), the
// state at h/2 read off the continuous extension: its error against the exact solution is the
// interpolant's local error, O(h^5) for a fourth-order extension (a cubic Hermite in the chart
// would give h^4). The slope over h = 0.2 .. 0.025 must be 5 within 0.3, wider than
// kOrderTolerance because at the coarse end the next term of the interpolation error still
// enters (h |Omega| = 0.6).
TEST(Rkmk45, ContinuousExtensionIsFourthOrder) {
  const baselines::FreeRigidBodyExact exact(free_J(), free_R0(), kFreeOmega0);
  std::array<double, 4> h{}, e{};
  for (int i = 0; i < 4; ++i) {
    h[i] = 0.2 / (1 << i);
    const AdaptiveRun r = run_rkmk45({0.0, 0.5 * h[i], h[i]}, 1.0, h[i]);
    ASSERT_TRUE(r.stats.ok()) << r.stats.brief();
    ASSERT_EQ(r.stats.steps, 1u);
    e[i] = distance(r.samples[1], exact.state(0.5 * h[i]));
  }
  const double slope = loglog_slope(h, e);
  std::cout << "[ slope    ] rkmk45 continuous extension: " << slope << " (errors " << e[0] << " .. " << e[3] << ")\n";
  EXPECT_NEAR(slope, 5.0, 0.3);
}

TEST(Rkmk45, StaysOnTheGroupAtInterpolatedTimes) {
  std::vector<double> times;
  for (int i = 0; i <= 1000; ++i) times.push_back(0.1 * i);
  const AdaptiveRun r = run_rkmk45(times, 1e-6);
  ASSERT_TRUE(r.stats.ok());
  double worst = 0.0;
  for (const auto& y : r.samples) worst = std::max(worst, so3::orthogonality_error(y.config.R[0]));
  EXPECT_LE(worst, 1e-13);
}

TEST(Rkmk45, RejectsBadTolerancesAndTimes) {
  EXPECT_THROW(run_rkmk45({0.0, 1.0}, 0.0), InvalidInput);
  EXPECT_THROW(run_rkmk45({0.0, 1.0}, std::nan("")), InvalidInput);
  EXPECT_THROW(run_rkmk45({0.0, 0.0}, 1e-6), InvalidInput);
}

}  // namespace
}  // namespace lgvi::test::lie_group_tests
