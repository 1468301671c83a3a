// Every method on every coordinate model of the multibody systems against a high-accuracy
// reference, with controls: the cart-pendulum (cart forces) and the connected bodies (joint
// moment), 3 s each, sampled every 0.1 s. The promise and the bounds are those of
// test_agreement.cpp (single bodies):
//  - reference: gsl-rk8pd on the quaternion model at rtol = atol = 1e-14, checked against
//    odeint-rkf78 on the rotation-matrix model at 1e-13 (kReferenceAgreement);
//  - adaptive methods at r: N r (1 + max|y_i|) sqrt(n) (adaptive_bound, multibody_cases.hpp);
//  - fixed-step fourth-order methods at h: T w (h w)^4, w the fastest rate of the motion:
//    max |Omega_i| over the reference and, for the cart-pendulum, the small-oscillation frequency
//    of the pendulum on a free cart, w^2 = m g |d| / (J_min - m^2 |d|^2 / (M + m)) (the cart's
//    recoil lowers the effective inertia about the horizontal axes).
// The distance is the Euclidean norm of the paper's variables (R's entries, Omega's, q, q').
// Unlike the single bodies', these motions amplify the local errors noticeably (the connected
// bodies exchange energy chaotically): both bounds are multiplied by the measured amplification
// G = max over samples and over perturbations delta of each initial Omega_i component of
// |z_delta(t) - z(t)| / |z_delta(0) - z(0)| (reference solver, delta = kPerturbation: linear
// regime, and far above the reference's error), G >= 1.
#include <gtest/gtest.h>

#include <iomanip>
#include <map>
#include <sstream>

#include "baseline_cases.hpp"
#include "multibody_cases.hpp"

namespace lgvi::test {
namespace {

constexpr double kMultibodyReferenceRtol = 1e-14;
constexpr double kMultibodyCheckRtol = 1e-13;
constexpr double kReferenceAgreement = 1e-11;
constexpr double kMultibodyRtol = 1e-9;
constexpr double kFixedStep = 1e-3;
constexpr double kMultibodyT = 3.0;
constexpr std::size_t kSamples = 30;
constexpr double kPerturbation = 1e-6;

struct MultibodyScenario {
  std::string name;
  std::function<Path(const std::string&, CoordinateModel, const SolverSettings&)> run;
  double gravity_rate;
  int bodies;
  /// The reference solver from the initial state with Omega_{i}(axis) += delta, i = component / 3.
  std::function<Path(int component, double delta)> perturbed;
};

MultibodyScenario cart_scenario() {
  static const CartPendulum cart = CartPendulum::paper();
  static const baselines::CartPendulumMechanics mech(cart, cart_control);
  const double J_min = std::min(cart.inertia.J(0, 0), cart.inertia.J(1, 1));
  const double md = cart.mass * cart.d.norm();
  return {"cart-pendulum",
          [](const std::string& method, CoordinateModel model, const SolverSettings& s) {
            return run_model(method, model, mech, {cart_R0()}, {cart_Omega0()}, cart_q0(), cart_q_dot0(),
                             uniform_times(kMultibodyT, kSamples), s);
          },
          std::sqrt(md * cart.gravity / (J_min - md * md / (cart.cart_mass + cart.mass))), 1,
          [](int component, double delta) {
            Vec3 Omega0 = cart_Omega0();
            Omega0(component) += delta;
            return run_model("gsl-rk8pd", CoordinateModel::Quaternion, mech, {cart_R0()}, {Omega0}, cart_q0(),
                             cart_q_dot0(), uniform_times(kMultibodyT, kSamples), adaptive(kMultibodyReferenceRtol));
          }};
}

MultibodyScenario bodies_scenario() {
  static const ConnectedBodies bodies = ConnectedBodies::paper();
  static const baselines::ConnectedBodiesMechanics mech(bodies, bodies_control);
  return {"connected bodies",
          [](const std::string& method, CoordinateModel model, const SolverSettings& s) {
            return run_model(method, model, mech, bodies_R0(), bodies_Omega0(), {}, {}, uniform_times(kMultibodyT, kSamples), s);
          },
          0.0, 2,
          [](int component, double delta) {
            std::array<Vec3, 2> Omega0 = bodies_Omega0();
            Omega0[component / 3](component % 3) += delta;
            return run_model("gsl-rk8pd", CoordinateModel::Quaternion, mech, bodies_R0(), Omega0, {}, {},
                             uniform_times(kMultibodyT, kSamples), adaptive(kMultibodyReferenceRtol));
          }};
}

/// The fastest angular rate in the paper's variables z (Omega_i after the N vec(R_i)).
double max_rate(const Path& p, int bodies) {
  double w = 0.0;
  for (const Eigen::VectorXd& z : p.z) {
    for (int i = 0; i < bodies; ++i) w = std::max(w, z.segment<3>(9 * bodies + 3 * i).norm());
  }
  return w;
}

struct Reference {
  Path path;
  double amplification;  ///< G
};

const Reference& reference(const MultibodyScenario& s) {
  static std::map<std::string, Reference> cache;
  auto it = cache.find(s.name);
  if (it == cache.end()) {
    Path ref = s.run("gsl-rk8pd", CoordinateModel::Quaternion, adaptive(kMultibodyReferenceRtol));
    EXPECT_TRUE(ref.stats.ok()) << ref.stats.brief();
    const Path check = s.run("odeint-rkf78", CoordinateModel::Matrix, adaptive(kMultibodyCheckRtol));
    EXPECT_TRUE(check.stats.ok()) << check.stats.brief();
    const double d = max_distance(ref, check);
    std::cout << "[ ref      ] " << s.name << ": gsl-rk8pd/quaternion at 1e-14 vs odeint-rkf78/matrix at 1e-13: " << d
              << "\n";
    EXPECT_LT(d, kReferenceAgreement);
    double G = 1.0;
    for (int component = 0; component < 3 * s.bodies; ++component) {
      const Path p = s.perturbed(component, kPerturbation);
      EXPECT_TRUE(p.stats.ok()) << p.stats.brief();
      const double d0 = (p.z.front() - ref.z.front()).norm();
      for (std::size_t k = 0; k < p.z.size(); ++k) G = std::max(G, (p.z[k] - ref.z[k]).norm() / d0);
    }
    std::cout << "[ ref      ] " << s.name << ": error amplification G = " << G << "\n";
    it = cache.emplace(s.name, Reference{std::move(ref), G}).first;
  }
  return it->second;
}

class MultibodyAgreementAll : public ::testing::TestWithParam<Combination> {
 protected:
  void check(const MultibodyScenario& s) {
    const Combination& c = GetParam();
    const Reference& r = reference(s);
    const Path& ref = r.path;
    const bool fixed_step = is_fixed_step(c.method);
    if (baselines::solver_info(c.method).projects_onto_invariants) {
      // The multibody systems give no invariant to project onto: refused, with the reason
      // (CoordinateOde::projection_refusal).
      EXPECT_THROW((void)s.run(c.method, c.model, adaptive(kMultibodyRtol)), InvalidInput);
      return;
    }
    const Path p = s.run(c.method, c.model, fixed_step ? fixed(kFixedStep) : adaptive(kMultibodyRtol));
    ASSERT_TRUE(p.stats.ok()) << p.stats.brief();
    ASSERT_EQ(p.z.size(), ref.z.size());
    const double err = max_distance(p, ref);
    const double w = std::max(s.gravity_rate, max_rate(ref, s.bodies));
    const double bound =
        r.amplification * (fixed_step ? kMultibodyT * w * std::pow(kFixedStep * w, 4) : adaptive_bound(p, kMultibodyRtol));
    std::ostringstream os;
    os << "[ error    ] " << s.name << " " << c.method << "/" << baselines::to_string(c.model) << ": "
       << std::setprecision(2) << std::scientific << err << " (bound " << bound << ", ratio " << err / bound << "), "
       << p.stats.brief() << "\n";
    std::cout << os.str();
    EXPECT_LT(err, bound);
  }
};

TEST_P(MultibodyAgreementAll, CartPendulumWithControl) { check(cart_scenario()); }
TEST_P(MultibodyAgreementAll, ConnectedBodiesWithControl) { check(bodies_scenario()); }

INSTANTIATE_TEST_SUITE_P(All, MultibodyAgreementAll, ::testing::ValuesIn(all_combinations()),
                         [](const auto& info) { return combination_name(info.param); });

}  // namespace
}  // namespace lgvi::test
