#include "experiments/output/atomic_file.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <mutex>
#include <set>

namespace lgvi::experiments {

namespace fs = std::filesystem;

namespace {
std::string system_error(const std::string& what, int err) { return what + ": " + std::strerror(err); }

constexpr std::string_view kTempPrefix = ".lgvi-tmp-";

/// The temporaries of this process not yet committed or removed.
struct LiveTemporaries {
  std::mutex mutex;
  std::set<fs::path> paths;
  bool closed = false;  ///< remove_live_temporaries ran: the process is ending
};
LiveTemporaries& live_temporaries() {
  static LiveTemporaries* live = new LiveTemporaries;  // never destroyed: used until _Exit
  return *live;
}
}  // namespace

namespace {

/// 64 unpredictable bits as 16 hex digits (getrandom(2); a clock and counter mix only if the
/// kernel refuses, which O_EXCL then still makes safe, if guessable).
std::string random_hex() {
  std::uint64_t r = 0;
  if (::getrandom(&r, sizeof r, 0) != static_cast<ssize_t>(sizeof r)) {
    static std::atomic<std::uint64_t> counter{0};
    r = static_cast<std::uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count()) ^
        (counter++ * 0x9e3779b97f4a7c15ull);
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(r));
  return buf;
}

/// A name in /dev itself, under /dev/fd or under /proc (/dev/stdout, /dev/fd/N, /proc/self/fd/N):
/// a descriptor or a device, written in place even when it leads to a regular file (standard
/// output redirected to a file). Replacing it by a rename would, as root, replace the system's
/// /dev/stdout link. (/dev/shm and other directories below /dev are file systems like any.)
bool names_a_descriptor_or_device(const fs::path& target) {
  std::error_code ec;
  const fs::path p = fs::absolute(target, ec).lexically_normal();
  if (ec) return false;
  const std::string s = p.string();
  return p.parent_path() == "/dev" || s.rfind("/dev/fd/", 0) == 0 || s.rfind("/proc/", 0) == 0;
}

void register_live(const fs::path& p) {
  LiveTemporaries& live = live_temporaries();
  const std::lock_guard lock(live.mutex);
  // After the cleanup of an ending process no temporary may start: a worker thread still running
  // a case would create one that nobody removes (seen: a suite interrupted by SIGTERM left one).
  if (live.closed) throw OutputError(p.parent_path().string() + ": the process is ending: no new temporary file");
  live.paths.insert(p);
}

void unregister_live(const fs::path& p) {
  LiveTemporaries& live = live_temporaries();
  const std::lock_guard lock(live.mutex);
  live.paths.erase(p);
}

}  // namespace

TempPath::TempPath(fs::path target) : target_(std::move(target)) {
  const std::string ext = target_.extension().string();
  constexpr int kTries = 100;
  int err = 0;
  for (int attempt = 0; attempt < kTries; ++attempt) {
    // Built by appending: GCC 12 warns falsely (-Wrestrict) on "literal" + std::string.
    std::string name(kTempPrefix);
    name.append(std::to_string(::getpid())).append("-").append(random_hex());
    if (ext.size() <= 16) name.append(ext);
    path_ = target_.parent_path() / name;
    // Registered before it exists: a signal's cleanup (remove_live_temporaries) sees it either way.
    register_live(path_);
    fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd_ >= 0) {
      struct stat st {};
      if (::fstat(fd_, &st) == 0) {
        dev_ = st.st_dev;
        ino_ = st.st_ino;
      }
      return;
    }
    err = errno;
    unregister_live(path_);
    if (err != EEXIST) break;  // a taken name (a planted link, a file): draw another
  }
  const std::string dir = target_.parent_path().empty() ? std::string(".") : target_.parent_path().string();
  throw OutputError(system_error(target_.string() + ": cannot create a temporary file in " + dir, err));
}

TempPath::~TempPath() {
  if (fd_ >= 0) ::close(fd_);
  if (!committed_) {
    // By name: the file this object created (the name was free, and is removed once only).
    ::unlink(path_.c_str());  // best effort; there is nothing more to do in a destructor
  }
  unregister_live(path_);
}

int TempPath::release_fd() {
  const int fd = fd_;
  fd_ = -1;
  return fd;
}

std::string TempPath::fd_path() const {
  static const bool proc_fd = ::access("/proc/self/fd", X_OK) == 0;
  if (fd_ < 0 || !proc_fd) return path_.string();
  return "/proc/self/fd/" + std::to_string(fd_);
}

void TempPath::write(std::string_view text) {
  while (!text.empty()) {
    const ssize_t n = ::write(fd_, text.data(), text.size());
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw OutputError(system_error(path_.string() + ": write error", n < 0 ? errno : ENOSPC));
    text.remove_prefix(static_cast<std::size_t>(n));
  }
}

void TempPath::commit() {
  if (fd_ >= 0) {
    const int fd = release_fd();
    if (::close(fd) != 0) throw OutputError(system_error(target_.string() + ": write error", errno));
  }
  // The name must still be the file created here: one replaced in between (by a link, by
  // another file) is not published as this run's result.
  struct stat st {};
  if (::lstat(path_.c_str(), &st) != 0 || st.st_dev != dev_ || st.st_ino != ino_) {
    throw OutputError(target_.string() + ": the temporary file " + path_.filename().string() +
                      " was replaced or removed by someone else before it was renamed onto the target");
  }
  if (std::rename(path_.c_str(), target_.c_str()) != 0) {
    throw OutputError(system_error(target_.string() + ": cannot rename the temporary file onto it", errno));
  }
  committed_ = true;
  unregister_live(path_);
}

std::size_t remove_live_temporaries() {
  LiveTemporaries& live = live_temporaries();
  const std::lock_guard lock(live.mutex);
  std::size_t removed = 0;
  for (const fs::path& p : live.paths) {
    std::error_code ec;
    removed += fs::remove(p, ec) ? 1 : 0;
  }
  live.paths.clear();
  live.closed = true;
  return removed;
}

std::size_t remove_stale_temporaries(const fs::path& dir) {
  std::size_t removed = 0;
  std::error_code ec;
  fs::recursive_directory_iterator it(dir, fs::directory_options::skip_permission_denied, ec);
  for (; !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.rfind(kTempPrefix, 0) != 0) continue;
    const char* first = name.data() + kTempPrefix.size();
    const char* last = name.data() + name.size();
    long pid = 0;
    const auto [end, perr] = std::from_chars(first, last, pid);
    if (perr != std::errc() || end == last || *end != '-' || pid <= 0) continue;
    if (pid == ::getpid() || ::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;
    std::error_code rec;
    if (it->is_regular_file(rec) && fs::remove(it->path(), rec)) ++removed;
  }
  return removed;
}

AtomicFile::AtomicFile(fs::path target) : target_(std::move(target)) {
  const fs::path& t = target_;
  if (t == "-") {
    mode_ = Mode::StandardOutput;
    file_ = stdout;
    return;
  }
  std::error_code ec;
  const fs::file_status status = fs::status(t, ec);  // follows symlinks (/dev/stdout)
  if (!ec && fs::is_directory(status)) throw OutputError(t.string() + ": is a directory, not a file");
  if (names_a_descriptor_or_device(t)) {
    if (ec || !fs::exists(status)) {
      throw OutputError(t.string() + ": does not exist (a name in /dev, /dev/fd or /proc is never created)");
    }
    if (fs::is_block_file(status)) {
      throw OutputError(t.string() + ": is a block device (a disk), not a results file; refusing to write onto it");
    }
    // Appended to: a regular file behind /dev/stdout was opened by the shell (with '>' it is
    // empty, with '>>' or after other output it is written after what it holds).
    mode_ = Mode::InPlace;
    file_ = std::fopen(t.c_str(), fs::is_regular_file(status) ? "a" : "w");
    if (file_ == nullptr) throw OutputError(system_error(t.string() + ": cannot open for writing", errno));
    return;
  }
  if (!ec && fs::is_block_file(status)) {
    throw OutputError(t.string() + ": is a block device (a disk), not a results file; refusing to write onto it");
  }
  if (!ec && fs::exists(status) && !fs::is_regular_file(status)) {
    mode_ = Mode::InPlace;
    file_ = std::fopen(t.c_str(), "w");
    if (file_ == nullptr) throw OutputError(system_error(t.string() + ": cannot open for writing", errno));
    return;
  }
  temp_.emplace(t);
  file_ = ::fdopen(temp_->fd(), "w+");
  if (file_ == nullptr) throw OutputError(system_error(t.string() + ": cannot open the temporary file", errno));
  (void)temp_->release_fd();  // the stream owns it now
}

AtomicFile::~AtomicFile() {
  if (file_ != nullptr && mode_ != Mode::StandardOutput) std::fclose(file_);
}

void AtomicFile::write(std::string_view text) {
  if (file_ == nullptr) throw OutputError(target().string() + ": write after commit");
  // A short write (a full disk, a quota) ends the run at once, not at commit: a long run would
  // otherwise go on computing rows that are lost.
  if (std::fwrite(text.data(), 1, text.size(), file_) != text.size()) {
    throw OutputError(system_error(target().string() + ": write error", errno));
  }
}

void AtomicFile::flush() {
  if (file_ == nullptr || std::fflush(file_) != 0 || std::ferror(file_) != 0) {
    throw OutputError(system_error(target().string() + ": write error", errno));
  }
}

void AtomicFile::close() {
  std::FILE* f = file_;
  file_ = nullptr;
  if (mode_ == Mode::StandardOutput) return;  // flushed; stdout stays open for the program
  if (std::fclose(f) != 0) throw OutputError(system_error(target().string() + ": write error", errno));
}

void AtomicFile::discard() {
  if (file_ != nullptr) {
    if (mode_ != Mode::StandardOutput) std::fclose(file_);
    file_ = nullptr;
  }
  if (mode_ != Mode::Temporary) return;  // what a stream received cannot be taken back
  temp_.reset();  // removes it
}

void AtomicFile::commit() {
  flush();
  close();
  if (mode_ == Mode::Temporary) temp_->commit();
}

}  // namespace lgvi::experiments
