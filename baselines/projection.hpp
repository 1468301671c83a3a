// Manifold projection of cvode-bdf-projected: after every step CVODE hands the new state y~ to
// the model, which moves it onto
//     M = { y : g(y) = g_0 },
// g the chart's constraints (|q|^2 = 1 per quaternion, R^T R = I per matrix body: exact targets)
// followed by the first integrals the mechanics vouches for (baselines/mechanics.hpp
// invariants(): the free body's energy and Casimir |Pi|, the pendulum's energy and vertical
// momentum e3.(R J Omega), the dumbbell's energy; the energy only without control), g_0 their
// values at the initial state.
//
// The projection (Hairer, Lubich, Wanner, Geometric Numerical Integration, 2nd ed., sec. IV.4,
// Algorithm 4.2): the orthogonal projection in the Euclidean metric of the model's state
// (quaternion or matrix entries, Euler angles, and the velocity state w as it is, unweighted),
//     y = y~ + G^T mu,   g(y~ + G^T mu) = g_0,   G = g'(y~),
// mu by simplified Newton iterations with G fixed at y~:
//     mu <- mu - (G G^T)^{-1} (g(y~ + G^T mu) - g_0).
// The rows of G and of the residual are scaled to unit gradient norm (the same projection: the
// span of G^T does not change; G G^T then has a unit diagonal), and G G^T + 1e-13 I is factored
// once (Cholesky): the regularization keeps the factorization defined when two constraints' gradients are
// parallel (the free body spinning about a principal axis: grad E and grad |Pi| both along it,
// where both constraints hold together) and changes nothing measurable otherwise.
// Stopping rule: every constraint within 1e-14 of its scale,
//     |g_i(y) - g_0,i| <= 1e-14 s_i,   s_i = max(|g_0,i|, sum_j |G_ij y~_j|)
// (s_i the size of the terms g_i is made of: the round-off of evaluating g_i is a few eps s_i),
// at most kMaxIterations iterations; an iteration that no longer shrinks the residual by half
// ends the loop (round-off), accepted when the residual is within 1e-12 s_i, else the projection
// fails (CVODE then retries the step with a smaller h: a recoverable failure).
// Error estimate: projected onto the tangent space of M, err <- err - G^T (G G^T)^{-1} G err (the
// CVODE user guide, section "Projection": the error test then measures only the part of the
// local error the projection leaves).
// G itself comes from the model: central differences of g in the state's entries (model.hpp),
// exact up to rounding for the polynomial constraints (|q|^2, R^T R, the quadratic energies and
// momenta of the free body; the pendulum's energy and vertical momentum are quadratic in q and in
// each entry), ~eps^(2/3) relative for the dumbbell's potential: the simplified Newton iteration
// converges either way (its contraction is ~ |y - y~| (the step's local error) times the
// constraints' curvature, plus the gradient's error), and the fixed point is g(y) = g_0 exactly.
// Fixed-size Eigen types (MaxC rows, the run's m constraints in the first m): nothing is allocated.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>

#include "baselines/coordinates.hpp"

namespace lgvi::baselines {

/// The constraint set of a chart: count per body, values at c, exact targets, name.
template <class Chart>
struct ChartConstraints;

/// |q|^2 = 1.
template <>
struct ChartConstraints<QuaternionChart> {
  static constexpr int count = 1;
  static constexpr const char* name = "|q| = 1";
  static void values(const QuaternionChart::Coords& q, double* g) { g[0] = q.squaredNorm(); }
  static void targets(double* g) { g[0] = 1.0; }
};

/// R^T R = I: its 6 entries on and above the diagonal.
template <>
struct ChartConstraints<MatrixChart> {
  static constexpr int count = 6;
  static constexpr const char* name = "R^T R = I";
  static void values(const MatrixChart::Coords& c, double* g) {
    const Mat3 R = MatrixChart::rotation(c);
    const Mat3 RtR = R.transpose() * R;
    int k = 0;
    for (int i = 0; i < 3; ++i) {
      for (int j = i; j < 3; ++j) g[k++] = RtR(i, j);
    }
  }
  static void targets(double* g) {
    int k = 0;
    for (int i = 0; i < 3; ++i) {
      for (int j = i; j < 3; ++j) g[k++] = i == j ? 1.0 : 0.0;
    }
  }
};

/// Euler angles are a chart of SO(3) itself: no constraint.
template <>
struct ChartConstraints<EulerChart> {
  static constexpr int count = 0;
  static constexpr const char* name = "";
  static void values(const EulerChart::Coords&, double*) {}
  static void targets(double*) {}
};

/// The simplified Newton projection above, for a state of Dim entries and at most MaxC
/// constraints.
template <int Dim, int MaxC>
struct ManifoldProjection {
  // Fixed MaxC rows: the m constraints of a run fill the first m, the others are zero (their
  // gradient rows too, so they neither move y nor count in the residual).
  using State = Eigen::Matrix<double, Dim, 1>;
  using Values = Eigen::Matrix<double, MaxC, 1>;
  using Gradient = Eigen::Matrix<double, MaxC, Dim, Eigen::RowMajor>;
  using Gram = Eigen::Matrix<double, MaxC, MaxC>;

  static constexpr int kMaxIterations = 10;
  static constexpr double kTolerance = 1e-14;       ///< the stopping rule, relative to s_i
  static constexpr double kRoundoffFloor = 1e-12;   ///< accepted when the iteration stagnates
  static constexpr double kRegularization = 1e-13;  ///< added to the unit diagonal of G G^T

  /// Projects y (in place) onto g(y) = g0 (the first m entries; the rest zero) with the gradient
  /// G = g'(y) (the first m rows; the rest zero), and err (unless null) onto the tangent space.
  /// `g(y, out)` evaluates the m constraints into out's first m entries. Returns the iterations,
  /// or -1 (not converged: y is the last iterate, err untouched).
  template <class Constraints>
  static int project(const Constraints& g, int m, Gradient G, const Values& g0, double* y_ptr, double* err_ptr) {
    if (m == 0) return 0;
    Eigen::Map<State> y(y_ptr);
    const State y_tilde = y;
    Values scale = Values::Ones(), r = Values::Zero();
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

    auto residual = [&](const State& at) {
      r.setZero();
      g(at, r);
      r -= g0;
      return (r.cwiseAbs().cwiseQuotient(scale)).maxCoeff();
    };
    Values mu = Values::Zero();
    double res = residual(y_tilde);
    int it = 0;
    while (res > kTolerance) {
      if (it == kMaxIterations) return res <= kRoundoffFloor ? it : -1;
      mu -= llt.solve(Values(row_scale.cwiseProduct(r)));
      y = y_tilde + G.transpose() * mu;
      ++it;
      const double previous = res;
      res = residual(y);
      if (!std::isfinite(res)) return -1;
      if (res > 0.5 * previous) {  // stagnation: round-off, or no contraction
        if (res <= kRoundoffFloor) break;
        if (res > previous) return -1;
      }
    }
    if (err_ptr != nullptr) {
      Eigen::Map<State> err(err_ptr);
      const Values Ge = G * err;
      err -= G.transpose() * llt.solve(Ge);
    }
    return it;
  }
};

}  // namespace lgvi::baselines
