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
// Work arrays of fixed capacity (the run's m constraints and the model's dim entries in the first rows and
// columns), compiled once for every model (projection.cpp): nothing is allocated.
#pragma once

#include "baselines/coordinates.hpp"
#include "baselines/ode.hpp"

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

/// Most entries of a model state the projection takes (the largest library model, the connected
/// bodies' matrix model, has 24).
inline constexpr int kMaxProjectionDim = 32;

/// The constraints g as a plain callable: `evaluate(context, y, g)` writes the run's m values at
/// the state y into g.
struct ConstraintFunction {
  const void* context = nullptr;
  void (*evaluate)(const void* context, const double* y, double* g) = nullptr;
};

/// The simplified Newton projection above, compiled once (projection.cpp) for every model: it
/// projects y (dim entries, in place) onto g(y) = g0 (m values) with the gradient G = g'(y)
/// (`gradient`: m rows of dim entries each, row after row), and err (unless null) onto the
/// tangent space. Work arrays of fixed capacity (m <= kMaxProjectionConstraints,
/// dim <= kMaxProjectionDim; InvalidInput beyond): nothing is allocated. Returns the iterations,
/// or -1 (not converged: y is the last iterate, err untouched).
int project_onto_constraints(const ConstraintFunction& g, int dim, int m, const double* gradient, const double* g0,
                             double* y, double* err);

}  // namespace lgvi::baselines
