// cvode-bdf-projected (baselines/projection.hpp): CVODE BDF with a projection after every step
// onto the chart's constraints and the system's invariants.
//  - it keeps them to 1e-12 over a run (free body: |q|, E, |Pi|; pendulum and Lagrange top: |q|,
//    E, e3.(R J Omega); dumbbell: |q|, E; the matrix and Euler charts too), where plain cvode-bdf
//    at the same rtol drifts measurably more;
//  - a controlled pendulum keeps |q| and e3.(R J Omega) (conserved under its control) and lets the
//    energy change;
//  - its error against the exact free-body solution follows rtol as cvode-bdf's does, within a
//    factor kErrorFactor of it (derived there);
//  - a model it does not take is one InvalidInput line; the projection allocates nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>

#include "allocation_counter.hpp"
#include "baseline_cases.hpp"
#include "baselines/exact/free_rigid_body_exact.hpp"

namespace lgvi::test {
namespace {

constexpr double kKept = 1e-12;  // the constraints over a run, relative (the brief's bound)

/// The largest relative deviations along a trajectory: | |q| - 1 | (the raw state's), |E - E_0| /
/// |E_0|, and of the system's momentum invariant (|Pi|, or e3.(R J Omega) relative to |J Omega_0|).
struct Deviation {
  double quaternion = 0.0, energy = 0.0, momentum = 0.0;
  double invariants() const { return std::max(energy, momentum); }
};

template <class System, class Momentum>
Deviation deviation(const Trajectory& tr, const System& system, Momentum&& momentum, double momentum_scale) {
  Deviation d;
  const double E0 = system.energy(tr.R[0], tr.Omega[0]);
  const double m0 = momentum(tr.R[0], tr.Omega[0]);
  for (std::size_t k = 0; k < tr.t.size(); ++k) {
    d.quaternion = std::max(d.quaternion, tr.quaternion_norm_error[k]);
    d.energy = std::max(d.energy, std::abs(system.energy(tr.R[k], tr.Omega[k]) - E0) / std::abs(E0));
    d.momentum = std::max(d.momentum, std::abs(momentum(tr.R[k], tr.Omega[k]) - m0) / momentum_scale);
  }
  return d;
}

Deviation free_body_deviation(const Trajectory& tr, const FreeRigidBody& body) {
  const auto casimir = [&](const Mat3&, const Vec3& Omega) { return (body.inertia.J * Omega).norm(); };
  return deviation(tr, body, casimir, casimir(tr.R[0], tr.Omega[0]));
}
Deviation pendulum_deviation(const Trajectory& tr, const Pendulum3D& p) {
  const auto vertical = [&](const Mat3& R, const Vec3& Omega) { return p.vertical_momentum(R, Omega); };
  return deviation(tr, p, vertical, (p.inertia.J * tr.Omega[0]).norm());
}

void print(const std::string& label, const Deviation& d) {
  std::cout << "[ project  ] " << label << ": |q|-1 " << d.quaternion << ", dE/E " << d.energy << ", momentum "
            << d.momentum << "\n";
}

/// Projected keeps every constraint to kKept; plain cvode-bdf's invariants drift at least 100
/// times more (and beyond 1e-10).
void expect_kept_where_plain_drifts(const std::string& label, const Deviation& projected, const Deviation& plain) {
  print(label + " cvode-bdf-projected", projected);
  print(label + " cvode-bdf          ", plain);
  EXPECT_LT(projected.quaternion, kKept) << label;
  EXPECT_LT(projected.energy, kKept) << label;
  EXPECT_LT(projected.momentum, kKept) << label;
  EXPECT_GT(plain.invariants(), 100.0 * std::max(projected.invariants(), 1e-16)) << label;
  EXPECT_GT(plain.invariants(), 1e-10) << label;
}

TEST(Projection, FreeBodyKeepsUnitQuaternionEnergyAndCasimir) {
  const FreeRigidBody body = free_body();
  const std::vector<double> times = uniform_times(50.0, 500);
  Deviation d[2];
  const char* methods[2] = {"cvode-bdf-projected", "cvode-bdf"};
  for (int i = 0; i < 2; ++i) {
    const Trajectory tr = run_attitude(methods[i], CoordinateModel::Quaternion, body, {}, free_body_R0(),
                                       free_body_Omega0(), times, adaptive(1e-8));
    ASSERT_TRUE(tr.stats.ok()) << methods[i] << ": " << tr.stats.brief();
    d[i] = free_body_deviation(tr, body);
  }
  expect_kept_where_plain_drifts("free body, rtol 1e-8", d[0], d[1]);
}

TEST(Projection, PendulumAndLagrangeTopKeepUnitQuaternionEnergyAndVerticalMomentum) {
  struct Case {
    std::string name;
    Pendulum3D system;
    Mat3 R0;
    Vec3 Omega0;
    double T;
  };
  const std::vector<Case> cases = {
      {"pendulum", Pendulum3D::paper(), pendulum_R0(), pendulum_Omega0(), 20.0},
      // experiments/scenes/lagrange-top.toml: spun at 20 rad/s, 30 deg from upright.
      {"lagrange top", Pendulum3D(1.0, Vec3(0.14, 0.14, 0.08).asDiagonal(), Vec3(0.0, 0.0, 0.3), 9.81),
       so3::exp(Vec3(5.0 * M_PI / 6.0, 0.0, 0.0)), Vec3(0.5, 0.0, 20.0), 10.0},
  };
  for (const Case& c : cases) {
    const std::vector<double> times = uniform_times(c.T, 400);
    Deviation d[2];
    const char* methods[2] = {"cvode-bdf-projected", "cvode-bdf"};
    for (int i = 0; i < 2; ++i) {
      const Trajectory tr =
          run_attitude(methods[i], CoordinateModel::Quaternion, c.system, {}, c.R0, c.Omega0, times, adaptive(1e-8));
      ASSERT_TRUE(tr.stats.ok()) << c.name << " " << methods[i] << ": " << tr.stats.brief();
      d[i] = pendulum_deviation(tr, c.system);
    }
    expect_kept_where_plain_drifts(c.name + ", rtol 1e-8", d[0], d[1]);
  }
}

// Under its control u the pendulum's energy changes, its vertical momentum does not (the moment
// R^T e3 x u has no vertical component): the projection keeps |q| and e3.(R J Omega) only.
TEST(Projection, ControlledPendulumKeepsVerticalMomentumNotEnergy) {
  const Pendulum3D p = Pendulum3D::paper();
  const Trajectory tr = run_attitude("cvode-bdf-projected", CoordinateModel::Quaternion, p, pendulum_control,
                                     pendulum_R0(), pendulum_Omega0(), uniform_times(10.0, 200), adaptive(1e-8));
  ASSERT_TRUE(tr.stats.ok()) << tr.stats.brief();
  const Deviation d = pendulum_deviation(tr, p);
  print("controlled pendulum", d);
  EXPECT_LT(d.quaternion, kKept);
  EXPECT_LT(d.momentum, kKept);
  EXPECT_GT(d.energy, 1e-3);  // the control does work
}

TEST(Projection, DumbbellKeepsUnitQuaternionAndEnergy) {
  const DumbbellSpacecraft system = DumbbellSpacecraft::paper();
  double drift[2] = {};
  const char* methods[2] = {"cvode-bdf-projected", "cvode-bdf"};
  for (int i = 0; i < 2; ++i) {
    const Trajectory tr = run_dumbbell(methods[i], CoordinateModel::Quaternion, system, {}, dumbbell_R0(),
                                       dumbbell_Omega0(), dumbbell_x0(), dumbbell_v0(), uniform_times(30.0, 300),
                                       adaptive(1e-8));
    ASSERT_TRUE(tr.stats.ok()) << methods[i] << ": " << tr.stats.brief();
    const double E0 = system.energy(tr.R[0], tr.x[0], tr.Omega[0], tr.v[0]);
    for (std::size_t k = 0; k < tr.t.size(); ++k) {
      drift[i] = std::max(drift[i], std::abs(system.energy(tr.R[k], tr.x[k], tr.Omega[k], tr.v[k]) - E0) / std::abs(E0));
      if (i == 0) {
        EXPECT_LT(tr.quaternion_norm_error[k], kKept);
      }
    }
  }
  std::cout << "[ project  ] dumbbell dE/E: cvode-bdf-projected " << drift[0] << ", cvode-bdf " << drift[1] << "\n";
  EXPECT_LT(drift[0], kKept);
  EXPECT_GT(drift[1], 100.0 * std::max(drift[0], 1e-16));
}

// The other charts: R^T R = I (matrix) and no chart constraint (Euler angles), with E and |Pi|.
TEST(Projection, MatrixAndEulerChartsKeepTheInvariants) {
  const FreeRigidBody body = free_body();
  for (const CoordinateModel model : {CoordinateModel::Matrix, CoordinateModel::Euler}) {
    const Trajectory tr = run_attitude("cvode-bdf-projected", model, body, {}, free_body_R0(), free_body_Omega0(),
                                       uniform_times(20.0, 200), adaptive(1e-8));
    ASSERT_TRUE(tr.stats.ok()) << baselines::to_string(model) << ": " << tr.stats.brief();
    const Deviation d = free_body_deviation(tr, body);
    print(std::string("free body, ") + baselines::to_string(model), d);
    EXPECT_LT(d.invariants(), kKept) << baselines::to_string(model);
    double orthogonality = 0.0;
    for (const Mat3& R : tr.R) orthogonality = std::max(orthogonality, so3::orthogonality_error(R));
    EXPECT_LT(orthogonality, kKept) << baselines::to_string(model);
  }
}

// Spinning exactly about a principal axis, grad E = J Omega and grad |Pi| = J^2 Omega / |J Omega|
// are parallel: G G^T is singular, and the regularized factorization must still project.
TEST(Projection, PrincipalAxisSpinWithParallelGradients) {
  const FreeRigidBody body = free_body();
  const Trajectory tr = run_attitude("cvode-bdf-projected", CoordinateModel::Quaternion, body, {}, free_body_R0(),
                                     Vec3(0.0, 0.0, 3.0), uniform_times(10.0, 100), adaptive(1e-8));
  ASSERT_TRUE(tr.stats.ok()) << tr.stats.brief();
  const Deviation d = free_body_deviation(tr, body);
  print("principal-axis spin", d);
  EXPECT_LT(d.quaternion, kKept);
  EXPECT_LT(d.invariants(), kKept);
}

// The error against the closed-form free body (Celledoni et al.) follows rtol as cvode-bdf's does.
// The factor: the exact solution y(t) lies on the manifold M, so the projection pi of a step's
// result y~ (orthogonal to first order) moves it by dist(y~, M) <= |y~ - y(t)|:
// |pi(y~) - y(t)| <= 2 |y~ - y(t)| + O(|y~ - y(t)|^2), a local error at most twice cvode-bdf's from
// the same state, hence (the same flow carries it on) a global error at most twice for the same
// steps. The steps are not the same (the error test sees the estimate projected onto the tangent
// space, which can only shorten it in the 2-norm): steps longer by a factor s make each local
// error s^(q+1) larger and their number 1/s, the global error s^q larger, q <= 5 for BDF. With the
// step counts within 10% of each other (checked), s^q <= 1.1^5 = 1.61. Allowed: 2 x 1.61.
constexpr double kStepSpread = 1.1;
constexpr double kErrorFactor = 2.0 * 1.61051;  // 2 kStepSpread^5

TEST(Projection, FreeBodyErrorFollowsRtolLikeCvodeBdf) {
  const FreeRigidBody body = free_body();
  const baselines::FreeRigidBodyExact exact(body.inertia.J, free_body_R0(), free_body_Omega0());
  const std::vector<double> times = uniform_times(20.0, 200);
  const std::vector<double> rtols = {1e-6, 1e-8, 1e-10};
  std::vector<double> errors[2];
  const char* methods[2] = {"cvode-bdf-projected", "cvode-bdf"};
  for (const double rtol : rtols) {
    std::size_t steps[2] = {};
    for (int i = 0; i < 2; ++i) {
      const Trajectory tr = run_attitude(methods[i], CoordinateModel::Quaternion, body, {}, free_body_R0(),
                                         free_body_Omega0(), times, adaptive(rtol));
      ASSERT_TRUE(tr.stats.ok()) << methods[i] << ": " << tr.stats.brief();
      double e = 0.0;
      for (std::size_t k = 0; k < tr.t.size(); ++k) {
        const baselines::ExactState s = exact.state(tr.t[k]);
        e = std::max(e, state_distance(tr.R[k], tr.Omega[k], s.R, s.Omega));
      }
      errors[i].push_back(e);
      steps[i] = tr.stats.steps;
    }
    std::cout << "[ project  ] free body vs exact, rtol " << rtol << ": cvode-bdf-projected " << errors[0].back()
              << " (" << steps[0] << " steps), cvode-bdf " << errors[1].back() << " (" << steps[1] << " steps)\n";
    EXPECT_LT(errors[0].back(), kErrorFactor * errors[1].back()) << "rtol " << rtol;
    const double spread = static_cast<double>(std::max(steps[0], steps[1])) /
                          static_cast<double>(std::min(steps[0], steps[1]));
    EXPECT_LT(spread, kStepSpread) << "rtol " << rtol;
  }
  // Following rtol: each factor 100 in rtol gains at least a factor 10 in the error, as cvode-bdf.
  for (std::size_t k = 1; k < rtols.size(); ++k) {
    EXPECT_LT(errors[0][k], 0.1 * errors[0][k - 1]) << "rtol " << rtols[k];
    EXPECT_LT(errors[1][k], 0.1 * errors[1][k - 1]) << "rtol " << rtols[k];
  }
}

// --- Input and allocation ---------------------------------------------------------------------------

TEST(Projection, RefusesTheRenormalizedModelInOneLine) {
  const FreeRigidBody body = free_body();
  try {
    run_attitude("cvode-bdf-projected", CoordinateModel::QuaternionRenormalized, body, {}, free_body_R0(),
                 free_body_Omega0(), uniform_times(1.0, 10), adaptive(1e-6));
    ADD_FAILURE() << "no InvalidInput";
  } catch (const InvalidInput& e) {
    std::cout << "[ project  ] " << e.what() << "\n";
    EXPECT_EQ(e.field(), "model");
    EXPECT_NE(std::string(e.what()).find("--model quaternion"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
  }
}

/// An ODE without a manifold projection (a plain Ode).
class Decay final : public baselines::Ode {
 public:
  int dimension() const override { return 1; }
  std::string model_name() const override { return "decay"; }
  baselines::RhsStatus rhs(double, const double* y, double* f) const override {
    f[0] = -y[0];
    return baselines::RhsStatus::Ok;
  }
  baselines::RhsStatus jacobian(double, const double*, double* J) const override {
    J[0] = -1.0;
    return baselines::RhsStatus::Ok;
  }
  bool time_dependent() const override { return false; }
};

TEST(Projection, RefusesAModelWithoutProjectionInOneLine) {
  const Decay ode;
  const double y0[1] = {1.0};
  const std::vector<double> times = {0.0, 1.0};
  try {
    baselines::integrate("cvode-bdf-projected", ode, y0, times, adaptive(1e-6),
                         [](std::size_t, double, const double*) { return true; });
    ADD_FAILURE() << "no InvalidInput";
  } catch (const InvalidInput& e) {
    std::cout << "[ project  ] " << e.what() << "\n";
    EXPECT_EQ(e.field(), "model");
    EXPECT_NE(std::string(e.what()).find("cvode-bdf-projected"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
  }
}

TEST(Projection, ProjectsOntoTheConstraintsWithoutAllocating) {
  const Pendulum3D p = Pendulum3D::paper();
  const baselines::AttitudeMechanics<Pendulum3D> mech(p);
  const baselines::CoordinateOde<baselines::QuaternionChart, baselines::AttitudeMechanics<Pendulum3D>> ode(mech);
  auto y = ode.initial_state({pendulum_R0()}, {pendulum_Omega0()});
  const baselines::ProjectionTarget target = ode.projection_target(y.data());
  ASSERT_EQ(target.count, 3);  // |q|^2, E, e3.(R J Omega)
  // A perturbation of the size of a local error at loose tolerances.
  decltype(y) perturbation;
  perturbation << 3e-5, -2e-5, 1e-5, 4e-5, -3e-4, 2e-4, 1e-4;
  y += perturbation;
  decltype(y) err = perturbation;
  const std::size_t before = allocation_count();
  const int iterations = ode.project(target, y.data(), err.data());
  const std::size_t allocations = allocation_count() - before;
  EXPECT_EQ(allocations, 0u);
  ASSERT_GE(iterations, 1);
  EXPECT_LE(iterations, 5);
  EXPECT_NEAR(y.head<4>().squaredNorm(), 1.0, 1e-14);
  // (projection_target gives the chart's constraint its exact target, the invariants their values.)
  const baselines::ProjectionTarget after = ode.projection_target(y.data());
  for (int i = 1; i < target.count; ++i) {
    EXPECT_NEAR(after.value[static_cast<std::size_t>(i)], target.value[static_cast<std::size_t>(i)],
                1e-14 * std::max(1.0, std::abs(target.value[static_cast<std::size_t>(i)])))
        << "constraint " << i;
  }
  std::cout << "[ project  ] " << ode.projection_constraints() << ": " << iterations << " iterations\n";
}

// The largest projection the models make (the dumbbell's matrix model: 6 + 1 constraints on 18
// entries, where Eigen's products of run-time size leave the coefficient-wise kernel): still no
// allocation, and the constraints met.
TEST(Projection, LargestProjectionAllocatesNothing) {
  const DumbbellSpacecraft d = DumbbellSpacecraft::paper();
  const baselines::DumbbellMechanics mech(d);
  const baselines::CoordinateOde<baselines::MatrixChart, baselines::DumbbellMechanics> ode(mech);
  auto y = ode.initial_state({dumbbell_R0()}, {dumbbell_Omega0()}, dumbbell_x0(), dumbbell_v0());
  const baselines::ProjectionTarget target = ode.projection_target(y.data());
  ASSERT_EQ(target.count, 7);  // R^T R = I (6), E
  decltype(y) perturbation = decltype(y)::Zero();
  for (int j = 0; j < perturbation.size(); ++j) perturbation(j) = 1e-5 * std::sin(1.0 + j);
  y += perturbation;
  decltype(y) err = perturbation;
  const std::size_t before = allocation_count();
  const int iterations = ode.project(target, y.data(), err.data());
  EXPECT_EQ(allocation_count() - before, 0u);
  ASSERT_GE(iterations, 1);
  const baselines::ProjectionTarget after = ode.projection_target(y.data());
  for (int i = 0; i < target.count; ++i) {
    EXPECT_NEAR(after.value[static_cast<std::size_t>(i)], target.value[static_cast<std::size_t>(i)],
                1e-13 * std::max(1.0, std::abs(target.value[static_cast<std::size_t>(i)])))
        << "constraint " << i;
  }
}

}  // namespace
}  // namespace lgvi::test
