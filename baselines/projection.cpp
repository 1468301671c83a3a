// The manifold projection of cvode-bdf-projected, compiled once for every model (the method, its
// stopping rule and its constants: projection.hpp).
#include "baselines/projection.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "lgvi/inertia.hpp"

namespace lgvi::baselines {

namespace {

constexpr int kMaxIterations = 10;
constexpr double kTolerance = 1e-14;       // the stopping rule, relative to s_i
constexpr double kRoundoffFloor = 1e-12;   // accepted when the iteration stagnates
constexpr double kRegularization = 1e-13;  // added to the unit diagonal of G G^T

// Fixed capacity, run-time size: the run's m constraints, the model's dim entries.
using Values = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxProjectionConstraints, 1>;
using State = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxProjectionDim, 1>;
using Gradient = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor, kMaxProjectionConstraints,
                               kMaxProjectionDim>;
using Gram = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxProjectionConstraints,
                           kMaxProjectionConstraints>;

}  // namespace

int project_onto_constraints(const ConstraintFunction& g, int dim, int m, const double* gradient, const double* g0_ptr,
                             double* y_ptr, double* err_ptr) {
  if (m == 0) return 0;
  if (m < 0 || m > kMaxProjectionConstraints) {
    throw InvalidInput("constraints", "the projection takes 1 to " + std::to_string(kMaxProjectionConstraints));
  }
  if (dim < 1 || dim > kMaxProjectionDim) {
    throw InvalidInput("dimension", "the projection takes states of 1 to " + std::to_string(kMaxProjectionDim) +
                                        " entries");
  }
  Eigen::Map<Eigen::VectorXd> y(y_ptr, dim);
  const Eigen::Map<const Eigen::VectorXd> g0(g0_ptr, m);
  Gradient G = Eigen::Map<const Gradient>(gradient, m, dim);
  const State y_tilde = y;
  Values scale = Values::Ones(m), r = Values::Zero(m);
  for (int i = 0; i < m; ++i) {
    scale(i) = std::max(std::abs(g0(i)), G.row(i).cwiseProduct(y_tilde.transpose()).cwiseAbs().sum());
    if (!(scale(i) > 0.0)) scale(i) = std::numeric_limits<double>::min();
    const double norm = G.row(i).norm();
    // A constraint without gradient (a free body at rest: E = 0 and grad E = 0) cannot be
    // corrected; its row stays zero (and its residual is checked as the others').
    r(i) = norm > 0.0 ? 1.0 / norm : 0.0;
  }
  const Values row_scale = r;
  G = row_scale.asDiagonal() * G;
  Gram A = G * G.transpose();
  A.diagonal().array() += kRegularization;
  const Eigen::LLT<Gram> llt(A);
  if (llt.info() != Eigen::Success) return -1;

  State at(dim);
  auto residual = [&](const State& point) {
    r.setZero();
    g.evaluate(g.context, point.data(), r.data());
    r -= g0;
    return (r.cwiseAbs().cwiseQuotient(scale)).maxCoeff();
  };
  Values mu = Values::Zero(m);
  double res = residual(y_tilde);
  int it = 0;
  while (res > kTolerance) {
    if (it == kMaxIterations) return res <= kRoundoffFloor ? it : -1;
    mu -= llt.solve(Values(row_scale.cwiseProduct(r)));
    at = y_tilde + G.transpose() * mu;
    y = at;
    ++it;
    const double previous = res;
    res = residual(at);
    if (!std::isfinite(res)) return -1;
    if (res > 0.5 * previous) {  // stagnation: round-off, or no contraction
      if (res <= kRoundoffFloor) break;
      if (res > previous) return -1;
    }
  }
  if (err_ptr != nullptr) {
    Eigen::Map<Eigen::VectorXd> err(err_ptr, dim);
    const Values Ge = G * err;
    err -= G.transpose() * llt.solve(Ge);
  }
  return it;
}

}  // namespace lgvi::baselines
