#include "experiments/methods/simulate.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <system_error>

#include "experiments/output/csv_writer.hpp"
#include "experiments/output/interrupt.hpp"

namespace lgvi::experiments {

namespace {

std::int64_t as_int(std::size_t n) { return static_cast<std::int64_t>(n); }

/// A file inside the source tree as a path relative to it ("experiments/scenes/pendulum.toml"),
/// so that committed results carry no machine-specific paths; other files as given.
std::string source_relative(const std::filesystem::path& file) {
  std::error_code ec1, ec2;
  const auto abs = std::filesystem::weakly_canonical(file, ec1);
  const auto src = std::filesystem::weakly_canonical(LGVI_SOURCE_DIR, ec2);
  if (ec1 || ec2) return file.string();
  const auto rel = abs.lexically_relative(src);
  if (rel.empty() || *rel.begin() == "..") return file.string();
  return rel.string();
}

/// Fewest bytes a CSV value takes with its separator: a finite double in shortest round-trip form
/// with more than one significant digit ("0.25,", "1e-05,") takes at least 5, and the values the
/// recorder writes (times, attitudes, rates, errors) have 16-17 digits unless they are exactly
/// representable short numbers; 5 makes the estimate below a lower bound of the file's size.
constexpr double kMinBytesPerValue = 5.0;

/// Refuses, before anything is written, a run whose CSV cannot fit in its file system: the rows
/// (steps / output_every + 2) times the columns times kMinBytesPerValue exceed the space free
/// where the file goes. Without it a 10^12-step scene written every step filled a disk (77 GB)
/// before the short write stopped it. Streams ("-", devices) are not checked. Throws OutputError.
void check_output_space(const std::filesystem::path& csv, const Horizon& horizon, std::size_t columns) {
  std::error_code ec;
  if (csv == "-") return;
  const auto status = std::filesystem::status(csv, ec);
  if (!ec && std::filesystem::exists(status) && !std::filesystem::is_regular_file(status)) return;
  const std::filesystem::path dir = csv.has_parent_path() ? csv.parent_path() : std::filesystem::path(".");
  const std::filesystem::space_info space = std::filesystem::space(dir, ec);
  if (ec) return;  // the writer reports a missing or unwritable directory itself
  const double rows = std::floor(static_cast<double>(horizon.steps) / static_cast<double>(horizon.output_every)) + 2.0;
  const double bytes = rows * static_cast<double>(columns) * kMinBytesPerValue;
  if (bytes <= static_cast<double>(space.available)) return;
  char text[256];
  std::snprintf(text, sizeof text,
                "not enough space: the run writes %.3g rows of %zu values (at least %.3g bytes) and %.3g bytes are "
                "free there; write every K-th step (integration.output_every, --every)",
                rows, columns, bytes, static_cast<double>(space.available));
  throw OutputError(csv.string() + ": " + text);
}

}  // namespace

Fields RunSummary::to_fields() const {
  const Diagnostics& d = diagnostics;
  const double energy_scale = d.energy_error_is_relative() ? std::abs(d.energy0) : 1.0;
  Fields f = {{"scene", scene}, {"system", system}, {"method", method}, {"version", std::string(version())}};
  f.insert(f.end(), method_settings.begin(), method_settings.end());
  const Fields rest = {
      {"h", horizon.h},
      {"solver_steps", as_int(stats.steps)},
      {"rejected_steps", as_int(stats.rejected_steps)},
      {"grid_steps", as_int(horizon.steps)},
      {"t_final", horizon.t_final},
      {"output_every", as_int(horizon.output_every)},
      {"output_rows", as_int(output_rows)},
      {"status", std::string(to_string(stats.status))},
      {"status_detail", stats.brief()},
      {"wall_seconds", stats.wall_seconds},
      {"recording_seconds", recording_seconds},
      {"newton_iterations", as_int(stats.newton_iterations)},
      {"max_newton_iterations", std::int64_t{stats.max_newton_iterations}},
      {"fallbacks", as_int(stats.fallbacks)},
      {"potential_evaluations", as_int(stats.potential_evaluations)},
      {"max_rotation_residual", stats.max_rotation_residual},
      {"rhs_evaluations", as_int(stats.rhs_evaluations)},
      {"output_rhs_evaluations", as_int(stats.output_rhs_evaluations)},
      {"jacobian_evaluations", as_int(stats.jacobian_evaluations)},
      {"nonlinear_iterations", as_int(stats.nonlinear_iterations)},
      {"diagnostics_over", std::string("the output_rows written samples (k = 0, output_every, ..., last step)")},
      {"energy0", d.energy0},
      {"max_energy_error", d.max_energy_error()},
      {"energy_error_normalization",
       std::string(d.energy_error_is_relative() ? "relative to |E0|" : "absolute (E0 = 0)")},
      {"max_abs_energy_error", d.max_abs_energy_error},
      // The same two numbers named by what they are (max_energy_error above is relative unless
      // E0 = 0); the relative one is null when E0 = 0.
      {"max_energy_error_relative",
       d.energy_error_is_relative() ? d.max_energy_error() : std::numeric_limits<double>::quiet_NaN()},
      {"max_energy_error_absolute", d.max_abs_energy_error},
      // The line through E - E0 (Diagnostics::energy_trend), normalized like max_energy_error.
      {"energy_drift_rate", d.energy_trend.slope() / energy_scale},
      {"energy_drift_rate_stderr", d.energy_trend.slope_standard_error() / energy_scale},
      {"energy_oscillation_rms", d.energy_trend.residual_rms() / energy_scale},
      {"energy_secular_change", d.energy_trend.secular_change() / energy_scale},
      {"energy_trend", std::string(d.energy_trend.drifts() ? "drifts" : "bounded")},
      {"max_orthogonality_error", d.max_orthogonality_error},
      {"max_determinant_error", d.max_determinant_error},
      {"momentum_map", momentum_map},
      {"momentum0_norm", d.momentum0_norm},
      {"max_momentum_drift", d.max_momentum_error},  // absolute: |m - m0|, momentum units
      {"max_momentum_drift_absolute", d.max_momentum_error},
      {"units", system_units(system)},
      {"csv", csv.filename().string()},
  };
  f.insert(f.end(), rest.begin(), rest.end());
  if (horizon.shorter_last_step) f.push_back({"last_step", horizon.last_step()});
  if (d.quaternion_norm_recorded) f.push_back({"max_quaternion_norm_error", d.max_quaternion_norm_error});
  return f;
}

RunSummary simulate(const Scene& scene, const Method& method, const SimulateOptions& options) {
  RunSummary s;
  s.scene = scene.name;
  s.system = scene.system();
  s.method = method.name();
  s.method_settings = method.settings(scene);
  s.horizon = scene.horizon;
  s.momentum_map = momentum_map(scene.model).description;
  s.csv = options.csv;

  // Everything but the run's outcome is known before it starts: written at once (csv_writer.hpp).
  Fields leading = {{"scene", scene.name},
                    {"scene_file", source_relative(scene.file)},
                    {"system", s.system},
                    {"method", s.method}};
  leading.insert(leading.end(), s.method_settings.begin(), s.method_settings.end());
  const Fields grid = {{"h", scene.horizon.h},
                       {"grid_steps", as_int(scene.horizon.steps)},
                       {"t_final", scene.horizon.t_final},
                       {"output_every", as_int(scene.horizon.output_every)},
                       {"momentum_map", s.momentum_map},
                       {"units", system_units(s.system)},
                       {"error_columns", std::string("energy_error = E - E0 and momentum_error = |m - m0| are "
                                                     "absolute (the units above); orthogonality_error = "
                                                     "|R^T R - I|_F, determinant_error = |det R - 1|")},
                       {"version", std::string(version())},
                       {"git_describe", std::string(git_describe())},
                       {"command_line", options.command_line}};
  leading.insert(leading.end(), grid.begin(), grid.end());
  if (scene.horizon.shorter_last_step) leading.push_back({"last_step", scene.horizon.last_step()});
  leading.insert(leading.end(), options.extra_metadata.begin(), options.extra_metadata.end());

  const bool quaternion_column = method.records_quaternion_norm();
  std::vector<std::string> columns = Recorder::columns(scene.model, quaternion_column);
  check_output_space(options.csv, scene.horizon, columns.size());
  CsvWriter csv(options.csv, std::move(columns), leading);
  Recorder recorder(scene.model, scene.horizon.output_every, &csv, quaternion_column);
  recorder.stop_on_interrupt(options.stop_on_interrupt);
  s.stats = method.run(scene, recorder);
  if (recorder.interrupted()) {
    // The CSV's temporary is removed as `csv` goes out of scope: no partial file is left.
    throw Interrupted(interrupt_signal(), scene.name + ": stopped at t = " + std::to_string(recorder.last().t) +
                                              " (no CSV written)");
  }
  recorder.finish();
  s.diagnostics = recorder.diagnostics();
  s.recording_seconds = recorder.seconds();
  s.output_rows = csv.rows();
  s.final_sample = recorder.last();
  csv.commit({{"status", s.stats.brief()},
              {"solver_steps", as_int(s.stats.steps)},
              {"rejected_steps", as_int(s.stats.rejected_steps)},
              {"output_rows", as_int(s.output_rows)}});
  return s;
}

}  // namespace lgvi::experiments
