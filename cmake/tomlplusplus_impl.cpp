// toml++'s implementation (its parser, formatters and node types), compiled into the build from
// the installed headers when LGVI_COMPILE_TOMLPLUSPLUS is on (CMakeLists.txt): the sanitizer and
// fuzzing build (tests/sanitize.sh) instruments it with its own flags instead of linking the
// uninstrumented libtomlplusplus. Every other file includes <toml++/toml.h> with
// TOML_HEADER_ONLY=0 and links this one.
//
// toml++'s internal assertions are off, as in its release build (the installed library): some do
// not hold on malformed text that toml++ goes on to report as a parse error ("[?" and "[" then a
// newline: parse_key's and parse_value's preconditions, found by the scene and study fuzzers), so
// with them on the build stopped at an assert where users get the error line. Off they are no-ops
// (with NDEBUG clang would make them assumptions, undefined behaviour when they fail).
#define TOML_ASSERT(expr) static_assert(true)
#define TOML_IMPLEMENTATION 1
#include <toml++/toml.h>
