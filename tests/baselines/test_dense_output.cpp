// Output times do not change an adaptive baseline's run (baselines/solver.hpp: the methods step
// over the whole horizon and interpolate the output times), and the interpolated samples are as
// accurate as the steps.
//
//  - Same run on every grid: each adaptive solver on the controlled free body and pendulum of
//    test_agreement.cpp, sampled every 1 ms and on every 1000th of those times (every 1 s): the
//    same accepted and rejected steps, and at the shared times the same samples. A sample is a
//    function of the accepted steps alone (CVODE's Nordsieck polynomial, odeint's dense output,
//    the quintic Hermite interpolant whose y'' difference step depends on the point only), so
//    its interpolation error is the same on both grids and the expected difference is zero: the
//    test asserts equality.
//  - The Hermite interpolant (rkf78, rk8pd, msbdf) is as accurate as a step: its sample at t
//    differs from the end of a run whose horizon ends at t by a local error at most.
//  - Interpolated samples within the solver's promise: the samples every 1 ms against a
//    reference (gsl-rk8pd at rtol 1e-14 on the same grid) stay below the bound
//    test_agreement.cpp derives for the steps, N r (1 + max|y_i|) sqrt(n) (N accepted steps).
//  - The Hermite interpolant is exact for polynomials of its degree: y = t^5 (y' = 5 t^4,
//    which rk8pd and rkf78 integrate exactly) up to the difference quotient of y''.
#include <gtest/gtest.h>

#include <iomanip>
#include <limits>
#include <sstream>

#include "baseline_cases.hpp"

namespace lgvi::test {
namespace {

constexpr double kFineStep = 1e-3;        // the fine output grid
constexpr std::size_t kCoarseEvery = 1000;  // the coarse grid: every 1000th fine time
constexpr double kDenseReferenceRtol = 1e-14;

std::vector<std::string> adaptive_methods() {
  std::vector<std::string> m;
  for (const baselines::SolverInfo& s : baselines::solver_list()) {
    if (s.step_control == baselines::StepControl::Adaptive) m.push_back(s.name);
  }
  return m;
}

std::vector<double> fine_times(double T) {
  return uniform_times(T, static_cast<std::size_t>(std::lround(T / kFineStep)));
}

/// Every `every`-th entry of `times` (the same doubles, not recomputed), and the last.
std::vector<double> every_nth(const std::vector<double>& times, std::size_t every) {
  std::vector<double> out;
  for (std::size_t k = 0; k < times.size(); k += every) out.push_back(times[k]);
  if (out.back() != times.back()) out.push_back(times.back());
  return out;
}

struct Case {
  std::string name;
  double T;
  std::function<Trajectory(const std::string&, CoordinateModel, const std::vector<double>&, const SolverSettings&)>
      run;
};

std::vector<Case> cases() {
  static const FreeRigidBody body = free_body();
  static const Pendulum3D pendulum = Pendulum3D::paper();
  return {{"free body", 5.0,
           [](const std::string& method, CoordinateModel model, const std::vector<double>& times,
              const SolverSettings& s) {
             return run_attitude(method, model, body, free_body_control, free_body_R0(), free_body_Omega0(), times, s);
           }},
          {"pendulum", 3.0, [](const std::string& method, CoordinateModel model, const std::vector<double>& times,
                               const SolverSettings& s) {
             return run_attitude(method, model, pendulum, pendulum_control, pendulum_R0(), pendulum_Omega0(), times, s);
           }}};
}

std::vector<CoordinateModel> models_of(const std::string& method) {
  std::vector<CoordinateModel> m = {CoordinateModel::Quaternion, CoordinateModel::Matrix};
  if (baselines::solver_info(method).post_step_hook) m.push_back(CoordinateModel::QuaternionRenormalized);
  return m;
}

TEST(DenseOutput, TheOutputGridDoesNotChangeTheRun) {
  for (const Case& c : cases()) {
    const std::vector<double> fine = fine_times(c.T);
    const std::vector<double> coarse = every_nth(fine, kCoarseEvery);
    for (const std::string& method : adaptive_methods()) {
      for (const CoordinateModel model : models_of(method)) {
        for (const double rtol : {1e-6, 1e-10}) {
          const std::string what = c.name + " " + method + "/" + baselines::to_string(model) + " rtol " +
                                   std::to_string(rtol);
          const Trajectory a = c.run(method, model, fine, adaptive(rtol));
          const Trajectory b = c.run(method, model, coarse, adaptive(rtol));
          ASSERT_TRUE(a.stats.ok()) << what << ": " << a.stats.brief();
          ASSERT_TRUE(b.stats.ok()) << what << ": " << b.stats.brief();
          ASSERT_EQ(a.t.size(), fine.size()) << what;
          ASSERT_EQ(b.t.size(), coarse.size()) << what;
          EXPECT_EQ(a.stats.steps, b.stats.steps) << what;
          EXPECT_EQ(a.stats.rejected_steps, b.stats.rejected_steps) << what;
          // The integration's own evaluations are the same; only the interpolation's differ.
          EXPECT_EQ(a.stats.rhs_evaluations - a.stats.output_rhs_evaluations,
                    b.stats.rhs_evaluations - b.stats.output_rhs_evaluations)
              << what;
          double d = 0.0;
          for (std::size_t k = 0; k < coarse.size(); ++k) {
            const std::size_t j = std::min(k * kCoarseEvery, fine.size() - 1);
            ASSERT_EQ(a.t[j], b.t[k]) << what;
            d = std::max(d, state_distance(a.R[j], a.Omega[j], b.R[k], b.Omega[k]));
          }
          EXPECT_EQ(d, 0.0) << what;
          if (rtol == 1e-6 && model == CoordinateModel::Quaternion) {
            std::cout << "[ grids    ] " << what << ": " << a.stats.steps << " steps, " << a.stats.rejected_steps
                      << " rejected on both; RHS " << a.stats.rhs_evaluations << " (" << a.stats.output_rhs_evaluations
                      << " for output) every 1 ms, " << b.stats.rhs_evaluations << " ("
                      << b.stats.output_rhs_evaluations << ") every 1 s; shared samples " << d << " apart\n";
          }
        }
      }
    }
  }
}

TEST(DenseOutput, InterpolatedSamplesKeepTheSolversPromise) {
  for (const Case& c : cases()) {
    const std::vector<double> fine = fine_times(c.T);
    const Trajectory ref = c.run("gsl-rk8pd", CoordinateModel::Quaternion, fine, adaptive(kDenseReferenceRtol));
    ASSERT_TRUE(ref.stats.ok()) << ref.stats.brief();
    double y_max = 1.0;
    for (const Vec3& O : ref.Omega) y_max = std::max(y_max, O.cwiseAbs().maxCoeff());
    for (const std::string& method : adaptive_methods()) {
      for (const CoordinateModel model : {CoordinateModel::Quaternion, CoordinateModel::Matrix}) {
        for (const double rtol : {1e-6, 1e-9}) {
          const Trajectory tr = c.run(method, model, fine, adaptive(rtol));
          ASSERT_TRUE(tr.stats.ok()) << tr.stats.brief();
          const double err = max_distance(tr, ref);
          const double n = model == CoordinateModel::Matrix ? 12.0 : 7.0;
          const double bound = static_cast<double>(tr.stats.steps) * rtol * (1.0 + y_max) * std::sqrt(n);
          std::ostringstream os;
          os << "[ dense    ] " << c.name << " " << method << "/" << baselines::to_string(model) << " rtol " << rtol
             << ": " << std::setprecision(3) << err << " over " << fine.size() << " samples (bound " << bound
             << ", ratio " << err / bound << "), " << tr.stats.steps << " steps\n";
          std::cout << os.str();
          EXPECT_LT(err, bound) << c.name << " " << method << "/" << baselines::to_string(model) << " rtol " << rtol;
        }
      }
    }
  }
}

/// The free-body scene (experiments/scenes/free-body.toml): torque-free, spinning at 3 rad/s near
/// its intermediate axis, sampled on its grid of 5 ms. At rtol 1e-6 rk8pd steps ~0.6 s here
/// (h w ~ 1.8 rad per step).
Case free_body_scene() {
  static const FreeRigidBody body(Vec3(0.13, 0.28, 0.17).asDiagonal());
  return {"free-body scene", 50.0,
          [](const std::string& method, CoordinateModel model, const std::vector<double>& times,
             const SolverSettings& s) {
            return run_attitude(method, model, body, {}, Mat3::Identity(), Vec3(0.05, 0.05, 3.0), times, s);
          }};
}

/// Largest distance between a run's interpolated samples at times[j] (j in probes) and the final
/// states of runs whose horizon ends there.
double interpolated_minus_landed(const Case& c, const std::string& method, CoordinateModel model,
                                 const std::vector<double>& times, const std::vector<std::size_t>& probes,
                                 const SolverSettings& settings, Trajectory* dense_out = nullptr) {
  const Trajectory dense = c.run(method, model, times, settings);
  EXPECT_TRUE(dense.stats.ok()) << dense.stats.brief();
  double worst = 0.0;
  for (const std::size_t j : probes) {
    const Trajectory landed = c.run(method, model, {0.0, times[j]}, settings);
    EXPECT_TRUE(landed.stats.ok()) << landed.stats.brief();
    if (!dense.stats.ok() || !landed.stats.ok()) return std::numeric_limits<double>::infinity();
    worst = std::max(worst, state_distance(dense.R[j], dense.Omega[j], landed.R[1], landed.Omega[1]));
  }
  if (dense_out != nullptr) *dense_out = dense;
  return worst;
}

TEST(DenseOutput, HermiteSamplesAreWithinALocalErrorOfTheSteps) {
  // The methods without dense output of their own (rkf78, rk8pd, msbdf: solver_detail.hpp,
  // HermiteOutput). A run whose horizon ends at t_j takes the same steps as the long run up to
  // t_j and then one shortened step onto it (the first step does not depend on the horizon
  // once it exceeds that step), so its final state differs from the long run's interpolated
  // sample at t_j by the interpolant's error plus the shortened step's local error, each
  // promised below r (1 + |y_i|) per component (sqrt(n) of that in the 2-norm of the distance):
  // bound 4 r (1 + max|y_i|) sqrt(n), a factor 2 for each.
  std::vector<Case> all = cases();
  all.push_back(free_body_scene());
  for (const Case& c : all) {
    const bool scene = c.T > 10.0;
    const std::vector<double> times = scene ? uniform_times(c.T, 10000) : fine_times(c.T);
    const std::vector<std::size_t> probes =
        scene ? std::vector<std::size_t>{1234, 3456, 5678, 7890, 9999} : std::vector<std::size_t>{617, 1234, 1851,
                                                                                                2468, 2999};
    for (const std::string method : {"odeint-rkf78", "gsl-rk8pd", "gsl-msbdf"}) {
      for (const CoordinateModel model : {CoordinateModel::Quaternion, CoordinateModel::Matrix}) {
        for (const double rtol : {1e-6, 1e-10}) {
          Trajectory dense;
          const double worst = interpolated_minus_landed(c, method, model, times, probes, adaptive(rtol), &dense);
          double y_max = 1.0;
          for (const Vec3& O : dense.Omega) y_max = std::max(y_max, O.cwiseAbs().maxCoeff());
          const double n = model == CoordinateModel::Matrix ? 12.0 : 7.0;
          const double bound = 4.0 * rtol * (1.0 + y_max) * std::sqrt(n);
          std::ostringstream os;
          os << "[ hermite  ] " << c.name << " " << method << "/" << baselines::to_string(model) << " rtol " << rtol
             << ": interpolated - landed " << std::setprecision(3) << worst << " (bound " << bound << ", ratio "
             << worst / bound << "), " << dense.stats.steps << " steps";
          if (scene && rtol == 1e-6 && method != "gsl-msbdf" && model == CoordinateModel::Quaternion) {
            // The bound tells the interpolant's degree: without the midpoint (a quintic) the
            // longest steps (quaternion model: h w ~ 1.8) exceed it.
            SolverSettings quintic = adaptive(rtol);
            quintic.hermite_midpoint = false;
            const double q = interpolated_minus_landed(c, method, model, times, probes, quintic);
            os << "; without the midpoint " << q << " (ratio " << q / bound << ")";
            EXPECT_GT(q, bound) << c.name << " " << method << "/" << baselines::to_string(model);
          }
          std::cout << os.str() << "\n";
          EXPECT_LT(worst, bound) << c.name << " " << method << "/" << baselines::to_string(model) << " rtol " << rtol;
        }
      }
    }
  }
}

/// y' = 5 t^4 (y = t^5 from y(0) = 0): a quintic in t.
class QuinticOde final : public baselines::Ode {
 public:
  int dimension() const override { return 1; }
  std::string model_name() const override { return "quintic"; }
  baselines::RhsStatus rhs(double t, const double*, double* f) const override {
    f[0] = 5.0 * t * t * t * t;
    return baselines::RhsStatus::Ok;
  }
  baselines::RhsStatus jacobian(double, const double*, double* J) const override {
    J[0] = 0.0;
    return baselines::RhsStatus::Ok;
  }
  bool time_dependent() const override { return true; }
};

TEST(DenseOutput, HermiteInterpolantIsExactForQuintics) {
  // Over [0, 2], samples every 0.01. The steps integrate y' = 5 t^4 exactly (a quadrature of a
  // quartic by methods of order 7 and 8), so the error is the interpolant's (degree 8): zero for
  // a quintic but for the central difference of y'' = 20 t^3 with step e <= 2 cbrt(eps)
  // (truncation 20 t e^2 <= 6e-9) and its round-off (eps |f| / e <= 7e-9 at t = 2), weighted by
  // <= 0.018 h^2 <= 0.07 (h <= 2): below 1e-9. A cubic interpolant would be off by
  // h^4 max|y''''| / 384 = 0.6 h^4 (0.04 at h = 0.5).
  const QuinticOde ode;
  const double y0[] = {0.0};
  const std::vector<double> times = uniform_times(2.0, 200);
  for (const std::string method : {"gsl-rk8pd", "odeint-rkf78"}) {
    double err = 0.0;
    const Stats stats = baselines::integrate(method, ode, y0, times, adaptive(1e-10),
                                             [&](std::size_t, double t, const double* y) {
                                               err = std::max(err, std::abs(y[0] - t * t * t * t * t));
                                               return true;
                                             });
    ASSERT_TRUE(stats.ok()) << stats.brief();
    std::cout << "[ quintic  ] " << method << ": max |p(t) - t^5| = " << err << " over " << times.size()
              << " samples, " << stats.steps << " steps\n";
    EXPECT_LT(err, 1e-9) << method;
    EXPECT_LT(stats.steps, times.size() / 4) << method << ": the samples must come from the interpolant";
  }
}

}  // namespace
}  // namespace lgvi::test
