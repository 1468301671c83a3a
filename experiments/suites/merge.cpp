#include "experiments/suites/merge.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <sstream>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "experiments/input/read_file.hpp"
#include "experiments/output/atomic_file.hpp"
#include "experiments/suites/suite.hpp"
#include "experiments/suites/journal.hpp"
#include "lgvi/inertia.hpp"

namespace lgvi::experiments {

namespace fs = std::filesystem;

namespace {

/// The head of a shard 0's summary.csv: its `# key: value` metadata lines and the header line
/// (without the last newline), checked.
std::string header_of(const fs::path& shard_dir) {
  const fs::path file = shard_dir / "summary.csv";
  std::istringstream in(read_regular_file(file, kMaxJournalFileBytes, "the shard's summary"));
  std::string head;
  std::string line;
  bool more = in && std::getline(in, line);
  while (more && line.starts_with("#")) {
    head += line + "\n";
    more = static_cast<bool>(std::getline(in, line));
  }
  if (!more || line.rfind("index,", 0) != 0) {
    throw InvalidInput(file.string(), "shard 0's summary has no header line 'index,...'");
  }
  return head + line;
}

/// Copies the regular file `from` (never through a symlink at its name) into the temporary
/// `to` (created exclusively: TempPath). Throws OutputError.
void copy_into(TempPath& to, const fs::path& from) {
  const auto fail = [&](const std::string& why) {
    return OutputError(to.target().string() + ": cannot copy from " + from.string() + ": " + why);
  };
  const int in = ::open(from.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (in < 0) throw fail(errno == ELOOP ? std::string("is a symbolic link") : std::strerror(errno));
  struct stat st {};
  if (::fstat(in, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(in);
    throw fail("not a regular file");
  }
  std::vector<char> buf(1 << 16);
  for (;;) {
    const ssize_t n = ::read(in, buf.data(), buf.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int err = errno;
      ::close(in);
      throw fail(std::strerror(err));
    }
    if (n == 0) break;
    try {
      to.write(std::string_view(buf.data(), static_cast<std::size_t>(n)));
    } catch (...) {
      ::close(in);
      throw;
    }
  }
  ::close(in);
}

/// Whether two paths name the same existing directory.
bool same_directory(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  return fs::equivalent(a, b, ec) && !ec;
}

}  // namespace

void merge_shards(const fs::path& out_dir, const std::vector<fs::path>& shard_dirs, std::ostream& progress) {
  if (shard_dirs.empty()) throw InvalidInput("merge", "no shard directories given");
  std::vector<SuiteManifest> manifests;
  for (const fs::path& dir : shard_dirs) {
    if (same_directory(dir, out_dir)) throw InvalidInput(dir.string(), "is the output directory; merge into a new one");
    manifests.push_back(read_manifest(dir));
  }
  const SuiteManifest& first = manifests.front();
  std::map<std::size_t, std::size_t> by_shard;  // shard index -> position in shard_dirs
  for (std::size_t n = 0; n < manifests.size(); ++n) {
    const SuiteManifest& m = manifests[n];
    const std::string where = manifest_path(shard_dirs[n]).string();
    const auto differs = [&](const std::string& what, const std::string& here, const std::string& there) {
      return InvalidInput(where, "is a run of " + what + " " + here + ", " + manifest_path(shard_dirs[0]).string() +
                                     " of " + there + ": not shards of one run");
    };
    if (m.suite != first.suite) throw differs("suite", m.suite, first.suite);
    if (m.quick != first.quick) throw differs("form", m.quick ? "quick" : "full", first.quick ? "quick" : "full");
    if (m.git_describe != first.git_describe) throw differs("version", m.git_describe, first.git_describe);
    if (m.fingerprint != first.fingerprint) {
      throw differs("fingerprint (cases, scene files)", m.fingerprint, first.fingerprint);
    }
    if (m.shard_count != first.shard_count || m.suite_cases != first.suite_cases) {
      throw differs("shard count", std::to_string(m.shard_count), std::to_string(first.shard_count));
    }
    if (!m.complete) {
      throw InvalidInput(where, "shard " + std::to_string(m.shard_index) + "/" + std::to_string(m.shard_count) +
                                    " is incomplete (" + std::to_string(m.finished) + " of " +
                                    std::to_string(m.shard_cases) + " cases finished" +
                                    (m.interrupted_by.empty() ? "" : ", interrupted by " + m.interrupted_by) +
                                    "): finish it with 'suite " + m.suite + " --shard " +
                                    std::to_string(m.shard_index) + "/" + std::to_string(m.shard_count) +
                                    " --resume --out " + shard_dirs[n].string() + "'");
    }
    if (!by_shard.emplace(m.shard_index, n).second) {
      throw InvalidInput(shard_dirs[n].string(), "shard " + std::to_string(m.shard_index) + " is also " +
                                                     shard_dirs[by_shard[m.shard_index]].string());
    }
  }
  std::string missing;
  for (std::size_t i = 0; i < first.shard_count && missing.size() < 200; ++i) {
    if (by_shard.count(i) == 0) missing += (missing.empty() ? "" : ", ") + std::to_string(i);
  }
  if (!missing.empty()) {
    throw InvalidInput("merge", "shards missing of " + std::to_string(first.shard_count) + ": " + missing);
  }

  // Every case of every shard recorded and its files verified, before anything is written.
  std::map<std::size_t, JournalEntry> all;
  std::map<std::size_t, const fs::path*> source;  // case index -> its shard directory
  for (const auto& item : by_shard) {
    const fs::path& dir = shard_dirs[item.second];
    const std::map<std::size_t, JournalEntry> entries = read_journal(dir);
    for (const std::size_t i : shard_cases(first.suite_cases, Shard{item.first, first.shard_count})) {
      const auto at = entries.find(i);
      if (at == entries.end()) {
        throw InvalidInput(journal_path(dir).string(), "case " + std::to_string(i) + " of shard " +
                                                           std::to_string(item.first) + " is not recorded");
      }
      if (at->second.fingerprint != first.fingerprint) {
        throw InvalidInput(journal_path(dir).string(), at->second.id + " was recorded by another run");
      }
      // The journal is data: each file it names must be a name inside the shard.
      for (const FileDigest& d : at->second.files) {
        if (const std::string why = case_file_name_problem(dir, d.path); !why.empty()) {
          throw InvalidInput(journal_path(dir).string(), "case " + at->second.id + ": the file '" + d.path + "' " +
                                                             why + " (a case's files are names inside its shard)");
        }
      }
      if (const std::string why = verify_files(dir, at->second); !why.empty()) {
        throw InvalidInput(dir.string(), at->second.id + ": " + why);
      }
      all[i] = at->second;
      source[i] = &dir;
    }
  }
  const std::string header = header_of(shard_dirs[by_shard.at(0)]);

  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec) throw OutputError(out_dir.string() + ": cannot create the output directory: " + ec.message());
  std::size_t copied = 0;
  for (const auto& item : all) {
    for (const FileDigest& d : item.second.files) {
      const fs::path target = out_dir / d.path;
      fs::create_directories(target.parent_path(), ec);
      if (ec) throw OutputError(target.parent_path().string() + ": cannot create the directory: " + ec.message());
      // Nor may a directory on the way in OUT be a symbolic link (one planted there would lead the
      // file elsewhere); a link at the target itself is replaced by the rename.
      if (const std::string why = case_file_name_problem(out_dir, d.path, /*check_last=*/false); !why.empty()) {
        throw OutputError(target.string() + ": " + why + " in the output directory");
      }
      TempPath temp(target);
      copy_into(temp, *source[item.first] / d.path);
      if (file_fnv1a64(temp.fd_path()) != d.fnv1a64) throw OutputError(target.string() + ": the copy differs from its source");
      temp.commit();
      ++copied;
    }
  }
  rewrite_journal(out_dir, all);
  write_summaries_from(out_dir, header, all);
  SuiteManifest merged = first;
  merged.shard_index = 0;
  merged.shard_count = 1;
  merged.shard_cases = first.suite_cases;
  merged.finished = all.size();
  merged.complete = true;
  merged.interrupted_by.clear();
  write_manifest(out_dir, merged);
  progress << "merged " << first.shard_count << " shards of suite " << first.suite << (first.quick ? " (quick)" : "")
           << ", " << first.git_describe << ": " << all.size() << " cases, " << copied << " files into "
           << out_dir.string() << "; 'suite " << first.suite << (first.quick ? " --quick" : "")
           << " --render-only --out " << out_dir.string() << "' draws the figures\n";
}

}  // namespace lgvi::experiments
