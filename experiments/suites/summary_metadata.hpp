// The metadata of a suite's summary.csv: `# key: value` lines before its header (shard 0 only,
// so that the shards' summaries still concatenate into the whole one). They state the suite, its
// form, the version, the units, and for every column whose meaning or unit is not evident from
// its name what it is and whether it is relative or absolute.
#pragma once

#include <string>
#include <vector>

#include "experiments/output/fields.hpp"
#include "experiments/suites/suite.hpp"

namespace lgvi::experiments {

/// The metadata for a summary of `suite` with the given columns (summary.csv's header), in the
/// form `quick` or full: suite, form, version, git_describe, units, errors (the naming rule),
/// then one "columns.NAME" entry per described column present.
Fields summary_metadata(const Suite& suite, const std::vector<std::string>& columns, bool quick);

}  // namespace lgvi::experiments
