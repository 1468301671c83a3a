// integrate(): a step whose result has a non-finite entry stops the run with status
// NonFiniteState, the step, the time and the part named, and the state left at the last good
// step; and the fast-spin rotation failure names the largest admissible h.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "lgvi/integrate.hpp"
#include "lgvi/lgvi.hpp"
#include "lgvi/systems/free_rigid_body.hpp"

namespace lgvi {
namespace fake {

/// A flow map that multiplies its one number by 1e100 per step: finite for 3 steps from 1,
/// overflowing in the 4th (1e300 * 1e100 = inf).
struct GrowingState {
  double value = 1.0;
};
inline const char* non_finite_part(const GrowingState& s) { return std::isfinite(s.value) ? nullptr : "value"; }

struct GrowingFlow {
  using State = GrowingState;
  using Control = double;
  static constexpr std::size_t potential_evaluations_per_step = 1;
  RotationUpdateSummary step(const State& in, double, double, double, State& out) const {
    out.value = in.value * 1e100;
    RotationUpdateSummary s;
    s.status = RotationUpdateStatus::Converged;
    return s;
  }
};

}  // namespace fake

namespace {

TEST(Integrate, NonFiniteStateStopsTheRunAtTheStepThatOverflowed) {
  fake::GrowingState state;
  std::size_t observed = 0;
  const Stats stats = integrate(fake::GrowingFlow{}, state, 0.5, 0.25, 10, [](double) { return 0.0; },
                                [&](std::size_t k, double, const fake::GrowingState& s, const RotationUpdateSummary&) {
                                  EXPECT_TRUE(std::isfinite(s.value)) << "step " << k;
                                  ++observed;
                                  return true;
                                });
  EXPECT_EQ(stats.status, IntegrationStatus::NonFiniteState);
  EXPECT_EQ(stats.steps, 3u);
  EXPECT_EQ(stats.failed_step, 3u);  // the step 3 -> 4
  EXPECT_EQ(stats.failed_time, 0.5 + 3 * 0.25);
  EXPECT_EQ(state.value, 1e300);  // the last good step
  EXPECT_EQ(observed, 4u);        // k = 0..3
  EXPECT_FALSE(stats.ok());
  EXPECT_NE(stats.brief().find("non-finite state at step 3 (t = 1.25): value is not finite"), std::string::npos)
      << stats.brief();
}

TEST(Integrate, NamesTheNonFinitePartOfEachState) {
  AttitudeState a;
  EXPECT_EQ(non_finite_part(a), nullptr);
  a.Pi(1) = std::numeric_limits<double>::infinity();
  EXPECT_STREQ(non_finite_part(a), "Pi (body momentum)");
  RigidBodyState r;
  r.x(2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_STREQ(non_finite_part(r), "x (position)");
}

// The free body spinning about its symmetry axis with h Omega = 2: the run stops at step 0
// naming the cause and the largest admissible h = h / 2 (issue 16: "not converged in 60 Newton
// iterations" before).
TEST(Integrate, FastSymmetricSpinNamesTheLargestAdmissibleStep) {
  const FreeRigidBody body(Mat3(Vec3(1.0, 1.0, 0.1).asDiagonal()));
  const AttitudeLgvi<FreeRigidBody> lgvi(body);
  AttitudeState state = lgvi.make_state(Mat3::Identity(), Vec3(0.0, 0.0, 400.0));
  const Stats stats = integrate(lgvi, state, 0.0, 0.005, 10, zero_control<Vec3>(), null_observer());
  EXPECT_EQ(stats.status, IntegrationStatus::RotationUpdateFailed);
  EXPECT_EQ(stats.failure.status, RotationUpdateStatus::OutsideDomain);
  const std::string brief = stats.brief();
  EXPECT_NE(brief.find("no rotation solves the update"), std::string::npos) << brief;
  EXPECT_NE(brief.find("largest admissible h about 0.0025"), std::string::npos) << brief;
}

}  // namespace
}  // namespace lgvi
