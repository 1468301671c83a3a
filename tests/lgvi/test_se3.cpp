// SE(3) maths (lgvi/se3.hpp): group law, action, exp/log, hat/vee and the adjoint, each a
// parameterized test over identity, tiny, near-pi and seeded random twists xi = (w, v).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <unsupported/Eigen/MatrixFunctions>
#include <vector>

#include "lgvi/se3.hpp"
#include "test_support.hpp"

namespace lgvi {
namespace {

using test::roundoff;

// Tolerances (derived). An O(1) 3x3 rotation block built in <= 8 flops per entry, 16 eps per
// flop (roundoff()), Frobenius factor 3 included in the generous count: see test_support.hpp.
using test::kMatTol;
// Translation-type quantities of size s (R x + y, Jl v, ...): each component a 3-term dot product
// plus a sum, <= 4 flops on terms of size s; the Frobenius factor sqrt(3) is covered by 16
// eps/flop.
double vec_tol(double s) { return roundoff(s, 4); }

struct TwistCase {
  std::string name;
  Vec6 xi;       // (w, v), |w| <= pi
  int salt = 0;  // seeds the second pose of the binary properties
};
std::ostream& operator<<(std::ostream& os, const TwistCase& c) {
  return os << c.name << " xi=(" << c.xi.transpose() << ")";
}

Vec6 twist(const Vec3& w, const Vec3& v) {
  Vec6 xi;
  xi << w, v;
  return xi;
}

std::vector<TwistCase> twist_cases() {
  const Vec3 a = Vec3(1, 2, 3).normalized(), b = Vec3(-2, 1, 1).normalized();
  std::vector<TwistCase> cases = {
      {"identity", Vec6::Zero()},
      {"tiny", twist(1e-8 * a, 1e-8 * b)},
      {"pure_translation", twist(Vec3::Zero(), Vec3(0.3, -1.2, 2.0))},
      {"near_pi_1e6", twist((M_PI - 1e-6) * a, Vec3(0.5, 0.1, -0.7))},
      {"near_pi_1e9", twist((M_PI - 1e-9) * b, Vec3(-1.0, 2.0, 0.3))},
  };
  auto rng = test::make_rng(/*salt=*/401);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int k = 0; k < 32; ++k) {
    const Vec3 n = Vec3(normal(rng), normal(rng), normal(rng)).normalized();
    const Vec3 v(normal(rng), normal(rng), normal(rng));
    cases.push_back({"random_" + std::to_string(k), twist(M_PI * uniform(rng) * n, v)});
  }
  for (std::size_t k = 0; k < cases.size(); ++k) cases[k].salt = static_cast<int>(k);
  return cases;
}

// A second, independent seeded pose for the binary properties (compose, adjoint).
se3::Pose other_pose(int salt) {
  auto rng = test::make_rng(402 + static_cast<std::uint64_t>(salt));
  std::normal_distribution<double> normal;
  return {so3::random_rotation(rng), Vec3(normal(rng), normal(rng), normal(rng))};
}

using Mat4L = Eigen::Matrix<long double, 4, 4>;

class Se3 : public testing::TestWithParam<TwistCase> {
 protected:
  Vec6 xi() const { return GetParam().xi; }
  Vec3 w() const { return GetParam().xi.head<3>(); }
  Vec3 v() const { return GetParam().xi.tail<3>(); }
  se3::Pose pose() const { return se3::exp(GetParam().xi); }
  int salt() const { return GetParam().salt; }
};

// hat/vee only copy and negate entries: exact inverse pair.
TEST_P(Se3, HatVeeInversePair) {
  const Mat4 X = se3::hat(xi());
  EXPECT_EQ(se3::vee(X), xi());
  EXPECT_EQ(se3::hat(se3::vee(X)), X);
  EXPECT_EQ(X.row(3), Eigen::RowVector4d::Zero());
  // hat(xi) [p; 1] = [w x p + v; 0] (velocity of the point p under the twist).
  const Vec3 p(0.3, -0.4, 1.1);
  const Eigen::Vector4d q = X * Eigen::Vector4d(p.x(), p.y(), p.z(), 1.0);
  EXPECT_LE((q.head<3>() - (w().cross(p) + v())).norm(),
            vec_tol(w().norm() * p.norm() + v().norm()));
  EXPECT_EQ(q(3), 0.0);
}

// g g^{-1} = g^{-1} g = e. The rotation block is R R^T (kMatTol); the translation
// x + R (-R^T x) = (I - R R^T) x is off by the orthogonality error times |x| plus its own flops.
TEST_P(Se3, ComposeWithInverseIsIdentity) {
  const se3::Pose g = pose();
  const double x = g.x.norm();
  for (const se3::Pose& e : {se3::compose(g, se3::inverse(g)), se3::compose(se3::inverse(g), g)}) {
    EXPECT_LE((e.R - Mat3::Identity()).norm(), kMatTol);
    EXPECT_LE(e.x.norm(), kMatTol * x + vec_tol(x));
  }
}

// The group law is the product of homogeneous matrices, and act is the matrix acting on [p; 1];
// act is an action: act(a b, p) = act(a, act(b, p)).
TEST_P(Se3, ComposeAndActMatchMatrices) {
  const se3::Pose a = pose(), b = other_pose(salt());
  const double scale = (1.0 + a.x.norm()) * (1.0 + b.x.norm());
  EXPECT_LE((se3::matrix(se3::compose(a, b)) - se3::matrix(a) * se3::matrix(b)).norm(),
            kMatTol * scale);
  const Vec3 p(-0.7, 0.2, 1.5);
  const Eigen::Vector4d hp(p.x(), p.y(), p.z(), 1.0);
  EXPECT_LE((se3::act(a, p) - (se3::matrix(a) * hp).head<3>()).norm(),
            vec_tol(p.norm() + a.x.norm()));
  EXPECT_LE((se3::act(se3::compose(a, b), p) - se3::act(a, se3::act(b, p))).norm(),
            kMatTol * scale * (1.0 + p.norm()));
  // The inverse undoes the action.
  EXPECT_LE((se3::act(se3::inverse(a), se3::act(a, p)) - p).norm(),
            kMatTol * (1.0 + a.x.norm()) * (1.0 + p.norm()));
}

// se3::exp against an independent 4x4 matrix exponential of hat(xi) in long double: checks the
// choice of the left Jacobian in the translation part. The rotation block is within kMatTol; the
// translation Jl v (|Jl| <= 1) within vec_tol(|v|) beyond the rotation-type error.
TEST_P(Se3, ExpMatchesMatrixExponential) {
  const Mat4L X = se3::hat(xi()).cast<long double>();
  const Mat4L E = X.exp();
  const Mat4 reference = E.cast<double>();
  const Mat4 T = se3::matrix(pose());
  EXPECT_LE((T.topLeftCorner<3, 3>() - reference.topLeftCorner<3, 3>()).norm(), kMatTol);
  EXPECT_LE((T.topRightCorner<3, 1>() - reference.topRightCorner<3, 1>()).norm(),
            kMatTol * v().norm() + vec_tol(v().norm()));
  EXPECT_EQ(T.row(3), Eigen::RowVector4d(0, 0, 0, 1));
}

TEST_P(Se3, ExpIsRigidMotion) {
  const se3::Pose g = pose();
  EXPECT_LE(so3::orthogonality_error(g.R), kMatTol);
  EXPECT_LE(so3::determinant_error(g.R), kMatTol);
  EXPECT_TRUE(g.x.allFinite());
}

// log(exp(xi)) = xi for rotation angles < pi (all cases here). The rotation part is so3::log
// (relative error roundoff(|w|, 4), see test_so3.cpp). The translation part is Jl(w)^{-1} Jl(w) v
// with |Jl|_2 = max sin(t/2)/(t/2) <= 1 and |Jl^{-1}|_2 <= (t/2)/sin(t/2) <= pi/2 for t <= pi:
// forming Jl v (~8 flops of |v|) and applying Jl^{-1} (~8 flops, amplified by pi/2) costs
// < 26 flop-equivalents of |v|; the error in w moves Jl^{-1} by O(1) x w_err, times |v|.
TEST_P(Se3, LogInvertsExp) {
  const Vec6 l = se3::log(pose());
  ASSERT_TRUE(l.allFinite());
  const double w_err = roundoff(w().norm(), 4);
  EXPECT_LE((l.head<3>() - w()).norm(), w_err);
  EXPECT_LE((l.tail<3>() - v()).norm(), roundoff(v().norm(), 26) + w_err * v().norm());
}

// exp(log(g)) = g.
TEST_P(Se3, ExpInvertsLog) {
  const se3::Pose g = pose();
  const se3::Pose h = se3::exp(se3::log(g));
  const double x = g.x.norm();
  EXPECT_LE((h.R - g.R).norm(), std::sqrt(2.0) * roundoff(M_PI, 4) + kMatTol);
  EXPECT_LE((h.x - g.x).norm(), roundoff(x, 26) + roundoff(M_PI, 4) * x);
}

// Adjoint: g exp(xi) g^{-1} = exp(Ad_g xi), checked on homogeneous matrices, and its
// infinitesimal form g hat(xi) g^{-1} = hat(Ad_g xi). Here g is an independent random pose and
// xi the case's twist. Entries of the conjugated matrices are products of three factors of size
// <= (1 + |x|), (1 + |v|) and (1 + |x|): the O(1) round-off scales accordingly.
TEST_P(Se3, AdjointConjugation) {
  const se3::Pose g = other_pose(salt());
  const Mat6 Ad = se3::adjoint(g);
  const double scale = (1.0 + g.x.norm()) * (1.0 + g.x.norm()) * (1.0 + v().norm());
  const Mat4 lhs = se3::matrix(g) * se3::matrix(se3::exp(xi())) * se3::matrix(se3::inverse(g));
  const Mat4 rhs = se3::matrix(se3::exp(Ad * xi()));
  EXPECT_LE((lhs - rhs).norm(), 2.0 * kMatTol * scale) << "lhs\n" << lhs << "\nrhs\n" << rhs;
  const Mat4 lhs_algebra = se3::matrix(g) * se3::hat(xi()) * se3::matrix(se3::inverse(g));
  EXPECT_LE((lhs_algebra - se3::hat(Ad * xi())).norm(), kMatTol * scale * (1.0 + xi().norm()));
  // Ad is a homomorphism: Ad_{g h} = Ad_g Ad_h, and Ad_{g^{-1}} = Ad_g^{-1}.
  const se3::Pose h = pose();
  const double s2 = (1.0 + g.x.norm()) * (1.0 + h.x.norm());
  EXPECT_LE((se3::adjoint(se3::compose(g, h)) - Ad * se3::adjoint(h)).norm(), 2.0 * kMatTol * s2);
  EXPECT_LE((se3::adjoint(se3::inverse(g)) * Ad - Mat6::Identity()).norm(),
            2.0 * kMatTol * (1.0 + g.x.norm()) * (1.0 + g.x.norm()));
}

INSTANTIATE_TEST_SUITE_P(Cases, Se3, testing::ValuesIn(twist_cases()),
                         [](const testing::TestParamInfo<TwistCase>& i) { return i.param.name; });

}  // namespace
}  // namespace lgvi
