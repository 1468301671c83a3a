#include "baselines/solver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "baselines/solver_detail.hpp"
#include "lgvi/inertia.hpp"
#include "lgvi/range.hpp"

namespace lgvi::baselines {

const std::vector<SolverInfo>& solver_list() {
  static const std::vector<SolverInfo> list = {
      {"cvode-adams", StepControl::Adaptive, false, "SUNDIALS CVODE Adams-Moulton (orders 1-12), Newton + dense LU", 0, 0,
       true, OutputInterpolation::Cvode, detail::run_cvode_adams, true},
      {"cvode-bdf", StepControl::Adaptive, true, "SUNDIALS CVODE BDF (orders 1-5), Newton + dense LU", 0, 0, true,
       OutputInterpolation::Cvode, detail::run_cvode_bdf, true},
      {"cvode-bdf-projected", StepControl::Adaptive, false,
       "SUNDIALS CVODE BDF (orders 1-5), Newton + dense LU, projected after every step onto |q| = 1 and the "
       "invariants (energy when uncontrolled; free body |Pi|, pendulum e3.(R J Omega))",
       0, 0, true, OutputInterpolation::Cvode, detail::run_cvode_bdf_projected, true, false, true},
      {"odeint-rk4", StepControl::Fixed, true, "Boost.Odeint classic Runge-Kutta 4, fixed step", 4, 4, false,
       OutputInterpolation::FixedGrid, detail::run_odeint_rk4},
      {"odeint-dopri5", StepControl::Adaptive, true, "Boost.Odeint Dormand-Prince 5(4), dense output", 0, 0, false,
       OutputInterpolation::DenseOutput, detail::run_odeint_dopri5},
      {"odeint-rkf78", StepControl::Adaptive, true, "Boost.Odeint Runge-Kutta-Fehlberg 7(8)", 0, 0, false,
       OutputInterpolation::Hermite, detail::run_odeint_rkf78},
      {"odeint-bs", StepControl::Adaptive, true, "Boost.Odeint Bulirsch-Stoer, dense output", 0, 0, false,
       OutputInterpolation::DenseOutput, detail::run_odeint_bs},
      {"gsl-rk8pd", StepControl::Adaptive, true, "GSL odeiv2 Prince-Dormand 8(9)", 0, 0, false,
       OutputInterpolation::Hermite, detail::run_gsl_rk8pd},
      {"gsl-rk4imp", StepControl::Fixed, true,
       "GSL odeiv2 Gauss-Legendre 2-stage (order 4, symplectic), fixed step, modified Newton", 4, 2, true,
       OutputInterpolation::FixedGrid, detail::run_gsl_rk4imp},
      {"gsl-msbdf", StepControl::Adaptive, false, "GSL odeiv2 variable-order BDF (orders 1-5), Newton", 0, 0, true,
       OutputInterpolation::Hermite, detail::run_gsl_msbdf},
      {"arkode-erk", StepControl::Adaptive, false, "SUNDIALS ARKODE ERKStep, Verner 6(5) 8-stage pair", 0, 0, false,
       OutputInterpolation::Arkode, detail::run_arkode_erk, false, true},
      {"arkode-dirk", StepControl::Adaptive, false,
       "SUNDIALS ARKODE ARKStep ESDIRK, Kennedy-Carpenter ARK5(4)8L[2]SA implicit part, Newton + dense LU", 0, 0, true,
       OutputInterpolation::Arkode, detail::run_arkode_dirk, false, true},
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
    check_tolerance(*s.rtol, "rtol");
    check_tolerance(*s.atol, "atol");
  }
  if (s.fixed_step_probe) {
    if (!info.offers_fixed_step_probe) {
      throw InvalidInput("fixed_step_probe", info.name + " has no fixed-step mode (ARKODE's methods only)");
    }
    if (!(std::isfinite(*s.fixed_step_probe) && *s.fixed_step_probe > 0.0)) {
      throw InvalidInput("fixed_step_probe", "must be finite and > 0");
    }
  }
  if (ode.renormalizes() && info.projects_onto_invariants) {
    throw InvalidInput("model", info.name + " projects the quaternion model onto |q| = 1 itself (and onto the "
                                            "invariants): use --model quaternion, not quaternion-renormalized");
  }
  if (ode.renormalizes() && !info.post_step_hook) {
    // Why each has none is in baselines/solver.hpp (a multistep history that would restart at order
    // 1 every step; ARKODE's post-processing, unseen by its error control).
    std::string with_hook;
    for (const SolverInfo& other : solver_list()) {
      if (other.post_step_hook) with_hook += (with_hook.empty() ? "" : ", ") + other.name;
    }
    throw InvalidInput("model", info.name + " has no post-step hook for renormalization (modifying the state "
                                            "between steps would restart a multistep history or bypass the error "
                                            "control); use one of " +
                                            with_hook + " (cvode-bdf: CVODE's projection)");
  }
  if (s.jacobian == JacobianSource::DifferenceQuotient && !info.difference_quotient_jacobian) {
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
  if (info.projects_onto_invariants) {
    // Here, not in resolve_settings: the harness checks settings against a stand-in model.
    const std::string why = ode.projection_refusal();
    if (!why.empty()) throw InvalidInput("model", info.name + ": " + why);
  }
  if (times.empty()) throw InvalidInput("times", "no output times");
  if (info.step_control == StepControl::Fixed && std::isfinite(times.back() - times.front())) {
    // The grid's step count, bounded as a scene's horizon is (lgvi/range.hpp): beyond it the
    // count of steps per interval overflows (an h of 1e-20 returned the initial state as if
    // completed).
    const double n = (times.back() - times.front()) / *s.h;
    if (!(n <= kMaxSteps)) {
      throw InvalidInput("h", "gives too many steps over the output times ((t_last - t_first) / h = " +
                                  Range::text(n) + ", limit " + Range::text(kMaxSteps) + ")");
    }
  }
  for (std::size_t i = 0; i < times.size(); ++i) {
    if (!std::isfinite(times[i])) throw InvalidInput("times", "has a non-finite entry");
    if (i > 0 && !(times[i] > times[i - 1])) throw InvalidInput("times", "must be strictly increasing");
    if (i > 0 && info.step_control == StepControl::Fixed) {
      const double span = times[i] - times[i - 1];
      // One step of span < h ends the run (fixed_step_loop takes max(1, round(span / h)) = 1 step).
      if (s.shorter_last_step && i + 1 == times.size() && span < *s.h) continue;
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
  } else {
    stats = info.adapter(run, y);
  }
  stats.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return stats;
}

namespace detail {

bool Run::rhs(double t, const double* y, double* f) {
  ++stats.rhs_evaluations;
  if (output_mode_) ++stats.output_rhs_evaluations;
  Failure failure = Failure::None;
  if (ode.rhs(t, y, f) != RhsStatus::Ok) {
    failure = Failure::Singular;
  } else if (!std::all_of(f, f + n, [](double v) { return std::isfinite(v); })) {
    failure = Failure::NonFinite;
  }
  if (failure == Failure::None) return true;
  if (failure_ == Failure::None && !output_mode_) {
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
  const double* bad = std::find_if(y, y + n, [](double v) { return !std::isfinite(v); });
  if (bad == y + n) return true;
  stop_failed(t, "non-finite state: component " + std::to_string(bad - y) + " of the " + std::to_string(n) +
                     " of the " + ode.model_name() + " state is " + (std::isnan(*bad) ? "NaN" : "infinite"));
  return false;
}

void Run::stop_at_event(double t0, const double* y0, double t1, const double* y1) {
  std::vector<double> f0(n), f1(n), y(n);
  // Evaluated without counting failures as the run's failure: the end point is singular.
  const bool have_f0 = ode.rhs(t0, y0, f0.data()) == RhsStatus::Ok;
  const bool have_f1 = have_f0 && ode.rhs(t1, y1, f1.data()) == RhsStatus::Ok;
  stats.rhs_evaluations += have_f0 ? 2 : 1;
  const double dt = t1 - t0;
  auto state_at = [&](double s) {  // s in [0, 1]
    if (have_f1) {  // cubic Hermite
      const double h00 = (1.0 + 2.0 * s) * (1.0 - s) * (1.0 - s), h10 = s * (1.0 - s) * (1.0 - s);
      const double h01 = s * s * (3.0 - 2.0 * s), h11 = s * s * (s - 1.0);
      for (std::size_t i = 0; i < n; ++i) y[i] = h00 * y0[i] + h10 * dt * f0[i] + h01 * y1[i] + h11 * dt * f1[i];
    } else if (have_f0) {  // the quadratic through y0, f0 and y1
      for (std::size_t i = 0; i < n; ++i) {
        y[i] = y0[i] + s * dt * f0[i] + s * s * (y1[i] - y0[i] - dt * f0[i]);
      }
    } else {
      for (std::size_t i = 0; i < n; ++i) y[i] = (1.0 - s) * y0[i] + s * y1[i];
    }
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
  const double t_event = t0 + hi * dt;
  // The output times the step passed before the event (the methods that step freely).
  while (!done() && times[next_] < t_event) {
    state_at((times[next_] - t0) / dt);
    if (!emit(next_, y.data())) return;
  }
  state_at(hi);
  stop_singular(t_event, y.data());
}

double Run::initial_step(int order, const double* y0) {
  const double span = times.back() - times.front();
  if (settings.initial_step > 0.0) return std::min(settings.initial_step, span);
  // Hairer, Norsett, Wanner, Solving ODEs I, sec. II.4, in the error control's scaled RMS norm.
  std::vector<double> f0(n), y1(n), f1(n);
  const double t0 = times.front();
  // Evaluated without counting failures as the run's failure (the first step reports them).
  auto evaluate = [&](double t, const double* y, double* f) {
    ++stats.rhs_evaluations;
    return ode.rhs(t, y, f) == RhsStatus::Ok && std::all_of(f, f + n, [](double v) { return std::isfinite(v); });
  };
  auto norm = [&](const double* v) {
    double sum = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double scaled = v[i] / (*settings.atol + *settings.rtol * std::abs(y0[i]));
      sum += scaled * scaled;
    }
    return std::sqrt(sum / static_cast<double>(n));
  };
  constexpr double kFallback = 1e-6;  // the book's step for a state or rate that is ~0
  if (!evaluate(t0, y0, f0.data())) return std::min(kFallback, span);
  const double d0 = norm(y0), d1 = norm(f0.data());
  const double h0 = std::min(d0 < 1e-5 || d1 < 1e-5 ? kFallback : 0.01 * d0 / d1, span);
  for (std::size_t i = 0; i < n; ++i) y1[i] = y0[i] + h0 * f0[i];
  if (!evaluate(t0 + h0, y1.data(), f1.data())) return h0;
  for (std::size_t i = 0; i < n; ++i) f1[i] -= f0[i];
  const double d2 = norm(f1.data()) / h0;
  const double d = std::max(d1, d2);
  const double h1 = d <= 1e-15 ? std::max(kFallback, 1e-3 * h0) : std::pow(0.01 / d, 1.0 / (order + 1));
  return std::min({100.0 * h0, h1, span});
}

double Run::min_step() const {
  return 16.0 * std::numeric_limits<double>::epsilon() *
         std::max(std::abs(times.back()), std::abs(times.back() - times.front()));
}

HermiteOutput::HermiteOutput(Run& run, MidpointStep midpoint)
    : run_(run), midpoint_(std::move(midpoint)), plus_(run.n), minus_(run.n), x_(run.n) {
  for (Point* p : {&a_, &b_, &m_}) {
    p->y.resize(run.n);
    p->f.resize(run.n);
    p->g.resize(run.n);
  }
  nodes_.reserve(9);
  coefficients_.resize(9 * run.n);
}

void HermiteOutput::start(double t, const double* y) {
  a_.t = t;
  std::copy(y, y + run_.n, a_.y.begin());
  a_.evaluated = false;
}

namespace {
/// Counts the evaluations in between as the dense output's (Run::set_output_evaluations).
struct OutputEvaluations {
  explicit OutputEvaluations(Run& run) : run(run) { run.set_output_evaluations(true); }
  ~OutputEvaluations() { run.set_output_evaluations(false); }
  Run& run;
};
}  // namespace

void HermiteOutput::evaluate(Point& p) {
  // cbrt(eps): the central difference's truncation (~e^2) and round-off (~eps / e) balance.
  constexpr double kCbrtEps = 6.0554544523933395e-06;
  const std::size_t n = run_.n;
  p.evaluated = true;
  p.level = 0;
  if (!run_.rhs(p.t, p.y.data(), p.f.data())) return;
  p.level = 1;
  // The difference step in time: cbrt(eps) over the fastest relative rate of the state, at most
  // cbrt(eps) times the horizon. A function of the point alone, so that every output grid
  // interpolates with the same numbers.
  double rate = 0.0;
  for (std::size_t i = 0; i < n; ++i) rate = std::max(rate, std::abs(p.f[i]) / (1.0 + std::abs(p.y[i])));
  const double span = run_.times.back() - run_.times.front();
  const double e = kCbrtEps / std::max(rate, 1.0 / span);
  for (std::size_t i = 0; i < n; ++i) plus_[i] = p.y[i] + e * p.f[i];
  if (!run_.rhs(p.t + e, plus_.data(), p.g.data())) return;
  for (std::size_t i = 0; i < n; ++i) minus_[i] = p.y[i] - e * p.f[i];
  if (!run_.rhs(p.t - e, minus_.data(), plus_.data())) return;
  for (std::size_t i = 0; i < n; ++i) p.g[i] = (p.g[i] - plus_[i]) / (2.0 * e);
  p.level = 2;
}

void HermiteOutput::prepare() {
  const std::size_t n = run_.n;
  const double h = b_.t - a_.t;
  if (!a_.evaluated) evaluate(a_);  // else evaluated as the end of the previous step
  if (!b_.evaluated) evaluate(b_);
  bool have_midpoint = false;
  if (midpoint_ && a_.level >= 1) {
    m_.t = a_.t + 0.5 * h;
    have_midpoint = midpoint_(a_.t, a_.y.data(), a_.f.data(), 0.5 * h, m_.y.data()) &&
                    std::all_of(m_.y.begin(), m_.y.end(), [](double v) { return std::isfinite(v); });
    if (have_midpoint) evaluate(m_);
  }
  // The nodes in s = (t - t0) / h, each repeated 1 + level times (value, h f, h^2 g).
  struct Node {
    double s;
    const Point* p;
    int conditions;
  };
  Node points[3];
  int count = 0;
  points[count++] = {0.0, &a_, 1 + a_.level};
  if (have_midpoint) points[count++] = {0.5, &m_, 1 + m_.level};
  points[count++] = {1.0, &b_, 1 + b_.level};
  nodes_.clear();
  std::vector<const Point*> owner;
  std::vector<int> order;  // derivative order of each repeated node
  for (int j = 0; j < count; ++j) {
    for (int k = 0; k < points[j].conditions; ++k) {
      nodes_.push_back(points[j].s);
      owner.push_back(points[j].p);
      order.push_back(k);
    }
  }
  // Divided differences of each component on the confluent nodes: where the nodes of a
  // difference coincide it is the derivative over k! (y' = h f, y'' / 2 = h^2 g / 2 in s).
  const std::size_t m = nodes_.size();
  double table[9];
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t r = 0; r < m; ++r) table[r] = owner[r]->y[i];
    coefficients_[i * m] = table[0];
    for (std::size_t k = 1; k < m; ++k) {
      for (std::size_t r = m - 1; r >= k; --r) {
        if (nodes_[r] == nodes_[r - k]) {
          table[r] = k == 1 ? h * owner[r]->f[i] : 0.5 * h * h * owner[r]->g[i];
        } else {
          table[r] = (table[r] - table[r - 1]) / (nodes_[r] - nodes_[r - k]);
        }
      }
      coefficients_[i * m + k] = table[k];
    }
  }
}

void HermiteOutput::interpolate(double t, double* y) const {
  const std::size_t m = nodes_.size();
  const double s = (t - a_.t) / (b_.t - a_.t);
  for (std::size_t i = 0; i < run_.n; ++i) {
    const double* c = &coefficients_[i * m];
    double p = c[m - 1];
    for (std::size_t k = m - 1; k-- > 0;) p = p * (s - nodes_[k]) + c[k];
    y[i] = p;
  }
}

bool HermiteOutput::step(double t1, const double* y1) {
  b_.t = t1;
  std::copy(y1, y1 + run_.n, b_.y.begin());
  b_.evaluated = false;
  bool prepared = false;
  while (!run_.done() && run_.times[run_.next_output()] <= t1) {
    const std::size_t i = run_.next_output();
    if (run_.times[i] == t1) {
      if (!run_.emit(i, b_.y.data())) return false;
      continue;
    }
    if (!prepared) {
      const OutputEvaluations counted(run_);
      prepare();
      prepared = true;
    }
    interpolate(run_.times[i], x_.data());
    if (!run_.emit(i, x_.data())) return false;
  }
  std::swap(a_, b_);
  return true;
}

}  // namespace detail

}  // namespace lgvi::baselines
