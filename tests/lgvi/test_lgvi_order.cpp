// Order of accuracy of the LGVI flow maps: the global error at a fixed time T against a much
// finer reference, over 4 step sizes h, h/2, h/4, h/8, fitted by a log-log regression.
//  - symmetric form: slope 2 +- 0.1 (self-adjoint discrete Lagrangian),
//  - printed form (eqs. 8-12, 21-23): slope 1 +- 0.1 (potential and control at one end).
// The reference is the symmetric form at h_ref = h_min / 16: its error is (1/16)^2 = 1/256 of
// the finest symmetric error, so it shifts the fitted slope by less than 0.01.
// The free body has no potential; its printed form differs only in where the control enters,
// so the free-body cases run with a smooth control (otherwise both forms coincide).
#include <gtest/gtest.h>

#include <array>
#include <iostream>
#include <functional>
#include <string>

#include "lgvi_cases.hpp"
#include "test_support.hpp"

namespace lgvi::test {
namespace {


struct OrderCase {
  std::string name;
  double T;       // horizon
  double h_max;   // coarsest step
  bool control;
};

template <class Lgvi, class MakeState, class Control, class Distance>
std::array<double, 4> errors(const Lgvi& lgvi, const Lgvi& reference, MakeState make_state,
                             Control control, Distance distance, const OrderCase& c) {
  auto run = [&](const Lgvi& integrator, double h) {
    auto s = make_state();
    const auto steps = static_cast<std::size_t>(std::llround(c.T / h));
    const Stats stats = integrate(integrator, s, 0.0, h, steps, control, null_observer());
    EXPECT_TRUE(stats.ok()) << stats.brief();
    return s;
  };
  const auto ref = run(reference, c.h_max / 8.0 / 16.0);
  std::array<double, 4> e{};
  for (int i = 0; i < 4; ++i) e[i] = distance(lgvi, run(lgvi, c.h_max / (1 << i)), ref);
  return e;
}

void expect_order(const std::array<double, 4>& e, double h_max, double expected) {
  const std::array<double, 4> h{h_max, h_max / 2, h_max / 4, h_max / 8};
  const double slope = loglog_slope(h, e);
  std::cout << "[ slope    ] " << slope << " (expected " << expected << ")\n";
  EXPECT_NEAR(slope, expected, kOrderTolerance)
      << "errors " << e[0] << ", " << e[1] << ", " << e[2] << ", " << e[3];
}

class LgviOrder : public ::testing::TestWithParam<LgviForm> {
 protected:
  double expected() const { return GetParam() == LgviForm::Symmetric ? 2.0 : 1.0; }
};

TEST_P(LgviOrder, FreeRigidBodyWithControl) {
  const FreeRigidBody body = free_body();
  const AttitudeLgvi lgvi(body, GetParam()), reference(body, LgviForm::Symmetric);
  const OrderCase c{"free body", 2.0, 0.02, true};
  const auto e = errors(
      lgvi, reference, [&] { return lgvi.make_state(free_body_R0(), free_body_Omega0()); },
      free_body_control, attitude_distance<AttitudeLgvi<FreeRigidBody>>, c);
  expect_order(e, c.h_max, expected());
}

TEST_P(LgviOrder, PendulumUncontrolled) {
  const Pendulum3D pendulum = Pendulum3D::paper();
  const AttitudeLgvi lgvi(pendulum, GetParam()), reference(pendulum, LgviForm::Symmetric);
  const OrderCase c{"pendulum", 1.0, 0.01, false};
  const auto e = errors(
      lgvi, reference, [&] { return lgvi.make_state(Mat3::Identity(), pendulum_Omega0()); },
      zero_control<Vec3>(), attitude_distance<AttitudeLgvi<Pendulum3D>>, c);
  expect_order(e, c.h_max, expected());
}

TEST_P(LgviOrder, PendulumWithControl) {
  const Pendulum3D pendulum = Pendulum3D::paper();
  const AttitudeLgvi lgvi(pendulum, GetParam()), reference(pendulum, LgviForm::Symmetric);
  const OrderCase c{"pendulum controlled", 1.0, 0.01, true};
  const auto e = errors(
      lgvi, reference, [&] { return lgvi.make_state(Mat3::Identity(), pendulum_Omega0()); },
      pendulum_control, attitude_distance<AttitudeLgvi<Pendulum3D>>, c);
  expect_order(e, c.h_max, expected());
}

TEST_P(LgviOrder, DumbbellUncontrolled) {
  const DumbbellSpacecraft dumbbell = DumbbellSpacecraft::paper();
  const DumbbellLgvi lgvi(dumbbell, GetParam()), reference(dumbbell, LgviForm::Symmetric);
  const OrderCase c{"dumbbell", 2.0, 0.04, false};
  const auto e = errors(
      lgvi, reference,
      [&] { return lgvi.make_state(dumbbell_R0(), dumbbell_x0(), dumbbell_Omega0(), dumbbell_v0()); },
      zero_control<DumbbellSpacecraft::Control>(), rigid_distance, c);
  expect_order(e, c.h_max, expected());
}

TEST_P(LgviOrder, DumbbellWithControl) {
  const DumbbellSpacecraft dumbbell = DumbbellSpacecraft::paper();
  const DumbbellLgvi lgvi(dumbbell, GetParam()), reference(dumbbell, LgviForm::Symmetric);
  const OrderCase c{"dumbbell controlled", 2.0, 0.04, true};
  const auto e = errors(
      lgvi, reference,
      [&] { return lgvi.make_state(dumbbell_R0(), dumbbell_x0(), dumbbell_Omega0(), dumbbell_v0()); },
      dumbbell_control, rigid_distance, c);
  expect_order(e, c.h_max, expected());
}

INSTANTIATE_TEST_SUITE_P(Forms, LgviOrder,
                         ::testing::Values(LgviForm::Symmetric, LgviForm::Printed),
                         [](const auto& info) { return std::string(to_string(info.param)); });

// Without potential and control the two forms are the same map: the printed form is not
// "accidentally" first order through some other term.
TEST(LgviForms, CoincideForTheUncontrolledFreeBody) {
  const FreeRigidBody body = free_body();
  const AttitudeLgvi symmetric(body, LgviForm::Symmetric), printed(body, LgviForm::Printed);
  auto a = symmetric.make_state(free_body_R0(), free_body_Omega0());
  auto b = printed.make_state(free_body_R0(), free_body_Omega0());
  integrate(symmetric, a, 0.0, 0.01, 100, zero_control<Vec3>(), null_observer());
  integrate(printed, b, 0.0, 0.01, 100, zero_control<Vec3>(), null_observer());
  EXPECT_EQ(a.R, b.R);
  EXPECT_EQ(a.Pi, b.Pi);
}

}  // namespace
}  // namespace lgvi::test
