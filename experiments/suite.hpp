// Suites: named lists of independent cases (scene x method x form), each run to its own CSV,
// summarized in one summary.json and drawn by gnuplot. Cases are independent so that later a
// suite can be listed, sharded and run in parallel without changing the outputs.
#pragma once

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "experiments/simulate.hpp"
#include "lgvi/lgvi.hpp"

namespace lgvi::experiments {

struct SuiteCase {
  std::string scene;  ///< scene name in the scenes directory
  std::string method = "lgvi";
  LgviForm form = LgviForm::Symmetric;

  /// File stem of the case's outputs: "<scene>-<form>" (the method joins when there are more).
  std::string id() const;
};

struct Suite {
  std::string name;
  std::string description;
  std::vector<SuiteCase> cases;
};

/// Known suite names with one-line descriptions.
std::vector<std::pair<std::string, std::string>> suite_list();

/// The cases of a suite. "default": every scene of `scenes_dir` with the symmetric and the
/// printed LGVI. Throws InvalidInput("suite", ...) for an unknown name.
Suite make_suite(const std::string& name, const std::filesystem::path& scenes_dir);

struct SuiteOptions {
  std::filesystem::path out_dir;
  std::filesystem::path scenes_dir;
  std::filesystem::path plots_dir;
  std::string gnuplot;
  bool plots = true;
  std::string command_line;
};

struct SuiteResult {
  std::vector<RunSummary> runs;
  std::vector<std::filesystem::path> plots;
  bool all_ok() const;
};

/// Validates every case's scene first (SceneError before anything runs), then runs the cases,
/// writes OUT/<case id>.csv, OUT/summary.json and, per scene, OUT/<scene>-{energy,
/// orthogonality,momentum}.png. One progress line per case on `progress`.
/// Throws SceneError, OutputError.
SuiteResult run_suite(const Suite& suite, const SuiteOptions& options, std::ostream& progress);

}  // namespace lgvi::experiments
