// Reading an input file whole, bounded: the one way the harness reads the files a scene, a study
// or an option names (scene and study files, control samples, literature references, validate's
// accepted values, a suite run's manifest and journal, --check-against's summaries).
//
// The file must be a regular file (after symlinks): a FIFO would block the read for ever (even
// its open, without a writer), a device such as /dev/zero never ends; both are refused before a
// byte is read, and the open itself never blocks (O_NONBLOCK). At most `max_bytes` are read: a
// larger file is refused (its size from fstat, and the read stops one byte past the limit should
// the file grow meanwhile). The limits:
//  - kMaxTomlFileBytes, 1 MiB, for the TOML and JSON inputs a person writes or a run writes once
//    (scenes, studies, literature references, a suite run's manifest): the shipped ones take
//    1-10 kB, so 1 MiB is 100 times the largest and still parses in milliseconds;
//  - kMaxDataFileBytes, 64 MiB, for data (control samples: about a million rows of t, u1..u3;
//    validate's accepted values: ~60 bytes per metric, ~1000 metrics), far above what a scene
//    needs and small enough to read into memory on any machine the harness runs on;
//  - kMaxJournalFileBytes, 1 GiB, for a suite run's journal and summaries (1-3 kB per case, so
//    ~300,000 cases), which grow with the run.
#pragma once

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>

#include "lgvi/inertia.hpp"  // InvalidInput

namespace lgvi::experiments {

inline constexpr std::size_t kMaxTomlFileBytes = std::size_t{1} << 20;
inline constexpr std::size_t kMaxDataFileBytes = std::size_t{64} << 20;
inline constexpr std::size_t kMaxJournalFileBytes = std::size_t{1} << 30;

/// "1 MiB", "64 MiB", "1 GiB", or the bytes.
inline std::string byte_limit_text(std::size_t bytes) {
  if (bytes >= (std::size_t{1} << 30) && bytes % (std::size_t{1} << 30) == 0) {
    return std::to_string(bytes >> 30) + " GiB";
  }
  if (bytes >= (std::size_t{1} << 20) && bytes % (std::size_t{1} << 20) == 0) {
    return std::to_string(bytes >> 20) + " MiB";
  }
  return std::to_string(bytes) + " bytes";
}

/// What a non-regular file is, for messages: "a FIFO", "a character device", ...
inline const char* file_kind(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

/// A file that cannot be read as one: what() is "PATH: cannot read WHAT: REASON" (an InvalidInput
/// of field PATH); reason() is REASON alone.
class UnreadableFile : public InvalidInput {
 public:
  UnreadableFile(const std::filesystem::path& path, std::string_view what, std::string reason)
      : InvalidInput(path.string(), "cannot read " + std::string(what) + ": " + reason), reason_(std::move(reason)) {}
  const std::string& reason() const { return reason_; }

 private:
  std::string reason_;
};

/// The bytes of the regular file `path`, at most `max_bytes` of them. `what` names the file in
/// the message ("the scene file"). Throws UnreadableFile with the reason "is a FIFO, not a
/// regular file", "is a directory", "is larger than 1 MiB (N bytes), the limit for WHAT", or the
/// system's ("No such file or directory").
inline std::string read_regular_file(const std::filesystem::path& path, std::size_t max_bytes, std::string_view what) {
  const auto fail = [&](const std::string& reason) { return UnreadableFile(path, what, reason); };
  // stat first: a device is not even opened (opening one can have effects of its own).
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw fail(std::strerror(errno));
  const auto not_regular = [&](mode_t mode) {
    return fail(S_ISDIR(mode) ? std::string("is a directory") : std::string("is ") + file_kind(mode) + ", not a regular file");
  };
  if (!S_ISREG(st.st_mode)) throw not_regular(st.st_mode);
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw fail(std::strerror(errno));
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  if (::fstat(fd, &st) != 0) throw fail(std::strerror(errno));
  if (!S_ISREG(st.st_mode)) throw not_regular(st.st_mode);  // replaced since the stat
  const auto too_large = [&](std::size_t size, bool at_least) {
    return fail("is larger than " + byte_limit_text(max_bytes) + " (" + (at_least ? "more than " : "") +
                std::to_string(size) + " bytes), the limit for " + std::string(what));
  };
  if (static_cast<std::uintmax_t>(st.st_size) > max_bytes) throw too_large(static_cast<std::size_t>(st.st_size), false);
  std::string text(static_cast<std::size_t>(st.st_size), '\0');
  std::size_t have = 0;
  for (;;) {
    if (have == text.size()) {
      if (have > max_bytes) throw too_large(max_bytes, true);  // grew past the limit while read
      text.resize(std::min(max_bytes + 1, std::max<std::size_t>(2 * have, 4096)));
    }
    const ssize_t n = ::read(fd, text.data() + have, text.size() - have);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw fail(std::strerror(errno));
    if (n == 0) break;
    have += static_cast<std::size_t>(n);
  }
  text.resize(have);
  if (have > max_bytes) throw too_large(max_bytes, true);
  return text;
}

}  // namespace lgvi::experiments
