// Scenarios and helpers of the baseline tests: run any method on any coordinate model of a
// system and collect the trajectory in the paper's variables.
#pragma once

#include <cmath>
#include <functional>
#include <iostream>
#include <span>
#include <string>
#include <vector>

#include "dumbbell_case.hpp"
#include "baselines/mechanics.hpp"
#include "baselines/model.hpp"
#include "baselines/solver.hpp"
#include "lgvi/systems/dumbbell.hpp"
#include "lgvi/systems/free_rigid_body.hpp"
#include "lgvi/systems/pendulum.hpp"
#include "test_support.hpp"

namespace lgvi::test {

using baselines::CoordinateModel;
using baselines::SolverSettings;

/// Every (method, model) pair the interface accepts: the renormalized quaternion needs a
/// post-step hook (cvode-adams and gsl-msbdf have none).
struct Combination {
  std::string method;
  CoordinateModel model;
};
inline std::vector<Combination> all_combinations() {
  std::vector<Combination> c;
  for (const baselines::SolverInfo& s : baselines::solver_list()) {
    for (const CoordinateModel m : {CoordinateModel::Quaternion, CoordinateModel::QuaternionRenormalized,
                                    CoordinateModel::Euler, CoordinateModel::Matrix}) {
      if (m == CoordinateModel::QuaternionRenormalized && !s.post_step_hook) continue;
      c.push_back({s.name, m});
    }
  }
  return c;
}
inline std::string combination_name(const Combination& c) {
  std::string n = c.method + "_" + baselines::to_string(c.model);
  for (char& ch : n) {
    if (ch == '-') ch = '_';
  }
  return n;
}
inline bool is_fixed_step(const std::string& method) {
  return baselines::solver_info(method).step_control == baselines::StepControl::Fixed;
}

/// The state at each requested time in the paper's variables, plus the raw ODE state.
struct Trajectory {
  std::vector<double> t;
  std::vector<Mat3> R;
  std::vector<Vec3> Omega;
  std::vector<double> quaternion_norm_error;  ///< of the raw state (before any sample normalization)
  std::vector<Vec3> x, v;                     ///< dumbbell only
  Stats stats;
};

template <class Chart, class Mech>
Trajectory run_ode(const std::string& method, const baselines::CoordinateOde<Chart, Mech>& ode, const Mat3& R0,
                   const Vec3& Omega0, const std::vector<double>& times, const SolverSettings& settings,
                   const baselines::Vector<Mech::positions>& x0 = {}, const baselines::Vector<Mech::positions>& v0 = {}) {
  const auto y0 = ode.initial_state({R0}, {Omega0}, x0, v0);
  Trajectory tr;
  const auto observer = [&](std::size_t, double t, const double* y) {
    const auto d = ode.decode(y);
    tr.t.push_back(t);
    tr.R.push_back(d.config.R[0]);
    tr.Omega.push_back(d.rates.Omega[0]);
    if constexpr (Mech::positions == 3) {
      tr.x.push_back(d.config.x);
      tr.v.push_back(d.rates.x_dot);
    }
    double qerr = 0.0;
    if constexpr (std::is_same_v<Chart, baselines::QuaternionChart>) {
      qerr = std::abs(Eigen::Map<const Eigen::Vector4d>(y).norm() - 1.0);
    }
    tr.quaternion_norm_error.push_back(qerr);
    return true;
  };
  tr.stats = baselines::integrate(method, ode, std::span<const double>(y0.data(), y0.size()), times, settings, observer);
  return tr;
}

/// Runs `method` on `model` of an attitude system with an optional control.
template <class System>
Trajectory run_attitude(const std::string& method, CoordinateModel model, const System& system,
                        std::function<Vec3(double)> control, const Mat3& R0, const Vec3& Omega0,
                        const std::vector<double>& times, const SolverSettings& settings) {
  using Mech = baselines::AttitudeMechanics<System>;
  const Mech mech(system, std::move(control));
  switch (model) {
    case CoordinateModel::Quaternion:
      return run_ode(method, baselines::CoordinateOde<baselines::QuaternionChart, Mech>(mech), R0, Omega0, times,
                     settings);
    case CoordinateModel::QuaternionRenormalized:
      return run_ode(method, baselines::CoordinateOde<baselines::QuaternionChart, Mech>(mech, true), R0, Omega0,
                     times, settings);
    case CoordinateModel::Euler:
      return run_ode(method, baselines::CoordinateOde<baselines::EulerChart, Mech>(mech), R0, Omega0, times, settings);
    case CoordinateModel::Matrix:
      return run_ode(method, baselines::CoordinateOde<baselines::MatrixChart, Mech>(mech), R0, Omega0, times,
                     settings);
  }
  return {};
}

/// Runs `method` on `model` of the dumbbell with an optional control.
inline Trajectory run_dumbbell(const std::string& method, CoordinateModel model, const DumbbellSpacecraft& system,
                               std::function<DumbbellSpacecraft::Control(double)> control, const Mat3& R0,
                               const Vec3& Omega0, const Vec3& x0, const Vec3& v0, const std::vector<double>& times,
                               const SolverSettings& settings) {
  using Mech = baselines::DumbbellMechanics;
  const Mech mech(system, std::move(control));
  using baselines::CoordinateOde;
  switch (model) {
    case CoordinateModel::Quaternion:
      return run_ode(method, CoordinateOde<baselines::QuaternionChart, Mech>(mech), R0, Omega0, times, settings, x0, v0);
    case CoordinateModel::QuaternionRenormalized:
      return run_ode(method, CoordinateOde<baselines::QuaternionChart, Mech>(mech, true), R0, Omega0, times, settings,
                     x0, v0);
    case CoordinateModel::Euler:
      return run_ode(method, CoordinateOde<baselines::EulerChart, Mech>(mech), R0, Omega0, times, settings, x0, v0);
    case CoordinateModel::Matrix:
      return run_ode(method, CoordinateOde<baselines::MatrixChart, Mech>(mech), R0, Omega0, times, settings, x0, v0);
  }
  return {};
}

inline std::vector<double> uniform_times(double T, std::size_t n) {
  std::vector<double> t(n + 1);
  for (std::size_t k = 0; k <= n; ++k) t[k] = T * static_cast<double>(k) / static_cast<double>(n);
  return t;
}

/// Distance of two states: ||R_a - R_b||_F + |Omega_a - Omega_b| (Frobenius, so that it is
/// defined for the quaternion and matrix models off SO(3)).
inline double state_distance(const Mat3& Ra, const Vec3& Oa, const Mat3& Rb, const Vec3& Ob) {
  return (Ra - Rb).norm() + (Oa - Ob).norm();
}
/// Largest distance over the common samples of two trajectories.
/// (Plus |x_a - x_b| + |v_a - v_b| for the dumbbell.)
inline double max_distance(const Trajectory& a, const Trajectory& b) {
  double d = 0.0;
  for (std::size_t k = 0; k < std::min(a.t.size(), b.t.size()); ++k) {
    double dk = state_distance(a.R[k], a.Omega[k], b.R[k], b.Omega[k]);
    if (k < a.x.size() && k < b.x.size()) dk += (a.x[k] - b.x[k]).norm() + (a.v[k] - b.v[k]).norm();
    d = std::max(d, dk);
  }
  return d;
}

inline SolverSettings adaptive(double rtol) {
  SolverSettings s;
  s.rtol = rtol;
  s.atol = rtol;
  return s;
}
inline SolverSettings fixed(double h) {
  SolverSettings s;
  s.h = h;
  return s;
}

// --- Scenarios ----------------------------------------------------------------------------------

/// Free body J = diag(0.13, 0.28, 0.17) (the paper's pendulum inertia), a generic tumble, with
/// a smooth body-frame control moment.
inline FreeRigidBody free_body() { return FreeRigidBody(Vec3(0.13, 0.28, 0.17).asDiagonal()); }
inline Mat3 free_body_R0() { return so3::exp(Vec3(0.3, -0.2, 0.5)); }
inline Vec3 free_body_Omega0() { return Vec3(1.0, 2.0, -0.5); }
inline Vec3 free_body_control(double t) {
  return Vec3(0.3 * std::sin(2.0 * t), 0.2 * std::cos(3.0 * t), 0.1 * std::sin(t + 0.4));
}

/// The paper's pendulum (m = 1, J = diag(0.13, 0.28, 0.17), rho = 0.3 e3, g = 9.81) swinging
/// from R0 = exp(0.4 e1 - 0.3 e2) with Omega0 = (1.5, -1, 2): large-angle 3D motion whose pitch
/// stays away from +-90 deg (so that the Euler model is tested for accuracy here; gimbal lock has
/// its own test), with a smooth control u (moment R^T e3 x u).
inline Mat3 pendulum_R0() { return so3::exp(Vec3(0.4, -0.3, 0.0)); }
inline Vec3 pendulum_Omega0() { return Vec3(1.5, -1.0, 2.0); }
inline Vec3 pendulum_control(double t) {
  return Vec3(0.5 * std::sin(2.0 * M_PI * 0.5 * t), 0.3 * std::sin(2.0 * M_PI * 0.9 * t + 1.0),
              0.4 * std::sin(2.0 * M_PI * 1.3 * t + 2.0));
}


}  // namespace lgvi::test
