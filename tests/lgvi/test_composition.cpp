// Higher order by composition of the symmetric LGVI (lgvi/composition.hpp): the fitted orders
// are 4 (yoshida4, suzuki4) and 6 (kahan-li6, yoshida6) within +-0.15 on the free rigid body, the
// pendulum and the connected bodies. Step sizes are chosen in each scheme's asymptotic range and
// above round-off (finest error >= 1e-11); the reference is the same scheme at h_min / 16, whose
// error is 16^-4 (16^-6) of the finest one's.
#include <gtest/gtest.h>

#include <array>
#include <iostream>
#include <string>

#include "lgvi/composition.hpp"
#include "lgvi/multibody_lgvi.hpp"
#include "lgvi_cases.hpp"
#include "test_support.hpp"

namespace lgvi::test {
namespace {

constexpr double kCompositionOrderTolerance = 0.15;  // the acceptance band

struct SchemeCase {
  std::string scheme;
  double h_max_free_body, h_max_pendulum, h_max_bodies;
};
std::ostream& operator<<(std::ostream& os, const SchemeCase& c) { return os << c.scheme; }

template <class Base, class Make, class Distance>
double composed_order(const Base& base, const std::string& scheme, Make make, Distance distance,
                      double T, double h_max) {
  const ComposedLgvi<Base> composed(base, composition_scheme(scheme));
  auto run = [&](double h) {
    auto s = make();
    const Stats st = integrate(composed, s, 0.0, h, static_cast<std::size_t>(std::llround(T / h)),
                               zero_control<typename Base::Control>(), null_observer());
    EXPECT_TRUE(st.ok()) << st.brief();
    return s;
  };
  const auto ref = run(h_max / 128.0);
  std::array<double, 4> h{}, e{};
  for (int i = 0; i < 4; ++i) {
    h[i] = h_max / (1 << i);
    e[i] = distance(run(h[i]), ref);
  }
  const double slope = loglog_slope(h, e);
  std::cout << "[ slope    ] " << scheme << ": " << slope << " (errors " << e[0] << " .. " << e[3] << ")\n";
  return slope;
}

class Composition : public ::testing::TestWithParam<SchemeCase> {
 protected:
  double expected() const { return composition_scheme(GetParam().scheme).order; }
};

TEST_P(Composition, FreeRigidBody) {
  const FreeRigidBody body = free_body();
  const AttitudeLgvi base(body);
  const double slope = composed_order(
      base, GetParam().scheme, [&] { return base.make_state(free_body_R0(), free_body_Omega0()); },
      [&](const AttitudeState& a, const AttitudeState& b) { return attitude_distance(base, a, b); }, 2.0,
      GetParam().h_max_free_body);
  EXPECT_NEAR(slope, expected(), kCompositionOrderTolerance);
}

TEST_P(Composition, Pendulum) {
  const Pendulum3D pendulum = Pendulum3D::paper();
  const AttitudeLgvi base(pendulum);
  const double slope = composed_order(
      base, GetParam().scheme, [&] { return base.make_state(Mat3::Identity(), pendulum_Omega0()); },
      [&](const AttitudeState& a, const AttitudeState& b) { return attitude_distance(base, a, b); }, 1.0,
      GetParam().h_max_pendulum);
  EXPECT_NEAR(slope, expected(), kCompositionOrderTolerance);
}

TEST_P(Composition, ConnectedBodies) {
  const ConnectedBodies bodies = ConnectedBodies::paper();
  const ConnectedBodiesLgvi base(bodies);
  auto distance = [&](const ConnectedBodiesState& a, const ConnectedBodiesState& b) {
    return so3::log(a.R1.transpose() * b.R1).norm() + so3::log(a.R2.transpose() * b.R2).norm() +
           (a.Pi1 - b.Pi1).norm() + (a.Pi2 - b.Pi2).norm();
  };
  const double slope = composed_order(
      base, GetParam().scheme,
      [&] {
        return base.make_state(Mat3::Identity(), so3::exp(Vec3(0.3, 0.2, -0.1)), Vec3(0.5, -0.4, 0.3),
                               Vec3(-0.2, 0.6, 0.1));
      },
      distance, 2.0, GetParam().h_max_bodies);
  EXPECT_NEAR(slope, expected(), kCompositionOrderTolerance);
}

INSTANTIATE_TEST_SUITE_P(Schemes, Composition,
                         ::testing::Values(SchemeCase{"yoshida4", 0.1, 0.02, 0.05},
                                           SchemeCase{"suzuki4", 0.2, 0.04, 0.1},
                                           SchemeCase{"kahan-li6", 0.2, 0.04, 0.1},
                                           SchemeCase{"yoshida6", 0.05, 0.02, 0.05}),
                         [](const auto& info) {
                           std::string n = info.param.scheme;
                           for (char& c : n) c = (c == '-') ? '_' : c;
                           return n;
                         });

TEST(Composition, RejectsTheNonSymmetricForm) {
  const Pendulum3D pendulum = Pendulum3D::paper();
  const AttitudeLgvi printed(pendulum, LgviForm::Printed);
  EXPECT_THROW(ComposedLgvi(printed, composition_scheme("yoshida4")), InvalidInput);
  EXPECT_THROW(composition_scheme("rk4"), InvalidInput);
}

TEST(Composition, CoefficientsSumToOne) {
  for (const char* name : {"yoshida4", "suzuki4", "kahan-li6", "yoshida6"}) {
    double sum = 0.0;
    for (const double g : composition_scheme(name).gammas) sum += g;
    EXPECT_NEAR(sum, 1.0, roundoff(1.0, 9)) << name;
  }
}

}  // namespace
}  // namespace lgvi::test
