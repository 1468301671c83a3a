// The observer side of a run: turns samples of a trajectory (in the paper's variables, whatever
// the method's internal state) into CSV rows and running diagnostics. Physics (energy, momentum
// maps) comes from the systems in lgvi/systems; nothing is re-derived here.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "experiments/csv_writer.hpp"
#include "experiments/scene.hpp"
#include "lgvi/types.hpp"

namespace lgvi::experiments {

/// The state at t_k in the paper's variables. x, v: the dumbbell's position and velocity, or
/// the cart's (x, y, 0) and (x', y', 0). R2, Omega2: the second of the connected bodies (R,
/// Omega are the first).
struct Sample {
  double t = 0.0;
  Mat3 R = Mat3::Identity();
  Vec3 Omega = Vec3::Zero();
  Vec3 x = Vec3::Zero();
  Vec3 v = Vec3::Zero();
  Mat3 R2 = Mat3::Identity();
  Vec3 Omega2 = Vec3::Zero();
  int newton_iterations = 0;  ///< of the step that produced this sample (0 at k = 0)
  /// | |q| - 1 | of a quaternion baseline's state (written only by a Recorder made with
  /// quaternion_column; see baselines/coordinates.hpp).
  double quaternion_norm_error = 0.0;
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

  /// Energy error normalized by |E0|, or absolute when E0 = 0 exactly.
  bool energy_error_is_relative() const { return energy0 != 0.0; }
  double max_energy_error() const;
};

/// Which momentum map a system conserves, as named in columns and summaries (the system's
/// binding, experiments/systems/).
struct MomentumMap {
  const char* description;     ///< e.g. "spatial angular momentum R J Omega"
  std::vector<std::string> columns;
};
MomentumMap momentum_map(const Model& model);

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
  /// finish(), so it must be the last).
  void record(std::size_t k, const Sample& sample);
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
  std::array<double, kMaxColumns> row_{};
  bool row_pending_ = false;
  std::size_t samples_ = 0;
  Sample last_;
  bool quaternion_column_ = false;
  double seconds_ = 0.0;
};

}  // namespace lgvi::experiments
