// SO(3): the rotation group and its Lie algebra so(3) ~ R^3.
//
// Conventions (paper, section 2 and eq. 8): hat(x) y = x cross y; exp/log are the matrix
// exponential and principal logarithm (rotation angle in [0, pi]); the Cayley map is
// cay(f) = (I + hat f)(I - hat f)^{-1}, whose parameter f = tan(theta/2) n.
// Small-angle branches use Taylor series below the thresholds stated next to each function;
// the thresholds keep the truncation error below 1e-17 relative.
#pragma once

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/Dense>

#include "lgvi/types.hpp"

namespace lgvi::so3 {

/// hat: R^3 -> so(3), hat(x) y = x cross y.
inline Mat3 hat(const Vec3& x) {
  Mat3 X;
  X << 0.0, -x.z(), x.y(),  //
      x.z(), 0.0, -x.x(),   //
      -x.y(), x.x(), 0.0;
  return X;
}

/// hat(x)^2 = x x^T - |x|^2 I, written entry by entry: each entry is the one or two non-zero
/// products of the generic product hat(x) * hat(x) (so the same value to the last bit), without
/// its 27 multiplications.
inline Mat3 hat_squared(const Vec3& x) {
  const double xx = x.x() * x.x(), yy = x.y() * x.y(), zz = x.z() * x.z();
  const double xy = x.x() * x.y(), xz = x.x() * x.z(), yz = x.y() * x.z();
  Mat3 X;
  X << -(zz + yy), xy, xz,  //
      xy, -(zz + xx), yz,   //
      xz, yz, -(yy + xx);
  return X;
}

/// vee: so(3) -> R^3, the inverse of hat. Reads the skew part (X - X^T)/2, so it is also the
/// projection of a general 3x3 matrix onto so(3) followed by vee.
inline Vec3 vee(const Mat3& X) {
  return 0.5 * Vec3(X(2, 1) - X(1, 2), X(0, 2) - X(2, 0), X(1, 0) - X(0, 1));
}

/// Coefficients of Rodrigues' formula exp(hat w) = I + a hat(w) + b hat(w)^2, with
/// a = sin(t)/t, b = (1 - cos t)/t^2, t = |w|, from the squared angle t^2.
/// Series branch for t < 1/2 (t^2 < 1/4), the Taylor series in t^2 through t^12:
///     a = sum_k (-t^2)^k / (2k+1)!,   b = sum_k (-t^2)^k / (2k+2)!,   k = 0..6;
/// the first omitted terms are t^14/15! <= 4.7e-17 and t^14/16! <= 2.9e-18 (relative to a >= 0.95,
/// b >= 0.48: below eps/2). No square root, no sine, no division: the step of a Lie group method
/// takes one exponential per stage, so these dominated its cost (tests/lgvi/test_so3.cpp checks
/// both branches against long double to a few eps).
/// Above, the half-angle form from one sin/cos pair of t/2: with q = sin(t/2) / (t/2),
/// a = q cos(t/2) and b = q^2 / 2. b never forms 1 - cos t, which cancels to a relative error
/// eps / t^2. In exp that would be harmless (b hat(w)^2 = O(t^2)), but the rotation update's
/// G = a J f + b f x J f - h p has size ~|J f| = O(t), where the cancellation leaves an error
/// ~eps ||J||, i.e. eps / t relative: its exponential chart stalled above the convergence
/// tolerance for t in ~(1e-4, 1e-2).
struct RodriguesCoefficients {
  double a;
  double b;
};
/// The half-angle form alone, for t > 0 (the branch above the series; the rotation update's
/// exponential chart uses it down to t = 1e-4).
inline RodriguesCoefficients rodrigues_half_angle(double t) {
  const double half = 0.5 * t;
  const double q = std::sin(half) / half;
  return {q * std::cos(half), 0.5 * q * q};
}
inline RodriguesCoefficients rodrigues_of_squared_angle(double t2) {
  if (t2 < 0.25) {
    // Estrin's scheme: p(x) = (c0 + c1 x) + x^2 (c2 + c3 x) + x^4 ((c4 + c5 x) + x^2 c6), three
    // levels of products instead of Horner's six (the latency of a step's exponential).
    const double x = t2, x2 = x * x, x4 = x2 * x2;
    // The coefficients are folded at compile time (a division by a constant is not).
    constexpr double a1 = -1.0 / 6.0, a2 = 1.0 / 120.0, a3 = -1.0 / 5040.0, a4 = 1.0 / 362880.0,
                     a5 = -1.0 / 39916800.0, a6 = 1.0 / 6227020800.0;
    constexpr double b1 = -1.0 / 24.0, b2 = 1.0 / 720.0, b3 = -1.0 / 40320.0, b4 = 1.0 / 3628800.0,
                     b5 = -1.0 / 479001600.0, b6 = 1.0 / 87178291200.0;
    const double a = (1.0 + a1 * x) + x2 * (a2 + a3 * x) + x4 * ((a4 + a5 * x) + a6 * x2);
    const double b = (0.5 + b1 * x) + x2 * (b2 + b3 * x) + x4 * ((b4 + b5 * x) + b6 * x2);
    return {a, b};
  }
  return rodrigues_half_angle(std::sqrt(t2));
}
/// The same coefficients from the angle t = |w| >= 0.
inline RodriguesCoefficients rodrigues(double theta) { return rodrigues_of_squared_angle(theta * theta); }

/// exp: so(3) -> SO(3) (Rodrigues).
inline Mat3 exp(const Vec3& w) {
  const auto [a, b] = rodrigues_of_squared_angle(w.squaredNorm());
  return Mat3::Identity() + a * hat(w) + b * hat_squared(w);
}

/// R exp(hat w) = R + a M + b M hat(w), M = R hat(w), without forming exp(hat w): row i of
/// M is r_i x w (r_i the i-th row of R; r^T hat(w) = (r x w)^T), and of M hat(w) is m_i x w.
/// The two sets of cross products do not wait for the coefficients a, b, so a step that moves
/// an attitude by an exponential (the Lie group methods' updates) overlaps them with the series;
/// R exp(hat w) formed as a product of matrices agrees to a few ulp.
inline Mat3 right_multiply_exp(const Mat3& R, const Vec3& w) {
  const auto [a, b] = rodrigues_of_squared_angle(w.squaredNorm());
  Mat3 out;
  for (int i = 0; i < 3; ++i) {
    const Vec3 r = R.row(i).transpose();
    const Vec3 m = r.cross(w);
    out.row(i) = (r + a * m + b * m.cross(w)).transpose();
  }
  return out;
}

/// exp(hat w) - I = a hat(w) + b hat(w)^2, accurate relative to its own size (no cancellation
/// against I): the form to use when a small rotation's deviation from I enters a difference.
inline Mat3 exp_minus_identity(const Vec3& w) {
  const auto [a, b] = rodrigues_of_squared_angle(w.squaredNorm());
  return a * hat(w) + b * hat_squared(w);
}

/// log: SO(3) -> so(3), principal branch, |result| in [0, pi]. Precondition: R orthonormal
/// with det +1 (to round-off).
///
/// The angle is atan2(|vee(R - R^T)|/2, (tr R - 1)/2), accurate over [0, pi]. Three branches:
/// theta < 1e-4: w = vee(R - R^T)/2 * (1 + theta^2/6) (Taylor of theta/sin theta);
/// theta > pi/2 (cos theta < 0): the axis comes from the symmetric part
/// R + R^T = 2 cos(theta) I + 2(1 - cos theta) n n^T, its sign from the skew part;
/// otherwise w = theta / (2 sin theta) vee(R - R^T).
/// Why pi/2: the skew-part axis n = vee(R - R^T) / (2 sin theta) carries an error
/// ~eps / sin theta, i.e. ~eps/(pi - theta) near pi (2400 eps at pi - 1e-3), whereas the
/// symmetric-part axis divides by 1 - cos theta >= 1 there and stays at a few eps. Switching at
/// pi/2 bounds the amplification by theta / sin theta <= pi/2 on the skew branch.
inline Vec3 log(const Mat3& R) {
  const Vec3 s = vee(R);  // = sin(theta) n
  const double sin_theta = s.norm();
  const double cos_theta = std::clamp(0.5 * (R.trace() - 1.0), -1.0, 1.0);
  const double theta = std::atan2(sin_theta, cos_theta);
  if (theta < 1e-4) {
    return (1.0 + theta * theta / 6.0) * s;
  }
  if (cos_theta < 0.0) {
    // n n^T = (R + R^T - 2 cos(theta) I) / (2 (1 - cos theta)); take the largest diagonal.
    const Mat3 B = (0.5 * (R + R.transpose()) - cos_theta * Mat3::Identity()) / (1.0 - cos_theta);
    Eigen::Index i = 0;
    B.diagonal().maxCoeff(&i);
    Vec3 n = B.col(i) / std::sqrt(B(i, i));
    n.normalize();
    if (n.dot(s) < 0.0) n = -n;
    return theta * n;
  }
  return (theta / sin_theta) * s;
}

/// Right Jacobian Jr(w): exp(w + dw) = exp(w) exp(Jr(w) dw) + O(dw^2).
/// Jr = I - b hat(w) + c hat(w)^2, b = (1 - cos t)/t^2, c = (t - sin t)/t^3.
/// Taylor branch for t < 1e-3 (next term t^4/5040 ~ 2e-16 relative to 1/6).
inline Mat3 right_jacobian(const Vec3& w) {
  const double t = w.norm();
  const double t2 = t * t;
  double b, c;
  if (t < 1e-3) {
    b = 0.5 - t2 / 24.0 + t2 * t2 / 720.0;
    c = 1.0 / 6.0 - t2 / 120.0 + t2 * t2 / 5040.0;
  } else {
    // b in the half-angle form 2 sin^2(t/2) / t^2: (1 - cos t) / t^2 cancels to a relative error
    // eps / t^2, which hat(w) (size t) turns into ~eps / t in Jr (165 eps just above 1e-3).
    // c's cancellation (6 eps / t^2 relative) is harmless: it multiplies hat(w)^2 (size t^2).
    const double s = std::sin(0.5 * t) / (0.5 * t);
    b = 0.5 * s * s;
    c = (t - std::sin(t)) / (t2 * t);
  }
  const Mat3 W = hat(w);
  return Mat3::Identity() - b * W + c * W * W;
}

/// Left Jacobian Jl(w) = Jr(-w): exp(w + dw) = exp(Jl(w) dw) exp(w) + O(dw^2).
inline Mat3 left_jacobian(const Vec3& w) { return right_jacobian(-w); }

/// Inverse right Jacobian: log(exp(w) exp(d)) = w + Jr^{-1}(w) d + O(d^2), for |w| < pi.
/// Jr^{-1} = I + hat(w)/2 + e hat(w)^2, e = 1/t^2 - (1 + cos t)/(2 t sin t).
/// Evaluated as e = 1/t^2 - 1/(2 t tan(t/2)) (the same function): near pi, 1 + cos t cancels
/// completely (relative error eps / (pi - t)^2; 7e-10 in Jr^{-1} at pi - 1e-9), while
/// 1/tan(t/2) -> 0 stays accurate.
/// Taylor branch for t < 1e-3: e = 1/12 + t^2/720 + t^4/30240.
inline Mat3 right_jacobian_inverse(const Vec3& w) {
  const double t = w.norm();
  const double t2 = t * t;
  const double e = (t < 1e-3) ? 1.0 / 12.0 + t2 / 720.0 + t2 * t2 / 30240.0
                              : 1.0 / t2 - 1.0 / (2.0 * t * std::tan(0.5 * t));
  const Mat3 W = hat(w);
  return Mat3::Identity() + 0.5 * W + e * W * W;
}

/// Jr^{-1}(w) v by its series through degree 3 in w: the right-trivialized dexp^{-1},
///     Jr^{-1}(w) v = sum_k (-1)^k B_k / k! ad_w^k(v) = v + w x v / 2 + w x (w x v) / 12 + O(|w|^4 |v|)
/// (B_k the Bernoulli numbers; B_3 = 0, so the degree-3 term vanishes; the first omitted one is
/// -w x (w x (w x (w x v))) / 720). The Runge-Kutta-Munthe-Kaas methods solve
/// theta' = Jr^{-1}(theta) Omega for R = R_0 exp(theta), and a truncation index q >= p - 2 keeps
/// their order p (Munthe-Kaas, "High order Runge-Kutta methods on manifolds", Appl. Numer. Math.
/// 29 (1999); Hairer, Lubich, Wanner, "Geometric Numerical Integration", Sec. IV.8): theta ~ t
/// Omega, so ad_theta^k(Omega) = O(h^(k+1)); this series serves up to order 5.
inline Vec3 right_jacobian_inverse_series(const Vec3& w, const Vec3& v) {
  const Vec3 wv = w.cross(v);
  return v + 0.5 * wv + (1.0 / 12.0) * w.cross(wv);
}

/// Inverse left Jacobian, Jl^{-1}(w) = Jr^{-1}(-w).
inline Mat3 left_jacobian_inverse(const Vec3& w) { return right_jacobian_inverse(-w); }

/// Cayley map cay(f) = (I + hat f)(I - hat f)^{-1} = I + 2/(1 + |f|^2) (hat f + hat(f)^2).
/// Orthonormal for every f; covers SO(3) except the rotations by pi.
inline Mat3 cayley(const Vec3& f) {
  return Mat3::Identity() + (2.0 / (1.0 + f.squaredNorm())) * (hat(f) + hat_squared(f));
}

/// Inverse Cayley map: f = vee(R - R^T) / (1 + tr R), i.e. tan(theta/2) n. Precondition:
/// tr R > -1 (rotation angle below pi); the result grows without bound as theta -> pi.
inline Vec3 cayley_inverse(const Mat3& R) { return (2.0 / (1.0 + R.trace())) * vee(R); }

/// Orthogonality error ||R^T R - I||_F (Frobenius norm).
inline double orthogonality_error(const Mat3& R) {
  return (R.transpose() * R - Mat3::Identity()).norm();
}

/// Determinant error |det R - 1|.
inline double determinant_error(const Mat3& R) { return std::abs(R.determinant() - 1.0); }

/// True when R is a rotation to within tol: orthogonality and determinant errors below tol.
inline bool is_rotation(const Mat3& R, double tol) {
  return R.allFinite() && orthogonality_error(R) <= tol && determinant_error(R) <= tol;
}

/// Uniformly distributed random rotation (Haar measure): a normalized 4-vector of independent
/// standard normals is a uniform unit quaternion.
template <class Rng>
Mat3 random_rotation(Rng& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
  q.normalize();
  return q.toRotationMatrix();
}

}  // namespace lgvi::so3
