#include "baselines/ocp_replay.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <ctime>
#include <functional>
#include <vector>

#include "baselines/model.hpp"
#include "baselines/solver.hpp"
#include "lgvi/cpu_time.hpp"
#include "lgvi/so3.hpp"

namespace lgvi::baselines {

const char* to_string(ReplayInterpolation interpolation) {
  switch (interpolation) {
    case ReplayInterpolation::ZeroOrderHold: return "zero-order-hold";
    case ReplayInterpolation::PiecewiseLinear: return "piecewise-linear";
    case ReplayInterpolation::PiecewiseQuadratic: return "piecewise-quadratic";
  }
  return "?";
}

ReplayInterpolation replay_interpolation(LgviForm form) {
  return form == LgviForm::Symmetric ? ReplayInterpolation::PiecewiseLinear : ReplayInterpolation::ZeroOrderHold;
}

namespace {

/// Number of intervals of c's nodes.
Eigen::Index intervals_of(const ReplayControls& c) {
  if (c.interpolation == ReplayInterpolation::PiecewiseQuadratic) {
    if (c.u.cols() < 3 || c.u.cols() % 2 == 0) {
      throw InvalidInput("controls", "piecewise quadratic: needs 2 N + 1 columns (nodes and midpoints), N >= 1");
    }
    return (c.u.cols() - 1) / 2;
  }
  if (c.u.cols() < 2) throw InvalidInput("controls", "needs at least 2 nodes (one step)");
  return c.u.cols() - 1;
}

void check(const ReplayControls& c, int nu) {
  intervals_of(c);
  if (c.u.rows() != nu) {
    throw InvalidInput("controls", "needs " + std::to_string(nu) + " components per node (got " +
                                       std::to_string(c.u.rows()) + ")");
  }
  require_finite(c.u, "controls");
  if (!(std::isfinite(c.h) && c.h > 0.0)) throw InvalidInput("controls", "the node spacing h must be positive and finite");
  if (c.W.size() != 0) {
    if (c.W.rows() != nu || c.W.cols() != nu) {
      throw InvalidInput("W", "must be " + std::to_string(nu) + " x " + std::to_string(nu));
    }
    require_finite(c.W, "W");
  }
}

double quadratic(const ReplayControls& c, const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return c.W.size() == 0 ? a.dot(b) : a.dot(c.W * b);
}

/// The control u(t) inside the current interval [t_k, t_{k+1}] (set before each solver call):
/// extended smoothly past its ends, so that a stage just outside sees the same formula.
struct Schedule {
  const ReplayControls* c = nullptr;
  Eigen::Index k = 0;
  Eigen::VectorXd at(double t) const { return value(*c, k, (t - static_cast<double>(k) * c->h) / c->h); }
  /// u in interval k at the fraction s of it.
  static Eigen::VectorXd value(const ReplayControls& c, Eigen::Index k, double s) {
    switch (c.interpolation) {
      case ReplayInterpolation::ZeroOrderHold: return c.u.col(k + 1);
      case ReplayInterpolation::PiecewiseLinear: return (1.0 - s) * c.u.col(k) + s * c.u.col(k + 1);
      case ReplayInterpolation::PiecewiseQuadratic:
        return 2.0 * (s - 0.5) * (s - 1.0) * c.u.col(2 * k) - 4.0 * s * (s - 1.0) * c.u.col(2 * k + 1) +
               2.0 * s * (s - 0.5) * c.u.col(2 * k + 2);
    }
    return c.u.col(k);
  }
};

/// Integrates the quaternion model of `mechanics` (whose control reads `schedule`) interval by
/// interval from y0; `residual(decoded)` gives the terminal residual.
template <class Mech, class Residual>
ReplayResult run(const Mech& mechanics, Schedule& schedule, const typename CoordinateOde<QuaternionChart, Mech>::State& y0,
                 const ReplayControls& c, const ReplayOptions& options, Residual residual) {
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = thread_cpu_seconds();
  using Ode = CoordinateOde<QuaternionChart, Mech>;
  const Ode ode(mechanics);
  ReplayResult out;
  const auto stamp = [&] {
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    out.cpu_seconds = thread_cpu_seconds() - cpu_start;
  };
  out.interpolation = c.interpolation;
  out.cost = replayed_cost(c);
  SolverSettings settings;
  settings.rtol = options.rtol;
  settings.atol = options.atol;
  std::vector<double> y(y0.data(), y0.data() + Ode::kDim), next(Ode::kDim);
  const Eigen::Index intervals = intervals_of(c);
  for (Eigen::Index k = 0; k < intervals; ++k) {
    schedule.k = k;
    if (out.steps >= options.max_steps) {
      out.message = "replay by " + options.method + " used its " + std::to_string(options.max_steps) +
                    " steps before the interval of step " + std::to_string(k);
      break;
    }
    settings.max_steps = options.max_steps - out.steps;
    const std::array<double, 2> times = {static_cast<double>(k) * c.h, static_cast<double>(k + 1) * c.h};
    const Stats stats = integrate(options.method, ode, y, times, settings, [&](std::size_t i, double, const double* yi) {
      if (i == 1) std::copy(yi, yi + Ode::kDim, next.begin());
      return true;
    });
    out.steps += stats.steps;
    out.rhs_evaluations += stats.rhs_evaluations;
    if (!stats.ok()) {
      out.message = "replay by " + options.method + " failed in the interval of step " + std::to_string(k) +
                    " (t = " + std::to_string(times[0]) + "): " + stats.brief();
      stamp();
      return out;
    }
    y.swap(next);
  }
  if (!out.message.empty()) {
    stamp();
    return out;
  }
  const typename Ode::Decoded d = ode.decode(y.data());
  for (const double e : d.quaternion_norm_error) out.quaternion_drift = std::max(out.quaternion_drift, e);
  out.residual = residual(d);
  out.violation = out.residual.norm();
  out.ok = std::isfinite(out.violation);
  if (!out.ok) out.message = "the replayed terminal state is not finite";
  stamp();
  return out;
}

template <class S>
ReplayResult replay_attitude(const S& system, const ocp::TransferProblem& p, const ReplayControls& c,
                             const ReplayOptions& options) {
  check(c, 3);
  Schedule schedule{&c};
  const AttitudeMechanics<S> mech(system, [&schedule](double t) -> Vec3 { return schedule.at(t); });
  const auto y0 = CoordinateOde<QuaternionChart, AttitudeMechanics<S>>(mech).initial_state({p.R0}, {p.Omega0});
  return run(mech, schedule, y0, c, options, [&](const auto& d) {
    Eigen::VectorXd r(6);
    r << so3::log(p.Rf.transpose() * d.config.R[0]), d.rates.Omega[0] - p.Omegaf;
    return r;
  });
}

}  // namespace

double replayed_cost(const ReplayControls& c) {
  const Eigen::Index intervals = intervals_of(c);
  double cost = 0.0;
  for (Eigen::Index k = 0; k < intervals; ++k) {
    if (c.interpolation == ReplayInterpolation::PiecewiseQuadratic) {
      // 3-point Gauss-Legendre on [0, 1], exact to degree 5
      const double r = std::sqrt(15.0) / 10.0;
      const std::array<double, 3> s = {0.5 - r, 0.5, 0.5 + r}, w = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};
      for (int i = 0; i < 3; ++i) {
        const Eigen::VectorXd u = Schedule::value(c, k, s[static_cast<std::size_t>(i)]);
        cost += 0.5 * c.h * w[static_cast<std::size_t>(i)] * quadratic(c, u, u);
      }
      continue;
    }
    const Eigen::VectorXd a = c.u.col(k), b = c.u.col(k + 1);
    cost += c.interpolation == ReplayInterpolation::ZeroOrderHold
                ? 0.5 * c.h * quadratic(c, b, b)
                : c.h / 6.0 * (quadratic(c, a, a) + quadratic(c, a, b) + quadratic(c, b, b));
  }
  return cost;
}

ReplayResult replay(const Pendulum3D& system, const ocp::TransferProblem& problem, const ReplayControls& c,
                    const ReplayOptions& options) {
  return replay_attitude(system, problem, c, options);
}

ReplayResult replay(const FreeRigidBody& system, const ocp::TransferProblem& problem, const ReplayControls& c,
                    const ReplayOptions& options) {
  return replay_attitude(system, problem, c, options);
}

ReplayResult replay(const DumbbellSpacecraft& system, const ocp::TransferProblem& p, const ReplayControls& c,
                    const ReplayOptions& options) {
  check(c, 6);
  Schedule schedule{&c};
  const DumbbellMechanics mech(system, [&schedule](double t) {
    const Eigen::VectorXd u = schedule.at(t);
    DumbbellSpacecraft::Control control;
    control.moment = u.head<3>();  // the layout of lgvi/ocp/models.hpp DumbbellModel: [u^m; u^f]
    control.force = u.tail<3>();
    return control;
  });
  const auto y0 = CoordinateOde<QuaternionChart, DumbbellMechanics>(mech).initial_state({p.R0}, {p.Omega0}, p.x0, p.v0);
  return run(mech, schedule, y0, c, options, [&](const auto& d) {
    Eigen::VectorXd r(12);
    r << so3::log(p.Rf.transpose() * d.config.R[0]), d.config.x - p.xf, d.rates.Omega[0] - p.Omegaf,
        d.rates.x_dot - p.vf;
    return r;
  });
}

ReplayResult replay(const CartPendulum& system, const ocp::CartPendulumTransfer& p, const ReplayControls& c,
                    const ReplayOptions& options) {
  check(c, 2);
  Schedule schedule{&c};
  const CartPendulumMechanics mech(system, [&schedule](double t) -> Vec2 { return schedule.at(t); });
  const auto y0 =
      CoordinateOde<QuaternionChart, CartPendulumMechanics>(mech).initial_state({p.R0}, {p.Omega0}, p.q0, p.q_dot0);
  return run(mech, schedule, y0, c, options, [&](const auto& d) {
    Eigen::VectorXd r(10);
    r << so3::log(d.config.R[0].transpose() * p.Rf), d.config.x - p.qf, d.rates.Omega[0] - p.Omegaf,
        d.rates.x_dot - p.q_dotf;
    return r;
  });
}

ReplayResult replay(const ConnectedBodies& system, const ocp::ConnectedBodiesTransfer& p, const ReplayControls& c,
                    const ReplayOptions& options) {
  check(c, 3);
  Schedule schedule{&c};
  const ConnectedBodiesMechanics mech(system, [&schedule](double t) -> Vec3 { return schedule.at(t); });
  const auto y0 = CoordinateOde<QuaternionChart, ConnectedBodiesMechanics>(mech).initial_state(
      {p.R1_0, p.R2_0}, {p.Omega1_0, p.Omega2_0});
  return run(mech, schedule, y0, c, options, [&](const auto& d) {
    Eigen::VectorXd r(12);
    r << so3::log(d.config.R[0].transpose() * p.R1_f), so3::log(d.config.R[1].transpose() * p.R2_f),
        d.rates.Omega[0] - p.Omega1_f, d.rates.Omega[1] - p.Omega2_f;
    return r;
  });
}

}  // namespace lgvi::baselines
