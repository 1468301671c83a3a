// Scenarios, runners and derived bounds of the multibody baseline tests (cart-pendulum and
// connected bodies): the same motion on a continuous-time model and on the LGVI, compared in
// the paper's variables.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include <Eigen/Dense>

#include "baselines/mechanics.hpp"
#include "baselines/model.hpp"
#include "baselines/solver.hpp"
#include "lgvi/integrate.hpp"
#include "lgvi/multibody_lgvi.hpp"
#include "test_support.hpp"

namespace lgvi::test {

// --- Scenarios (the scenes' parameters, initial states in the spirit of the scenes) -----------

/// Cart-pendulum, paper parameters (section 4.1): tilted by 0.6 rad about e1, swinging, the cart
/// moving; smooth cart forces (N).
inline Mat3 cart_R0() { return so3::exp(Vec3(0.6, 0.0, 0.0)); }
inline Vec3 cart_Omega0() { return Vec3(0.5, 1.0, 2.0); }
inline Vec2 cart_q0() { return Vec2(0.1, -0.2); }
inline Vec2 cart_q_dot0() { return Vec2(0.3, -0.1); }
inline Vec2 cart_control(double t) { return Vec2(0.5 * std::sin(1.3 * t), 0.3 * std::cos(0.7 * t + 0.2)); }

/// Connected bodies, paper parameters (section 4.2): body 2 turned by exp(hat(0.3, 0.2, -0.1)),
/// both tumbling; a smooth internal moment (N m) at the joint.
inline std::array<Mat3, 2> bodies_R0() { return {Mat3::Identity(), so3::exp(Vec3(0.3, 0.2, -0.1))}; }
inline std::array<Vec3, 2> bodies_Omega0() { return {Vec3(0.5, -0.4, 0.3), Vec3(-0.2, 0.6, 0.1)}; }
inline Vec3 bodies_control(double t) {
  return Vec3(0.05 * std::sin(0.7 * t), 0.025 * std::cos(1.1 * t), 0.015 * std::sin(1.9 * t + 0.5));
}

// --- Trajectories in the paper's variables ----------------------------------------------------

/// z = [vec(R_1) .. vec(R_N) | Omega_1 .. Omega_N | x | x'] (cart: 16 entries, connected bodies:
/// 24): what the CSV holds, so distances compare like with like.
struct Path {
  std::vector<double> t;
  std::vector<Eigen::VectorXd> z;
  std::vector<double> quaternion_norm_error;  ///< worst body, of the raw state
  std::vector<Eigen::VectorXd> raw;           ///< the ODE state (baselines only)
  Stats stats;
};

template <std::size_t N, int NX>
Eigen::VectorXd paper_variables(const std::array<Mat3, N>& R, const std::array<Vec3, N>& Omega,
                                const baselines::Vector<NX>& x, const baselines::Vector<NX>& x_dot) {
  Eigen::VectorXd z(12 * static_cast<int>(N) + 2 * NX);
  int n = 0;
  for (std::size_t i = 0; i < N; ++i) {
    z.segment<9>(n) = baselines::vec_rows(R[i]);
    n += 9;
  }
  for (std::size_t i = 0; i < N; ++i) {
    z.segment<3>(n) = Omega[i];
    n += 3;
  }
  if constexpr (NX > 0) {
    z.segment<NX>(n) = x;
    z.segment<NX>(n + NX) = x_dot;
  }
  return z;
}

/// Runs `method` on a coordinate model of a multibody mechanics.
template <class Chart, class Mech>
Path run_baseline(const std::string& method, const baselines::CoordinateOde<Chart, Mech>& ode,
                  const std::array<Mat3, Mech::bodies>& R0, const std::array<Vec3, Mech::bodies>& Omega0,
                  const baselines::Vector<Mech::positions>& x0, const baselines::Vector<Mech::positions>& x_dot0,
                  const std::vector<double>& times, const baselines::SolverSettings& settings) {
  const auto y0 = ode.initial_state(R0, Omega0, x0, x_dot0);
  Path p;
  const auto observer = [&](std::size_t, double t, const double* y) {
    const auto d = ode.decode(y);
    p.t.push_back(t);
    p.z.push_back(paper_variables(d.config.R, d.rates.Omega, d.config.x, d.rates.x_dot));
    double qerr = 0.0;
    if constexpr (std::is_same_v<Chart, baselines::QuaternionChart>) {
      for (int i = 0; i < Mech::bodies; ++i) qerr = std::max(qerr, std::abs(Eigen::Map<const Eigen::Vector4d>(y + 4 * i).norm() - 1.0));
    }
    p.quaternion_norm_error.push_back(qerr);
    p.raw.push_back(Eigen::Map<const typename std::decay_t<decltype(ode)>::State>(y));
    return true;
  };
  p.stats = baselines::integrate(method, ode, std::span<const double>(y0.data(), y0.size()), times, settings, observer);
  return p;
}

/// Runs the model `model` (quaternion, renormalized, euler, matrix) of a mechanics.
template <class Mech>
Path run_model(const std::string& method, baselines::CoordinateModel model, const Mech& mech,
               const std::array<Mat3, Mech::bodies>& R0, const std::array<Vec3, Mech::bodies>& Omega0,
               const baselines::Vector<Mech::positions>& x0, const baselines::Vector<Mech::positions>& x_dot0,
               const std::vector<double>& times, const baselines::SolverSettings& settings) {
  using baselines::CoordinateModel;
  using baselines::CoordinateOde;
  switch (model) {
    case CoordinateModel::Quaternion:
      return run_baseline(method, CoordinateOde<baselines::QuaternionChart, Mech>(mech), R0, Omega0, x0, x_dot0,
                          times, settings);
    case CoordinateModel::QuaternionRenormalized:
      return run_baseline(method, CoordinateOde<baselines::QuaternionChart, Mech>(mech, true), R0, Omega0, x0,
                          x_dot0, times, settings);
    case CoordinateModel::Euler:
      return run_baseline(method, CoordinateOde<baselines::EulerChart, Mech>(mech), R0, Omega0, x0, x_dot0, times,
                          settings);
    case CoordinateModel::Matrix:
      return run_baseline(method, CoordinateOde<baselines::MatrixChart, Mech>(mech), R0, Omega0, x0, x_dot0, times,
                          settings);
  }
  return {};
}

/// The symmetric LGVI of the cart-pendulum at step h, sampled every `every` steps.
inline Path run_cart_lgvi(const CartPendulum& system, double h, std::size_t steps, std::size_t every,
                          std::function<Vec2(double)> control) {
  const CartPendulumLgvi lgvi(system, LgviForm::Symmetric);
  CartPendulumState s = lgvi.make_state(cart_R0(), cart_q0(), cart_Omega0(), cart_q_dot0());
  Path p;
  p.stats = integrate(lgvi, s, 0.0, h, steps, control,
                      [&](std::size_t k, double t, const CartPendulumState& st, const RotationUpdateSummary&) {
                        if (k % every != 0) return true;
                        Vec3 Omega;
                        Vec2 q_dot;
                        lgvi.velocities(st, Omega, q_dot);
                        p.t.push_back(t);
                        p.z.push_back(paper_variables<1, 2>({st.R}, {Omega}, st.q, q_dot));
                        return true;
                      });
  return p;
}

/// The symmetric LGVI of the connected bodies at step h, sampled every `every` steps.
inline Path run_bodies_lgvi(const ConnectedBodies& system, double h, std::size_t steps, std::size_t every,
                            std::function<Vec3(double)> control) {
  const ConnectedBodiesLgvi lgvi(system, LgviForm::Symmetric);
  const auto R0 = bodies_R0();
  const auto Omega0 = bodies_Omega0();
  ConnectedBodiesState s = lgvi.make_state(R0[0], R0[1], Omega0[0], Omega0[1]);
  Path p;
  p.stats = integrate(lgvi, s, 0.0, h, steps, control,
                      [&](std::size_t k, double t, const ConnectedBodiesState& st, const RotationUpdateSummary&) {
                        if (k % every != 0) return true;
                        std::array<Vec3, 2> Omega;
                        lgvi.velocities(st, Omega[0], Omega[1]);
                        p.t.push_back(t);
                        p.z.push_back(paper_variables<2, 0>({st.R1, st.R2}, Omega, {}, {}));
                        return true;
                      });
  return p;
}

/// max_k |a_k - b_k| (Euclidean norm of the paper's variables) over the common samples.
inline double max_distance(const Path& a, const Path& b) {
  double d = 0.0;
  for (std::size_t k = 0; k < std::min(a.z.size(), b.z.size()); ++k) d = std::max(d, (a.z[k] - b.z[k]).norm());
  return d;
}

// --- Derived bounds ----------------------------------------------------------------------------

/// Global error an adaptive solver promises at tolerance r: the local errors of its N accepted
/// steps, each below r (1 + max|y_i|) per component (rtol = atol = r), i.e. sqrt(n) times that
/// in the Euclidean norm (CVODE controls an RMS norm), summed without damping:
///     N r (1 + max|y|) sqrt(n).
inline double adaptive_bound(const Path& p, double r) {
  double ymax = 0.0;
  for (const Eigen::VectorXd& y : p.raw) ymax = std::max(ymax, y.cwiseAbs().maxCoeff());
  const double n = p.raw.empty() ? 1.0 : static_cast<double>(p.raw.front().size());
  return static_cast<double>(p.stats.steps) * r * (1.0 + ymax) * std::sqrt(n);
}

/// The symmetric LGVI is second order: Y_h = Y + C h^2 + O(h^4) (even powers: the method is
/// symmetric). Then Y_h - Y_{h/2} = 3/4 C h^2 + O(h^4), so the error of Y_h is estimated by
/// 4/3 |Y_h - Y_{h/2}| (Richardson). kRichardsonSlack covers the O(h^2) relative remainder at
/// the steps used (C h^2 ~ 1e-4 relative) and the maximum over samples taken separately.
constexpr double kRichardsonSlack = 1.25;
// The order of the LGVI seen through a continuous-time reference (log2 of the errors at h and
// h/2) is held to kOrderTolerance (test_support.hpp).

}  // namespace lgvi::test
