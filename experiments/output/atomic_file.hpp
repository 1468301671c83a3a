// Atomic output: every results file is written under a temporary name in the target's directory
// and renamed onto the target only when complete (rename(2) is atomic within a file system).
// If anything fails, or the owner is destroyed without commit(), the temporary is removed, so
// no half-written (or empty) results file is ever left behind.
//
// Two targets are streams, written in place instead (nothing to replace; not seekable):
// "-" is standard output, and an existing file that is not a regular file (a FIFO, a character
// device such as /dev/stdout or /dev/null, a socket; through symlinks) is opened and written as it
// is, never replaced by a regular file. So is an existing name in /dev itself, under /dev/fd or
// under /proc (/dev/stdout, /dev/fd/N, /proc/self/fd/N) when it leads to a regular file (standard
// output redirected to a file: appended to); such a name is never created. A directory is
// refused (OutputError), and so is a block device (a disk): a symlink planted at a results name
// must not make a run write onto one. A symlink at the target that leads to a regular file is
// replaced by the rename (the file it led to is untouched); the temporary itself is never opened
// through a symlink (TempPath).
#pragma once

#include <cstdio>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace lgvi::experiments {

/// A results file could not be written (disk, permissions, missing directory, gnuplot failure).
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A temporary file next to `target`, created by the constructor: "<dir>/.lgvi-tmp-<pid>-<r><extension>"
/// with r 16 hex digits drawn from getrandom(2) (the extension only when at most 16 bytes), short
/// whatever the target's name, so that any target name the file system admits (up to 255 bytes)
/// has a temporary. The name cannot be guessed, and the file is opened with O_CREAT | O_EXCL |
/// O_NOFOLLOW: whatever already has the name (a symlink planted by someone who can write in the
/// directory, a file) is never opened, written or truncated; another name is drawn instead (up to
/// 100 tries). The file (created mode 0644 less the umask) is removed by the destructor unless
/// commit() renamed it. Live temporaries are registered process-wide (remove_live_temporaries);
/// a killed process leaves its own, which remove_stale_temporaries recognizes by the pattern and
/// the dead pid.
class TempPath {
 public:
  /// Throws OutputError naming the target (the directory is missing or not writable, ...).
  explicit TempPath(std::filesystem::path target);
  ~TempPath();
  TempPath(const TempPath&) = delete;
  TempPath& operator=(const TempPath&) = delete;

  const std::filesystem::path& path() const { return path_; }
  const std::filesystem::path& target() const { return target_; }
  bool committed() const { return committed_; }
  /// The descriptor of the created file (read-write, close-on-exec), -1 once closed or released.
  int fd() const { return fd_; }
  /// Hands the descriptor over (to fdopen); the temporary is still removed unless committed.
  int release_fd();
  /// "/proc/self/fd/N" (N = fd()): a name of the open file itself, whatever is at path() by then.
  /// Another program is handed this name, with the descriptor inherited (run_gnuplot_script), so
  /// that it opens the file this process created, never a file planted at path() in between.
  /// path() itself when /proc is not mounted.
  std::string fd_path() const;
  /// Writes all of `text` at the descriptor's offset. Throws OutputError.
  void write(std::string_view text);
  /// Closes the descriptor (if still held) and renames the temporary onto the target, provided
  /// the name still leads to the file created here (its device and inode). Throws OutputError.
  void commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path path_;
  int fd_ = -1;
  unsigned long long dev_ = 0;
  unsigned long long ino_ = 0;
  bool committed_ = false;
};

/// Removes every temporary of this process not yet committed or removed (a run interrupted by a
/// signal, about to _Exit: destructors will not run), and refuses every later one (TempPath throws
/// OutputError): another thread would otherwise create one between the removal and the exit.
/// Best effort; returns how many were removed.
std::size_t remove_live_temporaries();

/// Removes, in `dir` and below, the temporaries ".lgvi-tmp-<pid>-..." of processes that no longer
/// exist (kill(pid, 0) fails with ESRCH), left by killed runs. Returns how many were removed.
std::size_t remove_stale_temporaries(const std::filesystem::path& dir);

/// A file written through a temporary and published by commit().
class AtomicFile {
 public:
  /// Creates the temporary (TempPath), or opens a stream target (above). Throws OutputError
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
  /// The temporary's path (empty for a stream target).
  std::filesystem::path temp_path() const { return temp_ ? temp_->path() : std::filesystem::path(); }
  const std::filesystem::path& target() const { return target_; }

 private:
  enum class Mode { Temporary, StandardOutput, InPlace };
  void close();
  std::filesystem::path target_;
  std::optional<TempPath> temp_;
  Mode mode_ = Mode::Temporary;
  std::FILE* file_ = nullptr;
};

}  // namespace lgvi::experiments
