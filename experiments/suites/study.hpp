// Study files: a user's comparison of methods on scenes, written as TOML and run by the suite
// harness (experiments/suites/suite.hpp) like a built-in suite: scenes x methods x steps h (fixed-step
// methods) or tolerances rtol (adaptive ones) x horizons, graded by the chosen metrics against
// the chosen reference (the exact solution, a named fine run, or none). The format, every key
// with its type and default: experiments/studies/README.md.
//
// A study becomes a Suite: one SimulateJob case per scene, horizon, method and step or tolerance
// (the cases the built-in work-precision and long-horizon suites build), its summary columns, and
// a renderer drawing each metric against cost. Every bad input is a SceneError naming the study
// file, the dotted field ("methods[2].model", "quick.tolerances[0]") and the reason; a scene file
// that does not load reports its own file and field.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "experiments/suites/suite.hpp"

namespace lgvi::experiments {

/// Metrics a study can ask for (the `metrics` key).
inline constexpr std::string_view kStudyMetrics[] = {"final-error", "energy", "momentum", "orthogonality", "time"};

/// An error metric of a study (all but "time"): its summary column, its axis label and its name
/// in titles and file names.
struct StudyMetricView {
  const char* metric;
  const char* column;
  const char* ylabel;
  const char* what;
  const char* file;
};
inline constexpr StudyMetricView kStudyMetricViews[] = {
    {"final-error", "final_error", "final-state error (dimensionless)", "final-state error", "error"},
    {"energy", "max_energy_error_relative", "max |E - E_0| / |E_0|", "max energy error", "energy"},
    {"momentum", "max_momentum_drift_absolute", "max |m - m_0| (momentum unit)", "max momentum-map error", "momentum"},
    {"orthogonality", "max_orthogonality_error", "max ||R^T R - I||_F", "max orthogonality error", "orthogonality"},
};

/// Levels of a study's cheapest-method tables.
inline constexpr double kStudyLevels[] = {1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12};

/// Reads and validates the study file `file` and builds its cases; `params.quick` applies the
/// file's [quick] table. Named scenes are looked up in params.scenes_dir, scene paths relative to
/// the study file's directory. The suite is named after the study (`name`, default the file's
/// stem) and rendered by render_study (figures of each metric against cost, a table of the
/// cheapest method per accuracy level). Throws SceneError.
Suite load_study(const std::filesystem::path& file, const SuiteParams& params);

/// Same from TOML text; `file` names the source in messages, gives the default name and the
/// directory scene paths are relative to.
Suite parse_study(std::string_view toml_text, const std::filesystem::path& file, const SuiteParams& params);

/// The shipped studies: <source>/experiments/studies (or the installed copy).
std::filesystem::path default_studies_dir();

}  // namespace lgvi::experiments
