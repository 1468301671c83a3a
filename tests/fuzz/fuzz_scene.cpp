// libFuzzer target of the scene parser (experiments/scene/scene.cpp): every input either loads
// with finite starting values or fails with one SceneError line naming the file, the field and
// the reason (scene_property, fuzz_properties.hpp); anything else (another exception, a crash, a
// sanitizer report) is a finding. Built with LGVI_BUILD_FUZZERS=ON by clang (tests/sanitize.sh
// runs it from the shipped scenes and tests/fuzz/regressions/*.toml).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "tests/fuzz/fuzz_properties.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  // A [control] file naming a device (/dev/zero, /dev/stdin) reads without end or blocks: the
  // bounds of file reading have their own tests; here only regular files.
  if (text.find("/dev") != std::string_view::npos || text.find("/proc") != std::string_view::npos) return 0;
  if (const std::string why = lgvi::fuzz::scene_property(text); !why.empty()) {
    std::fprintf(stderr, "fuzz_scene: %s\n", why.c_str());
    std::abort();
  }
  return 0;
}
