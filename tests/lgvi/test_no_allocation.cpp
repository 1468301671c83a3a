// "No heap allocation inside a step": the global allocation functions of this test program
// count calls (allocation_counter.hpp), and whole integrations must not add to the count.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <new>
#include <vector>

#include "allocation_counter.hpp"
#include "lgvi/composition.hpp"
#include "lgvi/multibody_lgvi.hpp"
#include "lgvi_cases.hpp"

namespace lgvi::test {
namespace {

template <class Lgvi, class State, class Control>
std::size_t allocations_during(const Lgvi& lgvi, State s, Control control) {
  const std::size_t before = allocation_count();
  const Stats stats = integrate(lgvi, s, 0.0, 1e-3, 1000, control, null_observer());
  const std::size_t after = allocation_count();
  EXPECT_TRUE(stats.ok());
  return after - before;
}

TEST(LgviAllocation, StepsAllocateNothing) {
  const Pendulum3D pendulum = Pendulum3D::paper();
  const AttitudeLgvi pendulum_lgvi(pendulum);
  EXPECT_EQ(allocations_during(pendulum_lgvi, pendulum_lgvi.make_state(Mat3::Identity(), pendulum_Omega0()),
                               pendulum_control),
            0u);
  const FreeRigidBody body = free_body();
  const AttitudeLgvi body_lgvi(body);
  EXPECT_EQ(allocations_during(body_lgvi, body_lgvi.make_state(free_body_R0(), free_body_Omega0()),
                               free_body_control),
            0u);
  const DumbbellSpacecraft dumbbell = DumbbellSpacecraft::paper();
  const DumbbellLgvi dumbbell_lgvi(dumbbell);
  EXPECT_EQ(allocations_during(
                dumbbell_lgvi,
                dumbbell_lgvi.make_state(dumbbell_R0(), dumbbell_x0(), dumbbell_Omega0(), dumbbell_v0()),
                dumbbell_control),
            0u);
}

TEST(LgviAllocation, MultibodyAndComposedStepsAllocateNothing) {
  const CartPendulum cart = CartPendulum::paper();
  const CartPendulumLgvi cart_lgvi(cart);
  EXPECT_EQ(allocations_during(cart_lgvi,
                               cart_lgvi.make_state(so3::exp(Vec3(0.5, -0.3, 0.2)), Vec2(0.1, -0.2),
                                                    Vec3(1.0, -0.5, 2.0), Vec2(0.3, 0.1)),
                               [](double t) { return Vec2(std::sin(t), std::cos(t)); }),
            0u);
  const ConnectedBodies bodies = ConnectedBodies::paper();
  const ConnectedBodiesLgvi bodies_lgvi(bodies);
  EXPECT_EQ(allocations_during(bodies_lgvi,
                               bodies_lgvi.make_state(Mat3::Identity(), so3::exp(Vec3(0.3, 0.2, -0.1)),
                                                      Vec3(0.5, -0.4, 0.3), Vec3(-0.2, 0.6, 0.1)),
                               [](double t) { return Vec3(0.1 * std::sin(t), 0.0, 0.05); }),
            0u);
  const Pendulum3D pendulum = Pendulum3D::paper();
  const AttitudeLgvi base(pendulum);
  const ComposedLgvi composed(base, composition_scheme("kahan-li6"));
  EXPECT_EQ(allocations_during(composed, base.make_state(Mat3::Identity(), pendulum_Omega0()), pendulum_control),
            0u);
}

// The counter itself works (otherwise the test above could not fail).
TEST(LgviAllocation, CounterSeesAllocations) {
  const std::size_t before = allocation_count();
  void* p = ::operator new(sizeof(double));  // a direct call: not elidable like a new-expression
  ::operator delete(p);
  EXPECT_GT(allocation_count(), before);
}

// Every form is counted and freed by its own counterpart: the array and nothrow forms (std::stable_sort
// takes its temporary buffer with the nothrow new and gives it back with the sized delete; with only
// the plain forms replaced, AddressSanitizer's nothrow new met this program's delete:
// alloc-dealloc-mismatch, in test_baselines' splitting tests).
TEST(LgviAllocation, CounterSeesEveryFormAndPairsThem) {
  std::size_t before = allocation_count();
  void* p = ::operator new[](3 * sizeof(double));
  ::operator delete[](p);
  EXPECT_EQ(allocation_count(), before + 1);
  before = allocation_count();
  p = ::operator new(sizeof(double), std::nothrow);
  ::operator delete(p);
  EXPECT_EQ(allocation_count(), before + 1);
  before = allocation_count();
  p = ::operator new(64, std::align_val_t{64});
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(p) % 64, 0u);
  ::operator delete(p, std::align_val_t{64});
  EXPECT_EQ(allocation_count(), before + 1);
  std::vector<int> v = {3, 1, 2, 5, 4, 9, 8, 7, 6, 0};
  before = allocation_count();
  std::stable_sort(v.begin(), v.end());
  EXPECT_GT(allocation_count(), before);  // its buffer
  EXPECT_TRUE(std::is_sorted(v.begin(), v.end()));
}

}  // namespace
}  // namespace lgvi::test
