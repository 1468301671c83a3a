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

#include "experiments/csv_writer.hpp"
#include "experiments/scene.hpp"
#include "lgvi/integrate.hpp"
#include "lgvi/types.hpp"

namespace lgvi::experiments {

/// The state record of every system of Model, in Model's order: alternative i is
/// std::variant_alternative_t<i, Model>::State (a free body and a pendulum share one type, so
/// alternatives are addressed by index: state_of<M>).
template <class V>
struct StatesOfModels;
template <class... Ms>
struct StatesOfModels<std::variant<Ms...>> {
  using type = std::variant<typename Ms::State...>;
};
using SystemState = StatesOfModels<Model>::type;

/// The index of scene model M in Model.
template <class M, class V = Model>
struct ModelIndex;
template <class M, class... Ms>
struct ModelIndex<M, std::variant<Ms...>> {
  static constexpr std::size_t value = [] {
    constexpr bool same[] = {std::is_same_v<M, Ms>...};
    std::size_t i = 0;
    while (!same[i]) ++i;
    return i;
  }();
};

/// The state at t_k in the paper's variables: the record of the scene's system only (its model's
/// State: R, Omega; the dumbbell's x, v; the cart's q, q_dot; the two bodies' R1, R2, Omega1,
/// Omega2), so a scene records only what it models.
struct Sample {
  double t = 0.0;
  SystemState state;
  int newton_iterations = 0;  ///< of the step that produced this sample (0 at k = 0)
  /// | |q| - 1 | of a quaternion baseline's state (written only by a Recorder made with
  /// quaternion_column; see baselines/coordinates.hpp).
  double quaternion_norm_error = 0.0;
};

/// The state of model M's system in sample s. Precondition: s is a sample of an M scene (made by
/// sample_of(model) or sample_of<M>()); otherwise std::bad_variant_access.
template <class M>
typename M::State& state_of(Sample& s) {
  return std::get<ModelIndex<M>::value>(s.state);
}
template <class M>
const typename M::State& state_of(const Sample& s) {
  return std::get<ModelIndex<M>::value>(s.state);
}
/// A sample of model M's system at t = 0 in the record's default state (identity, zero).
template <class M>
Sample sample_of() {
  Sample s;
  s.state.template emplace<ModelIndex<M>::value>();
  return s;
}
/// A sample of `model`'s system at t = 0 in the model's initial state.
Sample sample_of(const Model& model);

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

/// Distance of two samples of `model`'s system over every part of its state: the sum of the
/// attitudes' Frobenius and the vectors' 2-norms (SystemBinding::distance). Precondition: both
/// are samples of that system.
double state_distance(const Model& model, const Sample& a, const Sample& b);

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
  double seconds_ = 0.0;
};

}  // namespace lgvi::experiments
