#include "baselines/solver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "baselines/solver_detail.hpp"
#include "lgvi/inertia.hpp"

namespace lgvi::baselines {

const std::vector<SolverInfo>& solver_list() {
  static const std::vector<SolverInfo> list = {
      {"cvode-adams", StepControl::Adaptive, false, "SUNDIALS CVODE Adams-Moulton (orders 1-12), Newton + dense LU"},
      {"cvode-bdf", StepControl::Adaptive, true, "SUNDIALS CVODE BDF (orders 1-5), Newton + dense LU"},
      {"odeint-rk4", StepControl::Fixed, true, "Boost.Odeint classic Runge-Kutta 4, fixed step"},
      {"odeint-dopri5", StepControl::Adaptive, true, "Boost.Odeint Dormand-Prince 5(4), dense output"},
      {"odeint-rkf78", StepControl::Adaptive, true, "Boost.Odeint Runge-Kutta-Fehlberg 7(8)"},
      {"odeint-bs", StepControl::Adaptive, true, "Boost.Odeint Bulirsch-Stoer, dense output"},
      {"gsl-rk8pd", StepControl::Adaptive, true, "GSL odeiv2 Prince-Dormand 8(9)"},
      {"gsl-rk4imp", StepControl::Fixed, true,
       "GSL odeiv2 Gauss-Legendre 2-stage (order 4, symplectic), fixed step, modified Newton"},
      {"gsl-msbdf", StepControl::Adaptive, false, "GSL odeiv2 variable-order BDF (orders 1-5), Newton"},
  };
  return list;
}

std::vector<std::string> solver_names() {
  std::vector<std::string> names;
  for (const SolverInfo& s : solver_list()) names.push_back(s.name);
  return names;
}

const SolverInfo& solver_info(const std::string& name) {
  for (const SolverInfo& s : solver_list()) {
    if (s.name == name) return s;
  }
  std::string known;
  for (const SolverInfo& s : solver_list()) known += (known.empty() ? "" : ", ") + s.name;
  throw InvalidInput("method", "unknown method '" + name + "' (known: " + known + ")");
}

SolverSettings resolve_settings(const SolverInfo& info, const SolverSettings& settings, const Ode& ode) {
  SolverSettings s = settings;
  if (info.step_control == StepControl::Fixed) {
    if (!s.h) throw InvalidInput("h", info.name + " is a fixed-step method: it needs a step h");
    if (!(std::isfinite(*s.h) && *s.h > 0.0)) throw InvalidInput("h", "must be finite and > 0");
    if (s.rtol || s.atol) {
      throw InvalidInput(s.rtol ? "rtol" : "atol",
                         info.name + " is a fixed-step method: it takes a step h, not tolerances");
    }
  } else {
    if (s.h) throw InvalidInput("h", info.name + " is an adaptive method: it takes rtol/atol, not a fixed step");
    if (!s.rtol) s.rtol = kDefaultRtol;
    if (!s.atol) s.atol = *s.rtol;
    if (!(std::isfinite(*s.rtol) && *s.rtol > 0.0)) throw InvalidInput("rtol", "must be finite and > 0");
    if (!(std::isfinite(*s.atol) && *s.atol > 0.0)) throw InvalidInput("atol", "must be finite and > 0");
  }
  if (ode.renormalizes() && !info.post_step_hook) {
    throw InvalidInput("model", info.name + " has no post-step hook for renormalization (modifying the state "
                                            "between steps would restart its multistep history at order 1 every "
                                            "step); use cvode-bdf (CVODE's projection) or a one-step method");
  }
  if (s.jacobian == JacobianSource::DifferenceQuotient && info.name.rfind("cvode-", 0) != 0) {
    throw InvalidInput("jacobian", "only CVODE has a difference-quotient Jacobian; " + info.name +
                                       " uses the model's");
  }
  if (s.max_steps == 0) throw InvalidInput("max_steps", "must be >= 1");
  if (!(s.newton_tolerance > 0.0 && std::isfinite(s.newton_tolerance))) {
    throw InvalidInput("newton_tolerance", "must be finite and > 0");
  }
  return s;
}

Stats integrate(const std::string& method, const Ode& ode, std::span<const double> y0, std::span<const double> times,
                const SolverSettings& settings, const SampleObserver& observer) {
  const SolverInfo& info = solver_info(method);
  const SolverSettings s = resolve_settings(info, settings, ode);
  if (y0.size() != static_cast<std::size_t>(ode.dimension())) {
    throw InvalidInput("y0", "has " + std::to_string(y0.size()) + " entries, the model " +
                                 std::to_string(ode.dimension()));
  }
  if (!std::all_of(y0.begin(), y0.end(), [](double v) { return std::isfinite(v); })) {
    throw InvalidInput("y0", "has a non-finite entry");
  }
  if (times.empty()) throw InvalidInput("times", "no output times");
  for (std::size_t i = 0; i < times.size(); ++i) {
    if (!std::isfinite(times[i])) throw InvalidInput("times", "has a non-finite entry");
    if (i > 0 && !(times[i] > times[i - 1])) throw InvalidInput("times", "must be strictly increasing");
    if (i > 0 && info.step_control == StepControl::Fixed) {
      const double span = times[i] - times[i - 1];
      const double m = std::max(1.0, std::round(span / *s.h));
      if (std::abs(m * *s.h - span) > 1e-9 * span) {
        throw InvalidInput("h", "the output times are not on the grid of h = " + std::to_string(*s.h) +
                                    " (interval " + std::to_string(span) + ")");
      }
    }
  }

  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  detail::Run run(method, ode, times, s, observer);
  std::vector<double> y(y0.begin(), y0.end());
  Stats stats;
  if (!run.emit(0, y.data())) {
    stats = run.stats;
  } else if (run.singular_at(y.data())) {
    run.stop_singular(times[0], y.data());
    stats = run.stats;
  } else if (method.rfind("cvode-", 0) == 0) {
    stats = detail::run_cvode(run, y, method == "cvode-bdf");
  } else if (method.rfind("odeint-", 0) == 0) {
    stats = detail::run_odeint(run, y);
  } else {
    stats = detail::run_gsl(run, y);
  }
  stats.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return stats;
}

namespace detail {

bool Run::rhs(double t, const double* y, double* f) {
  ++stats.rhs_evaluations;
  Failure failure = Failure::None;
  if (ode.rhs(t, y, f) != RhsStatus::Ok) {
    failure = Failure::Singular;
  } else if (!std::all_of(f, f + n, [](double v) { return std::isfinite(v); })) {
    failure = Failure::NonFinite;
  }
  if (failure == Failure::None) return true;
  if (failure_ == Failure::None) {
    failure_ = failure;
    failure_time_ = t;
    failure_state_.assign(y, y + n);
  }
  return false;
}

bool Run::jacobian(double t, const double* y, double* J) {
  ++stats.jacobian_evaluations;
  if (ode.jacobian(t, y, J) != RhsStatus::Ok) {
    if (failure_ == Failure::None) {
      failure_ = Failure::Singular;
      failure_time_ = t;
      failure_state_.assign(y, y + n);
    }
    return false;
  }
  if (!std::all_of(J, J + n * n, [](double v) { return std::isfinite(v); })) {
    if (failure_ == Failure::None) {
      failure_ = Failure::NonFinite;
      failure_time_ = t;
      failure_state_.assign(y, y + n);
    }
    return false;
  }
  return true;
}

bool Run::time_derivative(double t, const double* y, double* dfdt) {
  if (!ode.time_dependent()) {
    std::fill(dfdt, dfdt + n, 0.0);
    return true;
  }
  // Central difference with the step cbrt(eps) max(1, |t|) (see model.hpp).
  const double a = 6.0554544523933395e-06 * std::max(1.0, std::abs(t));
  std::vector<double> minus(n);
  if (!rhs(t + a, y, dfdt) || !rhs(t - a, y, minus.data())) return false;
  for (std::size_t i = 0; i < n; ++i) dfdt[i] = (dfdt[i] - minus[i]) / (2.0 * a);
  return true;
}

bool Run::emit(std::size_t index, const double* y) {
  next_ = index + 1;
  if (!observer_(index, times[index], y)) {
    stats.status = IntegrationStatus::ObserverStopped;
    return false;
  }
  return true;
}

void Run::stop_singular(double t, const double* y) {
  stats.status = IntegrationStatus::CoordinateSingularity;
  stats.failed_time = t;
  stats.failed_step = stats.steps;
  stats.failure_detail = ode.describe_singularity(y);
}

void Run::stop_failed(double t, const std::string& detail) {
  stats.status = IntegrationStatus::SolverFailed;
  stats.failed_time = t;
  stats.failed_step = stats.steps;
  stats.failure_detail = method + ": " + detail;
}

bool Run::stop_on_rhs_failure() {
  if (failure_ == Failure::Singular) {
    stop_singular(failure_time_, failure_state_.data());
    stats.failure_detail += " (a right-hand-side evaluation reached the singular set)";
    return true;
  }
  if (failure_ == Failure::NonFinite) {
    stop_failed(failure_time_, "non-finite right-hand side (the state has left the model's domain)");
    return true;
  }
  return false;
}

bool Run::check_finite(double t, const double* y) {
  if (std::all_of(y, y + n, [](double v) { return std::isfinite(v); })) return true;
  stop_failed(t, "non-finite state");
  return false;
}

void Run::stop_at_event(double t0, const double* y0, double t1, const double* y1) {
  std::vector<double> f0(n), f1(n), y(n);
  // Evaluate without counting failures as the run's failure: the end point may be singular.
  const bool have_slopes = ode.rhs(t0, y0, f0.data()) == RhsStatus::Ok && ode.rhs(t1, y1, f1.data()) == RhsStatus::Ok;
  stats.rhs_evaluations += 2;
  const double dt = t1 - t0;
  auto state_at = [&](double s) {  // s in [0, 1]
    if (!have_slopes) {
      for (std::size_t i = 0; i < n; ++i) y[i] = (1.0 - s) * y0[i] + s * y1[i];
      return;
    }
    const double h00 = (1.0 + 2.0 * s) * (1.0 - s) * (1.0 - s), h10 = s * (1.0 - s) * (1.0 - s);
    const double h01 = s * s * (3.0 - 2.0 * s), h11 = s * s * (s - 1.0);
    for (std::size_t i = 0; i < n; ++i) y[i] = h00 * y0[i] + h10 * dt * f0[i] + h01 * y1[i] + h11 * dt * f1[i];
  };
  // Bisection on the event function: g(s = 0) > 0 >= g(s = 1). 60 halvings reach the
  // resolution of double in s.
  double lo = 0.0, hi = 1.0;
  for (int k = 0; k < 60 && (hi - lo) * std::abs(dt) > 4e-16 * std::max(std::abs(t0), std::abs(t1)); ++k) {
    const double mid = 0.5 * (lo + hi);
    state_at(mid);
    if (ode.singularity_function(y.data()) > 0.0) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  state_at(hi);
  stop_singular(t0 + hi * dt, y.data());
}

double Run::initial_step() const {
  if (settings.initial_step > 0.0) return settings.initial_step;
  const double span = times.size() > 1 ? times[1] - times[0] : 1.0;
  return 1e-3 * span;
}

double Run::min_step() const {
  return 16.0 * std::numeric_limits<double>::epsilon() *
         std::max(std::abs(times.back()), std::abs(times.back() - times.front()));
}

}  // namespace detail

}  // namespace lgvi::baselines
