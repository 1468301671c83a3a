#include "experiments/suites/summary_metadata.hpp"

#include <algorithm>
#include <utility>

#include "experiments/methods/simulate.hpp"

namespace lgvi::experiments {

namespace {

/// Columns whose unit or normalization the name alone does not say (the suites' columns; the
/// harness's own and the labels are evident).
const std::vector<std::pair<std::string, std::string>>& column_notes() {
  static const std::vector<std::pair<std::string, std::string>> notes = {
      {"h", "time step (time unit)"},
      {"t_final", "horizon (time unit)"},
      {"T", "horizon of the transition matrix (time unit)"},
      {"rtol", "relative tolerance of an adaptive solver (dimensionless)"},
      {"h_omega", "h |Omega0|, rotation per step (rad)"},
      {"max_energy_error_relative",
       "max |E - E0| / |E0| over the written rows (relative, dimensionless; empty when E0 = 0)"},
      {"max_energy_error_absolute", "max |E - E0| over the written rows (absolute, energy unit)"},
      {"energy_drift_rate",
       "slope b of the least-squares line through E - E0 over the written rows, divided by |E0| (relative per time "
       "unit; absolute when E0 = 0)"},
      {"energy_drift_rate_stderr", "standard error of energy_drift_rate (white residuals: a lower bound when they "
                                   "oscillate; same unit)"},
      {"energy_oscillation_rms", "rms of E - E0 about that line, divided by |E0| (relative; absolute when E0 = 0)"},
      {"energy_trend",
       "drifts when |b| T > 5 energy_oscillation_rms and above the round-off floor 10 eps sqrt(steps) |E|, else "
       "bounded (experiments/methods/recorder.hpp, EnergyTrend)"},
      {"max_momentum_drift_absolute",
       "max |m - m0| of the momentum map (column momentum_map of summary.jsonl) over the written rows (absolute, "
       "momentum unit)"},
      {"max_orthogonality_error", "max ||R^T R - I||_F over the written rows (absolute, dimensionless)"},
      {"max_quaternion_norm_error", "max | |q| - 1 | of a quaternion model over the written rows (absolute, dimensionless)"},
      {"final_error",
       "distance of the final state from the reference (column reference): the largest of ||R - R_ref||_F and the "
       "relative errors |Omega - Omega_ref| / |Omega_ref| (and x, v) (dimensionless)"},
      {"phase_shift",
       "time shift tau that best aligns the final state with the exact trajectory, x(T + tau) nearest x_h(T) "
       "(time unit; exact references only)"},
      {"phase_drift_rate", "phase_shift / T (dimensionless)"},
      {"shape_error", "final_error after the shift: the distance of x_h(T) from x(T + tau) (dimensionless)"},
      {"integrator_seconds", "wall time of the integration, recording excluded, sharing the machine (s)"},
      {"integrator_seconds_min", "minimum wall time per run, timed alone and repeated (s)"},
      {"integrator_seconds_median", "median wall time per run, timed alone and repeated (s)"},
      {"integrator_cpu_seconds", "minimum thread CPU time per run (s)"},
      {"rss_before_mb", "resident memory of the process before the timed run (MiB, /proc/self/status VmRSS)"},
      {"peak_rss_mb", "peak resident memory of the process during the timed run (MiB, VmHWM reset before it)"},
      {"rss_growth_mb", "peak_rss_mb - rss_before_mb: the memory the run needed (MiB; flat in the steps when a step "
                        "allocates nothing)"},
      {"case_seconds", "wall time of the whole case, files included (s)"},
      {"seconds", "wall time of computing the transition matrix (s)"},
      {"wall_seconds", "wall time of the solver (s)"},
      {"phi_norm", "|Phi|_2 of the reference transition matrix (tangent coordinates in rad and rad/s)"},
      {"fd_step", "central-difference step a (rad; rad/s scaled by max(1, |Omega0|))"},
      {"fd_estimate", "estimated error of the differences, |Phi_2a - Phi_a|_F / |Phi_a|_F (relative)"},
      {"fd_tolerance", "bound fd_error must meet (relative)"},
      {"fd_error", "|Phi - Phi_fd|_F / |Phi_fd|_F (relative)"},
      {"continuous_difference", "|Phi - Phi_ref|_F / |Phi_ref|_F against the CVODES reference (relative)"},
      {"cost", "optimal cost, sum of the weighted squared controls times the step (control unit^2 time unit)"},
      {"violation",
       "terminal violation: 2-norm of the terminal errors, attitude log(R_f^T R_N)^vee (rad), angular velocity "
       "(rad/s) and position, velocity where the system has them (absolute)"},
      {"tolerance", "bound on violation (absolute)"},
      {"cond_min", "smallest condition number of the matrix inverted per iteration (dimensionless)"},
      {"cond_max", "largest condition number of the matrix inverted per iteration (dimensionless)"},
      {"cond_full_min", "smallest condition number of the full sensitivity (dimensionless)"},
      {"cond_full_max", "largest condition number of the full sensitivity (dimensionless)"},
  };
  return notes;
}

}  // namespace

Fields summary_metadata(const Suite& suite, const std::vector<std::string>& columns, bool quick) {
  Fields f = {
      {"suite", suite.name},
      {"form", std::string(quick ? "quick" : "full")},
      {"version", std::string(version())},
      {"git_describe", std::string(git_describe())},
      {"units", "per row's system: SI for free-body, pendulum, cart-pendulum, connected-bodies (" +
                    system_units("cart-pendulum") + "); for dumbbell the " + system_units("dumbbell")},
      {"errors", std::string("a column ending in _relative is normalized by the initial value's magnitude, one "
                             "ending in _absolute is in the quantity's unit; the others are described below")},
  };
  for (const auto& [column, note] : column_notes()) {
    if (std::find(columns.begin(), columns.end(), column) != columns.end()) f.push_back({"columns." + column, note});
  }
  return f;
}

}  // namespace lgvi::experiments
