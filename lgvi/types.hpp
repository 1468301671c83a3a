// Fixed-size Eigen aliases used across the project. Every per-step quantity is one of these,
// so a step never touches the heap.
#pragma once

#include <Eigen/Dense>

namespace lgvi {

using Vec3 = Eigen::Matrix<double, 3, 1>;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat3 = Eigen::Matrix<double, 3, 3>;
using Mat4 = Eigen::Matrix<double, 4, 4>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

}  // namespace lgvi
