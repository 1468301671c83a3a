// SO(3) maths (lgvi/so3.hpp): every property is a parameterized test over the same cases:
// identity, a tiny rotation (1e-8), rotations next to the branch thresholds (1e-4, 1e-3, pi/2),
// rotations near pi (pi - 1e-2, pi - 2e-3, pi - 1e-6, pi - 1e-9), exactly pi, and a seeded random
// batch (uniform angles, log-uniform small angles, and angles within [1e-3, 1e-1] of pi).
// Tolerances are derived next to each assertion; the seed is LGVI_TEST_SEED (test_support.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <string>
#include <unsupported/Eigen/MatrixFunctions>
#include <vector>

#include "lgvi/so3.hpp"
#include "test_support.hpp"

namespace lgvi {
namespace {

using test::kFdStep;
using test::kFdTolerance;
using test::roundoff;

// --- Tolerances (derived) ------------------------------------------------------------------
// kMatTol: an O(1) 3x3 result (test_support.hpp).
using test::kMatTol;
// Entrywise (max-abs) error of such a matrix when each entry takes <= 1 flop-equivalent of
// error beyond its inputs: 16 eps. Used where a sharper check is needed (branch continuity).
const double kEntryTol = roundoff(1.0, 1);
// log(exp(w)) relative to |w|: exp costs 8 flops, log 10 more, and after the pi/2 branch switch
// log amplifies an input error by at most theta / sin(theta) <= pi/2 on the skew branch (and ~1
// on the symmetric one): (8 + 10) * pi/2 < 32 flop-equivalents, counted as roundoff(|w|, 4)
// (64 eps, 16 per flop x 4 is twice 32 eps).
double log_tol(double angle) { return roundoff(angle, 4); }

struct RotationCase {
  std::string name;
  Vec3 w;  // rotation vector; |w| <= pi
};

std::ostream& operator<<(std::ostream& os, const RotationCase& c) {
  return os << c.name << " w=(" << c.w.transpose() << ") |w|=" << c.w.norm();
}

Vec3 unit(double x, double y, double z) { return Vec3(x, y, z).normalized(); }

std::vector<RotationCase> rotation_cases() {
  std::vector<RotationCase> cases = {
      {"identity", Vec3::Zero()},
      {"tiny", 1e-8 * unit(1, 2, 3)},
      {"below_1e4", 1e-4 * (1.0 - 1e-9) * unit(-2, 1, 1)},
      {"above_1e4", 1e-4 * (1.0 + 1e-9) * unit(-2, 1, 1)},
      {"below_1e3", 1e-3 * (1.0 - 1e-9) * unit(1, -3, 2)},
      {"above_1e3", 1e-3 * (1.0 + 1e-9) * unit(1, -3, 2)},
      {"below_half_pi", M_PI / 2 * (1.0 - 1e-9) * unit(3, 1, -1)},
      {"above_half_pi", M_PI / 2 * (1.0 + 1e-9) * unit(3, 1, -1)},
      // pi - 1e-2 and pi - 2e-3: where a skew-part log loses ~eps/(pi - theta) (see so3::log).
      {"near_pi_1e2", (M_PI - 1e-2) * unit(-3, 1, 2)},
      {"near_pi_2e3", (M_PI - 2e-3) * unit(1, 4, -1)},
      {"near_pi_1e6", (M_PI - 1e-6) * unit(1, 1, 1)},
      {"near_pi_1e9", (M_PI - 1e-9) * unit(-1, 2, -2)},
      {"pi_generic_axis", M_PI * unit(2, -1, 3)},
      {"pi_about_e1", M_PI * Vec3::UnitX()},
  };
  // Seeded random batch: uniform axis, angle uniform in [0, pi) and 16 log-uniform in
  // [1e-9, 1] so that the small-angle branches see random inputs too.
  auto rng = test::make_rng(/*salt=*/301);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int k = 0; k < 48; ++k) {
    const Vec3 n = Vec3(normal(rng), normal(rng), normal(rng)).normalized();
    const double angle = k < 32 ? M_PI * uniform(rng) : std::pow(10.0, -9.0 * uniform(rng));
    cases.push_back({"random_" + std::to_string(k), angle * n});
  }
  // 8 random axes with pi - theta log-uniform in [1e-3, 1e-1]: where a log computed from the skew
  // part would lose up to ~eps / (pi - theta) (2400 eps), unlike the pi/2 branch switch.
  for (int k = 0; k < 8; ++k) {
    const Vec3 n = Vec3(normal(rng), normal(rng), normal(rng)).normalized();
    const double angle = M_PI - std::pow(10.0, -1.0 - 2.0 * uniform(rng));
    cases.push_back({"random_near_pi_" + std::to_string(k), angle * n});
  }
  return cases;
}

std::string case_name(const testing::TestParamInfo<RotationCase>& info) { return info.param.name; }

bool is_exactly_pi(const Vec3& w) { return w.norm() >= M_PI; }

using MatL = Eigen::Matrix<long double, 3, 3>;

/// Reference exponential in long double precision (Pade scaling and squaring, no Rodrigues):
/// independent of the code under test, accurate to ~1e-19.
Mat3 reference_exp(const Vec3& w) {
  const MatL W = so3::hat(w).cast<long double>();
  const MatL E = W.exp();
  return E.cast<double>();
}

class So3 : public testing::TestWithParam<RotationCase> {};

// hat/vee are an exact inverse pair (they only copy and negate entries; vee's (X - X^T)/2 of an
// exactly skew matrix is exact in binary floating point).
TEST_P(So3, HatVeeInversePair) {
  const Vec3 w = GetParam().w;
  const Mat3 W = so3::hat(w);
  EXPECT_EQ(so3::vee(W), w);
  EXPECT_EQ(W + W.transpose(), Mat3::Zero());
  EXPECT_EQ(so3::hat(so3::vee(W)), W);
  // vee of a general matrix reads its skew part: hat(vee(A)) = (A - A^T)/2 (one subtraction and
  // one halving per entry, exact up to 1 rounding of entries of size |A|).
  Mat3 A = Mat3::Identity() * 0.3 + W;
  A(0, 1) += 0.7;
  EXPECT_LE((so3::hat(so3::vee(A)) - 0.5 * (A - A.transpose())).norm(), roundoff(A.norm()));
}

// hat(w) y = w x y: each component is a difference of two products in both forms, so they agree
// to 2 roundings of |w| |y|.
TEST_P(So3, HatIsCrossProduct) {
  const Vec3 w = GetParam().w;
  auto rng = test::make_rng(302);
  std::normal_distribution<double> normal;
  for (int k = 0; k < 4; ++k) {
    const Vec3 y(normal(rng), normal(rng), normal(rng));
    EXPECT_LE((so3::hat(w) * y - w.cross(y)).norm(), roundoff(w.norm() * y.norm(), 2));
  }
}

TEST_P(So3, ExpIsRotation) {
  const Mat3 R = so3::exp(GetParam().w);
  EXPECT_LE(so3::orthogonality_error(R), kMatTol);
  EXPECT_LE(so3::determinant_error(R), kMatTol);
  EXPECT_TRUE(so3::is_rotation(R, kMatTol));
}

// Rodrigues against an independent matrix exponential (long double Pade): the reference error
// is ~1e-19, so the bound is the round-off of exp itself.
TEST_P(So3, ExpMatchesMatrixExponential) {
  const Vec3 w = GetParam().w;
  EXPECT_LE((so3::exp(w) - reference_exp(w)).norm(), kMatTol);
}

// R exp(hat w) without forming exp(hat w) (so3::right_multiply_exp, the Lie group methods'
// update) against the product R * exp(w), for a rotation R drawn per case: both are
// R + a R hat(w) + b R hat(w)^2, each entry a sum of ~10 rounded products of O(1) terms in
// either form, so they differ by at most ~20 u = 10 eps: within kEntryTol (16 eps).
TEST_P(So3, RightMultiplyExpEqualsTheProductWithExp) {
  auto rng = test::make_rng(/*salt=*/304);
  const Mat3 R = so3::random_rotation(rng);
  const Vec3 w = GetParam().w;
  EXPECT_LE((so3::right_multiply_exp(R, w) - R * so3::exp(w)).cwiseAbs().maxCoeff(), kEntryTol);
}

// log(exp(w)) = w for |w| < pi; at exactly pi the principal log is +-w.
TEST_P(So3, LogInvertsExp) {
  const Vec3 w = GetParam().w;
  const Vec3 l = so3::log(so3::exp(w));
  ASSERT_TRUE(l.allFinite());
  if (is_exactly_pi(w)) {
    EXPECT_NEAR(l.norm(), M_PI, log_tol(M_PI));
    EXPECT_LE(std::min((l - w).norm(), (l + w).norm()), log_tol(M_PI));
  } else {
    EXPECT_LE((l - w).norm(), log_tol(w.norm()));
  }
  // Principal branch: theta = atan2(.) <= pi, times a unit axis and a norm (2 roundings).
  EXPECT_LE(l.norm(), M_PI + roundoff(M_PI, 1));
}

// exp(log(R)) = R for every case, including angle exactly pi (whichever sign log picked).
TEST_P(So3, ExpInvertsLog) {
  const Mat3 R = so3::exp(GetParam().w);
  // log adds log_tol(pi) <= 64 pi eps to w, which exp maps to at most that much in R (|d exp|
  // <= |dw| in the spectral norm, sqrt(2) in Frobenius), plus exp's own kMatTol.
  EXPECT_LE((so3::exp(so3::log(R)) - R).norm(), std::sqrt(2.0) * log_tol(M_PI) + kMatTol);
}

// Cayley parameter of the same rotation: f = tan(theta/2) n.
Vec3 cayley_parameter(const Vec3& w) {
  const double t = w.norm();
  return t == 0.0 ? Vec3::Zero() : Vec3(std::tan(0.5 * t) / t * w);
}

// cay(f) is orthonormal for every f, including |f| ~ 1.6e16 at theta = pi.
TEST_P(So3, CayleyIsRotation) {
  const Mat3 F = so3::cayley(cayley_parameter(GetParam().w));
  EXPECT_LE(so3::orthogonality_error(F), kMatTol);
  EXPECT_LE(so3::determinant_error(F), kMatTol);
}

// cay(tan(theta/2) n) = exp(theta n): f carries a relative error <= 2 eps (tan and scaling),
// which moves the angle by 2 df / (1 + |f|^2) <= 2 eps; both matrices are within kMatTol.
TEST_P(So3, CayleyMatchesExp) {
  const Vec3 w = GetParam().w;
  EXPECT_LE((so3::cayley(cayley_parameter(w)) - so3::exp(w)).norm(), 2.0 * kMatTol);
}

// cayley_inverse(cayley(f)) = f. The inverse divides by 1 + tr R = 4 / (1 + |f|^2), formed from
// three diagonal entries with absolute error <= kEntryTol each: relative error
// <= 3 kEntryTol (1 + |f|^2) / 4. The skew part vee(R) = 2 f / (1 + |f|^2) is
// formed from entries of size (|f| + |f|^2) 2/(1 + |f|^2) to a flop each: relative error
// <= roundoff(1 + |f|) ; plus the final scaling (2 flops). The Cayley chart thus loses digits
// as theta -> pi; where the bound leaves less than one digit (pi - 1e-9, pi) the check could not
// fail and is skipped (the precondition tr R > -1 is marginal or violated there).
TEST_P(So3, CayleyInverseRoundTrip) {
  const Vec3 f = cayley_parameter(GetParam().w);
  const double relative_bound =
      kEntryTol * (1.0 + f.squaredNorm()) + roundoff(1.0 + f.norm()) + roundoff(1.0, 2);
  if (relative_bound > 0.1) {
    GTEST_SKIP() << "Cayley chart ill-conditioned here: derived relative bound " << relative_bound;
  }
  const Vec3 g = so3::cayley_inverse(so3::cayley(f));
  EXPECT_LE((g - f).norm(), relative_bound * f.norm()) << "f = " << f.transpose();
}

// Central differences of a matrix-valued curve at t = 0, read through a map to R^3.
template <class Curve>
Mat3 fd_columns(Curve&& curve) {
  Mat3 D;
  for (int j = 0; j < 3; ++j) {
    D.col(j) = (curve(j, kFdStep) - curve(j, -kFdStep)) / (2.0 * kFdStep);
  }
  return D;
}

// Right Jacobian: exp(w + dw) = exp(w) exp(Jr dw), i.e. Jr e_j = vee(exp(w)^T d/dt exp(w + t e_j)).
// Central differences with step kFdStep: truncation and cancellation both below kFdTolerance
// (test_support.hpp) for these O(1) functions.
TEST_P(So3, RightJacobianMatchesFiniteDifferences) {
  const Vec3 w = GetParam().w;
  const Mat3 Rt = so3::exp(w).transpose();
  const Mat3 fd =
      fd_columns([&](int j, double a) { return so3::vee(Rt * so3::exp(w + a * Vec3::Unit(j))); });
  const Mat3 Jr = so3::right_jacobian(w);
  EXPECT_LE((fd - Jr).norm(), kFdTolerance * std::max(1.0, Jr.norm())) << "Jr =\n" << Jr;
}

// Left Jacobian: exp(w + dw) = exp(Jl dw) exp(w).
TEST_P(So3, LeftJacobianMatchesFiniteDifferences) {
  const Vec3 w = GetParam().w;
  const Mat3 Rt = so3::exp(w).transpose();
  const Mat3 fd =
      fd_columns([&](int j, double a) { return so3::vee(so3::exp(w + a * Vec3::Unit(j)) * Rt); });
  const Mat3 Jl = so3::left_jacobian(w);
  EXPECT_LE((fd - Jl).norm(), kFdTolerance * std::max(1.0, Jl.norm())) << "Jl =\n" << Jl;
}

// The inverse Jacobians are derivatives of log, which jumps across the cut locus |w| = pi: the
// stencil exp(w) exp(+-a e_j) must stay inside the ball, i.e. pi - |w| > a. Closer to pi the
// inverses are still checked by Jr Jr^{-1} = I below.
bool stencil_crosses_cut_locus(const Vec3& w) { return M_PI - w.norm() <= 2.0 * kFdStep; }

// Inverse right Jacobian: log(exp(w) exp(d)) = w + Jr^{-1}(w) d + O(d^2).
TEST_P(So3, RightJacobianInverseMatchesFiniteDifferences) {
  const Vec3 w = GetParam().w;
  if (stencil_crosses_cut_locus(w)) GTEST_SKIP() << "log is discontinuous within one FD step";
  const Mat3 R = so3::exp(w);
  const Mat3 fd =
      fd_columns([&](int j, double a) { return so3::log(R * so3::exp(a * Vec3::Unit(j))); });
  const Mat3 Jri = so3::right_jacobian_inverse(w);
  EXPECT_LE((fd - Jri).norm(), kFdTolerance * std::max(1.0, Jri.norm())) << "Jr^-1 =\n" << Jri;
}

// Inverse left Jacobian: log(exp(d) exp(w)) = w + Jl^{-1}(w) d + O(d^2).
TEST_P(So3, LeftJacobianInverseMatchesFiniteDifferences) {
  const Vec3 w = GetParam().w;
  if (stencil_crosses_cut_locus(w)) GTEST_SKIP() << "log is discontinuous within one FD step";
  const Mat3 R = so3::exp(w);
  const Mat3 fd =
      fd_columns([&](int j, double a) { return so3::log(so3::exp(a * Vec3::Unit(j)) * R); });
  const Mat3 Jli = so3::left_jacobian_inverse(w);
  EXPECT_LE((fd - Jli).norm(), kFdTolerance * std::max(1.0, Jli.norm())) << "Jl^-1 =\n" << Jli;
}

// Jr Jr^{-1} = I and Jl Jl^{-1} = I (also at and near pi, where the FD check is skipped): a
// product of O(1) matrices (|Jr| <= sqrt(3), |Jr^{-1}| <= ~3 for |w| <= pi), so the round-off of
// the factors times the other's norm.
TEST_P(So3, JacobianTimesInverseIsIdentity) {
  const Vec3 w = GetParam().w;
  const Mat3 Jr = so3::right_jacobian(w), Jri = so3::right_jacobian_inverse(w);
  const Mat3 Jl = so3::left_jacobian(w), Jli = so3::left_jacobian_inverse(w);
  const double tol = kMatTol * (Jr.norm() + Jri.norm());
  EXPECT_LE((Jr * Jri - Mat3::Identity()).norm(), tol);
  EXPECT_LE((Jri * Jr - Mat3::Identity()).norm(), tol);
  EXPECT_LE((Jl * Jli - Mat3::Identity()).norm(), tol);
  // Jl(w) = Jr(-w) = Jr(w)^T (the hat(w) term flips sign, the hat(w)^2 term is symmetric).
  EXPECT_LE((Jl - Jr.transpose()).norm(), kMatTol);
}

// Exact half turns (tr R = -1, vee(R) = 0 exactly): log must still return an angle pi vector
// along the axis (either sign), and exp must map it back.
TEST(So3HalfTurn, LogOfExactHalfTurns) {
  std::vector<Mat3> half_turns = {Vec3(1, -1, -1).asDiagonal(), Vec3(-1, 1, -1).asDiagonal(),
                                  Vec3(-1, -1, 1).asDiagonal()};
  const Vec3 n = unit(2, -1, 3);
  half_turns.push_back(2.0 * n * n.transpose() - Mat3::Identity());  // rounded, not exact
  for (const Mat3& R : half_turns) {
    const Vec3 w = so3::log(R);
    ASSERT_TRUE(w.allFinite()) << R;
    EXPECT_NEAR(w.norm(), M_PI, log_tol(M_PI)) << R;
    // The axis is the +1 eigenvector: R w = w.
    EXPECT_LE((R * w - w).norm(), log_tol(M_PI) + kMatTol * M_PI) << R;
    EXPECT_LE((so3::exp(w) - R).norm(), std::sqrt(2.0) * log_tol(M_PI) + kMatTol) << R;
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, So3, testing::ValuesIn(rotation_cases()), case_name);

// --- Small-angle branches against long double references at the thresholds ------------------
// Each function switches from a Taylor series to its closed form at a threshold t*. Just below
// (t*(1 - 1e-9)) and just above (t*(1 + 1e-9)) the value must agree with a long double
// reference of the closed form (cancellation-free where possible). Agreement on both sides to
// round-off is continuity across the switch, and a wrong Taylor coefficient shows up: e.g. the
// t^2/120 term of Jr's c coefficient contributes (t^2/120) t^2 = 8e-15 > kEntryTol at t = 1e-3.

long double ld_sinc(long double t) { return t == 0 ? 1.0L : std::sin(t) / t; }

struct Threshold {
  std::string name;
  double t;
};
std::ostream& operator<<(std::ostream& os, const Threshold& c) { return os << c.name; }

class So3Branch : public testing::TestWithParam<Threshold> {};

// Rodrigues coefficients a = sin t / t and b = (1 - cos t)/t^2. Reference: long double
// a = sinl(t)/t, b = (1/2) sinc(t/2)^2 (no cancellation). Both branches must be accurate to a
// few eps (the series: Estrin's scheme, < 4 eps; sin and a division: ~1 eps; b squares and
// halves: ~3 eps; kEntryTol = 16 eps, a <= 1, b <= 1/2). A closed form (1 - cos t)/t^2 would
// cancel to eps/t^2 relative (2.2e-8 at 1e-4): harmless in exp, but not in the rotation update's
// G (see so3::rodrigues), so it is excluded.
TEST_P(So3Branch, RodriguesCoefficientsAreContinuous) {
  for (const double side : {-1.0, 1.0}) {
    const double t = GetParam().t * (1.0 + side * 1e-9);
    const auto [a, b] = so3::rodrigues(t);
    const long double tl = t;
    const double a_ref = static_cast<double>(ld_sinc(tl));
    const double b_ref = static_cast<double>(0.5L * ld_sinc(tl / 2) * ld_sinc(tl / 2));
    EXPECT_NEAR(a, a_ref, kEntryTol) << "t = " << t;
    EXPECT_NEAR(b, b_ref, kEntryTol) << "t = " << t;
  }
}

// exp, Jr, Jr^{-1} (and their left versions via Jl(w) = Jr(-w)) and log, entrywise, both sides.
TEST_P(So3Branch, MatrixFunctionsAreContinuous) {
  const Vec3 n = unit(2, -1, 2);
  for (const double side : {-1.0, 1.0}) {
    const long double t = GetParam().t * (1.0 + side * 1e-9);
    const Vec3 w = static_cast<double>(t) * n;
    const long double tw = Eigen::Matrix<long double, 3, 1>(w.cast<long double>()).norm();
    const MatL W = so3::hat(w).cast<long double>();
    const MatL I = MatL::Identity();
    // Jr = I - b W + c W^2, c = (t - sin t)/t^3: in long double the cancellation costs
    // 3 eps_ld / t^2 relative on c (3e-13 at 1e-3), times |c W^2| <= t^2/6: < 1e-19.
    const long double b = 0.5L * ld_sinc(tw / 2) * ld_sinc(tw / 2);
    const long double c = (tw - std::sin(tw)) / (tw * tw * tw);
    // Jr^{-1} = I + W/2 + e W^2, e = (1 - (t/2) cot(t/2)) / t^2: cancellation 2 eps_ld / (t^2/12)
    // relative on e, times |e W^2| <= t^2/12: < 1e-18.
    const long double e = (1.0L - (tw / 2) / std::tan(tw / 2)) / (tw * tw);
    const Mat3 Jr_ref = (I - b * W + c * W * W).cast<double>();
    const Mat3 Jri_ref = (I + 0.5L * W + e * W * W).cast<double>();
    const MatL E = W.exp();
    const Mat3 exp_ref = E.cast<double>();
    const double tol = kEntryTol;
    EXPECT_LE((so3::exp(w) - exp_ref).cwiseAbs().maxCoeff(), tol) << "t = " << (double)t;
    EXPECT_LE((so3::right_jacobian(w) - Jr_ref).cwiseAbs().maxCoeff(), tol) << "t = " << (double)t;
    EXPECT_LE((so3::left_jacobian(w) - Jr_ref.transpose()).cwiseAbs().maxCoeff(), tol);
    EXPECT_LE((so3::right_jacobian_inverse(w) - Jri_ref).cwiseAbs().maxCoeff(), tol)
        << "t = " << (double)t;
    EXPECT_LE((so3::left_jacobian_inverse(w) - Jri_ref.transpose()).cwiseAbs().maxCoeff(), tol);
    // log of the reference rotation: relative accuracy as in LogInvertsExp.
    EXPECT_LE((so3::log(exp_ref) - w).norm(), log_tol(w.norm())) << "t = " << (double)t;
  }
}

INSTANTIATE_TEST_SUITE_P(Thresholds, So3Branch,
                         testing::Values(Threshold{"log_1e4", 1e-4}, Threshold{"rodrigues_series_half", 0.5},
                                         Threshold{"jacobians_1e3", 1e-3},
                                         Threshold{"log_half_pi", M_PI / 2}),
                         [](const testing::TestParamInfo<Threshold>& i) { return i.param.name; });

// Accuracy sweep of the closed forms (not only at the thresholds): exp, Jr and Jr^{-1} entrywise
// against long double references along one axis, t log-spaced over [1e-6, pi - 1e-9] (Jr^{-1}:
// |w| < pi). Closed forms that cancel ((1 - cos t)/t^2 multiplying hat(w) in Jr: ~eps/t;
// (1 + cos t)/sin t near pi in Jr^{-1}: ~eps/(pi - t)) exceed kEntryTol somewhere on the sweep.
TEST(So3Accuracy, ClosedFormsMatchLongDoubleOverAllAngles) {
  const Vec3 n = unit(1, -2, 2);
  const MatL I = MatL::Identity();
  double worst_exp = 0.0, worst_jr = 0.0, worst_jri = 0.0;
  const int steps = 2000;
  for (int k = 0; k <= steps; ++k) {
    const double log_gap = std::log(M_PI - 1e-9) - std::log(1e-6);
    const Vec3 w = std::exp(std::log(1e-6) + log_gap * k / steps) * n;
    const long double tw = Eigen::Matrix<long double, 3, 1>(w.cast<long double>()).norm();
    const MatL W = so3::hat(w).cast<long double>();
    const long double b = 0.5L * ld_sinc(tw / 2) * ld_sinc(tw / 2);
    const long double c = (tw - std::sin(tw)) / (tw * tw * tw);
    const long double e = (1.0L - (tw / 2) / std::tan(tw / 2)) / (tw * tw);
    const long double a = ld_sinc(tw);
    const Mat3 exp_ref = (I + a * W + b * W * W).cast<double>();
    const Mat3 Jr_ref = (I - b * W + c * W * W).cast<double>();
    const Mat3 Jri_ref = (I + 0.5L * W + e * W * W).cast<double>();
    worst_exp = std::max(worst_exp, (so3::exp(w) - exp_ref).cwiseAbs().maxCoeff());
    worst_jr = std::max(worst_jr, (so3::right_jacobian(w) - Jr_ref).cwiseAbs().maxCoeff());
    worst_jri =
        std::max(worst_jri, (so3::right_jacobian_inverse(w) - Jri_ref).cwiseAbs().maxCoeff());
  }
  // The long double references: c and e cancel by 3 eps_ld / t^2 and 12 eps_ld / t^2 relative,
  // multiplied by |W^2| = t^2: < 1e-18 absolute.
  EXPECT_LE(worst_exp, kEntryTol);
  EXPECT_LE(worst_jr, kEntryTol);
  EXPECT_LE(worst_jri, kEntryTol);
  std::cout << "[ measured ] max entry error over the sweep (eps): exp " << worst_exp / test::kEps
            << ", Jr " << worst_jr / test::kEps << ", Jr^-1 " << worst_jri / test::kEps << "\n";
}

// Rodrigues coefficients, relative to long double, over both branches of so3::rodrigues (the
// series in t^2 below t = 1/2, the half-angle sin/cos form above), t log-spaced over
// [1e-8, pi]. Bounds: Estrin's scheme over 7 coefficients of an alternating series in
// x = t^2 <= 1/4 (four levels of rounded operations on the way to the sum) errs by at most
// ~4 u sum |c_k| x^k / |p(x)| <= 4 u sinh(t)/sin(t) < 5 u, plus u for the rounded coefficients;
// the half-angle form by ~4 u (a: sin, a division, cos and a product) and ~5 u (b: q^2 / 2).
// Both within 7 eps = 14 u, with room for the series' truncation (t^14/15!, below eps/2).
TEST(So3Accuracy, RodriguesCoefficientsAreRelativelyAccurateOnBothBranches) {
  const double tolerance = 7.0 * test::kEps;
  double worst_series = 0.0, worst_half_angle = 0.0;
  const int steps = 4000;
  for (int k = 0; k <= steps; ++k) {
    const double t = std::exp(std::log(1e-8) + (std::log(M_PI) - std::log(1e-8)) * k / steps);
    const auto [a, b] = so3::rodrigues(t);
    const long double tl = t;
    const long double a_ref = ld_sinc(tl);
    const long double b_ref = 0.5L * ld_sinc(tl / 2) * ld_sinc(tl / 2);
    const double error = static_cast<double>(
        std::max(std::abs((a - a_ref) / a_ref), std::abs((b - b_ref) / b_ref)));
    double& worst = t < 0.5 ? worst_series : worst_half_angle;
    worst = std::max(worst, error);
  }
  EXPECT_LE(worst_series, tolerance);
  EXPECT_LE(worst_half_angle, tolerance);
  std::cout << "[ measured ] max relative error of a, b (eps): series " << worst_series / test::kEps
            << ", half-angle " << worst_half_angle / test::kEps << "\n";
}

// --- Random rotations ----------------------------------------------------------------------

// Haar measure: every column of R is uniform on the sphere, so each entry has mean 0 and
// variance 1/3 (and R_ij^2 ~ Beta(1/2, 1): mean 1/3, variance E[x^4] - 1/9 = 1/5 - 1/9 = 4/45).
// By the CLT the sample mean of n draws has std sqrt(1/(3n)) and the sample mean of R_ij^2 has
// std sqrt(4/(45 n)); we assert each of the 9 entries within 5 std (false alarm < 1e-5 in all).
TEST(So3Random, RandomRotationIsHaarDistributed) {
  auto rng = test::make_rng(303);
  const int n = 20000;
  Mat3 sum = Mat3::Zero(), sum_sq = Mat3::Zero();
  for (int k = 0; k < n; ++k) {
    const Mat3 R = so3::random_rotation(rng);
    ASSERT_TRUE(so3::is_rotation(R, kMatTol)) << R;
    sum += R;
    sum_sq += R.cwiseProduct(R);
  }
  const Mat3 mean = sum / n;
  const Mat3 mean_sq = sum_sq / n;
  const double std_mean = 1.0 / std::sqrt(3.0 * n);
  const double std_mean_sq = std::sqrt(4.0 / (45.0 * n));
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      EXPECT_LE(std::abs(mean(i, j)), 5.0 * std_mean) << "entry " << i << j;
      EXPECT_LE(std::abs(mean_sq(i, j) - 1.0 / 3.0), 5.0 * std_mean_sq) << "entry " << i << j;
    }
  }
}

}  // namespace
}  // namespace lgvi
