#include "experiments/atomic_file.hpp"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>

namespace lgvi::experiments {

namespace fs = std::filesystem;

namespace {
std::string system_error(const std::string& what, int err) { return what + ": " + std::strerror(err); }
}  // namespace

TempPath::TempPath(fs::path target) : target_(std::move(target)) {
  static std::atomic<unsigned long> counter{0};
  // Built by appending: GCC 12 warns falsely (-Wrestrict) on "literal" + std::string.
  std::string name = ".";
  name.append(target_.filename().string()).append(".tmp-").append(std::to_string(::getpid()));
  name.append("-").append(std::to_string(counter++)).append(target_.extension().string());
  path_ = target_.parent_path() / name;
}

TempPath::~TempPath() {
  if (!committed_) {
    std::error_code ec;
    fs::remove(path_, ec);  // best effort; there is nothing more to do in a destructor
  }
}

void TempPath::commit() {
  if (std::rename(path_.c_str(), target_.c_str()) != 0) {
    throw OutputError(system_error(target_.string() + ": cannot rename the temporary file onto it", errno));
  }
  committed_ = true;
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
  std::fwrite(text.data(), 1, text.size(), file_);
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
