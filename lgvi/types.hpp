// Fixed-size Eigen aliases used across the project. Every per-step quantity is one of these,
// so a step never touches the heap.
#pragma once

#include <limits>

#include <Eigen/Dense>

/// On a step function: inline every call inside it (recursively), so that a step with its
/// rotation-update Newton iteration and all the Eigen expressions compiles into one function.
/// GCC's inliner otherwise leaves the solver and many small Eigen kernels as calls (measured:
/// ~40% of a free-body step in call overhead and spills).
#if defined(__GNUC__) || defined(__clang__)
#define LGVI_FLATTEN __attribute__((flatten))
#else
#define LGVI_FLATTEN
#endif

namespace lgvi {

using Vec2 = Eigen::Matrix<double, 2, 1>;
using Vec3 = Eigen::Matrix<double, 3, 1>;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat3 = Eigen::Matrix<double, 3, 3>;
using Mat4 = Eigen::Matrix<double, 4, 4>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

/// The machine epsilon of double, 2^-52: the one constant every round-off bound is written in.
inline constexpr double kEps = std::numeric_limits<double>::epsilon();

}  // namespace lgvi
