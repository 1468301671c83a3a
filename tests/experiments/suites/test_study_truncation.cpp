// Truncated study files (issue N11): a copy cut short must not load as another study. The scene
// files' rule applied to studies (experiments/input/toml_text.hpp; experiments/studies/README.md,
// "A file cut short"): a last line without its newline warns, and the shipped studies end with a
// required key, so that a cut at a line boundary is refused. Every shipped study is cut at every
// line boundary and at seeded random byte offsets (long-horizon.toml at every 7th byte too); in
// each form (full and --quick) every cut either fails with one SceneError line or loads exactly
// the study of the whole file (its cases: ids, groups, expectations, labels).
#include <cstddef>
#include <iostream>
#include <random>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "experiments/cli/cli_support.hpp"
#include "experiments/output/fields.hpp"
#include "experiments/scene/scene.hpp"
#include "experiments/suites/study.hpp"
#include "test_support.hpp"

namespace lgvi::experiments {
namespace {

/// What a study runs: its name, description, columns and every case (id, group, expectation,
/// labels). The inputs (the study file's digest) differ for a cut copy by construction.
std::string study_text(const Suite& s) {
  std::string text = s.name + "\n" + s.description + "\n";
  for (const std::string& c : s.columns) text += c + ",";
  text += "\n";
  for (const SuiteCase& c : s.cases) {
    text += c.id + "\t" + c.group + "\t" + to_string(c.expect) + "\t" + to_json(c.labels) + "\n";
  }
  return text;
}

struct Counts {
  std::size_t errors = 0, same = 0, other = 0;
};

TEST(StudyTruncation, NoCutOfAShippedStudyLoadsAsAnotherStudy) {
  std::mt19937_64 rng = test::make_rng(11);
  Counts lines, bytes;
  std::size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(default_studies_dir())) {
    if (entry.path().extension() != ".toml") continue;
    ++files;
    const std::filesystem::path file = entry.path();
    const std::string text = test::read_text(file);
    ASSERT_FALSE(text.empty()) << file;
    ASSERT_EQ(text.back(), '\n') << file;
    std::set<std::size_t> line_cuts;
    for (std::size_t at = 0; at < text.size(); at = text.find('\n', at) + 1) {
      line_cuts.insert(at);
      if (text.find('\n', at) == std::string::npos) break;
    }
    line_cuts.erase(text.size());
    std::set<std::size_t> byte_cuts;
    std::uniform_int_distribution<std::size_t> offset(0, text.size() - 1);
    while (byte_cuts.size() < 40) byte_cuts.insert(offset(rng));
    if (file.filename() == "long-horizon.toml") {
      for (std::size_t at = 0; at < text.size(); at += 7) byte_cuts.insert(at);
    }
    byte_cuts.insert(text.size() - 1);  // the final newline alone
    for (const bool quick : {false, true}) {
      const SuiteParams params{quick, default_scenes_dir()};
      const Suite whole = parse_study(text, file, params);
      ASSERT_TRUE(whole.warnings.empty()) << file << ": a shipped study warns";
      const std::string expected = study_text(whole);
      for (const auto& [cuts, counts] : {std::pair{&line_cuts, &lines}, std::pair{&byte_cuts, &bytes}}) {
        for (const std::size_t n : *cuts) {
          try {
            const Suite s = parse_study(std::string_view(text).substr(0, n), file, params);
            if (study_text(s) == expected) {
              ++counts->same;
              // The full form reads up to the last line: only a cut of the final newline keeps
              // it (and warns). The quick form reads the lines before the full form's own.
              if (!quick) {
                EXPECT_EQ(n, text.size() - 1) << file << " cut to " << n << " bytes loads";
              }
              if (n == text.size() - 1) {
                EXPECT_EQ(s.warnings.size(), 1u) << file;
              }
            } else {
              ++counts->other;
              ADD_FAILURE() << file << " cut to its first " << n << " bytes loads another study"
                            << (quick ? " (--quick)" : "") << ": ..." << text.substr(n > 60 ? n - 60 : 0, 60);
            }
          } catch (const SceneError& e) {
            ++counts->errors;
            const std::string message = e.what();
            EXPECT_EQ(message.find('\n'), std::string::npos) << message;
            EXPECT_EQ(message.rfind(file.string() + ": ", 0), 0u) << message;
          }
        }
      }
    }
  }
  EXPECT_EQ(files, 4u);
  for (const auto& [kind, c] : {std::pair{"line-boundary", lines}, std::pair{"byte", bytes}}) {
    std::cout << "[ counts   ] " << kind << " cuts, both forms: " << c.errors << " errors, " << c.same
              << " the whole study, " << c.other << " another study\n";
  }
}

// The warning itself, as for scenes: a study file without its final newline loads (the same
// study) with one line naming the file.
TEST(StudyTruncation, AMissingFinalNewlineWarnsAndStillLoads) {
  const std::filesystem::path file = default_studies_dir() / "spacecraft-tumble.toml";
  std::string text = test::read_text(file);
  ASSERT_EQ(text.back(), '\n');
  const SuiteParams params{false, default_scenes_dir()};
  const std::string expected = study_text(parse_study(text, file, params));
  text.pop_back();
  const Suite s = parse_study(text, "mine.toml", params);
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_EQ(s.warnings[0], "mine.toml: does not end with a newline: the file may be truncated");
  EXPECT_EQ(study_text(s), expected);
}

}  // namespace
}  // namespace lgvi::experiments
