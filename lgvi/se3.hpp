// SE(3) = SO(3) x| R^3: rigid motions g = (R, x) acting by g p = R p + x (paper, section 3.1).
//
// Twists are ordered rotation first, xi = (w, v), matching the paper's variation
// z = [log(R^T dR)^vee; dx; ...] (eq. 16). The group law is (R1, x1)(R2, x2) = (R1 R2, x1 + R1 x2),
// the update (R_{k+1}, x_{k+1}) = (R_k, x_k)(F_k, Y_k) of section 3.1.
#pragma once

#include "lgvi/so3.hpp"
#include "lgvi/types.hpp"

namespace lgvi::se3 {

struct Pose {
  Mat3 R = Mat3::Identity();
  Vec3 x = Vec3::Zero();
};

/// Group product (R1 R2, x1 + R1 x2).
inline Pose compose(const Pose& a, const Pose& b) { return {a.R * b.R, a.x + a.R * b.x}; }

/// Group inverse (R^T, -R^T x).
inline Pose inverse(const Pose& g) { return {g.R.transpose(), -(g.R.transpose() * g.x)}; }

/// Action on a point: R p + x.
inline Vec3 act(const Pose& g, const Vec3& p) { return g.R * p + g.x; }

/// Homogeneous 4x4 matrix [R x; 0 1].
inline Mat4 matrix(const Pose& g) {
  Mat4 T = Mat4::Identity();
  T.topLeftCorner<3, 3>() = g.R;
  T.topRightCorner<3, 1>() = g.x;
  return T;
}

/// hat: R^6 -> se(3), xi = (w, v) -> [hat(w) v; 0 0].
inline Mat4 hat(const Vec6& xi) {
  Mat4 X = Mat4::Zero();
  X.topLeftCorner<3, 3>() = so3::hat(xi.head<3>());
  X.topRightCorner<3, 1>() = xi.tail<3>();
  return X;
}

/// vee: se(3) -> R^6, the inverse of hat.
inline Vec6 vee(const Mat4& X) {
  Vec6 xi;
  xi << so3::vee(X.topLeftCorner<3, 3>()), X.topRightCorner<3, 1>();
  return xi;
}

/// exp: se(3) -> SE(3), (exp(hat w), Jl(w) v) with Jl the left Jacobian of SO(3).
inline Pose exp(const Vec6& xi) {
  const Vec3 w = xi.head<3>();
  return {so3::exp(w), so3::left_jacobian(w) * xi.tail<3>()};
}

/// log: SE(3) -> se(3), (w, Jl(w)^{-1} x) with w = log R. Precondition: rotation angle < pi
/// (Jl is singular at 2 pi and its inverse loses accuracy as the angle nears pi).
inline Vec6 log(const Pose& g) {
  const Vec3 w = so3::log(g.R);
  Vec6 xi;
  xi << w, so3::left_jacobian_inverse(w) * g.x;
  return xi;
}

/// Adjoint Ad_g acting on twists (w, v): [R 0; hat(x) R  R].
inline Mat6 adjoint(const Pose& g) {
  Mat6 A = Mat6::Zero();
  A.topLeftCorner<3, 3>() = g.R;
  A.bottomRightCorner<3, 3>() = g.R;
  A.bottomLeftCorner<3, 3>() = so3::hat(g.x) * g.R;
  return A;
}

}  // namespace lgvi::se3
