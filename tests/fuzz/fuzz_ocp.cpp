// libFuzzer target of a scene's [ocp] table (experiments/scene/ocp_scene.cpp), seeded with the
// optimal control examples (experiments/scenes/ocp-*.toml and tests/fuzz/regressions/ocp/): a
// scene that loads has an [ocp] definition its solver accepts (finite target state with
// rotations, W symmetric positive definite, the solver settings finite and in range), else one
// SceneError line names the file and the field ("ocp.W"); scene_property, fuzz_properties.hpp.
// The same parser as fuzz_scene, another starting point: mutations of the [ocp] tables.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "tests/fuzz/fuzz_properties.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  // Devices named as control files (fuzz_scene.cpp): regular files only.
  if (text.find("/dev") != std::string_view::npos || text.find("/proc") != std::string_view::npos) return 0;
  if (const std::string why = lgvi::fuzz::scene_property(text, "fuzz-ocp.toml"); !why.empty()) {
    std::fprintf(stderr, "fuzz_ocp: %s\n", why.c_str());
    std::abort();
  }
  return 0;
}
