// `lgvi-testbed merge OUT SHARD_DIR...`: joins the output directories of a sharded suite run
// (`suite NAME --shard i/N --out SHARD_DIR`) into one, as if the suite had run unsharded.
#pragma once

#include <filesystem>
#include <ostream>
#include <vector>

namespace lgvi::experiments {

/// Checks that the shard directories are the N complete shards 0..N-1 (each exactly once) of
/// one run: the same suite, form (--quick), version and fingerprint (cases and scene files; see
/// suite_journal.hpp), every case of each shard finished with its files present and matching
/// the recorded sizes and digests. Then copies every case's files into out_dir (each through a
/// temporary, verified after the copy) and writes summary.csv, summary.jsonl (case order), the
/// journal and a complete manifest of shard 0/1. Prints what it merged on `progress`. Nothing
/// is written unless every check passes. Throws InvalidInput naming the shard directory and the
/// reason, OutputError.
void merge_shards(const std::filesystem::path& out_dir, const std::vector<std::filesystem::path>& shard_dirs,
                  std::ostream& progress);

}  // namespace lgvi::experiments
