// Controls as functions of time from samples, so that a control sequence found on the LGVI grid
// (u_k at t_k) can be replayed on every baseline.
//
//  - PiecewiseLinear: the continuous counterpart of the symmetric LGVI, whose impulses
//    h/2 u_k + h/2 u_{k+1} are the trapezoidal rule of exactly this function (the printed form's
//    h u_{k+1} is the right-endpoint rule of a piecewise-constant one). Kinks at every sample:
//    adaptive solvers see them as local errors and shorten their steps there.
//  - CubicSpline: natural cubic spline, C^2, O(dt^4) for smooth controls; the choice for
//    adaptive solvers when the samples come from a smooth control.
// Outside [t_0, t_last] the end values are held. Evaluation allocates nothing.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <vector>

#include <Eigen/Dense>

#include "lgvi/inertia.hpp"

namespace lgvi::baselines {

enum class Interpolation { PiecewiseLinear, CubicSpline };

template <int Dim>
class SampledControl {
 public:
  using Value = Eigen::Matrix<double, Dim, 1>;

  /// times strictly increasing and finite (at least 2), one value per time. Throws InvalidInput.
  SampledControl(std::vector<double> times, std::vector<Value> values, Interpolation kind)
      : t_(std::move(times)), u_(std::move(values)), kind_(kind) {
    if (t_.size() < 2 || t_.size() != u_.size()) {
      throw InvalidInput("control", "needs at least 2 samples and one value per time");
    }
    for (std::size_t k = 0; k < t_.size(); ++k) {
      if (!std::isfinite(t_[k]) || (k > 0 && !(t_[k] > t_[k - 1]))) {
        throw InvalidInput("control", "sample times must be finite and strictly increasing");
      }
      require_finite(u_[k], "control");
    }
    if (kind_ == Interpolation::CubicSpline) second_derivatives();
  }

  Value operator()(double t) const {
    if (t <= t_.front()) return u_.front();
    if (t >= t_.back()) return u_.back();
    const std::size_t k =
        static_cast<std::size_t>(std::upper_bound(t_.begin(), t_.end(), t) - t_.begin()) - 1;  // t_k <= t < t_k+1
    const double dt = t_[k + 1] - t_[k];
    const double b = (t - t_[k]) / dt, a = 1.0 - b;
    Value u = a * u_[k] + b * u_[k + 1];
    if (kind_ == Interpolation::CubicSpline) {
      u += ((a * a * a - a) * m_[k] + (b * b * b - b) * m_[k + 1]) * (dt * dt / 6.0);
    }
    return u;
  }

 private:
  /// Natural spline: m_0 = m_last = 0 and continuity of u' at the interior samples, a
  /// tridiagonal system solved by the Thomas algorithm (diagonally dominant).
  void second_derivatives() {
    const std::size_t n = t_.size();
    m_.assign(n, Value::Zero());
    std::vector<double> c(n, 0.0);  // modified super-diagonal
    std::vector<Value> r(n, Value::Zero());
    for (std::size_t i = 1; i + 1 < n; ++i) {
      const double h0 = t_[i] - t_[i - 1], h1 = t_[i + 1] - t_[i];
      const Value rhs = 6.0 * ((u_[i + 1] - u_[i]) / h1 - (u_[i] - u_[i - 1]) / h0);
      const double diag = 2.0 * (h0 + h1) - h0 * c[i - 1];
      c[i] = h1 / diag;
      r[i] = (rhs - h0 * r[i - 1]) / diag;
    }
    for (std::size_t i = n - 2; i >= 1; --i) {
      m_[i] = r[i] - c[i] * m_[i + 1];
    }
  }

  std::vector<double> t_;
  std::vector<Value> u_;
  Interpolation kind_;
  std::vector<Value> m_;
};

}  // namespace lgvi::baselines
