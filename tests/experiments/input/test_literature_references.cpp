// The literature problems' stored references (experiments/input/literature_references.hpp): the
// shipped file names shipped scenes at their t_final, trusted to at least 10 digits by the
// agreement of two independent computations, and rotations for R; the writer's text reads back
// bit for bit; a malformed file is one error naming the field.
#include "experiments/input/literature_references.hpp"

#include <gtest/gtest.h>

#include "experiments/cli/cli_support.hpp"
#include "experiments/input/scene_reader.hpp"
#include "experiments/scene/scene.hpp"
#include "lgvi/so3.hpp"

namespace lgvi::experiments {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

fs::path shipped() { return fs::path(test::source_dir()) / "validation" / "literature_references.toml"; }

TEST(LiteratureReferences, TheShippedFileNamesShippedScenesAtTheirFinalTime) {
  const std::vector<LiteratureReference> refs = read_literature_references(shipped());
  ASSERT_EQ(refs.size(), 5u);
  for (const LiteratureReference& r : refs) {
    const Scene scene = load_scene(default_scenes_dir() / (r.scene + ".toml"));
    EXPECT_EQ(r.t, scene.horizon.t_final) << r.scene;
    EXPECT_TRUE(so3::is_rotation(r.R, 1e-12)) << r.scene;
    EXPECT_GE(r.digits, 10) << r.scene;
    EXPECT_LT(r.agreement, 1e-10) << r.scene;
    EXPECT_FALSE(r.source.empty());
    EXPECT_FALSE(r.computed_by.empty());
  }
}

TEST(LiteratureReferences, TheWrittenTextReadsBackBitForBit) {
  const std::vector<LiteratureReference> refs = read_literature_references(shipped());
  TempDir dir;
  const fs::path file = dir.work() / "refs.toml";
  test::write_text(file, literature_references_toml(refs, "a header\n\nof two lines"));
  const std::vector<LiteratureReference> again = read_literature_references(file);
  ASSERT_EQ(again.size(), refs.size());
  for (std::size_t i = 0; i < refs.size(); ++i) {
    EXPECT_EQ(again[i].scene, refs[i].scene);
    EXPECT_EQ(again[i].R, refs[i].R);
    EXPECT_EQ(again[i].Omega, refs[i].Omega);
    EXPECT_EQ(again[i].agreement, refs[i].agreement);
    EXPECT_EQ(again[i].digits, refs[i].digits);
  }
}

TEST(LiteratureReferences, AMalformedFileNamesTheField) {
  TempDir dir;
  const fs::path file = dir.work() / "bad.toml";
  const std::string good = test::read_text(shipped());
  for (const auto& [from, to, field] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {"digits = 11", "digits = 11\nextra = 1", "problem[0].extra"},
           {"t = 100.0", "t = -1.0", "problem[0].t"},
           {"scene = \"hlw-rigid-body\"", "", "problem[0].scene"},
       }) {
    std::string text = good;
    text.replace(text.find(from), from.size(), to);
    test::write_text(file, text);
    try {
      (void)read_literature_references(file);
      ADD_FAILURE() << "accepted: " << to;
    } catch (const SceneError& e) {
      EXPECT_EQ(e.field(), field) << e.what();
    }
  }
  EXPECT_THROW((void)read_literature_references(dir.work() / "missing.toml"), SceneError);
}

}  // namespace
}  // namespace lgvi::experiments
