// JSON summaries: one object per run (DESIGN.md), written as a JSON array with one object per
// line, so that the file is valid JSON and still greps and diffs line by line.
#pragma once

#include <filesystem>
#include <vector>

#include "experiments/fields.hpp"

namespace lgvi::experiments {

/// Writes `[\n{...},\n{...}\n]\n` to `target` atomically. Throws OutputError.
void write_json_summary(const std::filesystem::path& target, const std::vector<Fields>& runs);

}  // namespace lgvi::experiments
