// Lie group methods over the continuous mechanics of baselines/mechanics.hpp: explicit one-step
// methods that keep every attitude on SO(3) by construction, integrating the same equations the
// coordinate baselines integrate (physics written once).
//
// The state y = (R_1..R_N, x, w) (MechanicsState) lives on G = SO(3)^N x R^NX x R^NW, and an
// increment xi = (theta_1..theta_N, dx, dw) of its algebra acts on the right,
//     y . xi = (R_i exp(hat(theta_i)), x + dx, w + dw),
// so the equations of motion R_i' = R_i hat(Omega_i), x' = x_dot, w' = a(t, R, x, w) read
// y' = y . F(t, y) with the vector field F = (Omega_i, x_dot, a) of the mechanics (rates(),
// acceleration()). On R^n with this additive action each method below is its classical
// Runge-Kutta tableau (tests/baselines/test_lie_group.cpp checks it to round-off).
//
//   RkmkFlow<Mech, Tableau>       Runge-Kutta-Munthe-Kaas (Munthe-Kaas, BIT 38 (1998); Appl.
//                                 Numer. Math. 29 (1999)): stage increments xi_i = h sum_j a_ij K_j,
//                                 Y_i = y . xi_i, K_i = dexp^{-1}_{xi_i}(F(t + c_i h, Y_i)),
//                                 y_1 = y . (h sum_i b_i K_i). dexp^{-1} of the right action is
//                                 Jr^{-1} (so3::right_jacobian_inverse_series: its series through
//                                 degree 3, which keeps orders up to 5); identity on x and w.
//   CrouchGrossmanFlow<Mech, T>   Crouch-Grossman (Crouch, Grossman, J. Nonlinear Sci. 3 (1993)):
//                                 products of exponentials, Y_i = y . (h a_i1 F_1) . (h a_i2 F_2) ...,
//                                 y_1 = y . (h b_1 F_1) ... (h b_s F_s); no dexp^{-1}. Its tableaus
//                                 satisfy extra (non-commutative) order conditions.
//   CommutatorFree4Flow<Mech>     the commutator-free method of order 4 (Celledoni, Marthinsen,
//                                 Owren, Future Gener. Comput. Syst. 19 (2003)), four stages over
//                                 the classical RK4 tableau, two exponentials in its update.
//   integrate_rkmk45(...)         RKMK over the Dormand-Prince 5(4) pair (Dormand, Prince, J.
//                                 Comput. Appl. Math. 6 (1980)) with error control on the algebra,
//                                 FSAL, and the pair's continuous extension in the chart for the
//                                 output times (Hairer, Norsett, Wanner, "Solving ODEs I", II.6).
//
// The methods are written for the right action because the mechanics gives body angular
// velocities (R' = R hat(Omega)); the published left-action forms (y' = A(y) y) map to these by
// y -> y^{-1}, which reverses every product of exponentials and turns dexp^{-1}_u into Jr^{-1}.
// A step allocates nothing (std::array, fixed-size Eigen); its cost is `stages` accelerations.
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <string>
#include <utility>

#include "baselines/mechanics.hpp"
#include "lgvi/flow_map.hpp"
#include "lgvi/integrate.hpp"
#include "lgvi/so3.hpp"

namespace lgvi::baselines::lie_group {

/// An element of the state group's algebra: rotation vectors theta_i of the attitudes, and the
/// additive increments of x and w.
template <Mechanics Mech>
struct Increment {
  std::array<Vec3, Mech::bodies> theta;
  Vector<Mech::positions> x;
  Vector<Mech::velocities> w;

  static Increment zero() {
    Increment z;
    for (Vec3& t : z.theta) t.setZero();
    z.x.setZero();
    z.w.setZero();
    return z;
  }
  /// *this += s k
  void add_scaled(double s, const Increment& k) {
    for (std::size_t i = 0; i < theta.size(); ++i) theta[i] += s * k.theta[i];
    x += s * k.x;
    w += s * k.w;
  }
};

/// F(t, y) = (Omega_i, x_dot, a(t, y)): the mechanics' equations as a field on the algebra.
template <Mechanics Mech>
Increment<Mech> vector_field(const Mech& mech, double t, const MechanicsState<Mech>& y) {
  Increment<Mech> f;
  typename Mech::Rate rates;
  mech.rates(y.config, y.w, rates);
  for (std::size_t i = 0; i < f.theta.size(); ++i) f.theta[i] = rates.Omega[i];
  f.x = rates.x_dot;
  f.w = acceleration_given_rates(mech, t, y.config, y.w, rates);
  return f;
}

/// Whether the field F(t, y) reads y's attitudes: false only where the mechanics says so
/// (attitude_unread(): a free body without control, F = (Omega, J^{-1}(J Omega x Omega))). Where
/// it does not, a stage's attitudes are not formed (their exponentials skipped): F at the stage
/// is the same, and so is the step, to the bit; the step's update always forms them.
template <Mechanics Mech>
bool field_reads_attitudes(const Mech& mech) {
  if constexpr (requires { { mech.attitude_unread() } -> std::convertible_to<bool>; }) {
    return !mech.attitude_unread();
  } else {
    return true;
  }
}

/// out = y . xi (out may be y); the attitudes only when `attitudes` (a stage whose field reads
/// none keeps y's).
template <Mechanics Mech>
void act(const MechanicsState<Mech>& y, const Increment<Mech>& xi, MechanicsState<Mech>& out, bool attitudes = true) {
  for (std::size_t i = 0; i < xi.theta.size(); ++i) {
    out.config.R[i] = attitudes ? so3::right_multiply_exp(y.config.R[i], xi.theta[i]) : y.config.R[i];
  }
  out.config.x = y.config.x + xi.x;
  out.w = y.w + xi.w;
}

/// y <- y . (s f): one exponential per body (Crouch-Grossman and commutator-free products); the
/// attitudes only when `attitudes`, as for act.
template <Mechanics Mech>
void act_scaled(MechanicsState<Mech>& y, double s, const Increment<Mech>& f, bool attitudes = true) {
  if (attitudes) {
    for (std::size_t i = 0; i < f.theta.size(); ++i) y.config.R[i] = so3::right_multiply_exp(y.config.R[i], s * f.theta[i]);
  }
  y.config.x += s * f.x;
  y.w += s * f.w;
}

/// out = y . (s_1 f_1) . (s_2 f_2) ... (s_K f_K) (out may be y): each attitude's product of
/// exponentials is accumulated as I + D, (I + D)(I + D_k) = I + D + D_k + D D_k with
/// D_k = exp(s_k hat(theta_k)) - I (so3::exp_minus_identity), and applied as R + R D: one
/// rounding of R per update instead of one per factor (a long run's orthogonality error grows
/// with the roundings of R per step; CG4a's five factors would otherwise give sqrt(5) times the
/// error of a one-exponential update).
template <Mechanics Mech, std::size_t K>
void act_product(const MechanicsState<Mech>& y, const std::array<double, K>& scales,
                 const std::array<const Increment<Mech>*, K>& factors, MechanicsState<Mech>& out) {
  for (std::size_t i = 0; i < y.config.R.size(); ++i) {
    Mat3 D = Mat3::Zero();
    for (std::size_t k = 0; k < K; ++k) {
      if (scales[k] == 0.0) continue;
      const Mat3 Dk = so3::exp_minus_identity(scales[k] * factors[k]->theta[i]);
      D += Dk + D * Dk;
    }
    out.config.R[i] = y.config.R[i] + y.config.R[i] * D;
  }
  out.config.x = y.config.x;
  out.w = y.w;
  for (std::size_t k = 0; k < K; ++k) {
    if (scales[k] == 0.0) continue;
    out.config.x += scales[k] * factors[k]->x;
    out.w += scales[k] * factors[k]->w;
  }
}

/// K <- dexp^{-1}_xi(K) for the right action: Jr^{-1}(theta_i) on each attitude (its series,
/// so3::right_jacobian_inverse_series), the identity on the additive parts.
template <Mechanics Mech>
void dexp_inverse(const Increment<Mech>& xi, Increment<Mech>& k) {
  for (std::size_t i = 0; i < k.theta.size(); ++i) k.theta[i] = so3::right_jacobian_inverse_series(xi.theta[i], k.theta[i]);
}

// Explicit Runge-Kutta tableaus (a strictly lower triangular, c_i = sum_j a_ij).

/// Explicit Euler: with RKMK, the Lie-Euler method (order 1).
struct EulerTableau {
  static constexpr int stages = 1;
  static constexpr int order = 1;
  static constexpr double a[1][1] = {{0.0}};
  static constexpr double b[1] = {1.0};
  static constexpr double c[1] = {0.0};
};

/// Heun's method (order 2): the explicit trapezoidal rule.
struct HeunTableau {
  static constexpr int stages = 2;
  static constexpr int order = 2;
  static constexpr double a[2][2] = {{0.0, 0.0}, {1.0, 0.0}};
  static constexpr double b[2] = {0.5, 0.5};
  static constexpr double c[2] = {0.0, 1.0};
};

/// The classical Runge-Kutta method of order 4.
struct ClassicalRk4Tableau {
  static constexpr int stages = 4;
  static constexpr int order = 4;
  static constexpr double a[4][4] = {{0.0, 0.0, 0.0, 0.0}, {0.5, 0.0, 0.0, 0.0}, {0.0, 0.5, 0.0, 0.0}, {0.0, 0.0, 1.0, 0.0}};
  static constexpr double b[4] = {1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0};
  static constexpr double c[4] = {0.0, 0.5, 0.5, 1.0};
};

/// Crouch and Grossman's three-stage method of order 3 (J. Nonlinear Sci. 3 (1993), 1-33), the
/// tableau that also satisfies the order-3 condition of the products of exponentials.
struct CrouchGrossman3Tableau {
  static constexpr int stages = 3;
  static constexpr int order = 3;
  static constexpr double a[3][3] = {{0.0, 0.0, 0.0}, {3.0 / 4.0, 0.0, 0.0}, {119.0 / 216.0, 17.0 / 108.0, 0.0}};
  static constexpr double b[3] = {13.0 / 51.0, -2.0 / 3.0, 24.0 / 17.0};
  static constexpr double c[3] = {0.0, 3.0 / 4.0, 17.0 / 24.0};
};

/// CG4a, the five-stage Crouch-Grossman method of order 4 of Jackiewicz, Marthinsen and Owren
/// ("Construction of Runge-Kutta methods of Crouch-Grossman type of high order", Adv. Comput.
/// Math. 13 (2000) 405-415), to the 16 digits published. a54 is the value that makes
/// sum_j a_5j = c_5 to the last digit (-1.1092979392113465; a copy with ...565 in its last digits
/// circulates, which misses c_5 by 1e-14).
struct CrouchGrossman4aTableau {
  static constexpr int stages = 5;
  static constexpr int order = 4;
  static constexpr double a[5][5] = {
      {0.0, 0.0, 0.0, 0.0, 0.0},
      {0.8177227988124852, 0.0, 0.0, 0.0, 0.0},
      {0.3199876375476427, 0.0659864263556022, 0.0, 0.0, 0.0},
      {0.9214417194464946, 0.4997857776773573, -1.0969984448371582, 0.0, 0.0},
      {0.3552358559023322, 0.2390958372307326, 1.3918565724203246, -1.1092979392113465, 0.0}};
  static constexpr double b[5] = {0.1370831520630755, -0.0183698531564020, 0.7397813985370780, -0.1907142565505889,
                                  0.3322195591068374};
  static constexpr double c[5] = {0.0, 0.8177227988124852, 0.3859740639032449, 0.3242290522866937, 0.8768903263420429};
};

/// The Dormand-Prince 5(4) pair (J. Comput. Appl. Math. 6 (1980) 19-26): b the fifth-order
/// weights (= the last row of a: first same as last), b_hat the embedded fourth-order ones, and
/// d the coefficients of its fourth-order continuous extension (Hairer, Norsett, Wanner,
/// "Solving Ordinary Differential Equations I", 2nd ed., Sec. II.6, the form of their DOPRI5).
struct DormandPrince54Tableau {
  static constexpr int stages = 7;
  static constexpr int order = 5;
  static constexpr double a[7][7] = {
      {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
      {1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
      {3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0, 0.0},
      {44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0, 0.0},
      {19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0, 0.0, 0.0, 0.0},
      {9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0, 0.0, 0.0},
      {35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0, 0.0}};
  static constexpr double b[7] = {35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0, 0.0};
  static constexpr double b_hat[7] = {5179.0 / 57600.0,    0.0,           7571.0 / 16695.0, 393.0 / 640.0,
                                      -92097.0 / 339200.0, 187.0 / 2100.0, 1.0 / 40.0};
  static constexpr double c[7] = {0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0};
  static constexpr double d[7] = {-12715105075.0 / 11282082432.0, 0.0, 87487479700.0 / 32700410799.0,
                                  -10690763975.0 / 1880347072.0,  701980252875.0 / 199316789632.0,
                                  -1453857185.0 / 822651844.0,    69997945.0 / 29380423.0};
};

/// The Runge-Kutta-Munthe-Kaas method of an explicit tableau (see the top of this file): a
/// FlowMap (lgvi/flow_map.hpp) whose Control is the time at each end of the step.
template <Mechanics Mech, class Tableau>
class RkmkFlow {
 public:
  using State = MechanicsState<Mech>;
  using Control = double;
  static constexpr int potential_evaluations_per_step = Tableau::stages;

  explicit RkmkFlow(const Mech& mech) : mech_(mech) {}

  StepSummary step(const State& in, double h, double t_k, double /*t_k1*/, State& out) const {
    constexpr int s = Tableau::stages;
    std::array<Increment<Mech>, s> K;
    const bool attitudes = field_reads_attitudes(mech_);
    State stage = in;
    for (int i = 0; i < s; ++i) {
      if (i == 0) {
        K[0] = vector_field(mech_, t_k, in);  // xi_1 = 0: dexp^{-1}_0 is the identity
        continue;
      }
      Increment<Mech> xi = Increment<Mech>::zero();
      for (int j = 0; j < i; ++j) {
        if (Tableau::a[i][j] != 0.0) xi.add_scaled(h * Tableau::a[i][j], K[j]);
      }
      act(in, xi, stage, attitudes);
      K[i] = vector_field(mech_, t_k + Tableau::c[i] * h, stage);
      dexp_inverse(xi, K[i]);
    }
    Increment<Mech> xi = Increment<Mech>::zero();
    for (int i = 0; i < s; ++i) {
      if (Tableau::b[i] != 0.0) xi.add_scaled(h * Tableau::b[i], K[i]);
    }
    act(in, xi, out);
    return {};
  }

 private:
  const Mech& mech_;
};

/// The Crouch-Grossman method of an explicit tableau (see the top of this file).
template <Mechanics Mech, class Tableau>
class CrouchGrossmanFlow {
 public:
  using State = MechanicsState<Mech>;
  using Control = double;
  static constexpr int potential_evaluations_per_step = Tableau::stages;

  explicit CrouchGrossmanFlow(const Mech& mech) : mech_(mech) {}

  StepSummary step(const State& in, double h, double t_k, double /*t_k1*/, State& out) const {
    constexpr int s = Tableau::stages;
    std::array<Increment<Mech>, s> F;
    const bool attitudes = field_reads_attitudes(mech_);
    for (int i = 0; i < s; ++i) {
      State stage = in;
      for (int j = 0; j < i; ++j) {
        if (Tableau::a[i][j] != 0.0) act_scaled(stage, h * Tableau::a[i][j], F[j], attitudes);
      }
      F[i] = vector_field(mech_, t_k + Tableau::c[i] * h, stage);
    }
    std::array<double, s> scales;
    std::array<const Increment<Mech>*, s> factors;
    for (int i = 0; i < s; ++i) {
      scales[i] = h * Tableau::b[i];
      factors[i] = &F[i];
    }
    act_product(in, scales, factors, out);
    return {};
  }

 private:
  const Mech& mech_;
};

/// The commutator-free Lie group method of order 4 (Celledoni, Marthinsen, Owren 2003, their
/// four-stage method over the classical RK4 tableau), in the right-action form:
///     Y_1 = y,  Y_2 = y . (h F_1 / 2),  Y_3 = y . (h F_2 / 2),  Y_4 = Y_2 . (h (F_3 - F_1 / 2)),
///     y_1 = y . (h (F_1 / 4 + F_2 / 6 + F_3 / 6 - F_4 / 12)) . (h (-F_1 / 12 + F_2 / 6 + F_3 / 6 + F_4 / 4)),
/// F_i = F(t + c_i h, Y_i), c = (0, 1/2, 1/2, 1). On R^n the two update exponentials add up to
/// RK4's weights (1/6, 1/3, 1/3, 1/6).
template <Mechanics Mech>
class CommutatorFree4Flow {
 public:
  using State = MechanicsState<Mech>;
  using Control = double;
  static constexpr int potential_evaluations_per_step = 4;

  explicit CommutatorFree4Flow(const Mech& mech) : mech_(mech) {}

  StepSummary step(const State& in, double h, double t_k, double /*t_k1*/, State& out) const {
    const bool attitudes = field_reads_attitudes(mech_);
    const Increment<Mech> F1 = vector_field(mech_, t_k, in);
    State Y2 = in;
    act_scaled(Y2, 0.5 * h, F1, attitudes);
    const Increment<Mech> F2 = vector_field(mech_, t_k + 0.5 * h, Y2);
    State Y3 = in;
    act_scaled(Y3, 0.5 * h, F2, attitudes);
    const Increment<Mech> F3 = vector_field(mech_, t_k + 0.5 * h, Y3);
    Increment<Mech> xi = Increment<Mech>::zero();
    xi.add_scaled(h, F3);
    xi.add_scaled(-0.5 * h, F1);
    State Y4 = Y2;
    act_scaled(Y4, 1.0, xi, attitudes);
    const Increment<Mech> F4 = vector_field(mech_, t_k + h, Y4);
    Increment<Mech> first = Increment<Mech>::zero();
    first.add_scaled(h / 4.0, F1);
    first.add_scaled(h / 6.0, F2);
    first.add_scaled(h / 6.0, F3);
    first.add_scaled(-h / 12.0, F4);
    Increment<Mech> second = Increment<Mech>::zero();
    second.add_scaled(-h / 12.0, F1);
    second.add_scaled(h / 6.0, F2);
    second.add_scaled(h / 6.0, F3);
    second.add_scaled(h / 4.0, F4);
    act_product(in, std::array<double, 2>{1.0, 1.0}, std::array<const Increment<Mech>*, 2>{&first, &second}, out);
    return {};
  }

 private:
  const Mech& mech_;
};

/// Settings of integrate_rkmk45. The local error of each component is kept below
/// atol + rtol |y_i| in the root-mean-square norm (Hairer, Norsett, Wanner II.4): for x and w
/// componentwise, |y_i| the larger of the step's two ends; for an attitude's three components
/// |y_i| = 1, the size of R's largest entries (the matrix model's scale at its largest).
struct Rkmk45Settings {
  double rtol = 1e-6;
  double atol = 1e-6;
  std::size_t max_steps = 50'000'000;  ///< accepted plus rejected steps over the whole run
  /// First step; 0: Hairer-Norsett-Wanner's starting step from the initial state (one extra
  /// field evaluation), whatever the output times.
  double initial_step = 0.0;
};

/// Receives the state at times[index]; returning false stops the run (ObserverStopped).
template <class Observer, class State>
concept StateObserver = requires(Observer& o, std::size_t i, double t, const State& y) {
  { o(i, t, y) } -> std::convertible_to<bool>;
};

namespace detail {

template <Mechanics Mech>
double scaled_rms(const Increment<Mech>& e, const MechanicsState<Mech>& y0, const MechanicsState<Mech>& y1,
                  const Rkmk45Settings& s) {
  double sum = 0.0;
  int n = 0;
  const auto add = [&](double err, double size) {
    const double r = err / (s.atol + s.rtol * size);
    sum += r * r;
    ++n;
  };
  for (const Vec3& t : e.theta) {
    for (int k = 0; k < 3; ++k) add(t(k), 1.0);
  }
  for (int k = 0; k < Mech::positions; ++k) add(e.x(k), std::max(std::abs(y0.config.x(k)), std::abs(y1.config.x(k))));
  for (int k = 0; k < Mech::velocities; ++k) add(e.w(k), std::max(std::abs(y0.w(k)), std::abs(y1.w(k))));
  return std::sqrt(sum / n);
}

}  // namespace detail

/// Integrates the mechanics from y at times[0] by RKMK over the Dormand-Prince 5(4) pair with
/// error control (see the top of this file and Rkmk45Settings), calling observer(i, times[i],
/// y(times[i])) for each output time until times.back() or the first failure. The steps depend
/// on times.front() and times.back() only: the method steps freely (the last step shortened to
/// end on times.back()) and the other output times are read off the continuous extension of the
/// step that covers them, y(t_n + sigma h) = y_n . xi(sigma) with xi(sigma) the pair's
/// fourth-order dense output in the chart (no extra evaluations). Step size control: the
/// elementary controller h <- h min(5, max(0.2, 0.9 err^(-1/5))), no growth right after a
/// rejection. Stats: steps (accepted), rejected_steps, rhs_evaluations (field evaluations, 6 per
/// step by first-same-as-last, plus the first and the starting-step estimate). Statuses:
/// SolverFailed (max_steps, a step size under 16 eps |t|, a non-finite state at t = failed_time),
/// ObserverStopped. Throws InvalidInput for times not strictly increasing and finite or bad
/// tolerances.
template <Mechanics Mech, class Observer>
  requires StateObserver<Observer, MechanicsState<Mech>>
Stats integrate_rkmk45(const Mech& mech, MechanicsState<Mech> y, std::span<const double> times,
                       const Rkmk45Settings& settings, Observer&& observer) {
  using State = MechanicsState<Mech>;
  using Inc = Increment<Mech>;
  using T = DormandPrince54Tableau;
  if (!(std::isfinite(settings.rtol) && settings.rtol > 0.0)) throw InvalidInput("rtol", "must be finite and > 0");
  if (!(std::isfinite(settings.atol) && settings.atol > 0.0)) throw InvalidInput("atol", "must be finite and > 0");
  if (times.empty()) throw InvalidInput("times", "no output times");
  for (std::size_t i = 0; i < times.size(); ++i) {
    if (!std::isfinite(times[i]) || (i > 0 && !(times[i] > times[i - 1]))) {
      throw InvalidInput("times", "output times must be finite and strictly increasing");
    }
  }
  Stats stats;
  const auto started = std::chrono::steady_clock::now();
  const auto finish = [&]() -> Stats& {
    stats.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    return stats;
  };
  double t = times.front();
  const double t_end = times.back();
  const auto fail = [&](const std::string& why) {
    stats.status = IntegrationStatus::SolverFailed;
    stats.failed_time = t;
    stats.failed_step = stats.steps;
    stats.failure_detail = why;
    return finish();
  };
  if (!observer(std::size_t{0}, t, std::as_const(y))) {
    stats.status = IntegrationStatus::ObserverStopped;
    return finish();
  }
  std::size_t next = 1;
  if (next == times.size()) return finish();

  Inc k1 = vector_field(mech, t, y);
  ++stats.rhs_evaluations;
  double h = settings.initial_step;
  if (h <= 0.0) {
    // Hairer-Norsett-Wanner's starting step (II.4): h0 = 0.01 |y| / |f| in the scaled norm, one
    // Euler step, then h1 from |f| and the change of f, h = min(100 h0, h1).
    const Inc zero = Inc::zero();
    Inc y_size = zero;  // |y|: an attitude counts 1 per component (Rkmk45Settings)
    for (Vec3& th : y_size.theta) th.setOnes();
    y_size.x = y.config.x;
    y_size.w = y.w;
    const auto norm = [&](const Inc& v) { return detail::scaled_rms(v, y, y, settings); };
    const double d0 = norm(y_size);
    const double d1 = norm(k1);
    double h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
    h0 = std::min(h0, t_end - t);
    Inc step = zero;
    step.add_scaled(h0, k1);
    State y1 = y;
    act(y, step, y1);
    Inc k2 = vector_field(mech, t + h0, y1);
    ++stats.rhs_evaluations;
    Inc diff = k2;
    diff.add_scaled(-1.0, k1);
    const double d2 = norm(diff) / h0;
    const double h1 = std::max(d1, d2) <= 1e-15 ? std::max(1e-6, h0 * 1e-3) : std::pow(0.01 / std::max(d1, d2), 1.0 / 5.0);
    h = std::min(100.0 * h0, h1);
  }

  std::array<Inc, 7> K;
  State stage = y;
  bool rejected_last = false;
  while (t < t_end) {
    if (stats.steps + stats.rejected_steps >= settings.max_steps) {
      return fail("rkmk45 reached its step budget of " + std::to_string(settings.max_steps) + " steps before t = " +
                  std::to_string(t_end));
    }
    if (h < 16.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(t))) {
      return fail("rkmk45's step size fell below 16 eps |t| (h = " + std::to_string(h) + ")");
    }
    const bool last = t + h >= t_end;
    if (last) h = t_end - t;
    // Stages 2..7; stage 7 is the fifth-order solution (first same as last).
    K[0] = k1;
    Inc xi = Inc::zero();
    for (int i = 1; i < 7; ++i) {
      xi = Inc::zero();
      for (int j = 0; j < i; ++j) {
        if (T::a[i][j] != 0.0) xi.add_scaled(h * T::a[i][j], K[j]);
      }
      act(y, xi, stage);
      K[i] = vector_field(mech, t + T::c[i] * h, stage);
      ++stats.rhs_evaluations;
      if (i < 6) dexp_inverse(xi, K[i]);
    }
    const Inc k7 = K[6];  // F(t + h, y_1): the next step's first stage
    dexp_inverse(xi, K[6]);
    Inc err = Inc::zero();
    for (int i = 0; i < 7; ++i) {
      const double e = T::b[i] - T::b_hat[i];
      if (e != 0.0) err.add_scaled(h * e, K[i]);
    }
    const double err_norm = detail::scaled_rms(err, y, stage, settings);
    const bool finite = std::isfinite(err_norm) && non_finite_part(stage) == nullptr;
    if (!finite || err_norm > 1.0) {
      ++stats.rejected_steps;
      h *= finite ? std::max(0.2, 0.9 * std::pow(err_norm, -0.2)) : 0.2;
      rejected_last = true;
      continue;
    }
    // Accepted: the output times in (t, t + h] from the continuous extension in the chart,
    //   xi(sigma) = sigma (r2 + (1 - sigma) (r3 + sigma (r4 + (1 - sigma) r5))),
    // r2 = xi, r3 = h K_1 - xi, r4 = xi - h K_7 - r3, r5 = h sum_i d_i K_i (HNW II.6, DOPRI5).
    const double t_new = last ? t_end : t + h;
    while (next < times.size() && times[next] <= t_new) {
      State at;
      if (times[next] == t_new) {
        at = stage;
      } else {
        const double sg = (times[next] - t) / h;
        Inc r3 = Inc::zero();
        r3.add_scaled(h, K[0]);
        r3.add_scaled(-1.0, xi);
        Inc r4 = xi;
        r4.add_scaled(-h, K[6]);
        r4.add_scaled(-1.0, r3);
        Inc r5 = Inc::zero();
        for (int i = 0; i < 7; ++i) {
          if (T::d[i] != 0.0) r5.add_scaled(h * T::d[i], K[i]);
        }
        // Horner form, from the inside out.
        Inc v = r4;
        v.add_scaled(1.0 - sg, r5);
        Inc u = r3;
        u.add_scaled(sg, v);
        Inc w = xi;
        w.add_scaled(1.0 - sg, u);
        Inc at_sigma = Inc::zero();
        at_sigma.add_scaled(sg, w);
        act(y, at_sigma, at);
      }
      if (!observer(next, times[next], std::as_const(at))) {
        ++stats.steps;
        stats.status = IntegrationStatus::ObserverStopped;
        return finish();
      }
      ++next;
    }
    y = stage;
    t = t_new;
    k1 = k7;
    ++stats.steps;
    const double grow = err_norm > 0.0 ? 0.9 * std::pow(err_norm, -0.2) : 5.0;
    h *= std::clamp(grow, 0.2, rejected_last ? 1.0 : 5.0);
    rejected_last = false;
  }
  return finish();
}

}  // namespace lgvi::baselines::lie_group
