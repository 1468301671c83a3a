// The LGVI on SE(3) (RigidBodyLgvi) with a body in uniform gravity, where it reduces to two
// classical methods it must reproduce: the symmetric form's translation is velocity Verlet on a
// constant force, exact for the parabola, and its rotation is the free body's LGVI (the gravity
// exerts no moment). The typed system properties (tests/experiments/systems/
// test_system_properties.cpp) check the potential body on SE(3)'s order, momentum maps,
// reversibility and baseline agreement through its scenes.
#include <gtest/gtest.h>

#include "lgvi/integrate.hpp"
#include "lgvi/lgvi.hpp"
#include "lgvi/systems/free_rigid_body.hpp"
#include "lgvi/systems/potential_body_se3.hpp"
#include "test_support.hpp"

namespace lgvi::test {
namespace {

constexpr std::size_t kSteps = 2000;
constexpr double kH = 1e-3;

const Mat3 kInertia = Vec3(0.0012, 0.0021, 0.0030).asDiagonal();
const Vec3 kGravity(0.0, 0.0, -9.81);
const Vec3 kOmega0(0.05, 12.0, 0.05);  // about the intermediate axis: the uniform-gravity scene's flip
const Vec3 kX0(0.2, -0.1, 0.0), kV0(3.0, 0.0, 8.0);

// Symmetric form: p^+ = m v_k + h/2 m g, x_{k+1} = x_k + h p^+ / m, v_{k+1} = (p^+ + h/2 m g) / m,
// so x_k = x0 + v0 t_k + g t_k^2 / 2 and v_k = v0 + g t_k exactly; what remains is the rounding
// of k additions of terms of size |x|, |v| <= 10: 4 operations per step and component.
TEST(PotentialBodySE3Lgvi, UniformGravityFollowsTheParabolaExactly) {
  const PotentialBodySE3 body(0.35, kInertia, UniformGravity{kGravity});
  const RigidBodyLgvi lgvi(body);
  RigidBodyState s = lgvi.make_state(Mat3::Identity(), kX0, kOmega0, kV0);
  double worst_x = 0.0, worst_v = 0.0;
  const Stats stats = integrate(lgvi, s, 0.0, kH, kSteps, zero_control<Wrench>(),
                                [&](std::size_t k, double t, const RigidBodyState& x, const RotationUpdateSummary&) {
                                  (void)k;
                                  worst_x = std::max(worst_x, (x.x - (kX0 + kV0 * t + 0.5 * kGravity * t * t)).norm());
                                  worst_v = std::max(worst_v, (x.v - (kV0 + kGravity * t)).norm());
                                  return true;
                                });
  ASSERT_TRUE(stats.ok()) << stats.brief();
  EXPECT_EQ(stats.potential_evaluations, kSteps);
  EXPECT_LE(worst_x, roundoff(10.0, 4.0 * kSteps)) << "x";
  EXPECT_LE(worst_v, roundoff(10.0, 4.0 * kSteps)) << "v";
}

// The rotation is the free body's LGVI: the same rotation update on the same momentum (the SE(3)
// step forms F and multiplies, the attitude step applies it in factored form: a few ulp per step
// apart). The intermediate-axis spin amplifies differences (the flip's instability, rate about
// Omega_2 sqrt((J2 - J1)(J3 - J2) / (J1 J3)) = 6.6 /s over 2 s, e^13): the bound is per step's
// rounding times that growth, so the check runs 0.5 s (growth e^3.3 = 27).
TEST(PotentialBodySE3Lgvi, UniformGravityRotatesAsTheFreeBodyLgvi) {
  const PotentialBodySE3 body(0.35, kInertia, UniformGravity{kGravity});
  const FreeRigidBody free_body(kInertia);
  const RigidBodyLgvi se3(body);
  const AttitudeLgvi so3_flow(free_body);
  RigidBodyState a = se3.make_state(Mat3::Identity(), kX0, kOmega0, kV0);
  AttitudeState b = so3_flow.make_state(Mat3::Identity(), kOmega0);
  const std::size_t steps = 500;
  double worst = 0.0;
  for (std::size_t k = 0; k < steps; ++k) {
    ASSERT_TRUE(se3.step(a, kH, Wrench{}, Wrench{}, a).converged());
    ASSERT_TRUE(so3_flow.step(b, kH, Vec3::Zero(), Vec3::Zero(), b).converged());
    worst = std::max({worst, (a.R - b.R).norm(), (a.Pi - b.Pi).norm() / b.Pi.norm()});
  }
  EXPECT_LE(worst, 27.0 * roundoff(1.0, 4.0 * steps));
}

}  // namespace
}  // namespace lgvi::test
