// Support for the experiments tests: a fresh temporary directory per test and a runner for the
// lgvi-testbed binary that captures exit code, stdout and stderr.
#pragma once

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/test_paths.hpp"

namespace lgvi::test {

namespace fs = std::filesystem;

inline std::string read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void write_text(const fs::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary);
  out << text;
}

inline std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

/// A fresh directory removed at the end of the test: `work` is where outputs go (and the
/// binary's working directory), `capture` holds the captured streams, `scenes` scene files.
class TempDir {
 public:
  TempDir() {
    static std::atomic<int> counter{0};
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::string name = info != nullptr ? std::string(info->test_suite_name()) + "." + info->name() : "test";
    root_ = fs::temp_directory_path() /
            ("lgvi-experiments-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + "-" + name);
    fs::remove_all(root_);
    fs::create_directories(work());
    fs::create_directories(capture());
    fs::create_directories(scenes());
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(root_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  fs::path work() const { return root_ / "work"; }
  fs::path capture() const { return root_ / "capture"; }
  fs::path scenes() const { return root_ / "scenes"; }

  /// Every entry of work(), hidden (temporary) files included.
  std::vector<std::string> work_entries() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(work())) names.push_back(e.path().filename().string());
    return names;
  }

 private:
  fs::path root_;
};

struct CliResult {
  int exit_code = -1;
  std::string out;
  std::string err;
  std::vector<std::string> err_lines() const { return lines_of(err); }
};

inline std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (const char c : s) q += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

/// Runs lgvi-testbed with `args` in dir.work(), capturing stdout/stderr into dir.capture().
inline CliResult run_testbed(const TempDir& dir, const std::vector<std::string>& args) {
  // Appends only: GCC 12 warns falsely (-Wrestrict) on "literal" + std::string.
  std::string cmd = "cd ";
  cmd.append(shell_quote(dir.work().string())).append(" && ").append(shell_quote(testbed_exe()));
  for (const std::string& a : args) cmd.append(" ").append(shell_quote(a));
  const fs::path out = dir.capture() / "stdout";
  const fs::path err = dir.capture() / "stderr";
  cmd.append(" >").append(shell_quote(out.string())).append(" 2>").append(shell_quote(err.string()));
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_text(out);
  r.err = read_text(err);
  return r;
}

inline fs::path default_scene_file(const std::string& name) {
  return fs::path(source_dir()) / "experiments" / "scenes" / (name + ".toml");
}

/// lgvi-testbed started with `args` in dir.work(), stdout discarded, stderr written to
/// `stderr_file` (discarded when empty); `in_child` runs in the child before the exec (a process
/// group, signal dispositions, resource limits). Returns its pid; the caller waits for it.
inline pid_t spawn_testbed(const TempDir& dir, const std::vector<std::string>& args,
                           const fs::path& stderr_file = {}, const std::function<void()>& in_child = {}) {
  std::vector<std::string> a = {testbed_exe()};
  a.insert(a.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& s : a) argv.push_back(s.data());
  argv.push_back(nullptr);
  const std::string work = dir.work().string();
  const std::string err = stderr_file.empty() ? std::string("/dev/null") : stderr_file.string();
  const pid_t pid = fork();
  if (pid == 0) {
    if (in_child) in_child();
    const int null = ::open("/dev/null", O_WRONLY);
    const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (null < 0 || e < 0 || chdir(work.c_str()) != 0) _exit(127);
    dup2(null, 1);
    dup2(e, 2);
    execv(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

/// A scene file's text with the first occurrence of `from` outside comment lines replaced by
/// `to` (which must exist).
inline std::string edited_scene(const std::string& name, const std::string& from, const std::string& to) {
  std::string text = read_text(default_scene_file(name));
  std::size_t at = text.find(from);
  while (at != std::string::npos) {
    const std::size_t line_start = text.rfind('\n', at) == std::string::npos ? 0 : text.rfind('\n', at) + 1;
    if (text[line_start] != '#') break;
    at = text.find(from, at + 1);
  }
  EXPECT_NE(at, std::string::npos) << "'" << from << "' not in " << name << ".toml";
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

/// CSV parts: the `# key: value` metadata, the header, the data rows (as text).
struct CsvParts {
  std::vector<std::pair<std::string, std::string>> metadata;
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;

  std::string meta(const std::string& key) const {
    for (const auto& [k, v] : metadata) {
      if (k == key) return v;
    }
    return "<missing>";
  }
  std::size_t column(const std::string& name) const {
    for (std::size_t i = 0; i < header.size(); ++i) {
      if (header[i] == name) return i;
    }
    ADD_FAILURE() << "no column " << name;
    return 0;
  }
};

inline std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(s);
  while (std::getline(in, part, sep)) parts.push_back(part);
  return parts;
}

inline CsvParts read_csv(const fs::path& file) {
  CsvParts csv;
  bool header_seen = false;
  for (const std::string& line : lines_of(read_text(file))) {
    if (!header_seen && line.find_first_not_of("# ") == std::string::npos) continue;  // a blank comment line
    if (!header_seen && line.rfind("# ", 0) == 0) {
      const std::size_t colon = line.find(": ");
      EXPECT_NE(colon, std::string::npos) << line;
      csv.metadata.emplace_back(line.substr(2, colon - 2), line.substr(colon + 2));
    } else if (!header_seen) {
      csv.header = split(line, ',');
      header_seen = true;
    } else {
      std::vector<double> row;
      for (const std::string& v : split(line, ',')) row.push_back(std::strtod(v.c_str(), nullptr));
      EXPECT_EQ(row.size(), csv.header.size()) << line;
      csv.rows.push_back(std::move(row));
    }
  }
  return csv;
}

/// Asserts the CLI failed with bad input: exit 1, one "error:" line containing every `needle`,
/// nothing on stdout, nothing (not even a temporary) in the output directory.
inline void expect_bad_input(const TempDir& dir, const CliResult& r, const std::vector<std::string>& needles) {
  EXPECT_EQ(r.exit_code, 1) << r.err;
  const std::vector<std::string> lines = r.err_lines();
  ASSERT_EQ(lines.size(), 1u) << r.err;
  EXPECT_EQ(lines[0].rfind("error: ", 0), 0u) << lines[0];
  for (const std::string& n : needles) EXPECT_NE(lines[0].find(n), std::string::npos) << "'" << n << "' not in: " << lines[0];
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_TRUE(dir.work_entries().empty()) << "left in the output dir: " << dir.work_entries().front();
}

}  // namespace lgvi::test
