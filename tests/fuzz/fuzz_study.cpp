// libFuzzer target of the study reader (experiments/suites/study.cpp, parse_study), seeded with
// experiments/studies/*.toml and tests/fuzz/regressions/study/: in the full and the quick form a
// study either builds a suite whose case ids are unique file names and whose first cases validate,
// or fails with one SceneError line naming the study file (study_property, fuzz_properties.hpp).
// The study is read as experiments/studies/fuzz.toml of the source tree: its named scenes are the
// shipped ones, its relative paths point from there.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>

#include "tests/fuzz/fuzz_properties.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path source(LGVI_SOURCE_DIR);
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  // Scene paths naming devices (fuzz_scene.cpp): regular files only.
  if (text.find("/dev") != std::string_view::npos || text.find("/proc") != std::string_view::npos) return 0;
  const std::string why = lgvi::fuzz::study_property(text, source / "experiments/studies/fuzz.toml",
                                                     source / "experiments/scenes");
  if (!why.empty()) {
    std::fprintf(stderr, "fuzz_study: %s\n", why.c_str());
    std::abort();
  }
  return 0;
}
