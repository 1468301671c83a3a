// The free body on a circular orbit ([parameters] orbit_rate): the gravity-gradient potential and
// its moment (lgvi/systems/gravity_gradient.hpp), the Jacobi integral, the LGVI's discretization
// (lgvi/gravity_gradient_lgvi.hpp, GravityGradientLgvi) and its order, agreement with the
// baselines' mechanics under a library solver, and the scene's bad input.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "baselines/model.hpp"
#include "baselines/solver.hpp"
#include "experiments/systems/binding_lgvi_support.hpp"
#include "experiments/cli/cli_support.hpp"
#include "experiments/scene/scene.hpp"
#include "experiments/systems/systems.hpp"
#include "lgvi/so3.hpp"

namespace lgvi::experiments {
namespace {

using test::default_scene_file;
using test::run_binding_lgvi;

// A fast orbit (n = 1 rad/s) so that the gravity gradient acts within a second: the moment
// 3 n^2 c x J c is of the order of the gyroscopic term J Omega x Omega here.
constexpr const char* kOrbit =
    "system = \"free-body\"\n"
    "[parameters]\ninertia = [1.2, 0.9, 0.6]\norbit_rate = 1.0\n"
    "[initial]\nOmega = [0.2, 0.1, 1.3]\n"
    "[integration]\nh = 0.01\nt_final = 1.0\n";


Mat3 random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  return so3::exp(Vec3(normal(rng), normal(rng), normal(rng)));
}

// d/de V(R exp(e hat(eta)), t) at e = 0 is -eta . M(R, t) (M is the moment of eq. 13: along
// R' = R hat(Omega), V' = -Omega . M). Central differences with e = 1e-5: truncation e^2/6 |V'''|
// with |V'''| <= 8 * 3 n^2 |J| (three derivatives of R, each bounded by |eta| = 1, through a
// quadratic form), rounding 2 eps |V| / e.
TEST(GravityGradient, MomentIsMinusTheAttitudeDerivativeOfThePotential) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const Mat3 J = Vec3(1.2, 0.9, 0.6).asDiagonal();
  for (const double n : {0.0011, 1.0, 2.5}) {
    const GravityGradient gravity(n);
    for (int trial = 0; trial < 20; ++trial) {
      const Mat3 R = random_rotation(rng);
      const double t = 10.0 * uniform(rng) / n;
      const Vec3 eta = Vec3(uniform(rng), uniform(rng), uniform(rng)).normalized();
      const double e = 1e-5;
      const double derivative =
          (gravity.potential(J, R * so3::exp(e * eta), t) - gravity.potential(J, R * so3::exp(-e * eta), t)) / (2 * e);
      const double scale = 3.0 * n * n * J.norm();
      const double bound = e * e / 6.0 * 8.0 * scale + 2.0 * kEps * scale / e;
      EXPECT_NEAR(derivative, -eta.dot(gravity.moment(J, R, t)), bound) << "n = " << n << ", trial " << trial;
    }
  }
  // A principal axis along r_hat(t), and an isotropic body, feel no moment.
  const GravityGradient gravity(1.0);
  const double t = 0.7;
  const Vec3 r = gravity.direction(t);
  const Mat3 R_aligned = so3::exp(Vec3(0.0, 0.0, t));  // body e1 along r_hat(t) = (cos t, sin t, 0)
  EXPECT_LE(gravity.moment(J, R_aligned, t).norm(), 16 * kEps * 3.0 * J.norm());
  EXPECT_LE((R_aligned.transpose() * r - Vec3::UnitX()).norm(), 4 * kEps);
  std::mt19937 rng2(3);
  EXPECT_LE(gravity.moment(0.5 * Mat3::Identity(), random_rotation(rng2), t).norm(), 16 * kEps * 3.0 * 0.5);
}

// The Jacobi integral E_J = 1/2 Omega^T J Omega + V - n e3^T R J Omega is a first integral of
// Omega' = J^{-1}(J Omega x Omega + M(R, t)), R' = R hat(Omega): its derivative along the flow,
// by central differences in time (step d = 1e-5: truncation d^2/6 |E_J'''|, |E_J'''| <= 100 s
// for |Omega| <= 2, n <= 2 with s = |Omega|^2 |J| + n^2 |J| + n |J| |Omega| the size of its terms;
// rounding 2 eps s / d), vanishes; the energy's does not (so the test can tell).
TEST(GravityGradient, JacobiIntegralIsAFirstIntegralOfTheFlow) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const Mat3 J = Vec3(1.2, 0.9, 0.6).asDiagonal();
  const Mat3 J_inv = J.inverse();
  double largest_energy_rate = 0.0;  // |dE/dt| / s
  for (const double n : {0.5, 1.0, 2.0}) {
    const GravityGradient gravity(n);
    for (int trial = 0; trial < 20; ++trial) {
      const Mat3 R = random_rotation(rng);
      const Vec3 Omega(uniform(rng), uniform(rng), uniform(rng));
      const double t = 3.0 * uniform(rng);
      const Vec3 Omega_dot = J_inv * ((J * Omega).cross(Omega) + gravity.moment(J, R, t));
      const double d = 1e-5;
      const auto along = [&](double s) {
        // First order in s: enough for d/ds at 0 (Mat3, Vec3: evaluated, not expression templates).
        return std::pair<Mat3, Vec3>{R * so3::exp(s * Omega), Omega + s * Omega_dot};
      };
      const auto [Rp, Op] = along(d);
      const auto [Rm, Om] = along(-d);
      const double dE_J = (gravity.jacobi_integral(J, Rp, Op, t + d) - gravity.jacobi_integral(J, Rm, Om, t - d)) / (2 * d);
      const double energy_p = 0.5 * Op.dot(J * Op) + gravity.potential(J, Rp, t + d);
      const double energy_m = 0.5 * Om.dot(J * Om) + gravity.potential(J, Rm, t - d);
      const double dE = (energy_p - energy_m) / (2 * d);
      const double s = J.norm() * (Omega.squaredNorm() + n * n + n * Omega.norm());
      // The second-order terms of `along` (R'' and Omega'' left out) cancel in the central difference.
      EXPECT_NEAR(dE_J, 0.0, 100.0 * s * d * d / 6.0 + 2.0 * kEps * s / d) << "n = " << n << ", trial " << trial;
      largest_energy_rate = std::max(largest_energy_rate, std::abs(dE) / s);
    }
  }
  // dE/dt = dV/dt at fixed R = 3 n^3 (J c) . R^T (e3 x r_hat): zero on some states, of the order
  // of s on most; if the energy were conserved too, the test above could not tell.
  EXPECT_GT(largest_energy_rate, 0.1);
}

// The discretization's order in h (test::expect_form_orders, as for the PD feedback): symmetric 2,
// printed 1.
TEST(GravityGradient, SymmetricFormIsSecondOrderPrintedFirst) {
  const FreeBodyModel m = std::get<FreeBodyModel>(parse_scene(kOrbit, "orbit.toml").model);
  ASSERT_TRUE(m.gravity_gradient);
  EXPECT_EQ(SystemBinding<FreeBodyModel>::printed_order(m), 1);
  test::expect_form_orders(m);
}

// The LGVI and the baselines' mechanics (AttitudeMechanicsWithMoment in a CoordinateOde, integrated by
// gsl-rk8pd at rtol 1e-12) model the same motion, time dependence included: over 1 s (one radian
// of orbit) the symmetric LGVI at h = 1e-3 is within C h^2 of it, C ~ 1 (the errors at h = 1/50 in
// the order test are ~1e-4 = 0.25 h^2): 1e-5 bounds it with margin, and a sign or phase error in
// either model (a moment of order 1) would give errors of order 0.1.
TEST(GravityGradient, LgviAgreesWithTheBaselineMechanics) {
  const FreeBodyModel m = std::get<FreeBodyModel>(parse_scene(kOrbit, "orbit.toml").model);
  using Mech = baselines::AttitudeMechanicsWithMoment<FreeRigidBody>;
  const Mech mech(
      m.system, {},
      [&m](double t, const Mat3& R, const Vec3&) { return m.gravity_gradient->moment(m.system.inertia.J, R, t); },
      {.time = true, .rate = false});
  static_assert(baselines::Mechanics<Mech>);
  const baselines::CoordinateOde<baselines::QuaternionChart, Mech> ode(mech);
  EXPECT_TRUE(ode.time_dependent());
  const auto y0 = ode.initial_state({m.initial.R}, {m.initial.Omega});
  baselines::SolverSettings settings;
  settings.rtol = 1e-12;
  settings.atol = 1e-12;
  const std::vector<double> times = {0.0, 1.0};
  Mat3 R_end;
  Vec3 Omega_end;
  const Stats stats = baselines::integrate("gsl-rk8pd", ode, std::span<const double>(y0.data(), y0.size()), times, settings,
                                           [&](std::size_t, double, const double* y) {
                                             const auto d = ode.decode(y);
                                             R_end = d.config.R[0];
                                             Omega_end = d.rates.Omega[0];
                                             return true;
                                           });
  ASSERT_TRUE(stats.ok()) << stats.brief();
  const auto lgvi = run_binding_lgvi(m, LgviForm::Symmetric, 1e-3, 1000);
  EXPECT_LT((lgvi.R - R_end).norm(), 1e-5);
  EXPECT_LT((lgvi.Omega - Omega_end).norm(), 1e-5);
  // Without the gravity gradient the motion differs at order 0.1: the comparison can tell.
  FreeBodyModel free = m;
  free.gravity_gradient.reset();
  EXPECT_GT((run_binding_lgvi(free, LgviForm::Symmetric, 1e-3, 1000).Omega - Omega_end).norm(), 1e-2);
}

// The symmetric LGVI is a variational integrator of an autonomous system in the orbit's frame,
// so its Jacobi integral error stays bounded (no drift) over long times: over 2 10^4 steps of
// h = 0.05 (1000 s at n = 1: 159 orbits) the largest error is within 3 times the largest of the
// first tenth (a linear drift would give ~10). And it is O(h^2) (a modified Jacobi integral is
// conserved): halving h over the same 1000 s divides the largest error by 4, log2 within +-0.3.
double largest_jacobi_error(const FreeBodyModel& m, double h, std::size_t steps, double* first_tenth) {
  std::vector<double> jacobi;
  (void)run_binding_lgvi(m, LgviForm::Symmetric, h, steps, [&](double t, const FreeBodyModel::State& s) {
    jacobi.push_back(SystemBinding<FreeBodyModel>::conserved(m, s, t).energy);
  });
  EXPECT_EQ(jacobi.size(), steps + 1);
  double all = 0.0;
  for (std::size_t k = 0; k < jacobi.size(); ++k) {
    const double error = std::abs(jacobi[k] - jacobi[0]);
    if (first_tenth != nullptr && k <= steps / 10) *first_tenth = std::max(*first_tenth, error);
    all = std::max(all, error);
  }
  return all;
}

TEST(GravityGradient, LgviJacobiIntegralErrorStaysBoundedAndIsSecondOrder) {
  const FreeBodyModel m = std::get<FreeBodyModel>(parse_scene(kOrbit, "orbit.toml").model);
  double first_tenth = 0.0;
  const double coarse = largest_jacobi_error(m, 0.05, 20000, &first_tenth);
  EXPECT_GT(first_tenth, 0.0);
  EXPECT_LE(coarse, 3.0 * first_tenth) << "first tenth " << first_tenth << ", whole run " << coarse;
  const double fine = largest_jacobi_error(m, 0.025, 40000, nullptr);
  EXPECT_NEAR(std::log2(coarse / fine), 2.0, 0.3) << "largest errors " << coarse << " (h = 0.05), " << fine
                                                  << " (h = 0.025)";
}

TEST(GravityGradient, BadInput) {
  struct Bad {
    std::string text;
    const char* field;
    const char* reason;
  };
  const auto with = [](const char* from, const char* to) {
    std::string text = kOrbit;
    text.replace(text.find(from), std::string(from).size(), to);
    return text;
  };
  std::string pendulum = test::read_text(default_scene_file("pendulum"));
  pendulum.replace(pendulum.find("[parameters]"), 12, "[parameters]\norbit_rate = 1.0");
  std::string ocp = test::read_text(default_scene_file("ocp-free-body-slew"));
  ocp.replace(ocp.find("[parameters]"), 12, "[parameters]\norbit_rate = 0.001");
  for (const Bad& b : {Bad{with("orbit_rate = 1.0", "orbit_rate = 0.0"), "parameters.orbit_rate", "must be > 0 (got 0)"},
                       Bad{with("orbit_rate = 1.0", "orbit_rate = -2.0"), "parameters.orbit_rate", "must be > 0 (got -2)"},
                       Bad{with("orbit_rate = 1.0", "orbit_rate = \"fast\""), "parameters.orbit_rate", "number"},
                       Bad{with("orbit_rate = 1.0", "orbit_rate = 1e300"), "parameters.orbit_rate", "magnitude"},
                       Bad{std::string(kOrbit) + "[control]\ntype = \"pd\"\nkp = 1\nkd = 1\n", "control.type",
                           "not available with parameters.orbit_rate"},
                       Bad{pendulum, "parameters.orbit_rate", ""},
                       Bad{ocp, "parameters.orbit_rate", "no gravity-gradient moment"}}) {
    try {
      (void)parse_scene(b.text, "orbit.toml");
      ADD_FAILURE() << "accepted:\n" << b.text;
    } catch (const SceneError& e) {
      EXPECT_EQ(e.field(), b.field) << e.what();
      EXPECT_NE(e.reason().find(b.reason), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace lgvi::experiments
