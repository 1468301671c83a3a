// The two cases with closed-form solutions the one-step methods' order tests use
// (test_lie_group.cpp, test_splitting.cpp; the cases of test_exact.cpp): the free body around its
// largest axis and the Lagrange top spun from hanging.
#pragma once

#include "lgvi/so3.hpp"
#include "lgvi/systems/pendulum.hpp"
#include "lgvi/types.hpp"

namespace lgvi::test::exact_cases {

inline const Mat3& free_J() {
  static const Mat3 J = Vec3(0.13, 0.28, 0.17).asDiagonal();
  return J;
}
inline const Mat3& free_R0() {
  static const Mat3 R0 = so3::exp(Vec3(0.3, -0.2, 0.5));
  return R0;
}
inline const Vec3 kFreeOmega0(0.5, 3.0, 0.4);
inline const Pendulum3D& top() {
  static const Pendulum3D p(1.0, Vec3(0.14, 0.14, 0.08).asDiagonal(), Vec3(0.0, 0.0, 0.3), 9.81);
  return p;
}
inline const Vec3 kTopOmega0(1.0, 2.0, 5.0);

}  // namespace lgvi::test::exact_cases
