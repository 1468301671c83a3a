// Solver adapters behind one interface: a method name, a model (an Ode), settings (a fixed step h
// or tolerances rtol/atol) -> the state at requested times and the project's Stats.
//
// Methods (see solver_list() for one-line descriptions):
//   cvode-adams, cvode-bdf     SUNDIALS CVODE, variable order; Newton iteration with a dense
//                              direct linear solver and the model's Jacobian (or CVODE's
//                              difference quotient); output from CVODE's interpolant (CVodeGetDky)
//   cvode-bdf-projected        cvode-bdf with a projection after every step (CVODE's projection
//                              interface, CVodeSetProjFn; Hindmarsh et al., SUNDIALS CVODE user
//                              guide, "Projection"; Hairer, Lubich, Wanner, Geometric Numerical
//                              Integration, sec. IV.4) onto the chart's constraints (|q| = 1 per
//                              quaternion, R^T R = I per matrix body; none for Euler angles) and the
//                              system's first integrals: free body E and the Casimir |Pi|, 3D
//                              pendulum (and Lagrange top) E and e3.(R J Omega), dumbbell E; the
//                              energy and Casimir only without control (a controlled pendulum
//                              keeps e3.(R J Omega)); the cart-pendulum, the connected bodies and a
//                              scene with an extra moment (PD feedback, gravity gradient) have no
//                              invariant here and are refused (InvalidInput "model": the chart's
//                              constraints alone are the renormalized model). Orthogonal in the model's Euclidean state, by
//                              simplified Newton to 1e-14 relative, the error estimate projected
//                              onto the tangent space; the output times' interpolated states are
//                              projected too. Models: quaternion, euler, matrix; the
//                              quaternion-renormalized model is refused (InvalidInput "model": the
//                              projection keeps |q| = 1 itself). baselines/projection.hpp
//   odeint-rk4                 Boost.Odeint classic Runge-Kutta 4, fixed step
//   odeint-dopri5              Dormand-Prince 5(4), error control and dense output
//   odeint-rkf78               Runge-Kutta-Fehlberg 7(8), error control; no dense output in
//                              odeint: output from a quintic Hermite interpolant (below)
//   odeint-bs                  Bulirsch-Stoer (dense-output variant)
//   gsl-rk8pd                  GSL odeiv2 Prince-Dormand 8(9), error control; Hermite output
//   gsl-rk4imp                 GSL odeiv2 implicit Gauss-Legendre (2 stages, order 4,
//                              symplectic), fixed step; modified Newton with the model's Jacobian
//   gsl-msbdf                  GSL odeiv2 variable-order BDF (Nordsieck), error control; Hermite
//                              output
//   arkode-erk                 SUNDIALS ARKODE ERKStep, Verner's 8-stage 6(5) pair, error control;
//                              output from ARKODE's Hermite interpolant (ERKStepGetDky, degree 5)
//   arkode-dirk                SUNDIALS ARKODE ARKStep implicit only, the ESDIRK 5(4) of Kennedy and
//                              Carpenter's ARK5(4)8L[2]SA; Newton with a dense direct linear solver
//                              and the model's Jacobian; output as arkode-erk (ARKStepGetDky)
//                              (arkode_solver.cpp: the tables and why)
//
// Output times do not change the run. The adaptive methods step freely over the whole horizon
// (times.front() to times.back(); only the last step is shortened to end there), from a first
// step that does not depend on the output times (CVODE's own estimate towards the end of the
// horizon, ARKODE's likewise; the others' by Run::initial_step), and the output times are
// interpolated: CVODE's Nordsieck polynomial, ARKODE's Hermite interpolant of the last step (y, f
// at its ends and f inside it, evaluated per output time: output_rhs_evaluations),
// odeint's dense output (dopri5, Bulirsch-Stoer), and for the methods
// without one (rkf78, rk8pd, msbdf) the quintic Hermite interpolant of each accepted step from y,
// f and y'' at its ends (order 6 locally; 3 extra RHS evaluations per interpolated step end,
// counted in rhs_evaluations and output_rhs_evaluations; solver_detail.hpp). The same steps
// are taken whatever the output grid, so a time that two grids share gets the same sample from
// both. Fixed-step methods take their grid of h, of which the output times are a subset.
//
// Error control: every adaptive method keeps the local error of component i below
// atol + rtol |y_i| (CVODE: in a weighted RMS norm; odeint, GSL: componentwise, odeint adds the
// rtol dt |y_i'| term of its default checker). Global errors are a modest multiple of rtol on
// these rigid-body models (tests/baselines measure it).
//
// Renormalization (the quaternion-renormalized model) needs a post-step hook:
//   cvode-bdf             CVODE's projection interface (CVodeSetProjFn): q <- q/|q| after each
//                         step, the error estimate projected on the tangent space; no restart
//   odeint-rk4, gsl-rk4imp  after each fixed step, free
//   odeint-rkf78, gsl-rk8pd  stepping in a loop, normalizing between accepted steps; they keep
//                         no history, so it costs nothing extra (the Hermite output interpolates
//                         between the normalized step ends)
//   odeint-dopri5         same loop; the stepper must be re-initialized with the normalized state,
//                         which discards its first-same-as-last derivative: +1 RHS per step
//                         (measured +15% RHS evaluations, same steps)
//   odeint-bs             same loop; re-initializing resets the extrapolation's "first step" flag
//                         and costs one derivative: measured +1-2% RHS evaluations, same steps
//   (cvode-bdf's projection: +0-3% steps; rkf78, rk8pd: no cost; baselines/README.md)
//   cvode-adams, gsl-msbdf  rejected: modifying the state between steps would restart their
//                         multistep history at order 1 on every step (CVODE offers projection for
//                         BDF only)
//   arkode-erk, arkode-dirk  rejected: ARKODE 5.4 has no projection, only a post-processing
//                         function applied after the error test, unseen by the error estimate and
//                         the step-size control, between the states its interpolant is built from
//
// Gimbal lock (Euler model): the event function is acos(sqrt(eps)) - |pitch| (see
// baselines/coordinates.hpp); CVODE and ARKODE watch it with their root finders (direction:
// decreasing);
// odeint's dense-output steppers locate a sign change on their own dense output; the other
// solvers evaluate it after every step and, on a sign change, find the root on the cubic Hermite
// interpolant of the step (exact for states cubic in t, O(h^4) otherwise; the quadratic through
// y0, f(y0), y1 when f cannot be evaluated at the singular end, as for the Euler model), from
// which the output times before the root in that step are read too. A right-hand side evaluated
// on the singular set (a stage that lands there) stops the run too, at that time. Either way:
// status CoordinateSingularity, failed_time the time, failure_detail the angle.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "baselines/ode.hpp"
#include "baselines/tolerance.hpp"
#include "lgvi/integrate.hpp"

namespace lgvi::baselines {

enum class StepControl { Fixed, Adaptive };

/// How a solver delivers the output times between its steps (see the top of this file).
enum class OutputInterpolation {
  FixedGrid,    ///< fixed step: the output times are steps
  Cvode,        ///< CVODE's interpolating (Nordsieck) polynomial, CVodeGetDky
  DenseOutput,  ///< the stepper's own dense output (odeint dopri5, Bulirsch-Stoer)
  Hermite,      ///< the quintic Hermite interpolant of the accepted steps (solver_detail.hpp)
  Arkode,       ///< ARKODE's Hermite interpolation module (degree 5), ERKStepGetDky / ARKStepGetDky
};

namespace detail {
class Run;  // solver_detail.hpp
}

/// A solver's adapter: runs its library's integrator on `run` from y (solver_detail.hpp).
using SolverAdapter = Stats (*)(detail::Run& run, std::vector<double>& y);

struct SolverInfo {
  std::string name;
  StepControl step_control;
  bool post_step_hook;  ///< can renormalize after every step without restarting a history
  std::string description;
  int order = 0;        ///< nominal order of the fixed-step methods; 0: variable or error-controlled
  int stages = 0;       ///< RHS stages per step of the fixed-step methods; 0: varies
  bool uses_jacobian = false;  ///< Newton iterations on the model's Jacobian (implicit methods)
  OutputInterpolation output = OutputInterpolation::Hermite;
  SolverAdapter adapter = nullptr;  ///< the solver itself: integrate() calls it, no name is compared
  /// Offers its library's difference-quotient Jacobian (JacobianSource::DifferenceQuotient: CVODE).
  bool difference_quotient_jacobian = false;
  /// An adaptive method that can also step at a fixed h without error control
  /// (SolverSettings::fixed_step_probe: ARKODE), so that its tables' orders can be measured.
  bool offers_fixed_step_probe = false;
  /// Projects every step onto the model's manifold of constraints and invariants
  /// (Ode::project: cvode-bdf-projected); integrate() refuses a model without one.
  bool projects_onto_invariants = false;
};

/// Every baseline method, in the order of the list above.
const std::vector<SolverInfo>& solver_list();
std::vector<std::string> solver_names();
/// Throws InvalidInput("method", ...) for an unknown name (listing the known ones).
const SolverInfo& solver_info(const std::string& name);

enum class JacobianSource {
  Analytic,            ///< the model's Jacobian (baselines/model.hpp)
  DifferenceQuotient,  ///< CVODE's internal difference quotient (CVODE only)
};


struct SolverSettings {
  std::optional<double> h;     ///< fixed-step methods: the step (required; forbidden otherwise)
  std::optional<double> rtol;  ///< adaptive methods (default kDefaultRtol; forbidden for fixed)
  std::optional<double> atol;  ///< adaptive methods (default rtol)
  std::size_t max_steps = 50'000'000;  ///< step budget over the whole run (CVODE: its mxstep)
  JacobianSource jacobian = JacobianSource::Analytic;
  /// gsl-rk4imp: error level of its modified Newton iteration, |dY_i| < tol (1 + |y_i|). GSL
  /// allows 7 iterations and fails on any non-contracting one, so it cannot be round-off.
  double newton_tolerance = 1e-12;
  /// First step of the adaptive methods that need one (odeint, GSL); CVODE estimates its own.
  /// 0: estimated from the initial state and the tolerances, whatever the output times
  /// (detail::Run::initial_step: Hairer-Norsett-Wanner's starting step, 2 RHS evaluations).
  double initial_step = 0.0;
  /// odeint-rkf78, gsl-rk8pd: their Hermite dense output uses a midpoint step (degree 8, order 9
  /// locally; ~18 RHS evaluations per interpolated step) or, if false, none (quintic, order 6;
  /// ~6 RHS). Without it, the steps these methods take at loose tolerances are too long for the
  /// quintic: see solver_detail.hpp. The run (steps, step-end states) is the same either way.
  bool hermite_midpoint = true;
  /// Adaptive methods that offer it (SolverInfo::offers_fixed_step_probe: ARKODE) step at this
  /// fixed h with the error control off (ERKStepSetFixedStep / ARKStepSetFixedStep), to measure
  /// the order of their tables; rtol and atol still set the implicit solve's tolerance. Each
  /// output interval must be a whole number of steps, as for the fixed-step methods.
  std::optional<double> fixed_step_probe;
  /// Fixed-step methods: the last output interval may be one step shorter than h (a horizon that
  /// is not a whole number of steps); every other interval stays a whole number of steps of h.
  bool shorter_last_step = false;
};

/// The settings with defaults filled in, checked against the method and the model. Throws
/// InvalidInput naming the option: "h" (fixed-step method without a positive finite h, or an
/// adaptive method given one), "rtol"/"atol" (given to a fixed-step method, or outside
/// kToleranceRange: check_tolerance),
/// "model" (a renormalized model with a method without a post-step hook, or with
/// cvode-bdf-projected, which projects the plain quaternion model itself), "jacobian"
/// (difference quotient requested from a non-CVODE method).
SolverSettings resolve_settings(const SolverInfo& info, const SolverSettings& settings, const Ode& ode);

/// Receives the state at times[index]; returning false stops the run (ObserverStopped).
using SampleObserver = std::function<bool(std::size_t index, double t, const double* y)>;

/// Integrates `ode` from y0 at times[0], calling observer(i, times[i], y(times[i])) for i = 0,
/// 1, ... (times strictly increasing and finite; fixed-step methods need every interval to be a
/// whole number of steps h, to 1e-9 relative) until times.back() or the first failure. The
/// steps depend on times.front() and times.back() only; the other times are interpolated (see
/// the top of this file). Stats: steps the accepted steps, rejected_steps the rejected ones
/// (where the library reports them: not odeint-bs), rhs_evaluations every call, of which
/// output_rhs_evaluations were spent on interpolating output times. Statuses:
///   SolverFailed           a solver flag (named, with the solver's message and the time reached)
///                          or a non-finite state or right-hand side;
///   CoordinateSingularity  the model's singular set (the time and the angle).
/// Samples are delivered only for times before the failure. Never prints (CVODE's, ARKODE's and GSL's
/// error handlers are redirected into the status). Throws InvalidInput for bad settings (see
/// resolve_settings), bad times/initial state, or ("model") a model without the manifold
/// projection a projecting method needs (Ode::projection_refusal).
Stats integrate(const std::string& method, const Ode& ode, std::span<const double> y0, std::span<const double> times,
                const SolverSettings& settings, const SampleObserver& observer);

}  // namespace lgvi::baselines
