// The checks of TOML text before toml++ parses it, and of a file cut short, shared by the scene
// and study readers (defined in experiments/input/scene_reader.cpp beside the scan they run).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace lgvi::experiments {

/// At most kMaxSceneBytes of text and at most kMaxSceneNesting levels of nesting (scene.hpp:
/// admissible input; toml++'s recursive descent overflows the stack on deeper text). `kind`
/// names the file in the message ("scene", "study"). Throws SceneError naming `file`.
void check_toml_text(std::string_view text, const std::string& file, const std::string& kind);

/// The scene and study files' rule for a file cut short (experiments/scenes/README.md, "File-level
/// rules"): text whose last line has no newline gives the warning "FILE: does not end with a
/// newline: the file may be truncated" (a cut inside a line leaves such a line; refusing it would
/// break hand-written files saved without one), else nothing. A cut at a line boundary is
/// caught by the files' order instead: the shipped ones end with a required key.
std::optional<std::string> truncation_warning(std::string_view text, const std::string& file);

/// Prints each of `warnings` as a line "warning: ..." on stderr, once per file (by its absolute
/// path) and process: a suite or study loads its scene once per case.
void warn_once(const std::filesystem::path& file, const std::vector<std::string>& warnings);

}  // namespace lgvi::experiments
