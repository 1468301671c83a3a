// Running one scene with one method: recorder -> CSV (atomic) + a run summary.
#pragma once

#include <filesystem>
#include <string>

#include "experiments/output/fields.hpp"
#include "experiments/methods/method.hpp"
#include "experiments/methods/recorder.hpp"
#include "experiments/scene/scene.hpp"
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
  std::size_t output_rows = 0;  ///< rows written, the samples the diagnostics are taken over
  Sample final_sample;  ///< the last recorded state (t_final, or the last good step)

  /// Ordered fields of the JSON summary object (see README/report for their meaning).
  Fields to_fields() const;
};

struct SimulateOptions {
  std::filesystem::path csv;  ///< output file
  std::string command_line;   ///< recorded in the metadata
  Fields extra_metadata;      ///< appended to the metadata (e.g. a suite case's reference run)
  /// On SIGINT/SIGTERM (interrupt_signal(), interrupt.hpp) stop at the next recorded row and
  /// throw Interrupted, leaving no CSV: the simulate command. A suite's cases leave it off (the
  /// runner stops between cases).
  bool stop_on_interrupt = false;
};

/// Integrates `scene` with `method`, writing the CSV atomically (metadata, header, rows of
/// every output_every-th step and of the last step computed; the rows are written once, see
/// csv_writer.hpp). Only those steps reach the recorder, so the diagnostics (maximum energy
/// error, ...) are over the written rows. Metadata: the scene, the method's settings, the grid
/// (h, grid_steps = t_final / h, output_every), provenance, then at the end of the run status,
/// solver_steps (accepted steps: the LGVI's steps, or an adaptive solver's own, which do not
/// depend on the output grid), rejected_steps and output_rows. A run stopped by a failure still
/// writes its CSV (status in the metadata); check summary.stats.ok(). Throws OutputError if the
/// CSV cannot be written (no file is left behind then), Interrupted (options.stop_on_interrupt).
RunSummary simulate(const Scene& scene, const Method& method, const SimulateOptions& options);

/// `git describe --always --dirty` of the source tree at configure time, or "unknown".
const char* git_describe();
/// The project's version (CMake's PROJECT_VERSION), recorded in every summary and CSV.
const char* version();

}  // namespace lgvi::experiments
