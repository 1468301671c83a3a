// Truncated scene files: a copy cut short must not load silently as another scene. Every shipped
// scene is cut at every line boundary and at seeded random byte offsets; each cut either fails
// with a SceneError or loads with the warning "does not end with a newline" (scene.cpp,
// parse_scene; README "File-level rules").
#include <cstddef>
#include <iostream>
#include <random>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "experiments/cli/cli_support.hpp"
#include "experiments/scene/scene.hpp"
#include "test_support.hpp"

namespace lgvi::experiments {
namespace {

struct TruncationCounts {
  std::size_t errors = 0;
  std::size_t warned = 0;
  std::size_t silent = 0;
  std::size_t total() const { return errors + warned + silent; }
};

TEST(SceneTruncation, NoCutOfAShippedSceneLoadsSilently) {
  constexpr std::size_t kRandomCutsPerScene = 40;
  std::mt19937_64 rng = test::make_rng(16);
  TruncationCounts lines;
  TruncationCounts bytes;
  for (const std::string& name : scene_names(default_scenes_dir())) {
    const std::filesystem::path file = test::default_scene_file(name);
    const std::string text = test::read_text(file);
    ASSERT_FALSE(text.empty()) << file;
    ASSERT_TRUE(parse_scene(text, file).warnings.empty()) << file << ": a shipped scene warns";
    // Cuts at a line boundary: the first n lines, n = 0 .. all but the last.
    std::set<std::size_t> line_cuts;
    for (std::size_t at = 0; at < text.size(); at = text.find('\n', at) + 1) {
      line_cuts.insert(at);
      if (text.find('\n', at) == std::string::npos) break;
    }
    line_cuts.erase(text.size());
    std::uniform_int_distribution<std::size_t> offset(0, text.size() - 1);
    std::set<std::size_t> byte_cuts;
    while (byte_cuts.size() < kRandomCutsPerScene) byte_cuts.insert(offset(rng));
    for (const auto& [cuts, counts] : {std::pair{&line_cuts, &lines}, std::pair{&byte_cuts, &bytes}}) {
      for (const std::size_t n : *cuts) {
        try {
          const Scene s = parse_scene(std::string_view(text).substr(0, n), file);
          if (s.warnings.empty()) {
            ++counts->silent;
            ADD_FAILURE() << file << " cut to its first " << n << " bytes loads silently";
          } else {
            ++counts->warned;
          }
        } catch (const SceneError&) {
          ++counts->errors;
        }
      }
    }
  }
  for (const auto& [kind, c] : {std::pair{"line-boundary", lines}, std::pair{"random-byte", bytes}}) {
    std::cout << "[ counts   ] " << kind << " cuts: " << c.total() << " tried, " << c.errors << " errors, " << c.warned
              << " warned, " << c.silent << " silent\n";
  }
  EXPECT_GT(lines.total(), 0u);
}

// The warning itself: a hand-written file without its final newline loads (the same scene) with
// one line naming the file; the shipped text with its newline does not warn.
TEST(SceneTruncation, AMissingFinalNewlineWarnsAndStillLoads) {
  const std::filesystem::path file = test::default_scene_file("free-body");
  std::string text = test::read_text(file);
  ASSERT_EQ(text.back(), '\n');
  text.pop_back();
  const Scene s = parse_scene(text, "mine.toml");
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_EQ(s.warnings[0], "mine.toml: does not end with a newline: the file may be truncated");
  EXPECT_EQ(s.horizon.steps, load_scene(file).horizon.steps);
}

}  // namespace
}  // namespace lgvi::experiments
