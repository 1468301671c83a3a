// JSON summaries: one object per run (DESIGN.md), written as a JSON array with one object per
// line, so that the file is valid JSON and still greps and diffs line by line.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "experiments/output/fields.hpp"

namespace lgvi::experiments {

/// Writes `[\n{...},\n{...}\n]\n` to `target` atomically. Throws OutputError.
void write_json_summary(const std::filesystem::path& target, const std::vector<Fields>& runs);

/// One run's summary as one JSON object (`{...}\n`, one key per line), written atomically; the
/// fields named in `arrays` are written as JSON arrays of numbers (non-finite entries as null)
/// in place of their text form. Throws OutputError.
void write_json_object(const std::filesystem::path& target, const Fields& fields,
                       const std::vector<std::pair<std::string, std::vector<double>>>& arrays);

}  // namespace lgvi::experiments
