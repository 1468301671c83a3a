// libFuzzer target of the control samples reader (a [control] type = "piecewise-linear" file:
// TomlReader::parse_samples, experiments/input/toml_reader.hpp), seeded with
// tests/fuzz/seeds/controls/ and tests/fuzz/regressions/controls/: for 3 and 2 components the
// bytes parse into samples whose interpolation is finite at any time, or fail with one SceneError
// line naming the scene file, control.file and the CSV's line (control_samples_property,
// fuzz_properties.hpp).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "tests/fuzz/fuzz_properties.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  if (const std::string why = lgvi::fuzz::control_samples_property(bytes); !why.empty()) {
    std::fprintf(stderr, "fuzz_controls: %s\n", why.c_str());
    std::abort();
  }
  return 0;
}
