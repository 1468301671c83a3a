// A suite run's record of what finished, for `suite --resume` and `merge`.
//
// In OUT, beside the case files and the summaries:
//   suite-run.json       the manifest: suite, quick, version (git describe), the fingerprint of
//                        the case list and scene files, the shard, the case counts, and whether
//                        the run finished (complete) or was interrupted; written atomically at
//                        the start (complete = false) and at the end.
//   suite-journal.jsonl  one line per finished case, appended as the case finishes, by one
//                        write(2) on an O_APPEND descriptor: the case's summary.csv and
//                        summary.jsonl lines, the size and FNV-1a 64 digest of each file it
//                        wrote, the fingerprint, and the completion marker "done": true as the
//                        last key. A process killed mid-append leaves at most a torn last line,
//                        which fails to parse or lacks the marker and is ignored.
// summary.csv and summary.jsonl are rebuilt from the journal's lines in case order at the end of
// a run, of an interrupted run (what finished), and by `merge`.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace lgvi::experiments {

struct Suite;

/// A file a suite was made from, in its fingerprint (suite_fingerprint): the study file, the
/// scene files it names and the files those read (Scene::inputs: control samples). `what`
/// names it in messages ("the study file x.toml"); `digest` is the FNV-1a 64 of its bytes.
struct SuiteInput {
  std::string what;
  std::string digest;
};

/// A written file of a case: path relative to OUT, size, FNV-1a 64 digest (16 hex digits).
struct FileDigest {
  std::string path;
  std::uintmax_t size = 0;
  std::string fnv1a64;
};

/// FNV-1a 64 of a file's bytes as 16 hex digits; "" when it cannot be read.
std::string file_fnv1a64(const std::filesystem::path& file);
/// FNV-1a 64 of a string as 16 hex digits.
std::string text_fnv1a64(const std::string& text);

/// The identity of a run's results: a digest of the suite's name, form (quick), version, its
/// cases (ids, groups, expectations, labels, in order), the bytes of the scene files
/// (scenes_dir/*.toml, by name) and of the files each reads (its control samples), and of the
/// suite's inputs (a study's own file, the scene files it names, wherever they are, and the
/// files those read). Runs with equal fingerprints compute the same cases.
std::string suite_fingerprint(const Suite& suite, bool quick, const std::filesystem::path& scenes_dir);

struct SuiteManifest {
  std::string suite;
  bool quick = false;
  std::string git_describe;
  std::string fingerprint;
  std::size_t shard_index = 0;
  std::size_t shard_count = 1;
  std::size_t suite_cases = 0;   ///< cases in the whole suite
  std::size_t shard_cases = 0;   ///< cases of this shard
  std::size_t finished = 0;      ///< cases in the summary
  bool complete = false;         ///< every case of the shard finished
  std::string interrupted_by;    ///< "SIGINT", "SIGTERM" or ""
  std::vector<SuiteInput> inputs;  ///< Suite::inputs ("inputs" in the JSON, only when there are any)
};

/// OUT/suite-run.json and OUT/suite-journal.jsonl.
std::filesystem::path manifest_path(const std::filesystem::path& out_dir);
std::filesystem::path journal_path(const std::filesystem::path& out_dir);

/// Writes the manifest atomically. Throws OutputError.
void write_manifest(const std::filesystem::path& out_dir, const SuiteManifest& m);
/// Reads it. Throws InvalidInput naming the file and what is missing or malformed.
SuiteManifest read_manifest(const std::filesystem::path& out_dir);

struct JournalEntry {
  std::size_t index = 0;  ///< in the whole suite
  std::string id;
  std::string fingerprint;
  std::string csv_line;    ///< summary.csv row, without the newline
  std::string jsonl_line;  ///< summary.jsonl row, without the newline
  std::vector<FileDigest> files;
};

/// The files a case wrote: the values of its summary fields whose key ends in "_path"
/// (csv_path, ...), relative to out_dir, that exist, with their digests.
std::vector<FileDigest> digest_case_files(const std::filesystem::path& out_dir, const std::string& jsonl_line);

/// Why `name`, a case's file as a journal records it, is not a name inside `dir` ("" when it
/// is): it must be relative, with no "..", "." or empty component and no NUL byte, and no
/// component of it that exists under `dir` may be a symbolic link (the last one not checked
/// when `check_last` is false: a link at a target is replaced by the rename). A journal is
/// data: a doctored one must not make `merge` or `--resume` read or write outside its directory.
std::string case_file_name_problem(const std::filesystem::path& dir, const std::string& name, bool check_last = true);

/// Why `e`'s files do not verify under out_dir ("" when every one is a name inside out_dir
/// (case_file_name_problem) and exists with its size and digest).
std::string verify_files(const std::filesystem::path& out_dir, const JournalEntry& e);

/// Appends one entry with its completion marker by one write(2). Throws OutputError.
class JournalWriter {
 public:
  /// Opens OUT/suite-journal.jsonl for appending; `truncate` starts it empty.
  JournalWriter(const std::filesystem::path& out_dir, bool truncate);
  ~JournalWriter();
  JournalWriter(const JournalWriter&) = delete;
  JournalWriter& operator=(const JournalWriter&) = delete;
  void append(const JournalEntry& e);

 private:
  std::filesystem::path path_;
  int fd_ = -1;
};

/// The complete entries of OUT/suite-journal.jsonl (lines that parse and carry the marker), the
/// last one per case index; a missing file has none.
std::map<std::size_t, JournalEntry> read_journal(const std::filesystem::path& out_dir);

/// Rewrites the journal atomically with `entries` only (resume drops what did not verify).
void rewrite_journal(const std::filesystem::path& out_dir, const std::map<std::size_t, JournalEntry>& entries);

/// Writes summary.csv (the header line `header` first unless empty) and summary.jsonl from the
/// entries in index order, atomically; and for the all suite, whose case ids are PART/ID, the
/// same two files in each existing folder PART with its rows alone (a first comment line says
/// that their paths are relative to out_dir). Throws OutputError.
void write_summaries_from(const std::filesystem::path& out_dir, const std::string& header,
                          const std::map<std::size_t, JournalEntry>& entries);

}  // namespace lgvi::experiments
