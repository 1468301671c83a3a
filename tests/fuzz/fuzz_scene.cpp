// libFuzzer target of the scene parser (experiments/scene/scene.cpp): every input either loads or
// fails with one SceneError line naming the file, the field and the reason; anything else
// (another exception, a crash, a sanitizer report, a loaded scene with a non-finite value) is a
// finding. Built with LGVI_BUILD_FUZZERS=ON by clang (tests/sanitize.sh runs it).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstdio>
#include <string>
#include <string_view>

#include "experiments/scene/scene.hpp"

namespace {

/// The property downstream of a successful load: everything the run starts from is finite.
bool all_finite(const lgvi::experiments::Scene& s) {
  bool ok = std::isfinite(s.horizon.h) && std::isfinite(s.horizon.t_final);
  std::visit(
      [&](const auto& m) {
        if constexpr (requires { m.initial.R; }) ok = ok && m.initial.R.allFinite() && m.initial.Omega.allFinite();
        if constexpr (requires { m.initial.x; }) ok = ok && m.initial.x.allFinite() && m.initial.v.allFinite();
        if constexpr (requires { m.initial.q; }) ok = ok && m.initial.q.allFinite() && m.initial.q_dot.allFinite();
        if constexpr (requires { m.initial.R1; }) {
          ok = ok && m.initial.R1.allFinite() && m.initial.R2.allFinite() && m.initial.Omega1.allFinite() &&
               m.initial.Omega2.allFinite();
        }
      },
      s.model);
  return ok;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const lgvi::experiments::Scene scene = lgvi::experiments::parse_scene(text, "fuzz.toml");
    if (!all_finite(scene)) {
      std::fprintf(stderr, "fuzz_scene: a scene loaded with a non-finite value\n");
      std::abort();
    }
  } catch (const lgvi::experiments::SceneError& e) {
    const std::string what = e.what();
    // One line, starting with the file name.
    if (what.find('\n') != std::string::npos || what.rfind("fuzz.toml: ", 0) != 0) {
      std::fprintf(stderr, "fuzz_scene: malformed error message: %s\n", what.c_str());
      std::abort();
    }
  }
  // Any other exception escapes and libFuzzer reports it as a crash (uncaught exception).
  return 0;
}
