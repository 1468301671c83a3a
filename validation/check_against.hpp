// `suite NAME --check-against DIR`: compares a suite run's summary.jsonl with an accepted one.
#pragma once

#include <filesystem>
#include <string>

#include "validation/validate.hpp"

namespace lgvi::experiments {

/// Compares RUN/summary.jsonl with ACCEPTED/summary.jsonl case by case and field by field
/// (timings, free text and provenance ignored). A numeric field is judged by the kind its name
/// says (order, cost, condition, counts; errors as round-off at or below 1e-11, else truncation;
/// other numbers as truncation, i.e. any change beyond 1e-6 relative); a text or boolean field
/// (status, as_expected) that changed is REGRESSED. Refuses (InvalidInput) summaries of another
/// suite or form, or ones that record neither.
ValidateReport check_suite_against(const std::filesystem::path& run_dir, const std::filesystem::path& accepted_dir,
                                   const std::string& suite, bool quick);

}  // namespace lgvi::experiments
