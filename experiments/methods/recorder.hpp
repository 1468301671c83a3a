// The observer side of a run: turns samples of a trajectory (in the paper's variables, whatever
// the method's internal state) into CSV rows and running diagnostics. Physics (energy, momentum
// maps) comes from the systems in lgvi/systems; nothing is re-derived here.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "experiments/output/csv_writer.hpp"
#include "experiments/scene/scene.hpp"
#include "lgvi/integrate.hpp"
#include "lgvi/types.hpp"

namespace lgvi::experiments {

/// The least-squares line e(t) = a + b t through the recorded energy errors e = E - E0,
/// accumulated in one pass with centred (Welford) updates, so that no sum of t^2 ~ 1e8 cancels
/// against its mean. It separates a secular drift (a non-symplectic method: e grows like t)
/// from a bounded oscillation (a symplectic one) by numbers rather than by eye:
///  - slope b and its standard error sqrt(RSS / ((n - 2) C_tt)) (the white-residual formula;
///    the residuals of an oscillation are correlated, so read it as a lower bound);
///  - the oscillation about the line, residual_rms = sqrt(RSS / n), resolved down to ~sqrt(eps)
///    of the spread of e (RSS = C_ee - C_te^2 / C_tt is a difference): far below any verdict;
///  - drifts(): the secular change |b| (t_n - t_1) exceeds 5 residual_rms and the round-off
///    floor. The 5: an oscillation e = A sin(w t + phi) fitted over n >= 1 whole periods T gives
///    b = -12 A cos(phi) / (w T^2), i.e. |b| T = 1.91 A |cos(phi)| / n, and leaves the residual
///    rms sqrt(A^2 / 2 - (b T)^2 / 12) >= 0.44 A, so |b| T / rms <= 4.3 (n = 1), 1.5 (n = 2):
///    a bounded oscillation is never called a drift; a drift c t is called one once c T exceeds
///    ~3.5 amplitudes of the oscillation riding on it. The floor, 10 eps sqrt(k) |E|max (k the
///    last step), is the random walk of the energy's round-off over k steps (Brouwer's law): a
///    symplectic method at a small step wanders by that much and is bounded.
struct EnergyTrend {
  std::size_t n = 0;
  double mean_t = 0.0, mean_e = 0.0;
  double c_tt = 0.0, c_te = 0.0, c_ee = 0.0;  ///< centred sums of products
  double t_first = 0.0, t_last = 0.0;
  std::size_t last_step = 0;
  double max_abs_energy = 0.0;  ///< max |E| over the samples (scale of the round-off floor)

  void add(std::size_t k, double t, double energy, double energy_error);
  /// b (energy unit per time unit); 0 with fewer than 2 samples.
  double slope() const;
  /// Standard error of b (white residuals); NaN with fewer than 3 samples.
  double slope_standard_error() const;
  /// sqrt(RSS / n), the oscillation about the line (energy unit); 0 with fewer than 2 samples.
  double residual_rms() const;
  /// |b| (t_last - t_first).
  double secular_change() const;
  /// 10 eps sqrt(last_step) max |E|.
  double round_off_floor() const;
  bool drifts() const { return n >= 3 && secular_change() > 5.0 * residual_rms() && secular_change() > round_off_floor(); }
};

/// Worst deviations over the recorded samples. The methods hand the recorder only the steps whose
/// rows are written (k = 0, output_every, 2 output_every, ..., and the last step), so these are
/// maxima over the CSV's rows: a coarse output_every can miss a peak between rows.
struct Diagnostics {
  double energy0 = 0.0;
  double max_abs_energy_error = 0.0;     ///< max |E - E0|
  double max_orthogonality_error = 0.0;  ///< max ||R^T R - I||_F
  double max_determinant_error = 0.0;    ///< max |det R - 1|
  double momentum0_norm = 0.0;           ///< |momentum map at t = 0|
  double max_momentum_error = 0.0;       ///< max |m - m0| (Euclidean norm)
  bool quaternion_norm_recorded = false;    ///< a quaternion baseline: the next field is meaningful
  double max_quaternion_norm_error = 0.0;   ///< max | |q| - 1 |
  EnergyTrend energy_trend;                 ///< the line through E - E0 over the samples

  /// Energy error normalized by |E0|, or absolute when E0 = 0 exactly.
  bool energy_error_is_relative() const { return energy0 != 0.0; }
  double max_energy_error() const;
};

class Recorder {
 public:
  /// `csv` may be null (diagnostics only). Rows are written for k % output_every == 0 and for
  /// the last recorded sample (see finish()); the methods call record() for those steps only.
  /// quaternion_column adds the column quaternion_norm_error (after determinant_error), for
  /// the quaternion baselines.
  Recorder(const Model& model, std::size_t output_every, CsvWriter* csv, bool quaternion_column = false);

  /// The CSV columns for a model: t, R11..R33, Omega1..3, [x1..3, v1..3], energy,
  /// energy_error, orthogonality_error, determinant_error, <momentum columns>,
  /// momentum_error, newton_iterations.
  static std::vector<std::string> columns(const Model& model, bool quaternion_column = false);

  /// Records the sample of step k: k = 0, output_every, 2 output_every, ... and the last step
  /// (every method passes only those; a k that is not a multiple of output_every is held until
  /// finish(), so it must be the last). False when a value of the row (a state entry, the
  /// energy, the momentum map, an error) is not finite: nothing of the sample is kept or
  /// written, and the method stops the run (its observer returns false, then
  /// stop_on_non_finite names the step, time and quantity).
  bool record(std::size_t k, const Sample& sample);
  /// With `on`, record() also refuses every sample once a SIGINT/SIGTERM was received
  /// (interrupt_signal(), interrupt.hpp), so the method stops at its next row; interrupted() is
  /// then true.
  void stop_on_interrupt(bool on) { stop_on_interrupt_ = on; }
  bool interrupted() const { return interrupted_; }
  /// When record() refused a sample: `stats` becomes NonFiniteState at that sample's step and
  /// time, failure_detail naming the column ("energy is not finite ..."). Otherwise unchanged.
  void stop_on_non_finite(Stats& stats) const;
  /// Writes the last recorded sample if its k was not a multiple of output_every, so a CSV
  /// always ends at the last step computed (t_final, or the last good step of a failed run).
  void finish();

  const Diagnostics& diagnostics() const { return diagnostics_; }
  std::size_t samples() const { return samples_; }
  /// The last recorded sample (the final state of the run, or its last good step).
  const Sample& last() const { return last_; }
  /// Time spent in record() (diagnostics and CSV formatting), to separate it from the
  /// integrator's own cost (two clock reads per recorded sample, i.e. per row).
  double seconds() const { return seconds_; }

 private:
  static constexpr std::size_t kMaxColumns = 40;
  const Model& model_;
  std::size_t output_every_;
  CsvWriter* csv_;
  std::size_t columns_;
  Diagnostics diagnostics_;
  Vec3 momentum0_ = Vec3::Zero();
  std::vector<std::string> column_names_;
  std::size_t state_columns_ = 0;  ///< t and the state's columns, the first of the row
  std::array<double, kMaxColumns> row_{};
  /// The sample record() refused (a non-finite value): its step, time and column.
  std::size_t non_finite_step_ = 0;
  double non_finite_time_ = 0.0;
  const std::string* non_finite_column_ = nullptr;
  bool row_pending_ = false;
  std::size_t samples_ = 0;
  Sample last_;
  bool quaternion_column_ = false;
  bool stop_on_interrupt_ = false;
  bool interrupted_ = false;
  double seconds_ = 0.0;
};

}  // namespace lgvi::experiments
