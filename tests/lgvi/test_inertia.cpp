// Inertia::from (lgvi/inertia.hpp): which inertias are accepted, which rejected and why, and the
// precomputed J_d = tr(J)/2 I - J (eq. 7) and J^{-1}.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "lgvi/inertia.hpp"
#include "lgvi/so3.hpp"
#include "test_support.hpp"

namespace lgvi {
namespace {

using test::roundoff;

Mat3 diag(double a, double b, double c) { return Vec3(a, b, c).asDiagonal(); }

/// Q D Q^T for a fixed seeded rotation Q, symmetrized (the product is symmetric only to
/// round-off, ~eps |D|, below the 1e-12 relative symmetry check anyway).
Mat3 rotated(const Mat3& D, std::uint64_t salt) {
  auto rng = test::make_rng(salt);
  const Mat3 Q = so3::random_rotation(rng);
  const Mat3 J = Q * D * Q.transpose();
  return 0.5 * (J + J.transpose());
}

struct AcceptCase {
  std::string name;
  Mat3 J;
  Vec3 moments;  // principal moments, ascending
};
std::ostream& operator<<(std::ostream& os, const AcceptCase& c) { return os << c.name; }

std::vector<AcceptCase> accept_cases() {
  return {
      {"paper_pendulum", diag(0.13, 0.28, 0.17), Vec3(0.13, 0.17, 0.28)},
      {"rotated_non_diagonal", rotated(diag(0.13, 0.28, 0.17), 501), Vec3(0.13, 0.17, 0.28)},
      {"flat_body", diag(1.0, 1.0, 2.0), Vec3(1.0, 1.0, 2.0)},
      {"rotated_flat_body", rotated(diag(1.0, 1.0, 2.0), 502), Vec3(1.0, 1.0, 2.0)},
      {"sphere", diag(2.5, 2.5, 2.5), Vec3(2.5, 2.5, 2.5)},
      {"paper_dumbbell", diag(0.001, 0.0235, 0.0235), Vec3(0.001, 0.0235, 0.0235)},
      {"rotated_dumbbell", rotated(diag(0.001, 0.0235, 0.0235), 503), Vec3(0.001, 0.0235, 0.0235)},
  };
}

class InertiaAccepts : public testing::TestWithParam<AcceptCase> {};

// Symmetric eigen-decomposition of a 3x3 matrix: eigenvalues accurate to a few eps |J|.
double eig_tol(const Mat3& J) { return roundoff(J.norm(), 2); }

TEST_P(InertiaAccepts, StoresJAndItsPrincipalMoments) {
  const AcceptCase& c = GetParam();
  Inertia I;
  ASSERT_NO_THROW(I = Inertia::from(c.J, "body.J"));
  // J is stored symmetrized: (J + J^T)/2 of an already symmetric matrix is J exactly.
  EXPECT_EQ(I.J, c.J);
  const Vec3 moments = Eigen::SelfAdjointEigenSolver<Mat3>(I.J).eigenvalues();
  EXPECT_LE((moments - c.moments).cwiseAbs().maxCoeff(), eig_tol(c.J));
}

// J_d = tr(J)/2 I - J (eq. 7); its eigenvalues are (J_i + J_j - J_k)/2 >= 0 on the principal axes,
// zero for a flat body. 2 flops per entry.
TEST_P(InertiaAccepts, JdIsTheNonStandardInertia) {
  const AcceptCase& c = GetParam();
  const Inertia I = Inertia::from(c.J);
  const Mat3 expected = 0.5 * c.J.trace() * Mat3::Identity() - c.J;
  EXPECT_LE((I.Jd - expected).norm(), roundoff(c.J.norm(), 2));
  const Vec3& m = c.moments;
  Vec3 jd_expected(0.5 * (m(0) + m(1) - m(2)), 0.5 * (m(0) + m(2) - m(1)),
                   0.5 * (m(1) + m(2) - m(0)));
  std::sort(jd_expected.data(), jd_expected.data() + 3);
  const Vec3 jd_moments = Eigen::SelfAdjointEigenSolver<Mat3>(I.Jd).eigenvalues();
  EXPECT_LE((jd_moments - jd_expected).cwiseAbs().maxCoeff(), 2.0 * eig_tol(c.J));
  EXPECT_GE(jd_moments(0), -2.0 * eig_tol(c.J));  // positive semi-definite
}

// J^{-1} J = I to cond(J) eps: the inverse of a matrix with condition number k is accurate to
// ~k eps relative (3x3 LU/cofactors, a few flops).
TEST_P(InertiaAccepts, JInverseIsTheInverse) {
  const AcceptCase& c = GetParam();
  const Inertia I = Inertia::from(c.J);
  const double cond = c.moments(2) / c.moments(0);
  EXPECT_LE((I.J_inverse * I.J - Mat3::Identity()).norm(), roundoff(cond, 4));
  EXPECT_LE((I.J * I.J_inverse - Mat3::Identity()).norm(), roundoff(cond, 4));
}

INSTANTIATE_TEST_SUITE_P(Valid, InertiaAccepts, testing::ValuesIn(accept_cases()),
                         [](const testing::TestParamInfo<AcceptCase>& i) { return i.param.name; });

// A tiny asymmetry (below 1e-12 relative) is round-off, accepted and symmetrized.
TEST(InertiaFrom, SymmetrizesRoundOffAsymmetry) {
  Mat3 J = diag(0.13, 0.28, 0.17);
  J(0, 1) = 1e-15;
  const Inertia I = Inertia::from(J);
  EXPECT_EQ(I.J(0, 1), 0.5e-15);
  EXPECT_EQ(I.J(1, 0), 0.5e-15);
}

struct RejectCase {
  std::string name;
  Mat3 J;
  std::string reason;  // a phrase the message must contain
};
std::ostream& operator<<(std::ostream& os, const RejectCase& c) { return os << c.name; }

std::vector<RejectCase> reject_cases() {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  Mat3 asym = diag(0.13, 0.28, 0.17);
  asym(0, 2) = 1e-3;
  Mat3 with_nan = diag(0.13, 0.28, 0.17);
  with_nan(1, 2) = nan;
  with_nan(2, 1) = nan;
  Mat3 with_inf = diag(0.13, 0.28, 0.17);
  with_inf(0, 0) = inf;
  return {
      {"non_symmetric", asym, "not symmetric"},
      {"negative_moment", diag(-0.1, 0.28, 0.17), "not positive definite"},
      {"zero_moment", diag(0.0, 1.0, 1.0), "not positive definite"},
      {"indefinite_rotated", rotated(diag(-0.5, 1.0, 1.0), 504), "not positive definite"},
      {"triangle_violated", diag(1.0, 1.0, 2.1), "triangle inequality"},
      // 1e-12 relative beyond flat: far outside the 64 eps round-off allowance.
      {"triangle_violated_barely", diag(1.0, 1.0, 2.0 * (1.0 + 1e-12)), "triangle inequality"},
      {"triangle_violated_rotated", rotated(diag(1.0, 1.0, 2.1), 505), "triangle inequality"},
      {"nan_entry", with_nan, "non-finite"},
      {"inf_entry", with_inf, "non-finite"},
      {"zero_matrix", Mat3::Zero(), "is zero"},
  };
}

class InertiaRejects : public testing::TestWithParam<RejectCase> {};

// Each rejection is an InvalidInput naming the field it was given, with the message
// "<field>: <reason>".
TEST_P(InertiaRejects, ThrowsInvalidInputNamingFieldAndReason) {
  const RejectCase& c = GetParam();
  for (const std::string field : {"inertia", "scene.body.J"}) {
    try {
      (void)Inertia::from(c.J, field);
      ADD_FAILURE() << "accepted " << c.name << ":\n" << c.J;
    } catch (const InvalidInput& e) {
      EXPECT_EQ(e.field(), field);
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(field + ": ", 0), 0u) << what;
      EXPECT_NE(what.find(c.reason), std::string::npos) << what;
    }
  }
  // The default field name is "inertia".
  try {
    (void)Inertia::from(c.J);
    ADD_FAILURE() << "accepted " << c.name;
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.field(), "inertia");
  }
}

INSTANTIATE_TEST_SUITE_P(Invalid, InertiaRejects, testing::ValuesIn(reject_cases()),
                         [](const testing::TestParamInfo<RejectCase>& i) { return i.param.name; });

// require_positive and require_finite, used by the systems' constructors.
TEST(InertiaFrom, ScalarAndVectorChecksNameTheField) {
  EXPECT_NO_THROW(require_positive(1e-300, "h"));
  for (const double bad : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(),
                           std::numeric_limits<double>::infinity()}) {
    try {
      require_positive(bad, "h");
      ADD_FAILURE() << "accepted " << bad;
    } catch (const InvalidInput& e) {
      EXPECT_EQ(e.field(), "h");
    }
  }
  EXPECT_THROW(require_finite(Vec3(0, std::numeric_limits<double>::quiet_NaN(), 0), "x0"),
               InvalidInput);
  EXPECT_NO_THROW(require_finite(Vec3(0, 1, 2), "x0"));
}

}  // namespace
}  // namespace lgvi
