#include "baselines/exact/lagrange_top.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "lgvi/inertia.hpp"
#include "lgvi/so3.hpp"

namespace lgvi::baselines {

namespace {


/// c0 + c1 v + c2 v^2 + c3 v^3.
struct Cubic {
  double c0, c1, c2, c3;
  double operator()(double v) const { return ((c3 * v + c2) * v + c1) * v + c0; }
  double derivative(double v) const { return (3.0 * c3 * v + 2.0 * c2) * v + c1; }
};

/// The root in [lo, hi] of a polynomial whose sign is sign_lo just above lo and -sign_lo just
/// below hi (the callers know these signs from the theory, not from evaluating at the ends):
/// Newton from `start`, falling back to bisection whenever a step leaves the bracket.
double bracketed_root(const Cubic& f, double lo, double hi, double sign_lo, double start) {
  double x = std::clamp(start, lo, hi);
  for (int i = 0; i < 400; ++i) {
    const double fx = f(x);
    if (fx == 0.0) return x;
    if ((fx < 0.0) == (sign_lo < 0.0)) {
      lo = x;
    } else {
      hi = x;
    }
    double next = x - fx / f.derivative(x);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - x) <= 2.0 * kEps * std::abs(x) || !(hi > lo)) return next;
    x = next;
  }
  return x;
}

/// [p1, p2, d], a rotation with third column d (unit).
Mat3 symmetric_frame(const Vec3& d) {
  Eigen::Index i = 0;
  d.cwiseAbs().minCoeff(&i);  // the coordinate axis least aligned with d
  const Vec3 p1 = (Vec3::Unit(i) - d(i) * d).normalized();
  Mat3 Q;
  Q.col(0) = p1;
  Q.col(1) = d.cross(p1);
  Q.col(2) = d;
  return Q;
}

struct AxisymmetricParts {
  double J1, J3;
  double residual;  ///< ||J - (J1 I + (J3 - J1) d d^T)||_F / ||J||_F
};
AxisymmetricParts axisymmetric_parts(const Mat3& J, const Vec3& d) {
  const double J3 = d.dot(J * d);
  const double J1 = 0.5 * (J.trace() - J3);
  const Mat3 model = J1 * Mat3::Identity() + (J3 - J1) * d * d.transpose();
  return {J1, J3, (J - model).norm() / J.norm()};
}

}  // namespace

bool is_lagrange_top(const Pendulum3D& pendulum) {
  if (pendulum.mass * pendulum.gravity * pendulum.rho.norm() == 0.0) return true;
  return axisymmetric_parts(pendulum.inertia.J, pendulum.rho.normalized()).residual <= kLagrangeTopTolerance;
}

LagrangeTopExact::LagrangeTopExact(const Pendulum3D& pendulum, const Mat3& R0, const Vec3& Omega0) {
  require_finite(R0, "R0");
  if (!so3::is_rotation(R0, 1e-10)) throw InvalidInput("R0", "is not a rotation matrix (R^T R != I or det R != 1)");
  require_finite(Omega0, "Omega0");
  const double M = pendulum.mass * pendulum.gravity * pendulum.rho.norm();
  if (M == 0.0) {  // no gravity torque: a free rigid body
    free_body_.emplace(pendulum.inertia.J, R0, Omega0);
    return;
  }
  const Vec3 d = pendulum.rho.normalized();
  const AxisymmetricParts parts = axisymmetric_parts(pendulum.inertia.J, d);
  if (!(parts.residual <= kLagrangeTopTolerance)) {
    throw InvalidInput("inertia", "is not axisymmetric about rho's direction (relative deviation " +
                                      std::to_string(parts.residual) + " > " +
                                      std::to_string(kLagrangeTopTolerance) + "): not a Lagrange top");
  }
  const double J1 = parts.J1, J3 = parts.J3;
  Qs_ = symmetric_frame(d);

  // The state in the symmetric frame: gamma = E^T e3 = (sin th sin psi, sin th cos psi, cos th).
  const Vec3 gamma = (Qs_.transpose() * R0.row(2).transpose()).normalized();
  const Vec3 Om = Qs_.transpose() * Omega0;
  omega3_ = Om.z();
  const double u0 = gamma.z();
  const double sin2 = gamma.x() * gamma.x() + gamma.y() * gamma.y();
  const double x0 = u0 >= 0.0 ? sin2 / (1.0 + u0) : 1.0 - u0;  // 1 - u0 without cancellation
  const double y0 = u0 < 0.0 ? sin2 / (1.0 - u0) : 1.0 + u0;   // 1 + u0
  const double W = Om.x() * Om.x() + Om.y() * Om.y();          // |Omega_perp|^2
  const double ell = Om.x() * gamma.x() + Om.y() * gamma.y();  // b - a u0 = phi' sin^2 th
  const double eta = gamma.x() * Om.y() - gamma.y() * Om.x();  // u'(0)
  const double beta = 2.0 * M / J1;
  const double a = J3 * omega3_ / J1;
  A_ = 0.5 * (ell - a * x0);
  B_ = 0.5 * (ell + a * y0);
  const double rounding = 8.0 * kEps * (std::sqrt(W) + std::abs(a));
  if (std::abs(A_) <= rounding) A_ = 0.0;
  if (std::abs(B_) <= rounding) B_ = 0.0;

  // f about u0 (v = u - u0), about 1 (x = 1 - u) and about -1 (y = 1 + u); every constant and
  // linear coefficient comes from the state directly (c0 = u'(0)^2, f(1) = -4A^2, f(-1) = -4B^2).
  const Cubic g{eta * eta, -2.0 * u0 * W + beta * x0 * y0 + 2.0 * a * ell, -W - 2.0 * beta * u0 - a * a, -beta};
  const Cubic g_deflated{g.c1, g.c2, g.c3, 0.0};  // g(v) / v when g(0) = 0
  const Cubic h{-4.0 * A_ * A_, 2.0 * (W + beta * x0) - 4.0 * a * A_, -(W + beta * x0) - 2.0 * beta - a * a, beta};
  const Cubic p{-4.0 * B_ * B_, 2.0 * (W - beta * y0) + 4.0 * a * B_, -(W - beta * y0) + 2.0 * beta - a * a, -beta};

  // Turning points u_c = u0 + v_c = 1 - x_c and u_b = u0 + v_b = y_b - 1. What is known exactly
  // is used as such: u0 itself is a turning point when u'(0) = 0 (g(0) = 0; which one by the
  // sign of f'(u0) = g.c1), 1 is u_c when A = 0, -1 is u_b when B = 0 and f'(-1) > 0.
  const bool at_turning_point = g.c0 == 0.0;
  double v_c = 0.0, v_b = 0.0;
  enum class Known { Exact, Solve } upper = Known::Exact, lower = Known::Exact;
  if (at_turning_point && g.c1 <= 0.0) {
    v_c = 0.0;
    x_c_ = x0;
  } else if (A_ == 0.0) {
    v_c = x0;  // f(1) = 0 and f < 0 above 1
    x_c_ = 0.0;
  } else {
    upper = Known::Solve;
    v_c = at_turning_point ? bracketed_root(g_deflated, 0.0, x0, +1.0, 0.5 * x0)
                           : bracketed_root(g, 0.0, x0, +1.0, 0.5 * x0);
  }
  if (at_turning_point && g.c1 >= 0.0) {
    v_b = 0.0;
    y_b_ = y0;
  } else if (B_ == 0.0) {
    // f(-1) = 0: -1 is u_b when f increases there (f'(-1) = p.c1 > 0), else u_a, and u_b is the
    // smallest positive root y of p(y) / y = p.c1 + p.c2 y - beta y^2.
    if (p.c1 > 0.0) {
      y_b_ = 0.0;
    } else if (p.c1 < 0.0) {
      const double root_disc = std::sqrt(std::max(0.0, p.c2 * p.c2 + 4.0 * beta * p.c1));
      const double r1 = (p.c2 + std::copysign(root_disc, p.c2)) / (2.0 * beta);  // no cancellation
      const double r2 = r1 != 0.0 ? -p.c1 / (beta * r1) : 0.0;                   // product -p.c1 / beta
      y_b_ = y0;
      for (const double r : {r1, r2}) {
        if (r > 0.0 && r < y_b_) y_b_ = r;
      }
    } else {
      throw InvalidInput("Omega0", "lies on the separatrix through the upright equilibrium (B = 0 and "
                                   "f'(-1) = 0): the motion takes infinite time to reach it");
    }
    v_b = y_b_ - y0;
  } else {
    lower = Known::Solve;
    v_b = at_turning_point ? bracketed_root(g_deflated, -y0, 0.0, +1.0, -0.5 * y0)
                           : bracketed_root(g, -y0, 0.0, -1.0, -0.5 * y0);
  }
  D_ = std::max(0.0, v_c - v_b);
  steady_ = D_ == 0.0;
  // 1 - u_c = x0 - v_c and 1 + u_b = y0 + v_b. Where the difference cancels (u_c near 1, u_b
  // near -1) they are recomputed to their own relative accuracy as the roots of h and p near 0,
  // bracketed by 0 (h(0) = -4A^2 < 0) and the middle of the nutation range (f > 0). Not
  // otherwise: a root of h or p far from its expansion point carries the rounding of terms of
  // size beta (measured: 2.4e-9 in 1 + u_b for a 1e-3 rad swing).
  const double x_mid = x0 - 0.5 * (v_b + v_c), y_mid = y0 + 0.5 * (v_b + v_c);
  if (upper == Known::Solve) {
    x_c_ = x0 - v_c;
    if (!steady_ && x_c_ < 0.5 * x0) x_c_ = bracketed_root(h, 0.0, x_mid, -1.0, x_c_);
  }
  if (lower == Known::Solve) {
    y_b_ = y0 + v_b;
    if (!steady_ && y_b_ < 0.5 * y0) y_b_ = bracketed_root(p, 0.0, y_mid, -1.0, y_b_);
  }
  x_b_ = x_c_ + D_;
  const double y_c = y_b_ + D_;

  // phi(0) = 0, psi(0) = atan2(gamma1, gamma2); at a pole (gamma_perp = 0) psi is free and is
  // chosen so that Omega_perp(0) = e^{-i psi0} (a positive number), the form the pole formulas of
  // euler_state take at t = 0.
  const double psi0 = sin2 > 0.0 ? std::atan2(gamma.x(), gamma.y()) : -std::atan2(Om.y(), Om.x());
  sigma0_ = 0.5 * psi0;
  delta0_ = -sigma0_;
  sigma_rate_ = 0.5 * (omega3_ + A_ - B_);
  delta_rate_ = 0.5 * (B_ - A_ - omega3_);

  if (steady_) {
    if (A_ != 0.0) delta_rate_ += A_ / x0;
    if (B_ != 0.0) sigma_rate_ += B_ / y0;
  } else {
    const double v_a = g.c2 / beta - v_b - v_c;  // sum of the roots of g
    const double span = v_c - v_a;               // u_c - u_a
    double ya_abs = -(y0 + v_a);                 // -1 - u_a; if that cancels, from f(-1) = -beta |y_a| y_b y_c
    if (ya_abs < 1e-3 * std::abs(v_a) && B_ != 0.0) ya_abs = 4.0 * B_ * B_ / (beta * y_b_ * y_c);
    const double k = std::sqrt(D_ / span);
    const double k_complement = std::sqrt((y_b_ + ya_abs) / span);  // (u_b - u_a) / (u_c - u_a)
    if (!(k < 1.0) || k_complement * k_complement / (1.0 + k) < exact_detail::kMinimumDistanceToSeparatrix) {
      throw InvalidInput("Omega0", "is within 1 - k = " + std::to_string(exact_detail::kMinimumDistanceToSeparatrix) +
                                       " of a separatrix of the nutation (k = " + std::to_string(k) +
                                       "), where the elliptic integrals lose their digits");
    }
    jacobi_ = exact_detail::Jacobi(k, k_complement);
    nu_ = 0.5 * std::sqrt(beta * span);
    through_bottom_ = x_c_ == 0.0;
    through_top_ = y_b_ == 0.0;
    // u(w0) = u0 with u' = -2 D nu sn cn dn of the sign of u'(0) = eta. The phase is kept from
    // the turning point nearer its pole, so that small sn (or cn) keep their relative accuracy
    // where 1 - u (1 + u) is small: from u_c, sn^2 w0 = v_c / D, cn^2 w0 = -v_b / D, cn >= 0 on
    // |w0| <= K; from u_b (w = K + w'), tan^2 am(w') = -v_b / (k'^2 v_c) and u' has the sign of
    // sn w'.
    anchor_bottom_ = y_b_ < x_c_;
    if (anchor_bottom_) {
      const double amplitude = std::atan2(std::sqrt(-v_b), k_complement * std::sqrt(v_c));
      w0_ = (eta < 0.0 ? -1.0 : 1.0) * jacobi_.argument_of_amplitude(amplitude);
    } else {
      const double amplitude = std::atan2(std::sqrt(v_c), std::sqrt(-v_b));
      w0_ = (eta > 0.0 ? -1.0 : 1.0) * jacobi_.argument_of_amplitude(amplitude);
    }
    const Points p0 = points(0.0);
    sign_s_ = p0.at_w.sn < 0.0 ? -1.0 : 1.0;
    if (A_ != 0.0) {
      x_integral_ = exact_detail::SnSquaredIntegral(jacobi_, x_c_, D_);
      delta_rate_ += A_ * x_integral_.mean();
      x_periodic0_ = x_integral_.periodic(p0.at_w);
    }
    if (B_ != 0.0) {
      // Direct form: Pi's parameter n = D / y_c carries 1 - n = y_b / y_c to eps / (1 - n)
      // relative. Shifted form: cancels in 1 + k^2 y_b / m. Take the better conditioned.
      const double k2 = k * k;
      const double m = D_ * ya_abs / (y_c + ya_abs);
      y_shifted_ = m > 0.0 && y_c / y_b_ > 1.0 + k2 * y_b_ / m;
      if (y_shifted_) {
        y_integral_ = exact_detail::SnSquaredIntegral(jacobi_, y_b_, m);
        y_coefficient_ = 1.0 + k2 * y_b_ / m;
        sigma_rate_ += B_ * (-k2 / m + y_coefficient_ * y_integral_.mean());
        y_periodic0_ = y_integral_.periodic(p0.at_w_minus_K);
      } else {
        y_integral_ = exact_detail::SnSquaredIntegral(jacobi_, y_c, -D_);
        y_coefficient_ = 1.0;
        sigma_rate_ += B_ * y_integral_.mean();
        y_periodic0_ = y_integral_.periodic(p0.at_w);
      }
    }
  }
  // Y from the same formulas state(0) uses, so that state(0) reproduces R0 to rounding.
  Mat3 E0;
  Vec3 unused;
  euler_state(0.0, E0, unused);
  Y_ = R0 * Qs_ * E0.transpose();
}

LagrangeTopExact::Points LagrangeTopExact::points(double t) const {
  const double phase = nu_ * t + w0_;
  if (anchor_bottom_) {
    const exact_detail::JacobiPoint below = jacobi_.at(phase);
    return {jacobi_.shifted(below, +1), below};
  }
  const exact_detail::JacobiPoint at = jacobi_.at(phase);
  return {at, jacobi_.shifted(at, -1)};
}

double LagrangeTopExact::nutation_period() const {
  if (free_body_ || steady_) return std::numeric_limits<double>::infinity();
  return 2.0 * jacobi_.quarter_period() / nu_;
}

void LagrangeTopExact::euler_state(double t, Mat3& E, Vec3& Omega_sym) const {
  double sigma = sigma0_ + sigma_rate_ * t;
  double delta = delta0_ + delta_rate_ * t;
  double s, c, x, y, x_dot = 0.0;
  double Omega1 = 0.0, Omega2 = 0.0;  // e^{i psi} (Omega1 + i Omega2), filled below
  if (steady_) {
    x = x_c_;
    y = y_b_;
    s = std::sqrt(0.5 * x);
    c = std::sqrt(0.5 * y);
    // At a pole the steady motion is a spin about the vertical axis d: Omega_perp = 0.
    if (s * c > 0.0) Omega2 = (A_ * y + B_ * x) / (2.0 * s * c);
  } else {
    const Points points_t = points(t);
    const exact_detail::JacobiPoint& pt = points_t.at_w;
    if (A_ != 0.0) delta += (A_ / nu_) * (x_integral_.periodic(pt) - x_periodic0_);
    if (B_ != 0.0) {
      const double periodic = y_integral_.periodic(y_shifted_ ? points_t.at_w_minus_K : pt);
      sigma += (B_ / nu_) * y_coefficient_ * (periodic - y_periodic0_);
    }
    const double sn2 = pt.sn * pt.sn, cn2 = pt.cn * pt.cn;
    x = x_c_ + D_ * sn2;
    y = y_b_ + D_ * cn2;
    x_dot = 2.0 * D_ * nu_ * pt.sn * pt.cn * pt.dn;
    const double half = std::sqrt(0.5 * D_);
    s = through_bottom_ ? sign_s_ * half * pt.sn : std::sqrt(0.5 * x);
    c = through_top_ ? half * pt.cn : std::sqrt(0.5 * y);
    // Omega1 + i Omega2 = e^{-i psi} (x' + i (A y + B x)) / (2 s c); at a pole the factor sn
    // (through the bottom) or cn (through the top) cancels from numerator and denominator.
    if (through_bottom_ && through_top_) {
      Omega1 = 2.0 * nu_ * pt.dn * sign_s_;
    } else if (through_bottom_) {  // x = D sn^2, s = sign_s half sn
      Omega1 = D_ * 2.0 * nu_ * pt.cn * pt.dn / (2.0 * sign_s_ * half * c);
      Omega2 = D_ * B_ * pt.sn / (2.0 * sign_s_ * half * c);
    } else if (through_top_) {  // y = D cn^2, c = half cn
      Omega1 = D_ * 2.0 * nu_ * pt.sn * pt.dn / (2.0 * s * half);
      Omega2 = D_ * A_ * pt.cn / (2.0 * s * half);
    } else {
      Omega1 = x_dot / (2.0 * s * c);
      Omega2 = (A_ * y + B_ * x) / (2.0 * s * c);
    }
  }
  const double cs = std::cos(sigma), ss = std::sin(sigma), cd = std::cos(delta), sd = std::sin(delta);
  Eigen::Quaterniond q(c * cs, s * cd, s * sd, c * ss);
  q.normalize();
  E = q.toRotationMatrix();
  // e^{i psi} = e^{i sigma} e^{-i delta} from the same sines and cosines as E: psi = sigma - delta
  // rounded on its own would differ from E's by eps |sigma| (1e-11 after 1e4 s of spin at 20 rad/s).
  const double cp = cs * cd + ss * sd, sp = ss * cd - cs * sd;
  Omega_sym = Vec3(cp * Omega1 + sp * Omega2, cp * Omega2 - sp * Omega1, omega3_);
}

ExactState LagrangeTopExact::state(double t) const {
  if (!std::isfinite(t)) throw InvalidInput("t", "must be finite");
  if (free_body_) return free_body_->state(t);
  Mat3 E;
  Vec3 Omega_sym;
  euler_state(t, E, Omega_sym);
  return {Y_ * E * Qs_.transpose(), Qs_ * Omega_sym};
}

}  // namespace lgvi::baselines
