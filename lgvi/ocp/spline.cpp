#include "lgvi/ocp/spline.hpp"

#include <cmath>
#include <vector>

#include "lgvi/inertia.hpp"

namespace lgvi::ocp {

const char* to_string(SplineEnd e) { return e == SplineEnd::Natural ? "natural" : "not-a-knot"; }

SplineEnd parse_spline_end(const std::string& name) {
  if (name == "natural") return SplineEnd::Natural;
  if (name == "not-a-knot") return SplineEnd::NotAKnot;
  throw InvalidInput("spline", "must be 'natural' or 'not-a-knot' (got '" + name + "')");
}

namespace {

void require_knots(int n) {
  if (n < 3) throw InvalidInput("knots", "a cubic spline needs at least 3 knots (got " + std::to_string(n) + ")");
}

// Solves the tridiagonal system (sub, diag, super) x = rhs in place of rhs (Thomas algorithm;
// the systems here are strictly diagonally dominant, so no pivoting is needed).
void solve_tridiagonal(const std::vector<double>& sub, const std::vector<double>& diag,
                       const std::vector<double>& super, Eigen::Ref<Eigen::VectorXd> rhs) {
  const std::size_t m = diag.size();
  std::vector<double> c(m);
  double denom = diag[0];
  c[0] = super[0] / denom;
  rhs(0) /= denom;
  for (std::size_t i = 1; i < m; ++i) {
    denom = diag[i] - sub[i] * c[i - 1];
    c[i] = super[i] / denom;
    rhs(i) = (rhs(i) - sub[i] * rhs(i - 1)) / denom;
  }
  for (std::size_t i = m - 1; i-- > 0;) rhs(i) -= c[i] * rhs(i + 1);
}

}  // namespace

Eigen::MatrixXd spline_moment_matrix(int n, double H, SplineEnd end) {
  require_knots(n);
  require_positive(H, "knot spacing");
  Eigen::MatrixXd Z = Eigen::MatrixXd::Zero(n, n);
  const int m = n - 2;  // unknowns M_1..M_{n-2}
  // Row i (1..n-2) of the right-hand side: 6 (c_{i+1} - 2 c_i + c_{i-1}) / H^2, as a matrix.
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(m, n);
  for (int i = 1; i <= m; ++i) {
    rhs(i - 1, i - 1) = 6.0 / (H * H);
    rhs(i - 1, i) = -12.0 / (H * H);
    rhs(i - 1, i + 1) = 6.0 / (H * H);
  }
  std::vector<double> sub(m, 1.0), diag(m, 4.0), super(m, 1.0);
  if (end == SplineEnd::NotAKnot) {
    // M_0 = 2 M_1 - M_2 in row 1: (2 M_1 - M_2) + 4 M_1 + M_2 = 6 M_1; likewise the last row.
    diag[0] = 6.0;
    super[0] = 0.0;
    diag[m - 1] = 6.0;
    sub[m - 1] = 0.0;
  }
  sub[0] = 0.0;
  super[m - 1] = 0.0;
  for (int col = 0; col < n; ++col) {
    Eigen::VectorXd r = rhs.col(col);
    if (end == SplineEnd::NotAKnot && m == 1) {
      r(0) /= 6.0;  // n = 3: the parabola, M_1 = rhs_1 / 6
    } else {
      solve_tridiagonal(sub, diag, super, r);
    }
    Z.block(1, col, m, 1) = r;
  }
  if (end == SplineEnd::NotAKnot) {
    if (m == 1) {
      Z.row(0) = Z.row(1);
      Z.row(2) = Z.row(1);
    } else {
      Z.row(0) = 2.0 * Z.row(1) - Z.row(2);
      Z.row(n - 1) = 2.0 * Z.row(n - 2) - Z.row(n - 3);
    }
  }
  return Z;
}

Eigen::MatrixXd spline_sampling_matrix(int n, double t_final, long steps, SplineEnd end) {
  require_knots(n);
  require_positive(t_final, "t_final");
  if (steps < 1) throw InvalidInput("steps", "must be >= 1");
  const double H = t_final / (n - 1);
  const Eigen::MatrixXd Z = spline_moment_matrix(n, H, end);
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(steps + 1, n);
  for (long j = 0; j <= steps; ++j) {
    // t_j / H = j (n - 1) / steps, split exactly in integers into interval i and fraction b.
    const long x = j * (n - 1);
    long i = x / steps;
    if (i > n - 2) i = n - 2;
    const double b = static_cast<double>(x - i * steps) / static_cast<double>(steps);
    const double a = 1.0 - b;
    S(j, i) += a;
    S(j, i + 1) += b;
    const double wa = (a * a * a - a) * H * H / 6.0, wb = (b * b * b - b) * H * H / 6.0;
    S.row(j) += wa * Z.row(i) + wb * Z.row(i + 1);
  }
  return S;
}

double spline_evaluate(const Eigen::VectorXd& c, double t_final, double t, SplineEnd end) {
  const int n = static_cast<int>(c.size());
  require_knots(n);
  const double H = t_final / (n - 1);
  const Eigen::VectorXd M = spline_moment_matrix(n, H, end) * c;
  int i = static_cast<int>(std::floor(t / H));
  if (i < 0) i = 0;
  if (i > n - 2) i = n - 2;
  const double b = (t - i * H) / H, a = 1.0 - b;
  return a * c(i) + b * c(i + 1) + ((a * a * a - a) * M(i) + (b * b * b - b) * M(i + 1)) * H * H / 6.0;
}

}  // namespace lgvi::ocp
