// Controls as functions of time from samples (baselines/control.hpp), and the replay of a control
// found on the LGVI grid on a baseline.
#include <gtest/gtest.h>

#include <array>

#include "baseline_cases.hpp"
#include "baselines/control.hpp"
#include "lgvi/integrate.hpp"
#include "lgvi/lgvi.hpp"

namespace lgvi::test {
namespace {

using baselines::Interpolation;
using baselines::SampledControl;

/// u(t) = (sin 3t, cos 2t, sin(t + 1)): |u''| <= 9, |u''''| <= 81.
Vec3 smooth(double t) { return Vec3(std::sin(3 * t), std::cos(2 * t), std::sin(t + 1)); }

SampledControl<3> sample(double dt, double T, Interpolation kind) {
  std::vector<double> t;
  std::vector<Vec3> u;
  for (double s = 0.0; s <= T + 1e-12; s += dt) {
    t.push_back(s);
    u.push_back(smooth(s));
  }
  return SampledControl<3>(t, u, kind);
}

TEST(SampledControl, InterpolationErrorsMatchTheirBounds) {
  const double T = 2.0;
  for (const double dt : {0.1, 0.05}) {
    const SampledControl<3> linear = sample(dt, T, Interpolation::PiecewiseLinear);
    const SampledControl<3> spline = sample(dt, T, Interpolation::CubicSpline);
    double e_linear = 0.0, e_spline = 0.0;
    for (double t = 0.0; t <= T; t += 0.001) {
      e_linear = std::max(e_linear, (linear(t) - smooth(t)).cwiseAbs().maxCoeff());
      // The natural end conditions (u'' = 0) cost O(dt^2) near the ends: judge the interior.
      if (t > 0.5 && t < T - 0.5) e_spline = std::max(e_spline, (spline(t) - smooth(t)).cwiseAbs().maxCoeff());
    }
    // Linear: dt^2 / 8 max|u''|. Spline (interior): 5/384 dt^4 max|u''''| plus the decaying
    // influence of the end conditions (a factor 2 of margin).
    std::cout << "[ control  ] dt = " << dt << ": linear " << e_linear << ", spline (interior) " << e_spline << "\n";
    EXPECT_LT(e_linear, dt * dt / 8 * 9);
    EXPECT_LT(e_spline, 2 * 5.0 / 384 * std::pow(dt, 4) * 81);
    // Exact at the samples, held outside.
    EXPECT_LT((linear(dt) - smooth(dt)).norm(), roundoff(1.0, 4));
    EXPECT_LT((spline(dt) - smooth(dt)).norm(), roundoff(1.0, 16));
    EXPECT_EQ(linear(-1.0), smooth(0.0));
  }
  EXPECT_THROW(SampledControl<3>({0.0, 0.0}, {Vec3::Zero(), Vec3::Zero()}, Interpolation::PiecewiseLinear), InvalidInput);
}

// The symmetric LGVI applies the control as impulses h/2 (u_k + u_{k+1}), the trapezoidal rule of
// the piecewise-linear interpolant of the samples u_k = u(t_k). Replaying those samples on a
// baseline (gsl-rk8pd, quaternion, tight tolerance) with PiecewiseLinear must therefore approach
// the LGVI trajectory as the LGVI's own error, O(h^2): slope 2 +- 0.15 over three step sizes.
TEST(Replay, AnLgviControlSequenceOnABaselineConvergesAtTheLgvisOrder) {
  const Pendulum3D pendulum = Pendulum3D::paper();
  const double T = 1.0;
  const AttitudeLgvi lgvi(pendulum, LgviForm::Symmetric);
  std::array<double, 3> hs{0.02, 0.01, 0.005}, e{};
  for (int i = 0; i < 3; ++i) {
    const double h = hs[i];
    const auto steps = static_cast<std::size_t>(std::llround(T / h));
    std::vector<double> t;
    std::vector<Vec3> u;
    for (std::size_t k = 0; k <= steps; ++k) {
      t.push_back(static_cast<double>(k) * h);
      u.push_back(pendulum_control(t.back()));
    }
    const SampledControl<3> replay(t, u, Interpolation::PiecewiseLinear);
    AttitudeState s = lgvi.make_state(pendulum_R0(), pendulum_Omega0());
    // The LGVI sees exactly the samples (the grid's controls); the baseline their interpolant.
    const Stats stats = integrate(lgvi, s, 0.0, h, steps, [&](double tk) { return replay(tk); }, null_observer());
    ASSERT_TRUE(stats.ok()) << stats.brief();
    const Trajectory tr = run_attitude("gsl-rk8pd", CoordinateModel::Quaternion, pendulum,
                                       [&](double tk) { return replay(tk); }, pendulum_R0(), pendulum_Omega0(),
                                       {0.0, T}, adaptive(1e-13));
    ASSERT_TRUE(tr.stats.ok()) << tr.stats.brief();
    e[i] = state_distance(tr.R.back(), tr.Omega.back(), s.R, lgvi.omega(s));
  }
  const double slope = loglog_slope(hs, e);
  std::cout << "[ replay   ] LGVI vs replayed baseline: errors " << e[0] << ", " << e[1] << ", " << e[2]
            << ", slope " << slope << "\n";
  EXPECT_NEAR(slope, 2.0, 0.15);
}

}  // namespace
}  // namespace lgvi::test
