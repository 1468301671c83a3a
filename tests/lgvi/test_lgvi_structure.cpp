// Structure preserved by the LGVI over long horizons (the "Structure" block):
// orthogonality, momentum maps (with and without symmetric control), bounded energy without
// drift, time reversibility of the symmetric form.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "lgvi_cases.hpp"
#include "test_support.hpp"

namespace lgvi::test {
namespace {

// kOrthogonalityBound, kMomentumRelativeBound: the long runs' bounds (test_support.hpp).

struct LongRun {
  double max_orthogonality = 0.0;
  double max_momentum_drift = 0.0;  // relative to |momentum_0|
  std::vector<double> energy_error;  // E_k - E_0, every step
};

LongRun run_pendulum(bool controlled, std::size_t steps, double h) {
  const Pendulum3D pendulum = Pendulum3D::paper();
  const AttitudeLgvi lgvi(pendulum);
  auto s = lgvi.make_state(Mat3::Identity(), pendulum_Omega0());
  const double m0 = pendulum.vertical_momentum(s.R, lgvi.omega(s));
  const double E0 = pendulum.energy(s.R, lgvi.omega(s));
  LongRun out;
  out.energy_error.reserve(steps + 1);
  auto observer = [&](std::size_t, double, const AttitudeState& x, const RotationUpdateSummary&) {
    out.max_orthogonality = std::max(out.max_orthogonality, so3::orthogonality_error(x.R));
    // e3^T R Pi: the momentum map evaluated on the carried momentum Pi = J Omega.
    out.max_momentum_drift = std::max(out.max_momentum_drift, std::abs(x.R.row(2).dot(x.Pi) - m0));
    out.energy_error.push_back(pendulum.energy(x.R, lgvi.omega(x)) - E0);
    return true;
  };
  const Stats stats =
      controlled ? integrate(lgvi, s, 0.0, h, steps, pendulum_control, observer)
                 : integrate(lgvi, s, 0.0, h, steps, zero_control<Vec3>(), observer);
  EXPECT_TRUE(stats.ok()) << stats.brief();
  EXPECT_EQ(stats.potential_evaluations, steps);  // one potential evaluation per step
  std::cout << "[ stats    ] " << stats.brief() << "\n";
  out.max_momentum_drift /= std::abs(m0);
  return out;
}

TEST(LgviStructure, PendulumMillionStepsUncontrolled) {
  const LongRun r = run_pendulum(false, 1'000'000, 1e-3);
  std::cout << "[ measured ] orthogonality " << r.max_orthogonality << ", momentum drift "
            << r.max_momentum_drift << "\n";
  EXPECT_LE(r.max_orthogonality, kOrthogonalityBound);
  EXPECT_LE(r.max_momentum_drift, kMomentumRelativeBound);

  // No energy drift: the mean energy error over the last tenth lies inside the band
  // [min, max] that the energy error oscillates in during the first tenth.
  const std::size_t n = r.energy_error.size(), tenth = n / 10;
  const auto first = r.energy_error.begin(), last = r.energy_error.end();
  const auto [lo, hi] = std::minmax_element(first, first + tenth);
  double mean_last = 0.0;
  for (auto it = last - tenth; it != last; ++it) mean_last += *it;
  mean_last /= static_cast<double>(tenth);
  std::cout << "[ measured ] energy band first tenth [" << *lo << ", " << *hi
            << "], mean last tenth " << mean_last << "\n";
  EXPECT_GE(mean_last, *lo);
  EXPECT_LE(mean_last, *hi);
}

TEST(LgviStructure, PendulumMillionStepsWithSymmetricControl) {
  const LongRun r = run_pendulum(true, 1'000'000, 1e-3);
  std::cout << "[ measured ] orthogonality " << r.max_orthogonality << ", momentum drift "
            << r.max_momentum_drift << "\n";
  EXPECT_LE(r.max_orthogonality, kOrthogonalityBound);
  EXPECT_LE(r.max_momentum_drift, kMomentumRelativeBound);
}

// Free body: the spatial angular momentum R Pi is conserved exactly by the map
// (R_{k+1} Pi_{k+1} = R_k F F^T Pi_k), so only round-off remains; 1e5 steps.
TEST(LgviStructure, FreeBodySpatialMomentum) {
  const FreeRigidBody body = free_body();
  const AttitudeLgvi lgvi(body);
  auto s = lgvi.make_state(free_body_R0(), free_body_Omega0());
  const Vec3 m0 = s.R * s.Pi;
  double drift = 0.0, orth = 0.0;
  integrate(lgvi, s, 0.0, 0.01, 100'000, zero_control<Vec3>(),
            [&](std::size_t, double, const AttitudeState& x, const RotationUpdateSummary&) {
              drift = std::max(drift, (x.R * x.Pi - m0).norm());
              orth = std::max(orth, so3::orthogonality_error(x.R));
              return true;
            });
  std::cout << "[ measured ] spatial momentum drift " << drift / m0.norm() << ", orthogonality "
            << orth << "\n";
  EXPECT_LE(drift / m0.norm(), kMomentumRelativeBound);
  EXPECT_LE(orth, kOrthogonalityBound);
}

// Dumbbell: the central field is invariant under rotations about the central body, so the
// total angular momentum x x m v + R Pi is a discrete momentum map of the symmetric form
// (velocity-Verlet translation, LGVI attitude); 1e5 steps over ~160 orbits.
TEST(LgviStructure, DumbbellTotalAngularMomentumAndEnergy) {
  const DumbbellSpacecraft dumbbell = DumbbellSpacecraft::paper();
  const DumbbellLgvi lgvi(dumbbell);
  auto s = lgvi.make_state(dumbbell_R0(), dumbbell_x0(), dumbbell_Omega0(), dumbbell_v0());
  auto momentum = [&](const RigidBodyState& x) {
    return Vec3(x.x.cross(dumbbell.mass * x.v) + x.R * x.Pi);
  };
  const Vec3 m0 = momentum(s);
  const double E0 = dumbbell.energy(s.R, s.x, lgvi.omega(s), s.v);
  double drift = 0.0, orth = 0.0;
  std::vector<double> energy_error;
  const Stats stats = integrate(lgvi, s, 0.0, 0.01, 100'000, zero_control<DumbbellSpacecraft::Control>(),
            [&](std::size_t, double, const RigidBodyState& x, const RotationUpdateSummary&) {
              drift = std::max(drift, (momentum(x) - m0).norm());
              orth = std::max(orth, so3::orthogonality_error(x.R));
              energy_error.push_back(dumbbell.energy(x.R, x.x, lgvi.omega(x), x.v) - E0);
              return true;
            });
  ASSERT_TRUE(stats.ok()) << stats.brief();
  std::cout << "[ measured ] total angular momentum drift " << drift / m0.norm()
            << ", orthogonality " << orth << "\n";
  EXPECT_LE(drift / m0.norm(), kMomentumRelativeBound);
  EXPECT_LE(orth, kOrthogonalityBound);
  const std::size_t n = energy_error.size(), tenth = n / 10;
  const auto [lo, hi] = std::minmax_element(energy_error.begin(), energy_error.begin() + tenth);
  double mean_last = 0.0;
  for (std::size_t i = n - tenth; i < n; ++i) mean_last += energy_error[i];
  mean_last /= static_cast<double>(tenth);
  std::cout << "[ measured ] energy band first tenth [" << *lo << ", " << *hi
            << "], mean last tenth " << mean_last << "\n";
  EXPECT_GE(mean_last, *lo);
  EXPECT_LE(mean_last, *hi);
}

// Time reversibility of the uncontrolled symmetric flow: n steps with h then n steps with -h
// return to the start. Round-off grows like sqrt(2n) eps per step at worst linearly, 2n eps
// ~ 4e-13 for n = 1e3, inside the 1e-12.
constexpr double kReversibilityBound = 1e-12;

TEST(LgviStructure, PendulumTimeReversible) {
  const Pendulum3D pendulum = Pendulum3D::paper();
  const AttitudeLgvi lgvi(pendulum);
  const auto s0 = lgvi.make_state(Mat3::Identity(), pendulum_Omega0());
  auto s = s0;
  ASSERT_TRUE(integrate(lgvi, s, 0.0, 1e-3, 1000, zero_control<Vec3>(), null_observer()).ok());
  ASSERT_TRUE(integrate(lgvi, s, 1.0, -1e-3, 1000, zero_control<Vec3>(), null_observer()).ok());
  const double error = (s.R - s0.R).norm() + (s.Pi - s0.Pi).norm();
  std::cout << "[ measured ] return error " << error << "\n";
  EXPECT_LE(error, kReversibilityBound);
}

TEST(LgviStructure, DumbbellTimeReversible) {
  const DumbbellSpacecraft dumbbell = DumbbellSpacecraft::paper();
  const DumbbellLgvi lgvi(dumbbell);
  const auto s0 = lgvi.make_state(dumbbell_R0(), dumbbell_x0(), dumbbell_Omega0(), dumbbell_v0());
  auto s = s0;
  const auto u = zero_control<DumbbellSpacecraft::Control>();
  ASSERT_TRUE(integrate(lgvi, s, 0.0, 1e-2, 1000, u, null_observer()).ok());
  ASSERT_TRUE(integrate(lgvi, s, 10.0, -1e-2, 1000, u, null_observer()).ok());
  const double error =
      (s.R - s0.R).norm() + (s.x - s0.x).norm() + (s.Pi - s0.Pi).norm() + (s.v - s0.v).norm();
  std::cout << "[ measured ] return error " << error << "\n";
  EXPECT_LE(error, kReversibilityBound);
}

// The printed form is not self-adjoint: stepping back with -h does not return (its error is
// first order in h), which is what tells the two forms apart structurally.
TEST(LgviStructure, PrintedFormIsNotTimeReversible) {
  const Pendulum3D pendulum = Pendulum3D::paper();
  const AttitudeLgvi lgvi(pendulum, LgviForm::Printed);
  const auto s0 = lgvi.make_state(Mat3::Identity(), pendulum_Omega0());
  auto s = s0;
  integrate(lgvi, s, 0.0, 1e-3, 1000, zero_control<Vec3>(), null_observer());
  integrate(lgvi, s, 1.0, -1e-3, 1000, zero_control<Vec3>(), null_observer());
  EXPECT_GT((s.R - s0.R).norm() + (s.Pi - s0.Pi).norm(), 1e3 * kReversibilityBound);
}

}  // namespace
}  // namespace lgvi::test
