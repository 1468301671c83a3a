// [control] type = "pd": reading, the LGVI's discretization of the feedback (lgvi/feedback_lgvi.hpp,
// FeedbackLgvi) and its order, and the baselines' right-hand side with the same law.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "baselines/mechanics.hpp"
#include "experiments/systems/binding_lgvi_support.hpp"
#include "experiments/cli/cli_support.hpp"
#include "experiments/scene/scene.hpp"
#include "experiments/systems/systems.hpp"
#include "lgvi/so3.hpp"

namespace lgvi::experiments {
namespace {

using test::default_scene_file;
using test::run_binding_lgvi;

constexpr const char* kFreeBodyPd =
    "system = \"free-body\"\n"
    "[parameters]\ninertia = [0.13, 0.28, 0.17]\n"
    "[initial]\nOmega = [0.3, -0.2, 0.5]\n"
    "[integration]\nh = 0.01\nt_final = 1.0\n"
    "[control]\ntype = \"pd\"\nkp = 0.5\nkd = 0.4\ntarget_euler = { sequence = \"ZYX\", angles = [1.0, 0.5, -0.3] }\n";

/// The attitude error |e_R| = |1/2 vee(R_d^T R - R^T R_d)| = sin(angle of R_d^T R).
double attitude_error(const AttitudeFeedback& f, const Mat3& R) {
  const Mat3 E = f.target.transpose() * R;
  return (0.5 * so3::vee(E - E.transpose())).norm();
}

TEST(PdControl, ReadsGainsAndTarget) {
  const Scene s = parse_scene(kFreeBodyPd, "pd.toml");
  const FreeBodyModel& m = std::get<FreeBodyModel>(s.model);
  ASSERT_TRUE(m.feedback);
  EXPECT_FALSE(m.control);
  EXPECT_EQ(m.feedback->kp, 0.5);
  EXPECT_EQ(m.feedback->kd, 0.4);
  EXPECT_EQ(m.feedback->target, euler_rotation("ZYX", Vec3(1.0, 0.5, -0.3)));
  // At the target the attitude term is R_d^T R_d's antisymmetric part, rounding only (a few eps);
  // the rate term is -kd Omega.
  EXPECT_LE(m.feedback->moment(0.0, m.feedback->target, Vec3::Zero()).norm(), 1e-15);
  EXPECT_LE((m.feedback->moment(0.0, m.feedback->target, Vec3(1.0, 2.0, 3.0)) - Vec3(-0.4, -0.8, -1.2)).norm(), 1e-15);
  // A rotation error by theta about n gives -kp sin(theta) n.
  const Mat3 R = m.feedback->target * so3::exp(Vec3(0.0, 0.7, 0.0));
  EXPECT_LE((m.feedback->moment(0.0, R, Vec3::Zero()) - Vec3(0.0, -0.5 * std::sin(0.7), 0.0)).norm(), 1e-15);
}

TEST(PdControl, BadInput) {
  struct Bad {
    const char* from;
    const char* to;
    const char* field;
    const char* reason;
  };
  for (const Bad& b : {Bad{"kp = 0.5", "kp = -0.5", "control.kp", "must be >= 0 (got -0.5)"},
                       Bad{"kd = 0.4", "", "control.kd", "is required"},
                       Bad{"kd = 0.4", "kd = 0.4\namplitude = [1, 1, 1]", "control.amplitude",
                           "is not a key of a pd control"},
                       Bad{"target_euler", "target = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]\ntarget_euler", "control.target_euler",
                           "conflicts with control.target"},
                       Bad{"target_euler = { sequence = \"ZYX\", angles = [1.0, 0.5, -0.3] }",
                           "target = [[1, 0, 0], [0, 1, 0], [0, 0.5, 1]]", "control.target", "is not a rotation"},
                       Bad{"target_euler = { sequence = \"ZYX\", angles = [1.0, 0.5, -0.3] }", "target_quaternion = [1, 1, 0, 0]",
                           "control.target_quaternion", "not a unit quaternion"}}) {
    std::string text = kFreeBodyPd;
    text.replace(text.find(b.from), std::string(b.from).size(), b.to);
    try {
      (void)parse_scene(text, "pd.toml");
      ADD_FAILURE() << "accepted: " << b.to;
    } catch (const SceneError& e) {
      EXPECT_EQ(e.field(), b.field) << e.what();
      EXPECT_NE(e.reason().find(b.reason), std::string::npos) << e.what();
    }
  }
  // Only the attitude systems take a pd control.
  const std::string cart = test::read_text(default_scene_file("cart-pendulum")) + "\n[control]\ntype = \"pd\"\nkp = 1\nkd = 1\n";
  try {
    (void)parse_scene(cart, "c.toml");
    ADD_FAILURE() << "a pd control was accepted for the cart";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field(), "control.type");
    EXPECT_NE(e.reason().find("free-body, pendulum and potential-body systems only"), std::string::npos) << e.what();
  }
}

// The closed loop is a damped oscillator about the target (natural rate sqrt(kp / J) ~ 1-2
// rad/s, decay rate kd / (2 J) >= 0.7 1/s for J <= 0.28): over 40 s the error shrinks by
// e^-28 or more from O(1); 1e-6 of the initial error leaves a wide margin for the LGVI's O(h^2)
// error, which does not grow on a contracting flow.
TEST(PdControl, DrivesTheAttitudeErrorDown) {
  const FreeBodyModel m = std::get<FreeBodyModel>(parse_scene(kFreeBodyPd, "pd.toml").model);
  const double e0 = attitude_error(*m.feedback, m.initial.R);
  ASSERT_GT(e0, 0.5);
  const auto end = run_binding_lgvi(m, LgviForm::Symmetric, 0.01, 4000);
  EXPECT_LT(attitude_error(*m.feedback, end.R), 1e-6 * e0);
  EXPECT_LT(end.Omega.norm(), 1e-6);
  // The pendulum: only the moment normal to the vertical acts, so the target is reached when
  // it differs from the start by a rotation about the vertical's normal plane; a target rotated
  // about e1 (the pendulum swings to it) with gravity off.
  std::string text = test::read_text(default_scene_file("pendulum"));
  text.replace(text.find("gravity = 9.81"), 14, "gravity = 0.0");
  text += "\n[control]\ntype = \"pd\"\nkp = 2.0\nkd = 1.0\ntarget_euler = { sequence = \"XYZ\", angles = [0.8, 0, 0] }\n";
  PendulumModel p = std::get<PendulumModel>(parse_scene(text, "p.toml").model);
  p.initial.Omega = Vec3::Zero();
  const auto swung = run_binding_lgvi(p, LgviForm::Symmetric, 0.01, 4000);
  EXPECT_LT(attitude_error(*p.feedback, swung.R), 1e-6);
}

// The discretization's order in h (test::expect_form_orders): symmetric form (feedback at both
// ends, the end implicit) 2; printed form (feedback at the end only) 1; h = 0.02 over 1 s is small
// enough that the leading error term dominates.
TEST(PdControl, SymmetricFormIsSecondOrderPrintedFirst) {
  test::expect_form_orders(std::get<FreeBodyModel>(parse_scene(kFreeBodyPd, "pd.toml").model));
}

// The baselines' right-hand side evaluates the same law: with h -> 0 the LGVI converges to the
// ODE Omega' = J^{-1}(J Omega x Omega + tau(R, Omega)). Compared with a classical RK4 on (R,
// Omega) written here (R by the exponential of the stage rates is not needed: RK4 on the 12
// entries, its O(dt^4) drift from SO(3) is 1e-13 at dt = 1e-3). LGVI at h = 1e-3, order 2:
// error ~ C h^2 with C ~ 1 (the errors at h = 0.01 in the order test are ~1e-4): 1e-5 bounds it.
TEST(PdControl, LgviConvergesToTheBaselineRightHandSide) {
  const FreeBodyModel m = std::get<FreeBodyModel>(parse_scene(kFreeBodyPd, "pd.toml").model);
  const baselines::AttitudeMechanicsWithMoment<FreeRigidBody> mech(
      m.system, {}, [&m](double t, const Mat3& R, const Vec3& Omega) { return m.feedback->moment(t, R, Omega); },
      {.time = false, .rate = true});
  static_assert(baselines::Mechanics<baselines::AttitudeMechanicsWithMoment<FreeRigidBody>>);
  using Y = std::pair<Mat3, Vec3>;
  const auto f = [&](const Y& y) {
    baselines::Configuration<1, 0> c;
    c.R[0] = y.first;
    return Y{y.first * so3::hat(y.second), mech.acceleration(0.0, c, y.second)};
  };
  const auto axpy = [](const Y& y, double a, const Y& k) { return Y{y.first + a * k.first, y.second + a * k.second}; };
  Y y{m.initial.R, m.initial.Omega};
  const double dt = 1e-3;
  for (int i = 0; i < 1000; ++i) {
    const Y k1 = f(y), k2 = f(axpy(y, dt / 2, k1)), k3 = f(axpy(y, dt / 2, k2)), k4 = f(axpy(y, dt, k3));
    y.first += dt / 6 * (k1.first + 2 * k2.first + 2 * k3.first + k4.first);
    y.second += dt / 6 * (k1.second + 2 * k2.second + 2 * k3.second + k4.second);
  }
  const auto lgvi = run_binding_lgvi(m, LgviForm::Symmetric, 1e-3, 1000);
  EXPECT_LT((lgvi.R - y.first).norm(), 1e-5);
  EXPECT_LT((lgvi.Omega - y.second).norm(), 1e-5);
}

}  // namespace
}  // namespace lgvi::experiments
