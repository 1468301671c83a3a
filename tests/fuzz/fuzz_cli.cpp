// libFuzzer target of the command line (experiments/cli/cli.cpp, parse_cli: run_cli's parse step,
// which runs nothing): the input is an argument vector, split at NUL and newline bytes, seeded
// with the example commands of the README and docs/ (tests/fuzz/cli_seeds.py) and
// tests/fuzz/regressions/cli/. Every vector is accepted, ends with --help/--version, or is
// refused with exit 1 and one "error:" line (cli_property, fuzz_properties.hpp).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "tests/fuzz/fuzz_properties.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  if (const std::string why = lgvi::fuzz::cli_property(bytes); !why.empty()) {
    std::fprintf(stderr, "fuzz_cli: %s\n", why.c_str());
    std::abort();
  }
  return 0;
}
