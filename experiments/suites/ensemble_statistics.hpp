// The statistics of an ensemble study (experiments/suites/ensemble.hpp), computed from the
// summary rows in the render phase: a merged sharded run (`merge`, then `study FILE
// --render-only`) gives the statistics of a single-process run of the same study.
//
// Per group (scene and horizon), method (its label: method, model, form) and setting (h or rtol)
// over the samples: median, 5/25/75/95% quantiles and maximum of each metric of the completed
// runs, the count of runs per status other than "completed", and the samples that did not
// complete. Written as NAME-statistics.csv and NAME-statistics.md with work-precision figures
// (the median curve per method with its 25-75% and 5-95% bands) and the cheapest method per
// accuracy level by median and by 95% quantile.
#pragma once

#include <string>
#include <vector>

#include "experiments/suites/suite.hpp"

namespace lgvi::experiments {

/// The quantile p in [0, 1] of `sorted` (ascending, not empty): definition 7 of Hyndman and
/// Fan, "Sample quantiles in statistical packages", The American Statistician 50 (1996): with
/// h = (n - 1) p, x[floor h] + (h - floor h) (x[floor h + 1] - x[floor h]) (0-based): linear
/// interpolation between the order statistics, the default of R and numpy.
double quantile(const std::vector<double>& sorted, double p);

/// The summary columns whose distributions are reported, in this order, each when some row has
/// a number in it: final_error, phase_shift, phase_drift_rate, shape_error,
/// max_energy_error_relative, max_momentum_drift_absolute, max_orthogonality_error,
/// max_quaternion_norm_error, evaluations, integrator_seconds, integrator_seconds_min.
const std::vector<std::string>& ensemble_metric_columns();

/// One metric of one method and setting over the samples.
struct EnsembleStatistic {
  std::string group;
  std::string label;   ///< the method's legend label (method, model, form)
  std::string method;
  std::string model;
  std::string h;       ///< the summary's text ("" for an adaptive method)
  std::string rtol;    ///< the summary's text ("" for a fixed-step method)
  std::string metric;  ///< the summary column
  std::size_t samples = 0;    ///< rows (samples) of this method and setting
  std::size_t completed = 0;  ///< of them, status "completed"
  std::size_t count = 0;      ///< of those, with a finite value of the metric: the statistics' sample
  double median = 0.0, q05 = 0.0, q25 = 0.0, q75 = 0.0, q95 = 0.0, max = 0.0;  ///< NaN when count = 0
  std::string failures;         ///< "status: count" per status other than completed, "; "-separated
  std::string failing_samples;  ///< the sample numbers not completed, space-separated
};

/// The columns of NAME-statistics.csv, in order.
const std::vector<std::string>& ensemble_statistics_columns();

/// The statistics of `rows` (a study's summary rows), blocks in the rows' first-appearance order
/// of (group, label, setting), metrics in ensemble_metric_columns' order.
std::vector<EnsembleStatistic> ensemble_statistics(const std::vector<SummaryRow>& rows);

/// NAME-statistics.csv's text: `# key: value` lines (quantile definition), the header
/// (ensemble_statistics_columns), one line per statistic; numbers %.17g, NaN as empty.
std::string ensemble_statistics_csv(const std::vector<EnsembleStatistic>& stats);

/// The renderer of an ensemble study: NAME-statistics.csv and .md, per group and error metric
/// (`metrics`: final-error, energy, momentum, orthogonality) the banded work-precision figures
/// SCENE-METRIC-bands-evaluations (and -time with the metric "time"), and the cheapest-method
/// tables by median and by 95% quantile in NAME-statistics.md.
SuiteRenderer ensemble_renderer(std::string name, std::vector<std::string> metrics);

}  // namespace lgvi::experiments
