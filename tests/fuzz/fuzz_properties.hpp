// The properties the libFuzzer targets of tests/fuzz check on each input, one function per input
// a user hands the tool (fuzz_properties.cpp), shared with the test that replays the regression
// inputs (tests/experiments/test_fuzz_regressions.cpp). Each returns "" when the input satisfies
// the property, else what went wrong (the target then aborts: a finding). Exceptions other than
// the input errors the property allows propagate: libFuzzer reports them as crashes, the test as
// failures.
//
// The property of every reader: an input either loads into values a run can start from (finite,
// within the ranges the reader states) or fails with exactly one error line naming the file (or
// the option) and the field; never another exception, a crash or a sanitizer report.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace lgvi::fuzz {

/// Scene files (fuzz_scene; fuzz_ocp with the [ocp] examples as seeds): parse_scene loads a scene
/// whose horizon and starting state are finite (its [ocp] definition one its solver accepts,
/// ocp_definition_property; its warnings one line each), or throws one SceneError line naming
/// the file.
std::string scene_property(std::string_view text, const std::string& file = "fuzz.toml");

/// Study files (fuzz_study): parse_study, in its full and its quick form, builds a suite with at
/// least one case, the case ids unique and usable as file names, the first cases' inputs valid
/// (Job::validate, what a run checks before it starts), or throws one SceneError line naming the
/// study file. `file`'s directory is where relative scene paths point; named scenes are looked up
/// in `scenes_dir`.
std::string study_property(std::string_view text, const std::filesystem::path& file,
                           const std::filesystem::path& scenes_dir);

/// Control sample CSV files (fuzz_controls): for 3 and for 2 components (the cart), the samples
/// parse into a control whose values are finite at any time, or the reader throws one SceneError
/// line naming the scene file, the field and the CSV.
std::string control_samples_property(std::string_view bytes);

/// The arguments of an argument vector input: split at NUL and newline bytes (a last empty one,
/// after a final separator, dropped), after the program name.
std::vector<std::string> split_arguments(std::string_view bytes);

/// The command line (fuzz_cli): parse_cli (the parse step of run_cli, which runs nothing) either
/// accepts the arguments (nothing on the error stream), ends with --help or --version (exit 0), or
/// refuses them with exit 1 and exactly one "error: ..." line; never another exit status (3: an
/// internal error).
std::string cli_property(std::string_view bytes);

}  // namespace lgvi::fuzz
