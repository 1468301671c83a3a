// The fuzz targets' properties (tests/fuzz/fuzz_properties.hpp) on their regression inputs, the
// inputs a fuzzer once found failing (tests/fuzz/regressions/: scene files at the top, one
// folder per other target), and on their shipped seeds: each input must satisfy the property
// its target checks, in every build (the sanitizer job also replays them under ASan and UBSan as
// the fuzzers' first inputs). docs/testing.md lists the targets and what each found.
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "experiments/cli/cli_support.hpp"
#include "experiments/scene/ocp_scene.hpp"
#include "experiments/scene/scene.hpp"
#include "tests/fuzz/fuzz_properties.hpp"

namespace lgvi::test {
namespace {

/// The files of `dir` (relative to the source tree) whose names end in `extension` ("" for
/// any), sorted; none when there is no such directory (a target without findings yet).
std::vector<fs::path> inputs(const std::string& dir, const std::string& extension) {
  std::vector<fs::path> files;
  if (!fs::is_directory(fs::path(source_dir()) / dir)) return files;
  for (const auto& e : fs::directory_iterator(fs::path(source_dir()) / dir)) {
    if (e.is_regular_file() && e.path().filename().string().ends_with(extension)) files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

TEST(FuzzRegressions, SceneFilesLoadOrFailWithOneLine) {
  const std::vector<fs::path> files = inputs("tests/fuzz/regressions", ".toml");
  ASSERT_GE(files.size(), 9u);
  for (const fs::path& f : files) EXPECT_EQ(fuzz::scene_property(read_text(f)), "") << f;
  for (const fs::path& f : inputs("experiments/scenes", ".toml")) EXPECT_EQ(fuzz::scene_property(read_text(f)), "") << f;
}

TEST(FuzzRegressions, OcpTablesLoadAsTheirSolverAcceptsOrFailWithOneLine) {
  std::vector<fs::path> files = inputs("tests/fuzz/regressions/ocp", ".toml");
  for (const fs::path& f : files) EXPECT_EQ(fuzz::scene_property(read_text(f), "fuzz-ocp.toml"), "") << f;
  std::size_t examples = 0;
  for (const fs::path& f : inputs("experiments/scenes", ".toml")) {
    if (!f.filename().string().starts_with("ocp-")) continue;
    ++examples;
    // The examples load with their [ocp] definition.
    ASSERT_TRUE(lgvi::experiments::parse_scene(read_text(f), f).ocp) << f;
    EXPECT_EQ(fuzz::scene_property(read_text(f), "fuzz-ocp.toml"), "") << f;
  }
  EXPECT_GE(examples, 5u);
}

TEST(FuzzRegressions, StudiesBuildTheirCasesOrFailWithOneLine) {
  const fs::path studies = fs::path(source_dir()) / "experiments/studies";
  const fs::path scenes = fs::path(source_dir()) / "experiments/scenes";
  for (const fs::path& f : inputs("tests/fuzz/regressions/study", ".toml")) {
    EXPECT_EQ(fuzz::study_property(read_text(f), studies / "fuzz.toml", scenes), "") << f;
  }
  const std::vector<fs::path> shipped = inputs("experiments/studies", ".toml");
  ASSERT_GE(shipped.size(), 3u);
  for (const fs::path& f : shipped) EXPECT_EQ(fuzz::study_property(read_text(f), f, scenes), "") << f;
}

TEST(FuzzRegressions, ControlSamplesParseOrFailWithOneLine) {
  for (const fs::path& f : inputs("tests/fuzz/regressions/controls", "")) {
    EXPECT_EQ(fuzz::control_samples_property(read_text(f)), "") << f;
  }
  const std::vector<fs::path> seeds = inputs("tests/fuzz/seeds/controls", ".csv");
  ASSERT_GE(seeds.size(), 5u);
  for (const fs::path& f : seeds) EXPECT_EQ(fuzz::control_samples_property(read_text(f)), "") << f;
}

TEST(FuzzRegressions, CommandLinesParseOrFailWithOneLine) {
  for (const fs::path& f : inputs("tests/fuzz/regressions/cli", "")) {
    EXPECT_EQ(fuzz::cli_property(read_text(f)), "") << f;
  }
  // The argument vectors as fuzz_cli splits them.
  EXPECT_EQ(fuzz::split_arguments(std::string_view("simulate\npendulum\0--h\n\n", 23)),
            (std::vector<std::string>{"lgvi-testbed", "simulate", "pendulum", "--h", ""}));
  EXPECT_EQ(fuzz::cli_property("simulate\npendulum\n--h\n0.01"), "");
  EXPECT_EQ(fuzz::cli_property("simulate\npendulum\n--h\nx"), "");  // refused: one error line
}

}  // namespace
}  // namespace lgvi::test
