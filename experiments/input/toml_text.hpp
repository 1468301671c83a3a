// The checks of TOML text before toml++ parses it, shared by the scene and study readers
// (defined in experiments/scene/scene.cpp beside the scan they run).
#pragma once

#include <string>
#include <string_view>

namespace lgvi::experiments {

/// At most kMaxSceneBytes of text and at most kMaxSceneNesting levels of nesting (scene.hpp:
/// admissible input; toml++'s recursive descent overflows the stack on deeper text). `kind`
/// names the file in the message ("scene", "study"). Throws SceneError naming `file`.
void check_toml_text(std::string_view text, const std::string& file, const std::string& kind);

}  // namespace lgvi::experiments
