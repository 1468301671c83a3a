// Cubic-spline control parameterization of the direct method (sections 4.1, 4.2): the values at
// n knots, uniformly spread over [0, T], interpolated by a cubic spline and sampled at the grid
// nodes t_j = j h. The map from knot values to node values is linear; it is built once as a
// matrix S ((N+1) x n) with u_j = sum_i S(j, i) c_i.
//
// Moments form (de Boor, "A practical guide to splines", ch. IV): with knot spacing H and the
// second derivatives M_i at the knots, on [t_i, t_{i+1}], a = (t_{i+1} - t)/H, b = 1 - a,
//     s(t) = a c_i + b c_{i+1} + ((a^3 - a) M_i + (b^3 - b) M_{i+1}) H^2/6,
// and continuity of s' at the interior knots gives, for i = 1..n-2,
//     M_{i-1} + 4 M_i + M_{i+1} = 6 (c_{i+1} - 2 c_i + c_{i-1}) / H^2.
// End conditions:
//   Natural (GSL's gsl_interp_cspline): M_0 = M_{n-1} = 0. Reproduces linear data exactly.
//   NotAKnot (MATLAB's spline default): s''' continuous at t_1 and t_{n-2}, i.e. with uniform
//     knots M_0 = 2 M_1 - M_2 and M_{n-1} = 2 M_{n-2} - M_{n-3}. Substituted into the rows i = 1
//     and i = n-2 they become 6 M_1 = rhs_1 and 6 M_{n-2} = rhs_{n-2} (the neighbours cancel),
//     so the system stays tridiagonal. Reproduces cubic data exactly. With n = 3 the only row
//     gives the parabola through the three values (M_0 = M_1 = M_2), as MATLAB does.
// The tridiagonal systems are solved by the Thomas algorithm (diagonally dominant: no pivoting).
#pragma once

#include <string>

#include <Eigen/Dense>

namespace lgvi::ocp {

enum class SplineEnd { Natural, NotAKnot };
const char* to_string(SplineEnd e);
/// Parses "natural" or "not-a-knot"; throws InvalidInput("spline", ...) otherwise.
SplineEnd parse_spline_end(const std::string& name);

/// The second derivatives M (n x n matrix, M = Z c) of the spline through n >= 3 uniformly spaced
/// knots with spacing H > 0 (n >= 3 for both end conditions). Throws InvalidInput on bad n, H.
Eigen::MatrixXd spline_moment_matrix(int n, double H, SplineEnd end);

/// The matrix S with S(j, :) c = s(t_j), t_j = j * t_final / steps, j = 0..steps, for the spline
/// through n >= 3 knots at i * t_final / (n - 1). Throws InvalidInput on bad arguments.
Eigen::MatrixXd spline_sampling_matrix(int n, double t_final, long steps, SplineEnd end);

/// Evaluates the spline with knot values c (n >= 3, uniform on [0, t_final]) at t in [0, t_final]
/// (for tests and output).
double spline_evaluate(const Eigen::VectorXd& c, double t_final, double t, SplineEnd end);

}  // namespace lgvi::ocp
