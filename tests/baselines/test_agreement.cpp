// Every method on every coordinate model against a high-accuracy reference, on the free rigid
// body and the 3D pendulum (the cases) and the dumbbell (its translational states), all
// with controls (functions of time).
//
// Reference: gsl-rk8pd (Prince-Dormand 8(9)) on the quaternion model at rtol = atol = 1e-14,
// checked against odeint-rkf78 on the rotation-matrix model at 1e-13 (another library, method
// and model): they agree to ~1e-12 (asserted: kReferenceAgreement). CVODE Adams at 1e-12, the
// reference the issue suggests, is only ~5e-10 accurate here (multistep, error per step; printed
// and asserted below 1e-9): too close to the 4th-order fixed-step errors (~1e-9) to judge them.
//
// What the settings promise (the distance is ||R - R_ref||_F + |Omega - Omega_ref| over the
// samples, every 0.1 s):
//  - adaptive methods at rtol = atol = r control the local error of each step: per component
//    below r (1 + |y_i|) (odeint, GSL: max norm), or in CVODE's weighted RMS norm (a component
//    up to sqrt(n) times that). The global error is the sum of the local errors, propagated; on
//    these horizons the motions do not amplify them much, so the promise of N accepted steps is
//        N r (1 + max |y_i|) sqrt(n)
//    (the sqrt(n) also covers the distance summing components). The measured ratios (printed)
//    are 4e-4 to 0.7: BDF codes sit at the top (low order, error per step), explicit high-order
//    pairs at the bottom. A badly set-up baseline (tolerances not applied, a wrong Jacobian, an
//    output time missed or interpolated wrongly) lands orders of magnitude above.
//  - fixed-step fourth-order methods (odeint-rk4, gsl-rk4imp) at step h: the local error of a
//    step of a rotation at rate w is ~(h w)^5, so over T the global error is ~T w (h w)^4, with w
//    the fastest rate of the motion (max |Omega| and, for the pendulum, the small-oscillation
//    frequency sqrt(m g |rho| / J_min)). Their order itself is tested in test_order.cpp.
#include <gtest/gtest.h>

#include <iomanip>
#include <map>
#include <sstream>

#include "baseline_cases.hpp"

namespace lgvi::test {
namespace {

constexpr double kReferenceRtol = 1e-14;
constexpr double kCheckRtol = 1e-13;
constexpr double kReferenceAgreement = 1e-11;
constexpr double kCvodeReferenceAgreement = 1e-9;
constexpr double kRtol = 1e-9;
constexpr double kFixedStep = 1e-3;

struct Scenario {
  std::string name;
  double T;
  std::function<Trajectory(const std::string&, CoordinateModel, const SolverSettings&)> run;
  double gravity_rate;  ///< small-oscillation frequency (0 for the free body)
};

Scenario free_body_scenario() {
  static const FreeRigidBody body = free_body();
  const std::vector<double> times = uniform_times(5.0, 50);
  return {"free body", 5.0,
          [times](const std::string& method, CoordinateModel model, const SolverSettings& s) {
            return run_attitude(method, model, body, free_body_control, free_body_R0(), free_body_Omega0(), times, s);
          },
          0.0};
}

Scenario pendulum_scenario() {
  static const Pendulum3D pendulum = Pendulum3D::paper();
  const std::vector<double> times = uniform_times(3.0, 30);
  const double J_min = pendulum.inertia.J.diagonal().minCoeff();
  return {"pendulum", 3.0,
          [times](const std::string& method, CoordinateModel model, const SolverSettings& s) {
            return run_attitude(method, model, pendulum, pendulum_control, pendulum_R0(), pendulum_Omega0(), times, s);
          },
          std::sqrt(pendulum.mass * pendulum.gravity * pendulum.rho.norm() / J_min)};
}

const Trajectory& reference(const Scenario& s) {
  static std::map<std::string, Trajectory> cache;
  auto it = cache.find(s.name);
  if (it == cache.end()) {
    Trajectory ref = s.run("gsl-rk8pd", CoordinateModel::Quaternion, adaptive(kReferenceRtol));
    EXPECT_TRUE(ref.stats.ok()) << ref.stats.brief();
    const Trajectory check = s.run("odeint-rkf78", CoordinateModel::Matrix, adaptive(kCheckRtol));
    EXPECT_TRUE(check.stats.ok()) << check.stats.brief();
    const double d = max_distance(ref, check);
    const Trajectory cvode = s.run("cvode-adams", CoordinateModel::Quaternion, adaptive(1e-12));
    EXPECT_TRUE(cvode.stats.ok()) << cvode.stats.brief();
    const double d_cvode = max_distance(ref, cvode);
    std::cout << "[ ref      ] " << s.name << ": gsl-rk8pd/quaternion at 1e-14 vs odeint-rkf78/matrix at 1e-13: " << d
              << "; vs cvode-adams/quaternion at 1e-12: " << d_cvode << "\n";
    EXPECT_LT(d_cvode, kCvodeReferenceAgreement);
    EXPECT_LT(d, kReferenceAgreement);
    it = cache.emplace(s.name, std::move(ref)).first;
  }
  return it->second;
}

/// Dimension of a single-body attitude model: chart coordinates + Omega.
double model_dimension(CoordinateModel m) {
  switch (m) {
    case CoordinateModel::Quaternion:
    case CoordinateModel::QuaternionRenormalized: return 7;
    case CoordinateModel::Euler: return 6;
    case CoordinateModel::Matrix: return 12;
  }
  return 12;
}

class Agreement : public ::testing::TestWithParam<Combination> {
 protected:
  void check(const Scenario& s) {
    const Combination& c = GetParam();
    const Trajectory& ref = reference(s);
    const bool fixed_step = is_fixed_step(c.method);
    const Trajectory tr = s.run(c.method, c.model, fixed_step ? fixed(kFixedStep) : adaptive(kRtol));
    ASSERT_TRUE(tr.stats.ok()) << tr.stats.brief();
    ASSERT_EQ(tr.t.size(), ref.t.size());
    const double err = max_distance(tr, ref);
    double w = s.gravity_rate, y_max = 1.0;
    for (const Vec3& O : ref.Omega) {
      w = std::max(w, O.norm());
      y_max = std::max(y_max, O.cwiseAbs().maxCoeff());
    }
    const double n = model_dimension(c.model) + (tr.x.empty() ? 0.0 : 6.0);
    const double bound = fixed_step ? s.T * w * std::pow(kFixedStep * w, 4)
                                    : static_cast<double>(tr.stats.steps) * kRtol * (1.0 + y_max) * std::sqrt(n);
    std::ostringstream os;  // (a local stream: the precision must not stick to std::cout)
    os << "[ error    ] " << s.name << " " << c.method << "/" << baselines::to_string(c.model) << ": "
       << std::setprecision(3) << err << " (bound " << bound << ", ratio " << err / bound << "), " << tr.stats.brief()
       << "\n";
    std::cout << os.str();
    EXPECT_LT(err, bound);
  }
};

Scenario dumbbell_scenario() {
  static const DumbbellSpacecraft dumbbell = DumbbellSpacecraft::paper();
  const std::vector<double> times = uniform_times(6.0, 30);
  return {"dumbbell", 6.0,
          [times](const std::string& method, CoordinateModel model, const SolverSettings& s) {
            return run_dumbbell(method, model, dumbbell, dumbbell_control, dumbbell_R0(), dumbbell_Omega0(),
                                dumbbell_x0(), dumbbell_v0(), times, s);
          },
          1.0};  // the orbital rate (normalized units)
}

TEST_P(Agreement, FreeBodyWithControl) { check(free_body_scenario()); }
TEST_P(Agreement, PendulumWithControl) { check(pendulum_scenario()); }
// Not required by the issue (free body and pendulum are), but the translational states are the
// dumbbell's own: the same promise on x, v too.
TEST_P(Agreement, DumbbellWithControl) { check(dumbbell_scenario()); }

INSTANTIATE_TEST_SUITE_P(All, Agreement, ::testing::ValuesIn(all_combinations()),
                         [](const auto& info) { return combination_name(info.param); });

// CVODE with its own difference-quotient Jacobian instead of the model's: same accuracy.
TEST(AgreementCvode, DifferenceQuotientJacobian) {
  const Scenario s = pendulum_scenario();
  for (const std::string method : {"cvode-bdf", "cvode-adams"}) {
    SolverSettings settings = adaptive(kRtol);
    settings.jacobian = baselines::JacobianSource::DifferenceQuotient;
    const Trajectory tr = s.run(method, CoordinateModel::Quaternion, settings);
    ASSERT_TRUE(tr.stats.ok()) << tr.stats.brief();
    const double err = max_distance(tr, reference(s));
    std::cout << "[ error    ] " << method << " difference-quotient Jacobian: " << err << ", " << tr.stats.brief() << "\n";
    EXPECT_LT(err, static_cast<double>(tr.stats.steps) * kRtol * 6.0 * 2.0);  // (1 + max |Omega_i|) sqrt(n), n = 7
  }
}

}  // namespace
}  // namespace lgvi::test
