// Plain-double 3-vectors and 3x3 matrices for the innermost arithmetic of a step: the rotation
// update's Newton iteration (rotation_update.hpp), the LGVI steps' kick and drift (lgvi.hpp) and
// the step benchmark's yardsticks (experiments/benchmarks). GCC compiles Eigen's 3-vector
// expressions into 2-wide packets mixed with scalars, stored and reloaded in halves; on plain
// doubles the free-body step ran 23% faster (177 -> 137 ns, callgrind 1232 -> 1192 instructions),
// and reading the state by scalars avoids the failed store forwarding of a 2-wide load over a
// previous step's scalar stores (pendulum step 102 -> 94 ns, measured with the kick and the
// momentum update on Eigen against on plain doubles). Every function is forced inline, so that a
// step flattened with LGVI_FLATTEN keeps no call to them.
#pragma once

#include <cmath>

#include "lgvi/types.hpp"

#if defined(__GNUC__) || defined(__clang__)
#define LGVI_PLAIN_INLINE [[gnu::always_inline]] inline
#else
#define LGVI_PLAIN_INLINE inline
#endif

namespace lgvi::plain {

struct V3 {
  double x, y, z;
};
LGVI_PLAIN_INLINE V3 v3(const Vec3& a) { return {a(0), a(1), a(2)}; }
LGVI_PLAIN_INLINE Vec3 vec3(const V3& a) { return Vec3(a.x, a.y, a.z); }
LGVI_PLAIN_INLINE V3 operator+(const V3& a, const V3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
LGVI_PLAIN_INLINE V3 operator-(const V3& a, const V3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
LGVI_PLAIN_INLINE V3 operator*(double c, const V3& a) { return {c * a.x, c * a.y, c * a.z}; }
LGVI_PLAIN_INLINE double dot(const V3& a, const V3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
LGVI_PLAIN_INLINE V3 cross(const V3& a, const V3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
LGVI_PLAIN_INLINE bool all_finite(const V3& a) {
  return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}

/// A 3x3 matrix by columns c0, c1, c2.
struct M3 {
  V3 c0, c1, c2;
};
LGVI_PLAIN_INLINE M3 m3(const Mat3& A) { return {v3(A.col(0)), v3(A.col(1)), v3(A.col(2))}; }
LGVI_PLAIN_INLINE V3 operator*(const M3& A, const V3& x) { return x.x * A.c0 + x.y * A.c1 + x.z * A.c2; }

/// A 3x3 matrix by rows r0, r1, r2.
struct Rows3 {
  V3 r0, r1, r2;
};
LGVI_PLAIN_INLINE Rows3 rows3(const Mat3& A) {
  return {{A(0, 0), A(0, 1), A(0, 2)}, {A(1, 0), A(1, 1), A(1, 2)}, {A(2, 0), A(2, 1), A(2, 2)}};
}
LGVI_PLAIN_INLINE Mat3 mat3(const Rows3& A) {
  Mat3 M;
  M << A.r0.x, A.r0.y, A.r0.z, A.r1.x, A.r1.y, A.r1.z, A.r2.x, A.r2.y, A.r2.z;
  return M;
}
LGVI_PLAIN_INLINE V3 operator*(const Rows3& A, const V3& x) { return {dot(A.r0, x), dot(A.r1, x), dot(A.r2, x)}; }
LGVI_PLAIN_INLINE Rows3 operator+(const Rows3& A, const Rows3& B) { return {A.r0 + B.r0, A.r1 + B.r1, A.r2 + B.r2}; }
LGVI_PLAIN_INLINE Rows3 operator*(double c, const Rows3& A) { return {c * A.r0, c * A.r1, c * A.r2}; }
/// A hat(w): row i of A hat(w) is r_i x w.
LGVI_PLAIN_INLINE Rows3 times_hat(const Rows3& A, const V3& w) {
  return {cross(A.r0, w), cross(A.r1, w), cross(A.r2, w)};
}

}  // namespace lgvi::plain
