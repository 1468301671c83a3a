// Checks shared by the model tests: random states, the ODE Jacobian against central differences
// of the right-hand side, and derivatives of a quantity along the flow.
#pragma once

#include <functional>
#include <random>
#include <string>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "baselines/model.hpp"
#include "lgvi/so3.hpp"
#include "test_support.hpp"

namespace lgvi::test {

/// A vector with independent entries uniform in [-1, 1] from the seeded generator.
template <class Rng>
inline Vec3 random_vector(Rng& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  return Vec3(u(rng), u(rng), u(rng));
}

/// A random attitude away from gimbal lock (|cos pitch| > 0.2) for the Euler chart.
template <class Rng>
inline Mat3 random_attitude(Rng& rng) {
  for (;;) {
    const Mat3 R = so3::random_rotation(rng);
    if (std::abs(std::cos(baselines::EulerChart::from_rotation(R)(1))) > 0.2) return R;
  }
}

/// Central-difference Jacobian of the ODE's right-hand side, steps scaled like the model's.
template <class Ode>
Eigen::MatrixXd fd_jacobian(const Ode& ode, double t, const typename Ode::State& y) {
  const int n = ode.dimension();
  Eigen::MatrixXd J(n, n);
  typename Ode::State fp, fm;
  for (int j = 0; j < n; ++j) {
    const double a = kFdStep * std::max(1.0, std::abs(y(j)));
    typename Ode::State yp = y, ym = y;
    yp(j) += a;
    ym(j) -= a;
    EXPECT_EQ(ode.rhs(t, yp.data(), fp.data()), baselines::RhsStatus::Ok);
    EXPECT_EQ(ode.rhs(t, ym.data(), fm.data()), baselines::RhsStatus::Ok);
    J.col(j) = (fp - fm) / (2 * a);
  }
  return J;
}

/// Checks the analytic Jacobian at y (and at a state pushed off the constraint set, where the
/// quaternion and matrix models wander) against central differences. The tolerance is
/// kFdTolerance relative to the size of the Jacobian's entries (third derivatives of these
/// polynomial/trigonometric right-hand sides are of the order of their first ones), times
/// amplification(y) squared when given: the momentum-form models recover velocities through
/// A(R)^{-1}, each further R-derivative of which brings a factor kappa = ||A^{-1}|| ||dA/dR||,
/// so the O(a^2 |f^(3)|) truncation of both difference quotients (the test's and the model's
/// own) grows by kappa^2.
template <class Ode>
void expect_jacobian(const Ode& ode, double t, typename Ode::State y, const std::string& what,
                     const std::function<double(const typename Ode::State&)>& amplification = {}) {
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1) y.head(ode.dimension() - Ode::NW - Ode::NX) *= 1.01;  // off SO(3) / the unit sphere
    typename Ode::Jacobian J;
    ASSERT_EQ(ode.jacobian(t, y.data(), J.data()), baselines::RhsStatus::Ok);
    const Eigen::MatrixXd fd = fd_jacobian(ode, t, y);
    const double scale = std::max(1.0, J.cwiseAbs().maxCoeff());
    const double kappa = amplification ? std::max(1.0, amplification(y)) : 1.0;
    const double err = (Eigen::MatrixXd(J) - fd).cwiseAbs().maxCoeff();
    EXPECT_LT(err, kFdTolerance * kappa * kappa * scale)
        << what << (pass ? " (off the constraint set)" : "") << ": max |J - J_fd| = " << err << ", scale " << scale
        << ", kappa " << kappa;
  }
}

/// d/dt E(y(t)) along the right-hand side, by a central difference along f (step kFdStep / |f|):
/// zero for a first integral. Compared with kFdTolerance times max(1, |E|).
template <class Ode, class Fn>
double derivative_along_flow(const Ode& ode, const typename Ode::State& y, Fn&& quantity) {
  typename Ode::State f;
  EXPECT_EQ(ode.rhs(0.0, y.data(), f.data()), baselines::RhsStatus::Ok);
  const double a = kFdStep / std::max(1.0, f.norm());
  const typename Ode::State yp = y + a * f, ym = y - a * f;
  return (quantity(ode.decode(yp.data())) - quantity(ode.decode(ym.data()))) / (2 * a);
}

}  // namespace lgvi::test
