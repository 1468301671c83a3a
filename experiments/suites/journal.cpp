#include "experiments/suites/journal.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <sstream>

#include <nlohmann/json.hpp>

#include "experiments/input/read_file.hpp"
#include "experiments/output/atomic_file.hpp"
#include "experiments/scene/scene.hpp"
#include "experiments/methods/simulate.hpp"
#include "experiments/suites/suite.hpp"
#include "lgvi/inertia.hpp"

namespace lgvi::experiments {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr std::uint64_t kFnvOffset = 14695981039346656037ull;
constexpr std::uint64_t kFnvPrime = 1099511628211ull;

std::uint64_t fnv_update(std::uint64_t h, const char* data, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    h ^= static_cast<unsigned char>(data[i]);
    h *= kFnvPrime;
  }
  return h;
}

std::string hex(std::uint64_t h) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

// The files a scene reads besides itself (Scene::inputs: control samples); none when it does not
// parse (the suite reports that when it loads the scene).
std::vector<fs::path> scene_inputs(const fs::path& scene_file) {
  try {
    return parse_scene_file(scene_file).inputs;
  } catch (const SceneError&) {
    return {};
  }
}

}  // namespace

std::string text_fnv1a64(const std::string& text) { return hex(fnv_update(kFnvOffset, text.data(), text.size())); }

std::string file_fnv1a64(const fs::path& file) {
  // Regular files only (a FIFO would block, a device such as /dev/zero never end); the open
  // never blocks.
  const int fd = ::open(file.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return "";
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    return "";
  }
  std::uint64_t h = kFnvOffset;
  std::vector<char> buf(1 << 16);
  for (;;) {
    const ssize_t n = ::read(fd, buf.data(), buf.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      ::close(fd);
      return "";
    }
    if (n == 0) break;
    h = fnv_update(h, buf.data(), static_cast<std::size_t>(n));
  }
  ::close(fd);
  return hex(h);
}

std::string suite_fingerprint(const Suite& suite, bool quick, const fs::path& scenes_dir) {
  std::string text = suite.name + "\n" + (quick ? "quick" : "full") + "\n" + std::string(git_describe()) + "\n";
  for (const SuiteCase& c : suite.cases) {
    text += c.id + "\t" + c.group + "\t" + to_string(c.expect) + "\t" + to_json(c.labels) + "\n";
  }
  std::vector<fs::path> scenes;
  std::error_code ec;
  for (fs::directory_iterator it(scenes_dir, ec); !ec && it != fs::directory_iterator(); it.increment(ec)) {
    if (it->path().extension() == ".toml") scenes.push_back(it->path());
  }
  std::sort(scenes.begin(), scenes.end());
  for (const fs::path& p : scenes) {
    text += p.filename().string() + "\t" + file_fnv1a64(p) + "\n";
    for (const fs::path& in : scene_inputs(p)) text += "reads\t" + in.filename().string() + "\t" + file_fnv1a64(in) + "\n";
  }
  for (const SuiteInput& in : suite.inputs) text += "input\t" + in.what + "\t" + in.digest + "\n";
  return text_fnv1a64(text);
}

fs::path manifest_path(const fs::path& out_dir) { return out_dir / "suite-run.json"; }
fs::path journal_path(const fs::path& out_dir) { return out_dir / "suite-journal.jsonl"; }

void write_manifest(const fs::path& out_dir, const SuiteManifest& m) {
  json j = {{"suite", m.suite},
            {"quick", m.quick},
            {"git_describe", m.git_describe},
            {"fingerprint", m.fingerprint},
            {"shard", std::to_string(m.shard_index) + "/" + std::to_string(m.shard_count)},
            {"shard_index", m.shard_index},
            {"shard_count", m.shard_count},
            {"suite_cases", m.suite_cases},
            {"shard_cases", m.shard_cases},
            {"finished", m.finished},
            {"complete", m.complete},
            {"interrupted_by", m.interrupted_by}};
  if (!m.inputs.empty()) {
    json inputs = json::array();
    for (const SuiteInput& in : m.inputs) inputs.push_back({{"what", in.what}, {"digest", in.digest}});
    j["inputs"] = inputs;
  }
  AtomicFile f(manifest_path(out_dir));
  f.write(j.dump(1) + "\n");
  f.commit();
}

SuiteManifest read_manifest(const fs::path& out_dir) {
  const fs::path file = manifest_path(out_dir);
  std::error_code ec;
  if (!fs::exists(file, ec)) {
    throw InvalidInput(file.string(), "cannot be read (not the output directory of a suite run?)");
  }
  const json j = json::parse(read_regular_file(file, kMaxTomlFileBytes, "the suite manifest"), nullptr, false);
  if (j.is_discarded() || !j.is_object()) throw InvalidInput(file.string(), "is not a JSON object");
  SuiteManifest m;
  try {
    m.suite = j.at("suite").get<std::string>();
    m.quick = j.at("quick").get<bool>();
    m.git_describe = j.at("git_describe").get<std::string>();
    m.fingerprint = j.at("fingerprint").get<std::string>();
    m.shard_index = j.at("shard_index").get<std::size_t>();
    m.shard_count = j.at("shard_count").get<std::size_t>();
    m.suite_cases = j.at("suite_cases").get<std::size_t>();
    m.shard_cases = j.at("shard_cases").get<std::size_t>();
    m.finished = j.at("finished").get<std::size_t>();
    m.complete = j.at("complete").get<bool>();
    m.interrupted_by = j.value("interrupted_by", std::string());
    if (j.contains("inputs")) {
      for (const json& in : j.at("inputs")) {
        m.inputs.push_back({in.at("what").get<std::string>(), in.at("digest").get<std::string>()});
      }
    }
  } catch (const json::exception& e) {
    throw InvalidInput(file.string(), std::string("malformed manifest: ") + e.what());
  }
  return m;
}

std::vector<FileDigest> digest_case_files(const fs::path& out_dir, const std::string& jsonl_line) {
  const json row = json::parse(jsonl_line, nullptr, false);
  std::vector<FileDigest> files;
  if (!row.is_object()) return files;
  for (const auto& item : row.items()) {
    const std::string& key = item.key();
    if (key.size() < 5 || key.compare(key.size() - 5, 5, "_path") != 0 || !item.value().is_string()) continue;
    FileDigest d;
    d.path = item.value().get<std::string>();
    if (d.path.empty()) continue;
    const fs::path p = out_dir / d.path;
    std::error_code ec;
    d.size = fs::file_size(p, ec);
    if (ec) continue;  // named but not written (a rejected case): not one of its outputs
    d.fnv1a64 = file_fnv1a64(p);
    files.push_back(std::move(d));
  }
  return files;
}

std::string case_file_name_problem(const fs::path& dir, const std::string& name, bool check_last) {
  if (name.empty()) return "is empty";
  if (name.find('\0') != std::string::npos) return "contains a NUL byte";
  const fs::path rel(name);
  if (rel.is_absolute() || rel.has_root_name() || rel.has_root_directory()) return "is an absolute path";
  std::vector<fs::path> parts(rel.begin(), rel.end());
  for (const fs::path& part : parts) {
    if (part == "..") return "has a '..' component";
    if (part.empty() || part == ".") return "has an empty or '.' component";
  }
  fs::path at = dir;
  fs::path shown;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    at /= parts[i];
    shown /= parts[i];
    if (i + 1 == parts.size() && !check_last) break;
    struct stat st {};
    if (::lstat(at.c_str(), &st) != 0) break;  // missing from here on: verify_files says so
    if (S_ISLNK(st.st_mode)) return "has a component that is a symbolic link ('" + shown.string() + "')";
  }
  return "";
}

std::string verify_files(const fs::path& out_dir, const JournalEntry& e) {
  for (const FileDigest& d : e.files) {
    if (const std::string why = case_file_name_problem(out_dir, d.path); !why.empty()) {
      return "the recorded file '" + d.path + "' " + why;
    }
    const fs::path p = out_dir / d.path;
    std::error_code ec;
    const std::uintmax_t size = fs::file_size(p, ec);
    if (ec) return p.string() + " is missing";
    if (size != d.size) return p.string() + " has " + std::to_string(size) + " bytes, " + std::to_string(d.size) + " recorded";
    if (file_fnv1a64(p) != d.fnv1a64) return p.string() + " differs from the file recorded (digest)";
  }
  return "";
}

namespace {

std::string entry_line(const JournalEntry& e) {
  json files = json::array();
  for (const FileDigest& d : e.files) files.push_back({{"path", d.path}, {"size", d.size}, {"fnv1a64", d.fnv1a64}});
  // nlohmann::json orders keys alphabetically; "done" is written last by hand (the marker).
  const json j = {{"index", e.index},          {"case", e.id},   {"fingerprint", e.fingerprint},
                  {"csv_line", e.csv_line},    {"jsonl_line", e.jsonl_line}, {"files", files}};
  std::string line = j.dump();
  line.pop_back();  // '}'
  line += ",\"done\":true}\n";
  return line;
}

}  // namespace

JournalWriter::JournalWriter(const fs::path& out_dir, bool truncate) : path_(journal_path(out_dir)) {
  // A new journal is created empty through a temporary renamed onto the name (which replaces a
  // symlink planted there instead of truncating what it points to); the journal is then opened
  // without following a symlink (O_NOFOLLOW) and must be a regular file with one link (not a
  // hard link to another file), so appends go into this run's journal only.
  if (truncate) rewrite_journal(out_dir, {});
  fd_ = ::open(path_.c_str(), O_WRONLY | O_APPEND | O_NOFOLLOW | O_CLOEXEC);
  if (fd_ < 0) {
    const int err = errno;
    throw OutputError(path_.string() + ": cannot open the suite journal: " +
                      (err == ELOOP ? std::string("is a symbolic link") : std::strerror(err)));
  }
  struct stat st {};
  if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode) || st.st_nlink != 1) {
    ::close(fd_);
    fd_ = -1;
    throw OutputError(path_.string() + ": cannot open the suite journal: not a regular file with a single link");
  }
}

JournalWriter::~JournalWriter() {
  if (fd_ >= 0) ::close(fd_);
}

void JournalWriter::append(const JournalEntry& e) {
  const std::string line = entry_line(e);
  // One write: O_APPEND places it at the end as a whole; a short write (disk full) is an error.
  const ssize_t n = ::write(fd_, line.data(), line.size());
  if (n != static_cast<ssize_t>(line.size())) {
    throw OutputError(path_.string() + ": cannot append to the suite journal: " +
                      (n < 0 ? std::strerror(errno) : "short write (disk full?)"));
  }
}

std::map<std::size_t, JournalEntry> read_journal(const fs::path& out_dir) {
  std::map<std::size_t, JournalEntry> entries;
  const fs::path file = journal_path(out_dir);
  std::error_code ec;
  if (!fs::exists(file, ec)) return entries;
  std::istringstream in(read_regular_file(file, kMaxJournalFileBytes, "the suite journal"));
  std::string line;
  while (std::getline(in, line)) {
    const json j = json::parse(line, nullptr, false);
    if (j.is_discarded() || !j.is_object() || !j.contains("done") || j["done"] != true) continue;
    try {
      JournalEntry e;
      e.index = j.at("index").get<std::size_t>();
      e.id = j.at("case").get<std::string>();
      e.fingerprint = j.at("fingerprint").get<std::string>();
      e.csv_line = j.at("csv_line").get<std::string>();
      e.jsonl_line = j.at("jsonl_line").get<std::string>();
      for (const json& f : j.at("files")) {
        e.files.push_back({f.at("path").get<std::string>(), f.at("size").get<std::uintmax_t>(),
                           f.at("fnv1a64").get<std::string>()});
      }
      entries[e.index] = std::move(e);
    } catch (const json::exception&) {
      continue;  // not an entry of this format: as good as absent
    }
  }
  return entries;
}

void rewrite_journal(const fs::path& out_dir, const std::map<std::size_t, JournalEntry>& entries) {
  AtomicFile f(journal_path(out_dir));
  for (const auto& item : entries) f.write(entry_line(item.second));
  f.commit();
}

void write_summaries_from(const fs::path& out_dir, const std::string& header,
                          const std::map<std::size_t, JournalEntry>& entries) {
  AtomicFile csv(out_dir / "summary.csv");
  AtomicFile jsonl(out_dir / "summary.jsonl");
  if (!header.empty()) csv.write(header + "\n");
  for (const auto& item : entries) {
    csv.write(item.second.csv_line + "\n");
    jsonl.write(item.second.jsonl_line + "\n");
  }
  csv.commit();
  jsonl.commit();

  // The all suite's cases are PART/ID: each part's folder gets its own summary of its rows.
  std::map<std::string, std::vector<const JournalEntry*>> parts;
  for (const auto& item : entries) {
    const std::size_t slash = item.second.id.find('/');
    if (slash != std::string::npos) parts[item.second.id.substr(0, slash)].push_back(&item.second);
  }
  for (const auto& [part, rows] : parts) {
    if (!fs::is_directory(out_dir / part)) continue;
    AtomicFile part_csv(out_dir / part / "summary.csv");
    AtomicFile part_jsonl(out_dir / part / "summary.jsonl");
    part_csv.write("# rows: the cases " + part + "/* of the run in the parent directory; their file paths are relative to it\n");
    if (!header.empty()) part_csv.write(header + "\n");
    for (const JournalEntry* e : rows) {
      part_csv.write(e->csv_line + "\n");
      part_jsonl.write(e->jsonl_line + "\n");
    }
    part_csv.commit();
    part_jsonl.commit();
  }
}

}  // namespace lgvi::experiments
