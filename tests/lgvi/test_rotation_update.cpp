// The implicit rotation update h hat(p) = F J_d - J_d F^T (eqs. 8, 21), RotationUpdateSolver.
//
// Random batches: seeded random valid inertias (principal moments J1, J2 in [0.1, 1], J3 in
// [max(|J1 - J2|, 0.1), J1 + J2], so every triangle inequality holds; random principal axes) and
// momenta h p = J Omega_h with |Omega_h| <= 0.1, 0.5, 1.0 (half exactly at the bound, half
// log-uniform down to 1e-8 so that the small-angle branches are exercised too).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "lgvi/rotation_update.hpp"
#include "lgvi/so3.hpp"
#include "test_support.hpp"

namespace lgvi {
namespace {

using test::kEps;
using test::roundoff;

// O(1) rotation matrix built in <= 8 flops per entry (see test_so3.cpp): 128 eps.
using test::kMatTol;

Inertia paper_inertia() { return Inertia::from(Vec3(0.13, 0.28, 0.17).asDiagonal()); }

/// A random inertia: principal moments in [0.1, 1] satisfying the triangle inequality (J3 drawn
/// between max(|J1 - J2|, 0.1) and J1 + J2), random principal axes, symmetrized to round-off.
template <class Rng>
Mat3 random_valid_inertia(Rng& rng) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double J1 = 0.1 + 0.9 * uniform(rng), J2 = 0.1 + 0.9 * uniform(rng);
  const double lo = std::max(std::abs(J1 - J2), 0.1), hi = J1 + J2;
  const double J3 = lo + (hi - lo) * uniform(rng);
  const Mat3 Q = so3::random_rotation(rng);
  const Mat3 J = Q * Vec3(J1, J2, J3).asDiagonal() * Q.transpose();
  return 0.5 * (J + J.transpose());
}

struct Sample {
  Inertia inertia;
  Vec3 hp;
};

std::vector<Sample> random_batch(double max_h_omega, int n, std::uint64_t salt) {
  auto rng = test::make_rng(salt);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> normal;
  std::vector<Sample> batch;
  for (int k = 0; k < n; ++k) {
    const Mat3 J = random_valid_inertia(rng);
    const Vec3 n_dir = Vec3(normal(rng), normal(rng), normal(rng)).normalized();
    const double mag =
        k % 2 == 0 ? max_h_omega : max_h_omega * std::pow(1e-8 / max_h_omega, uniform(rng));
    const Inertia I = Inertia::from(J);
    batch.push_back({I, I.J * (mag * n_dir)});
  }
  return batch;
}

/// a |f| + b |f|^2 = sin(theta) + 1 - cos(theta) for the rotation F (chart independent): the
/// size of the terms of G relative to ||J|| (see rotation_update.hpp).
double term_size(const Mat3& F) {
  const double theta = so3::log(F).norm();
  return std::sin(theta) + 1.0 - std::cos(theta);
}

/// The solver's documented convergence test, relative to |h p| as summary.residual is:
/// relative_tolerance (|h p| + ||J||_F size) / |h p| (+ the negligible absolute tolerance).
/// size is recomputed here from F (via log) rather than from the solver's f: equal to a few eps
/// relative, hence the factor (1 + roundoff(1, 1)) on the bound.
double residual_contract(const RotationUpdateSolver& s, const Vec3& hp, const Mat3& F) {
  const double h = hp.norm();
  return (1.0 + roundoff(1.0, 1)) *
         (s.options().relative_tolerance * (h + s.inertia().J.norm() * term_size(F)) / h +
          s.options().absolute_tolerance / h);
}

/// Derivative of F -> vee(F J_d - J_d F^T) along F exp(hat(d)): column j is
/// vee(F hat(e_j) J_d + J_d hat(e_j) F^T). Its smallest singular value bounds how far two
/// approximate solutions can be apart given their residuals.
double sensitivity(const Mat3& F, const Mat3& Jd) {
  Mat3 A;
  for (int j = 0; j < 3; ++j) {
    const Mat3 E = so3::hat(Vec3::Unit(j));
    A.col(j) = so3::vee(F * E * Jd + Jd * E * F.transpose());
  }
  // Smallest singular value of A: square root of the smallest eigenvalue of A^T A.
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(A.transpose() * A, Eigen::EigenvaluesOnly);
  return 1.0 / std::sqrt(std::max(eig.eigenvalues()(0), 0.0));
}

struct BatchParam {
  std::string name;
  double max_h_omega;
};
std::ostream& operator<<(std::ostream& os, const BatchParam& p) { return os << p.name; }

class RandomBatch : public testing::TestWithParam<BatchParam> {
 protected:
  static constexpr int kSamples = 400;
  std::vector<Sample> batch() const {
    return random_batch(GetParam().max_h_omega, kSamples,
                        601 + static_cast<std::uint64_t>(1000 * GetParam().max_h_omega));
  }
};

// Converges for every sample; at h|Omega| <= 0.1 within 5 Newton iterations in the primary
// (Cayley) chart (the paper: "converges to machine precision within two or three iterations").
// At 0.5 and 1.0 more iterations are allowed (up to the cap); the maxima are recorded.
TEST_P(RandomBatch, ConvergesAndCountsIterations) {
  int max_iterations = 0, fallbacks = 0;
  double max_residual = 0.0;
  for (const Sample& s : batch()) {
    const RotationUpdateSolver solver(s.inertia);
    Mat3 F = Mat3::Identity();
    const RotationUpdateSummary r = solver.solve(s.hp, F);
    ASSERT_TRUE(r.converged()) << r.brief() << "\nJ =\n"
                               << s.inertia.J << "\nhp = " << s.hp.transpose();
    // The acceptance bound on the residual relative to |h p|. The convergence test alone
    // allows 16 eps (|h p| + ||J|| size), up to ~1e-14 for ill-conditioned J; the polishing step
    // brings it to the few-eps floor.
    EXPECT_LE(r.residual(), 1e-14) << r.brief();
    if (GetParam().max_h_omega <= 0.1) {
      EXPECT_LE(r.iterations, 5) << r.brief();
      EXPECT_FALSE(r.used_fallback) << r.brief();
    }
    max_iterations = std::max(max_iterations, r.iterations);
    max_residual = std::max(max_residual, r.residual());
    fallbacks += r.used_fallback;
  }
  std::cout << "[ measured ] h|Omega| <= " << GetParam().max_h_omega << ": max Newton iterations "
            << max_iterations << ", max relative residual " << max_residual << ", fallbacks "
            << fallbacks << " of " << kSamples << "\n";
  RecordProperty("max_newton_iterations", max_iterations);
  RecordProperty("max_relative_residual", std::to_string(max_residual));
}

// Residuals at round-off. (1) summary.residual = |G(f)| / |h p| obeys the documented test. For
// this family ||J||_F <= sqrt(6), J_min >= 0.1 and size ~ |Omega_h| <= |h p| / J_min, so the
// contract is <= 16 eps (1 + 25) ~ 9e-14; the maximum is printed by the test above.
// (2) Independently, the MATRIX residual vee(F J_d - J_d F^T) - h p, formed from the returned F:
// it equals G(f) up to forming F (kMatTol, times ||J_d||) and the two 3-term products and the
// subtraction (3 flops of ||J_d||), and evaluating G itself (1 flop of |h p| + ||J|| size).
TEST_P(RandomBatch, ResidualsAreAtRoundOff) {
  double max_matrix_residual = 0.0;  // relative to ||J_d||_F
  for (const Sample& s : batch()) {
    const RotationUpdateSolver solver(s.inertia);
    Mat3 F = Mat3::Identity();
    const RotationUpdateSummary r = solver.solve(s.hp, F);
    ASSERT_TRUE(r.converged()) << r.brief();
    const double h = s.hp.norm();
    if (h > 0.0) {
      EXPECT_LE(r.residual(), residual_contract(solver, s.hp, F)) << r.brief();
    }
    const double Jd = s.inertia.Jd.norm(), J = s.inertia.J.norm();
    const double bound =
        r.residual() * h + (kMatTol + roundoff(1.0, 3)) * Jd + roundoff(h + J * term_size(F), 1);
    const double matrix_residual = solver.matrix_residual(F, s.hp).norm();
    EXPECT_LE(matrix_residual, bound)
        << r.brief() << " (bound relative to ||J_d|| " << bound / Jd << ")";
    EXPECT_TRUE(std::isfinite(r.residual()));
    max_matrix_residual = std::max(max_matrix_residual, matrix_residual / Jd);
  }
  std::cout << "[ measured ] h|Omega| <= " << GetParam().max_h_omega
            << ": max |matrix residual| / ||J_d||_F = " << max_matrix_residual << " ("
            << max_matrix_residual / kEps << " eps)\n";
}

TEST_P(RandomBatch, ResultIsARotation) {
  for (const Sample& s : batch()) {
    const RotationUpdateSolver solver(s.inertia);
    Mat3 F = Mat3::Identity();
    ASSERT_TRUE(solver.solve(s.hp, F).converged());
    EXPECT_LE(so3::orthogonality_error(F), kMatTol);
    EXPECT_LE(so3::determinant_error(F), kMatTol);
  }
}

// The Cayley and exponential parametrizations solve the same equation: their F agree to the
// residual of each, propagated through the inverse derivative of the matrix equation
// (|F_c - F_e|_F <= sqrt(2) |A^{-1}| |G_c - G_e|, A from `sensitivity`), plus evaluating each G
// (1 flop of its terms, size <= 3) and forming each F (kMatTol).
TEST_P(RandomBatch, CayleyAndExponentialAgree) {
  for (const Sample& s : batch()) {
    const RotationUpdateSolver solver(s.inertia);
    Vec3 fc, fe;
    const RotationUpdateSummary rc = solver.solve_in(Parametrization::Cayley, s.hp, fc);
    const RotationUpdateSummary re = solver.solve_in(Parametrization::Exponential, s.hp, fe);
    ASSERT_TRUE(rc.converged()) << rc.brief();
    ASSERT_TRUE(re.converged()) << re.brief();
    EXPECT_EQ(rc.parametrization, Parametrization::Cayley);
    EXPECT_EQ(re.parametrization, Parametrization::Exponential);
    const Mat3 Fc = rotation_from(Parametrization::Cayley, fc);
    const Mat3 Fe = rotation_from(Parametrization::Exponential, fe);
    const double h = s.hp.norm();
    const double dG =
        (rc.residual() + re.residual()) * h + 2.0 * roundoff(h + 3.0 * s.inertia.J.norm());
    const double tol = std::sqrt(2.0) * sensitivity(Fc, s.inertia.Jd) * dG + 2.0 * kMatTol;
    EXPECT_LE((Fc - Fe).norm(), tol) << "cayley: " << rc.brief() << "\nexponential: " << re.brief();
  }
}

INSTANTIATE_TEST_SUITE_P(HOmega, RandomBatch,
                         testing::Values(BatchParam{"up_to_0_1", 0.1}, BatchParam{"up_to_0_5", 0.5},
                                         BatchParam{"up_to_1_0", 1.0}),
                         [](const testing::TestParamInfo<BatchParam>& i) { return i.param.name; });

// The default relative_tolerance (16 eps of G's term size) rests on Newton settling within twice
// the evaluation error of G, <= 8 eps of the term size (rotation_update.hpp). Check that floor
// directly: with a zero tolerance Newton runs all its iterations, and after 12 (enough for
// |Omega_h| <= 0.5, which converges in <= 4) the residual must be at most 8 eps of the term size,
// in both charts. Momenta log-uniform in [1e-6, 0.5]: the exponential chart used a cancelling
// (1 - cos t)/t^2 that left errors ~eps/t of the term size (observed 190 eps at t ~ 1e-3).
TEST(RotationUpdate, NewtonSettlesWithinTheEvaluationFloor) {
  auto rng = test::make_rng(605);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> normal;
  RotationUpdateOptions o;
  o.relative_tolerance = 0.0;
  o.absolute_tolerance = 0.0;
  o.max_iterations = 12;
  double worst[2] = {0.0, 0.0};
  for (int k = 0; k < 10000; ++k) {
    const Mat3 J = random_valid_inertia(rng);
    const Vec3 n = Vec3(normal(rng), normal(rng), normal(rng)).normalized();
    const double mag = 0.5 * std::pow(2e-6, uniform(rng));
    const Inertia I = Inertia::from(J);
    const Vec3 hp = I.J * (mag * n);
    const RotationUpdateSolver solver(I, o);
    for (const Parametrization p : {Parametrization::Cayley, Parametrization::Exponential}) {
      Vec3 f;
      const RotationUpdateSummary r = solver.solve_in(p, hp, f);
      // The rotation angle is within a few percent of |Omega_h| here: size from the reference
      // solve (default options) keeps the bound independent of the run under test.
      Mat3 F;
      ASSERT_TRUE(RotationUpdateSolver(I).solve(hp, F).converged());
      const double scale = hp.norm() + I.J.norm() * term_size(F);
      const double floor_in_eps = r.residual() * hp.norm() / (kEps * scale);
      EXPECT_LE(floor_in_eps, 8.0) << to_string(p) << " |Omega_h| = " << mag;
      worst[p == Parametrization::Exponential] =
          std::max(worst[p == Parametrization::Exponential], floor_in_eps);
    }
  }
  std::cout << "[ measured ] Newton residual floor / (eps term size): cayley " << worst[0]
            << ", exponential " << worst[1] << "\n";
}

// --- Special right-hand sides ------------------------------------------------------------------

// h p = 0: F = I exactly (warm start f = 0 already has G = 0), no iteration, in either chart.
TEST(RotationUpdate, ZeroMomentumGivesIdentityExactly) {
  for (const Parametrization p : {Parametrization::Cayley, Parametrization::Exponential}) {
    RotationUpdateOptions o;
    o.primary = p;
    const RotationUpdateSolver solver(paper_inertia(), o);
    Mat3 F = Mat3::Constant(7.0);
    const RotationUpdateSummary r = solver.solve(Vec3::Zero(), F);
    EXPECT_TRUE(r.converged()) << r.brief();
    EXPECT_EQ(r.iterations, 0);
    EXPECT_EQ(r.residual(), 0.0);
    EXPECT_FALSE(r.used_fallback);
    EXPECT_EQ(F, Mat3::Identity());
  }
}

const Mat3 kSentinel = Mat3::Constant(42.0);

struct OutsideCase {
  std::string name;
  Vec3 hp;
};
std::ostream& operator<<(std::ostream& os, const OutsideCase& c) { return os << c.name; }

std::vector<OutsideCase> outside_cases() {
  const double bound = RotationUpdateSolver(paper_inertia()).domain_bound();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  return {
      {"just_beyond_bound_e1", Vec3(bound * (1.0 + 1e-12), 0.0, 0.0)},
      {"just_beyond_bound_generic", bound * (1.0 + 1e-12) * Vec3(1, -2, 2).normalized()},
      {"ten_times_bound", 10.0 * bound * Vec3(0.3, 0.4, -0.5).normalized()},
      {"nan", Vec3(0.01, nan, 0.0)},
      {"inf", Vec3(inf, 0.0, 0.0)},
  };
}

class OutsideDomain : public testing::TestWithParam<OutsideCase> {};

// Beyond sqrt(2) ||J_d||_F no rotation solves the equation (and NaN/Inf are no momenta): the
// solver says so without iterating and leaves F untouched.
TEST_P(OutsideDomain, ReportsWithoutIteratingAndLeavesFUnchanged) {
  const RotationUpdateSolver solver(paper_inertia());
  Mat3 F = kSentinel;
  const RotationUpdateSummary r = solver.solve(GetParam().hp, F);
  EXPECT_EQ(r.status, RotationUpdateStatus::OutsideDomain);
  EXPECT_FALSE(r.converged());
  EXPECT_EQ(r.iterations, 0);
  EXPECT_FALSE(r.used_fallback);
  EXPECT_EQ(F, kSentinel);
  EXPECT_NE(r.brief().find("outside"), std::string::npos) << r.brief();
}

INSTANTIATE_TEST_SUITE_P(Momenta, OutsideDomain, testing::ValuesIn(outside_cases()),
                         [](const testing::TestParamInfo<OutsideCase>& i) { return i.param.name; });

TEST(RotationUpdate, DomainBoundIsSqrt2TimesFrobeniusNormOfJd) {
  const Inertia I = paper_inertia();
  // J_d = diag(0.16, 0.01, 0.12): ||J_d||_F = sqrt(0.0401).
  EXPECT_NEAR(RotationUpdateSolver(I).domain_bound(), std::sqrt(2.0 * 0.0401), roundoff(0.3, 4));
}

// --- Reachable set along a principal axis -------------------------------------------------------
// For J = diag(J1, J2, J3), J_d = diag(d1, d2, d3) with d_j + d_k = J_i ({i, j, k} a permutation),
// and e1^T vee(F J_d - J_d F^T) = F32 d2 - F23 d3 <= d2 + d3 = J1 because |F_ij| <= 1 and
// d_j >= 0; equality at F = rotation by pi/2 about e1 (F32 = 1, F23 = -1). Likewise for e2, e3.
// So h p = alpha e_i has no solution for alpha > J_i, even though J_i < sqrt(2) ||J_d||_F.

double axis_component(const Inertia& I, const Mat3& F, int i) {
  return so3::vee(F * I.Jd - I.Jd * F.transpose())(i);
}

TEST(RotationUpdateReachable, PrincipalAxisComponentIsAtMostJi) {
  const Inertia I = paper_inertia();
  auto rng = test::make_rng(602);
  for (int i = 0; i < 3; ++i) {
    const double Ji = I.J(i, i);
    // The maximizer: a quarter turn about e_i (entries of F exact to kMatTol; 3 flops of ||J_d||).
    const double at_quarter_turn = axis_component(I, so3::exp(M_PI / 2 * Vec3::Unit(i)), i);
    EXPECT_NEAR(at_quarter_turn, Ji, (kMatTol + roundoff(1.0, 3)) * I.Jd.norm()) << "axis " << i;
    // No rotation exceeds it (20000 Haar samples plus small perturbations of the maximizer).
    double best = -1.0;
    for (int k = 0; k < 20000; ++k) {
      Mat3 F = so3::random_rotation(rng);
      if (k % 2 == 1) F = so3::exp(M_PI / 2 * Vec3::Unit(i)) * so3::exp(1e-2 * so3::log(F));
      best = std::max(best, axis_component(I, F, i));
    }
    EXPECT_LE(best, Ji + (kMatTol + roundoff(1.0, 3)) * I.Jd.norm()) << "axis " << i;
    EXPECT_GT(best, 0.999 * Ji) << "axis " << i << ": samples near the maximizer reach it";
    EXPECT_LT(Ji, RotationUpdateSolver(I).domain_bound());
  }
}

// Between J_i and the domain bound there is no solution: after both charts failed, the solver
// names the cause (OutsideDomain with axis_ratio = |(h p)_i| / J_i > 1, not "not converged"),
// F is left unchanged, and the summary is finite (no NaN anywhere).
TEST(RotationUpdateReachable, NoSolutionInsideBoundIsNamedOutsideTheDomain) {
  const Inertia I = paper_inertia();
  const RotationUpdateSolver solver(I);
  for (int i = 0; i < 3; ++i) {
    const double Ji = I.J(i, i);
    for (const double alpha :
         {Ji * (1.0 + 1e-9), Ji * (1.0 + 1e-6), 0.5 * (Ji + solver.domain_bound())}) {
      const Vec3 hp = alpha * Vec3::Unit(i);
      ASSERT_LE(hp.norm(), solver.domain_bound());
      Mat3 F = kSentinel;
      const RotationUpdateSummary r = solver.solve(hp, F);
      EXPECT_EQ(r.status, RotationUpdateStatus::OutsideDomain) << r.brief();
      // paper_inertia is diagonal: the eigendecomposition is exact to a few ulps of J_i.
      EXPECT_NEAR(r.axis_ratio, alpha / Ji, 1e-14 * alpha / Ji);
      EXPECT_EQ(F, kSentinel);
      EXPECT_TRUE(r.used_fallback);
      EXPECT_GT(r.iterations, 0);
      EXPECT_LE(r.iterations, 2 * solver.options().max_iterations);
      EXPECT_TRUE(std::isfinite(r.residual())) << r.brief();
      EXPECT_GT(r.residual(), 0.0) << r.brief();
      EXPECT_TRUE(std::isfinite(r.rhs_norm));
      EXPECT_NE(r.brief().find("no rotation solves the update"), std::string::npos) << r.brief();
      EXPECT_EQ(r.brief().find("nan"), std::string::npos) << r.brief();
    }
  }
}

// Up to the fold alpha = J_i the solver converges, to the quarter-turn-or-less branch:
// F = rotation about e_i by asin(alpha / J_i). Near the fold the root is double, Newton is
// linear (error halves per step): reaching J_i dtheta^2 / 2 <= tol = 16 eps (J_i + 2 ||J||_F)
// ~ 3e-15 from dtheta ~ 1 takes log2(1 / sqrt(2 tol / J_i)) ~ 22 < 30 iterations even at
// alpha = J_i. The angle is sensitive:
// dtheta = dG / (J_i cos theta) with dG the residual plus evaluating G (1 flop of |h p| + 2||J||),
// and the reference asin(x) amplifies x's rounding (eps) by 1 / cos theta.
TEST(RotationUpdateReachable, ConvergesUpToTheFold) {
  const Inertia I = paper_inertia();
  const RotationUpdateSolver solver(I);
  for (int i = 0; i < 3; ++i) {
    const double Ji = I.J(i, i);
    int last_iterations = 0;
    for (int k = 1; k <= 13; ++k) {
      const double x = k == 13 ? 1.0 : 1.0 - std::pow(10.0, -k);
      const Vec3 hp = (x * Ji) * Vec3::Unit(i);
      Mat3 F = kSentinel;
      const RotationUpdateSummary r = solver.solve(hp, F);
      ASSERT_TRUE(r.converged()) << "axis " << i << " alpha/J_i = 1 - 1e-" << k << ": "
                                 << r.brief();
      const double theta = std::asin(x);
      const double cos_theta = std::max(std::cos(theta), 1e-300);
      const double dG = r.residual() * hp.norm() + roundoff(hp.norm() + 2.0 * I.J.norm());
      const double angle_tol = (dG / Ji + 2.0 * kEps) / cos_theta + roundoff(M_PI, 4);
      const Vec3 w = so3::log(F);
      EXPECT_NEAR(w(i), theta, k == 13 ? std::sqrt(4.0 * dG / Ji) + roundoff(M_PI, 4) : angle_tol)
          << "axis " << i << " k " << k;
      EXPECT_LE((w - w(i) * Vec3::Unit(i)).norm(), roundoff(M_PI, 4)) << "stays on the axis";
      last_iterations = r.iterations;
    }
    std::cout << "[ measured ] axis " << i << ": " << last_iterations
              << " Newton iterations at alpha = J_i (the fold)\n";
  }
}

// The smallest failing |h p| along each principal axis (bisection over doubles between
// alpha = J_i, which converges, and J_i (1 + 1e-6), which must not; it finds a transition point,
// the first one if there is a single transition). It must fail once alpha - J_i (the least
// possible |G|, from the bound above) exceeds the convergence tolerance
// relative_tolerance (alpha + ||J||_F size), size = sin + 1 - cos <= 1 + sqrt(2).
TEST(RotationUpdateReachable, FailureThresholdIsJiWithinTolerance) {
  const Inertia I = paper_inertia();
  const RotationUpdateSolver solver(I);
  for (int i = 0; i < 3; ++i) {
    const double Ji = I.J(i, i);
    auto converges = [&](double alpha) {
      Mat3 F;
      return solver.solve(alpha * Vec3::Unit(i), F).converged();
    };
    double lo = Ji, hi = Ji * (1.0 + 1e-6);
    ASSERT_TRUE(converges(lo));
    ASSERT_FALSE(converges(hi));
    while (std::nextafter(lo, hi) < hi) {
      const double mid = 0.5 * (lo + hi);
      if (mid <= lo || mid >= hi) break;
      (converges(mid) ? lo : hi) = mid;
    }
    const double tol =
        solver.options().relative_tolerance * (Ji + (1.0 + std::sqrt(2.0)) * I.J.norm());
    const double ulp = std::nextafter(Ji, 2.0 * Ji) - Ji;
    std::cout.precision(17);
    std::cout << "[ measured ] axis " << i << ": J_i = " << Ji
              << ", smallest failing |h p| = " << hi << " = J_i + " << std::round((hi - Ji) / ulp)
              << " ulp (J_i (1 + " << (hi - Ji) / Ji << "))\n";
    std::cout.precision(6);
    EXPECT_GT(hi, Ji);
    EXPECT_LE(hi, Ji + tol + 2.0 * ulp) << "axis " << i;
  }
}

// --- Fallback -----------------------------------------------------------------------------------
// max_iterations applies to each chart. When one chart needs more Newton steps than the other for
// the same h p, a budget equal to the faster chart's count makes exactly the slower chart fail:
// with it as primary, the fallback must run, succeed and be reported. The case is searched for
// (near the folds along the principal axes, then seeded random momenta h p = J Omega_h with
// |Omega_h| in [0.2, 1], where ~5% of the momenta have differing counts) rather than hard-coded,
// and the premise is asserted.
TEST(RotationUpdateFallback, UsedAndSucceedsWhenPrimaryRunsOutOfIterations) {
  const Inertia I = paper_inertia();
  const RotationUpdateSolver probe(I);
  std::vector<Vec3> candidates;
  for (int i = 0; i < 3; ++i) {
    for (int k = 1; k <= 12; ++k) {
      candidates.push_back((I.J(i, i) * (1.0 - std::pow(10.0, -k))) * Vec3::Unit(i));
    }
  }
  auto rng = test::make_rng(604);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(0.2, 1.0);
  for (int k = 0; k < 2000; ++k) {
    const Vec3 n = Vec3(normal(rng), normal(rng), normal(rng)).normalized();
    candidates.push_back(I.J * (uniform(rng) * n));
  }
  Vec3 hp = Vec3::Zero();
  int n_cayley = 0, n_exponential = 0;
  bool found = false;
  for (const Vec3& candidate : candidates) {
    Vec3 f;
    const RotationUpdateSummary rc = probe.solve_in(Parametrization::Cayley, candidate, f);
    const RotationUpdateSummary re = probe.solve_in(Parametrization::Exponential, candidate, f);
    // The slower chart's Newton iterations proper (without the optional polishing step, which
    // is skipped when the budget is used up) must exceed the faster chart's whole count.
    const auto newton_only = [](const RotationUpdateSummary& r) { return r.iterations - r.polished; };
    if (rc.converged() && re.converged() &&
        (newton_only(rc) > re.iterations || newton_only(re) > rc.iterations)) {
      hp = candidate;
      n_cayley = rc.iterations;
      n_exponential = re.iterations;
      found = true;
      break;
    }
  }
  ASSERT_TRUE(found)
      << "no momentum among the candidates where the charts' iteration counts differ";
  const bool cayley_slower = n_cayley > n_exponential;
  RotationUpdateOptions o;
  o.primary = cayley_slower ? Parametrization::Cayley : Parametrization::Exponential;
  const Parametrization other =
      cayley_slower ? Parametrization::Exponential : Parametrization::Cayley;
  o.max_iterations = std::min(n_cayley, n_exponential);
  const RotationUpdateSolver solver(I, o);

  Vec3 f_primary, f_other;
  const RotationUpdateSummary primary_alone = solver.solve_in(o.primary, hp, f_primary);
  ASSERT_EQ(primary_alone.status, RotationUpdateStatus::NotConverged) << primary_alone.brief();
  const RotationUpdateSummary other_alone = solver.solve_in(other, hp, f_other);
  ASSERT_TRUE(other_alone.converged()) << other_alone.brief();

  Mat3 F = kSentinel;
  const RotationUpdateSummary r = solver.solve(hp, F);
  EXPECT_TRUE(r.converged()) << r.brief();
  EXPECT_TRUE(r.used_fallback);
  EXPECT_EQ(r.parametrization, other);
  EXPECT_EQ(r.iterations, primary_alone.iterations + other_alone.iterations);
  EXPECT_EQ(F, rotation_from(other, f_other));
  EXPECT_NE(r.brief().find("after fallback"), std::string::npos) << r.brief();
  EXPECT_LE(so3::orthogonality_error(F), kMatTol);
  std::cout << "[ measured ] fallback case: cayley " << n_cayley << " vs exponential "
            << n_exponential << " iterations; " << r.brief() << "\n";

  // Without the fallback the same solve fails and F is left unchanged.
  o.fallback = false;
  const RotationUpdateSolver no_fallback(I, o);
  Mat3 G = kSentinel;
  const RotationUpdateSummary r2 = no_fallback.solve(hp, G);
  EXPECT_EQ(r2.status, RotationUpdateStatus::NotConverged) << r2.brief();
  EXPECT_FALSE(r2.used_fallback);
  EXPECT_EQ(r2.parametrization, o.primary);
  EXPECT_EQ(r2.iterations, o.max_iterations);
  EXPECT_EQ(G, kSentinel);
}

// Both charts as primary give a converged solve with no fallback on an ordinary momentum, and
// brief() names the status, the chart and the iteration count.
TEST(RotationUpdateFallback, BriefNamesStatusChartAndIterations) {
  for (const Parametrization p : {Parametrization::Cayley, Parametrization::Exponential}) {
    RotationUpdateOptions o;
    o.primary = p;
    const RotationUpdateSolver solver(paper_inertia(), o);
    Mat3 F;
    const RotationUpdateSummary r = solver.solve(Vec3(0.01, -0.02, 0.015), F);
    ASSERT_TRUE(r.converged());
    EXPECT_FALSE(r.used_fallback);
    EXPECT_EQ(r.parametrization, p);
    const std::string b = r.brief();
    EXPECT_NE(b.find("converged in " + std::to_string(r.iterations) + " Newton iterations"),
              std::string::npos)
        << b;
    EXPECT_NE(b.find(to_string(p)), std::string::npos) << b;
  }
}

// The tolerance scales with the size of G's terms: an ill-conditioned inertia in a non-principal
// frame, momentum along the weak axis (|h p| << ||J|| |f|). Regression for the solver reporting
// NotConverged here because |G| <= 4 eps |h p| was below G's round-off floor (it stalled at
// ~2e-15 relative). The dumbbell rod along (1, 1, 1): J = m (l^2 I - rho rho^T) + (2/5) m r^2 I.
TEST(RotationUpdate, ConvergesForIllConditionedInertiaInGenericFrame) {
  const Vec3 rho = 0.15 * Vec3(1, 1, 1).normalized();
  const Mat3 J = rho.squaredNorm() * Mat3::Identity() - rho * rho.transpose() +
                 0.4 * 0.02 * 0.02 * Mat3::Identity();
  const Inertia I = Inertia::from(J);
  const RotationUpdateSolver solver(I);
  auto rng = test::make_rng(603);
  std::normal_distribution<double> normal;
  const Vec3 weak = rho.normalized();
  int max_iterations = 0;
  for (int k = 0; k < 2000; ++k) {
    // Omega_h mostly along the weak axis (the rod), with a random small transverse part.
    const Vec3 Omega_h = 0.5 * weak + 0.02 * Vec3(normal(rng), normal(rng), normal(rng));
    const Vec3 hp = I.J * Omega_h;
    Mat3 F;
    const RotationUpdateSummary r = solver.solve(hp, F);
    ASSERT_TRUE(r.converged()) << r.brief();
    EXPECT_LE(r.residual(), residual_contract(solver, hp, F));
    max_iterations = std::max(max_iterations, r.iterations);
  }
  std::cout << "[ measured ] ill-conditioned generic-frame inertia: max Newton iterations "
            << max_iterations << "\n";
}


// --- A fast spin about a symmetry axis: no solution although |h p| is inside the bound -----------
// J = diag(1, 1, 0.1) in a rotated body frame, h p = h J3 Omega3 along the symmetry axis. Along a
// principal axis the update reaches |(h p)_i| <= J_i only (the reachable-set bound above), so
// h Omega3 = 2 has no solution while |h p| = 0.2 is far below sqrt(2) ||J_d||_F = 1.35. The solver
// must name that cause and the factor 2 (largest admissible step h / 2), not "not converged".
TEST(RotationUpdate, FastSymmetricSpinIsReportedAsOutsideTheDomainWithTheAdmissibleFactor) {
  std::mt19937_64 rng(16);
  const Mat3 Q = so3::random_rotation(rng);
  const Inertia I = Inertia::from(Q * Vec3(1.0, 1.0, 0.1).asDiagonal() * Q.transpose());
  const RotationUpdateSolver solver(I);
  const Vec3 axis = Q.col(2);  // the symmetry axis, body frame
  for (const double h_omega : {2.0, 1.0 + 1e-6}) {
    const Vec3 hp = 0.1 * h_omega * axis;
    ASSERT_LT(hp.norm(), solver.domain_bound());
    Mat3 F = kSentinel;
    const RotationUpdateSummary r = solver.solve(hp, F);
    EXPECT_EQ(r.status, RotationUpdateStatus::OutsideDomain) << r.brief();
    // axis_ratio = |Q^T hp|_3 / J3 = h Omega3, to the round-off of the eigendecomposition.
    EXPECT_NEAR(r.axis_ratio, h_omega, 1e-12 * h_omega);
    EXPECT_EQ(r.axis, 0);  // the smallest moment, 0.1
    EXPECT_EQ(F, kSentinel);
    EXPECT_NE(r.brief().find("no rotation solves the update"), std::string::npos) << r.brief();
    EXPECT_NE(r.brief().find("principal axis of the smallest moment of inertia"), std::string::npos) << r.brief();
  }
  // Just inside: the rotation about the axis by asin(h Omega3) solves it (and Newton finds one).
  Mat3 F;
  const Vec3 hp = 0.1 * 0.9 * axis;
  const RotationUpdateSummary r = solver.solve(hp, F);
  ASSERT_TRUE(r.converged()) << r.brief();
  EXPECT_LT(solver.matrix_residual(F, hp).norm(), 1e-14);
}


// --- The fast path hands over to the whole method without changing the result -----------------
// solve() runs the primary chart's Newton iteration inline until it meets what it does not handle
// (a nearly singular Newton matrix, a non-finite value, the cap, a converged |G| that wants the
// polishing step), then slow_path() continues the whole method from that iterate
// (rotation_update.hpp). So whenever the whole method in the primary chart from its warm start
// (solve_in) converges, solve() must return its f to the last bit, with its iteration count,
// polishing flag and residual, and no fallback. Cases: random valid inertias at h |Omega| up to
// the fold (where Newton matrices turn nearly singular and the cap is met), and the
// ill-conditioned rod of the test above (where the polishing step is taken); both primaries.
// The counts printed show that each hand-over was exercised.
TEST(RotationUpdateFastPath, GivesTheWholeMethodsIteratesCountsAndResiduals) {
  std::vector<Sample> cases;
  for (const double max_h_omega : {0.1, 1.0, 1.6, 2.0}) {
    for (const Sample& s : random_batch(max_h_omega, 400, 707 + static_cast<std::uint64_t>(10 * max_h_omega))) {
      cases.push_back(s);
    }
  }
  const Vec3 rho = 0.15 * Vec3(1, 1, 1).normalized();
  const Inertia rod = Inertia::from(rho.squaredNorm() * Mat3::Identity() - rho * rho.transpose() +
                                    0.4 * 0.02 * 0.02 * Mat3::Identity());
  auto rng = test::make_rng(709);
  std::normal_distribution<double> normal;
  for (int k = 0; k < 400; ++k) {
    const Vec3 Omega_h = 0.5 * rho.normalized() + 0.02 * Vec3(normal(rng), normal(rng), normal(rng));
    cases.push_back({rod, rod.J * Omega_h});
  }
  for (const Parametrization primary : {Parametrization::Cayley, Parametrization::Exponential}) {
    RotationUpdateOptions options;
    options.primary = primary;
    int agreed = 0, polished = 0, primary_failed = 0;
    for (const Sample& s : cases) {
      const RotationUpdateSolver solver(s.inertia, options);
      Vec3 f_whole = Vec3::Constant(std::nan(""));
      const RotationUpdateSummary whole = solver.solve_in(primary, s.hp, f_whole);
      RotationStep step;
      const RotationUpdateSummary r = solver.solve(s.hp, step);
      if (!whole.converged()) {
        ++primary_failed;
        if (r.iterations == 0) {  // refused before iterating: |h p| beyond the domain bound
          EXPECT_EQ(r.status, RotationUpdateStatus::OutsideDomain) << r.brief();
        } else {  // the fallback chart's business, its iterations counted on top of the primary's
          EXPECT_TRUE(!r.converged() || r.used_fallback) << r.brief();
          EXPECT_GE(r.iterations, whole.iterations) << r.brief();
        }
        continue;
      }
      ASSERT_TRUE(r.converged()) << r.brief();
      EXPECT_FALSE(r.used_fallback);
      EXPECT_EQ(step.chart, primary);
      EXPECT_EQ(step.f, f_whole) << r.brief() << "\n" << whole.brief();
      EXPECT_EQ(r.iterations, whole.iterations);
      EXPECT_EQ(r.polished, whole.polished);
      EXPECT_EQ(r.residual(), whole.residual());
      EXPECT_EQ(step.matrix(), rotation_from(primary, f_whole));
      ++agreed;
      polished += whole.polished ? 1 : 0;
    }
    std::cout << "[ measured ] " << to_string(primary) << " primary: " << agreed
              << " solves equal to the whole method (" << polished << " polished), "
              << primary_failed << " where the primary chart failed\n";
    EXPECT_GT(polished, 0) << "no case took the polishing hand-over";
    EXPECT_GT(primary_failed, 0) << "no case reached the slow path's failure branch";
  }
}

// The fast path's Cayley guard (rotation_update.hpp, newton_fast) rests on two facts, checked
// here on random inertias, right-hand sides up to the domain bound and iterates up to the guard's
// limit |f| ((1 + sqrt 2) ||J||_F + |h p|) <= 0.9 ||J||_F: the Newton matrix's Frobenius norm is
// then at most 1.9 ||J||_F (the triangle inequality of newton_fast's comment; a wrong term in it
// would show here as a norm above the bound), and wherever the cheaper guard det^2 > 64 eps
// ||J||_F^6 lets the adjugate solve, the whole method's guard (eps ||dH||_F^6) does too and gives
// the same bits. Matrices scaled to be nearly singular exercise the guard's other side.
TEST(RotationUpdateFastPath, CayleyGuardImpliesTheWholeMethodsGuard) {
  namespace d = rotation_update_detail;
  auto rng = test::make_rng(713);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> normal;
  int solved = 0, refused = 0;
  double worst_norm_ratio = 0.0;
  for (int k = 0; k < 4000; ++k) {
    const Inertia I = Inertia::from(random_valid_inertia(rng));
    const RotationUpdateSolver solver(I);
    const double J_norm = I.J.norm();
    const Vec3 hp = uniform(rng) * solver.domain_bound() *
                    Vec3(normal(rng), normal(rng), normal(rng)).normalized();
    const double t_limit = d::cayley_fast_t_limit(J_norm, hp.norm());
    const Vec3 f = t_limit * std::sqrt(uniform(rng)) * Vec3(normal(rng), normal(rng), normal(rng)).normalized();
    d::CayleyChart::Evaluation e;
    const d::M3 J = d::m3(I.J);
    d::CayleyChart::evaluate(J, d::v3(hp), d::v3(f), e);
    ASSERT_LE(e.t, t_limit);
    d::M3 A = d::CayleyChart::newton_matrix(J, d::v3(hp), d::v3(f), e);
    const double frobenius = std::sqrt(d::dot(A.c0, A.c0) + d::dot(A.c1, A.c1) + d::dot(A.c2, A.c2));
    worst_norm_ratio = std::max(worst_norm_ratio, frobenius / J_norm);
    EXPECT_LE(frobenius, 1.9 * J_norm * (1.0 + 8.0 * kEps));
    if (k % 4 == 3) A.c2 = A.c0 + 1e-9 * uniform(rng) * A.c2;  // nearly singular
    const double floor = d::cayley_det2_floor(J_norm);
    d::V3 cheap{0, 0, 0}, whole{0, 0, 0};
    if (d::solve_adjugate_above(A, e.H, floor, cheap)) {
      ++solved;
      ASSERT_TRUE(d::solve_adjugate(A, e.H, whole));
      EXPECT_EQ(cheap.x, whole.x);
      EXPECT_EQ(cheap.y, whole.y);
      EXPECT_EQ(cheap.z, whole.z);
    } else {
      ++refused;
    }
  }
  std::cout << "[ measured ] Cayley guard: " << solved << " solved, " << refused
            << " refused; worst ||dH||_F / ||J||_F " << worst_norm_ratio << " (bound 1.9)\n";
  EXPECT_GT(refused, 0) << "no nearly singular case reached the guard's other side";
  EXPECT_GT(solved, 2000);
}

// RotationStep applies F without forming it: R F and F^T k agree with the products by F =
// step.matrix(). Bound: each entry, either way, is a sum of at most three terms of size <= its
// row's norm (|r_i| = 1; |k|), rounded at most 4 times, so within ~2 eps of the exact value and
// 4 eps of each other; over the 9 entries of R F (3 of F^T k) in the Frobenius norm, 12 eps.
TEST(RotationStep, AppliesFAsTheProductsWithTheMatrixDo) {
  auto rng = test::make_rng(711);
  std::normal_distribution<double> normal;
  for (const Parametrization chart : {Parametrization::Cayley, Parametrization::Exponential}) {
    RotationUpdateOptions options;
    options.primary = chart;
    const RotationUpdateSolver solver(paper_inertia(), options);
    for (int k = 0; k < 200; ++k) {
      const Vec3 hp = paper_inertia().J * (0.5 * Vec3(normal(rng), normal(rng), normal(rng)).normalized());
      RotationStep step;
      const RotationUpdateSummary r = solver.solve(hp, step);
      ASSERT_TRUE(r.converged()) << r.brief();
      const Mat3 F = step.matrix();
      const Mat3 R = so3::random_rotation(rng);
      const Vec3 kick(normal(rng), normal(rng), normal(rng));
      EXPECT_LE((step.right_multiply(R) - R * F).norm(), 12.0 * kEps);
      EXPECT_LE((step.transpose_times(kick) - F.transpose() * kick).norm(), 12.0 * kEps * kick.norm());
    }
  }
}

}  // namespace
}  // namespace lgvi
