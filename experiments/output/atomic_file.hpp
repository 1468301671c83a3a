// Atomic output: every results file is written under a temporary name in the target's directory
// and renamed onto the target only when complete (rename(2) is atomic within a file system).
// If anything fails, or the owner is destroyed without commit(), the temporary is removed, so
// no half-written (or empty) results file is ever left behind.
//
// Two targets are streams, written in place instead (nothing to replace; not seekable):
// "-" is standard output, and an existing file that is not a regular file (a FIFO, a character
// device such as /dev/stdout or /dev/null, a socket; through symlinks) is opened and written as it
// is, never replaced by a regular file. A directory is refused (OutputError).
#pragma once

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

namespace lgvi::experiments {

/// A results file could not be written (disk, permissions, missing directory, gnuplot failure).
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A unique temporary path next to `target`: "<dir>/.lgvi-tmp-<pid>-<n><extension>" (the
/// extension only when at most 16 bytes), short whatever the target's name, so that any target
/// name the file system admits (up to 255 bytes) has a temporary. The file (if any was created
/// there) is removed by the destructor unless commit() renamed it. Live temporaries are
/// registered process-wide (remove_live_temporaries); a killed process leaves its own, which
/// remove_stale_temporaries recognizes by the pattern and the dead pid.
class TempPath {
 public:
  explicit TempPath(std::filesystem::path target);
  ~TempPath();
  TempPath(const TempPath&) = delete;
  TempPath& operator=(const TempPath&) = delete;

  const std::filesystem::path& path() const { return path_; }
  const std::filesystem::path& target() const { return target_; }
  bool committed() const { return committed_; }
  /// Renames the temporary onto the target. Throws OutputError.
  void commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path path_;
  bool committed_ = false;
};

/// Removes every temporary of this process not yet committed or removed (a run interrupted by a
/// signal, about to _Exit: destructors will not run). Best effort; returns how many were removed.
std::size_t remove_live_temporaries();

/// Removes, in `dir` and below, the temporaries ".lgvi-tmp-<pid>-..." of processes that no longer
/// exist (kill(pid, 0) fails with ESRCH), left by killed runs. Returns how many were removed.
std::size_t remove_stale_temporaries(const std::filesystem::path& dir);

/// A file written through a temporary and published by commit().
class AtomicFile {
 public:
  /// Creates the temporary (exclusively), or opens a stream target (above). Throws OutputError
  /// naming the target.
  explicit AtomicFile(std::filesystem::path target);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::FILE* stream() { return file_; }
  /// True for the stream targets ("-", existing non-regular files): written in place, in order,
  /// no seeking back; commit() flushes (and closes) them.
  bool is_stream() const { return mode_ != Mode::Temporary; }
  void write(std::string_view text);
  /// Flushes and checks for write errors (throws OutputError); the file stays open.
  void flush();
  /// Flushes, closes and renames onto the target. Throws OutputError; the temporary is then
  /// removed by the destructor.
  void commit();
  /// Closes and removes the temporary without publishing it.
  void discard();
  const std::filesystem::path& temp_path() const { return temp_.path(); }
  const std::filesystem::path& target() const { return temp_.target(); }

 private:
  enum class Mode { Temporary, StandardOutput, InPlace };
  void close();
  TempPath temp_;
  Mode mode_ = Mode::Temporary;
  std::FILE* file_ = nullptr;
};

}  // namespace lgvi::experiments
