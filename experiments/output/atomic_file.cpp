#include "experiments/output/atomic_file.hpp"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <charconv>
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
};
LiveTemporaries& live_temporaries() {
  static LiveTemporaries* live = new LiveTemporaries;  // never destroyed: used until _Exit
  return *live;
}
}  // namespace

TempPath::TempPath(fs::path target) : target_(std::move(target)) {
  static std::atomic<unsigned long> counter{0};
  // Built by appending: GCC 12 warns falsely (-Wrestrict) on "literal" + std::string.
  std::string name(kTempPrefix);
  name.append(std::to_string(::getpid())).append("-").append(std::to_string(counter++));
  const std::string ext = target_.extension().string();
  if (ext.size() <= 16) name.append(ext);
  path_ = target_.parent_path() / name;
  LiveTemporaries& live = live_temporaries();
  const std::lock_guard lock(live.mutex);
  live.paths.insert(path_);
}

TempPath::~TempPath() {
  if (!committed_) {
    std::error_code ec;
    fs::remove(path_, ec);  // best effort; there is nothing more to do in a destructor
  }
  LiveTemporaries& live = live_temporaries();
  const std::lock_guard lock(live.mutex);
  live.paths.erase(path_);
}

void TempPath::commit() {
  if (std::rename(path_.c_str(), target_.c_str()) != 0) {
    throw OutputError(system_error(target_.string() + ": cannot rename the temporary file onto it", errno));
  }
  committed_ = true;
  LiveTemporaries& live = live_temporaries();
  const std::lock_guard lock(live.mutex);
  live.paths.erase(path_);
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

AtomicFile::AtomicFile(fs::path target) : temp_(std::move(target)) {
  const fs::path& t = temp_.target();
  if (t == "-") {
    mode_ = Mode::StandardOutput;
    file_ = stdout;
    return;
  }
  std::error_code ec;
  const fs::file_status status = fs::status(t, ec);  // follows symlinks (/dev/stdout)
  if (!ec && fs::is_directory(status)) throw OutputError(t.string() + ": is a directory, not a file");
  if (!ec && fs::exists(status) && !fs::is_regular_file(status)) {
    mode_ = Mode::InPlace;
    file_ = std::fopen(t.c_str(), "w");
    if (file_ == nullptr) throw OutputError(system_error(t.string() + ": cannot open for writing", errno));
    return;
  }
  // "x": fail rather than clobber if the name is somehow taken.
  file_ = std::fopen(temp_.path().c_str(), "wx");
  if (file_ == nullptr) {
    throw OutputError(system_error(temp_.target().string() + ": cannot create a temporary file in " +
                                       (temp_.target().parent_path().empty() ? std::string(".")
                                                                             : temp_.target().parent_path().string()),
                                   errno));
  }
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
  std::error_code ec;
  std::filesystem::remove(temp_.path(), ec);
}

void AtomicFile::commit() {
  flush();
  close();
  if (mode_ == Mode::Temporary) temp_.commit();
}

}  // namespace lgvi::experiments
