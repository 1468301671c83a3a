// Running one scene with one method: recorder -> CSV (atomic) + a run summary.
#pragma once

#include <filesystem>
#include <string>

#include "experiments/fields.hpp"
#include "experiments/method.hpp"
#include "experiments/recorder.hpp"
#include "experiments/scene.hpp"
#include "lgvi/integrate.hpp"

namespace lgvi::experiments {

/// What a run did and what it cost: the JSON summary's content.
struct RunSummary {
  std::string scene;
  std::string system;
  std::string method;
  Fields method_settings;
  Horizon horizon;
  Stats stats;
  Diagnostics diagnostics;
  std::string momentum_map;    ///< which momentum map the diagnostics track
  double recording_seconds = 0.0;  ///< part of stats.wall_seconds spent recording
  std::filesystem::path csv;
  std::size_t csv_rows = 0;
  Sample final_sample;  ///< the last recorded state (t_final, or the last good step)

  /// Ordered fields of the JSON summary object (see README/report for their meaning).
  Fields to_fields() const;
};

struct SimulateOptions {
  std::filesystem::path csv;  ///< output file
  std::string command_line;   ///< recorded in the metadata
  Fields extra_metadata;      ///< appended to the metadata (e.g. a suite case's reference run)
};

/// Integrates `scene` with `method`, writing the CSV atomically (metadata, header, rows of
/// every output_every-th step and of the last step computed). A run stopped by a failed
/// rotation update still writes its CSV (status in the metadata); check summary.stats.ok().
/// Throws OutputError if the CSV cannot be written (no file is left behind then).
RunSummary simulate(const Scene& scene, const Method& method, const SimulateOptions& options);

/// `git describe --always --dirty` of the source tree at configure time, or "unknown".
const char* git_describe();

}  // namespace lgvi::experiments
