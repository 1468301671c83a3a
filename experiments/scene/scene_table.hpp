// A scene from a parsed TOML table: what parse_scene does after parsing the text, for a table
// edited in memory (an ensemble's sample: the scene file's table with drawn values in place,
// experiments/suites/ensemble.hpp), without printing it and parsing it again.
#pragma once

#include <filesystem>
#include <string_view>

#include <toml++/toml.h>

#include "experiments/scene/scene.hpp"

namespace lgvi::experiments {

/// The scene of `doc`, validated as parse_scene validates a file's (every error a SceneError
/// naming `file` and the field). `toml_text` is the text the table was parsed from: the
/// truncation warning and Scene::text are made from it; empty for a table edited in memory
/// (then no warning and no text).
Scene parse_scene_table(const toml::table& doc, std::string_view toml_text, const std::filesystem::path& file,
                        const SceneOverrides& overrides = {});

}  // namespace lgvi::experiments
