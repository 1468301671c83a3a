// `merge` reads the files a shard's journal names and writes them under OUT: a doctored journal
// (a path with "..", an absolute path, a symlink inside the shard) must not make it read or write
// outside the shard and OUT (issue 34, N2). Refused with one error line naming the journal and the
// entry, exit 1, nothing written.
#include <functional>

#include <gtest/gtest.h>

#include "experiments/suites/journal.hpp"
#include "tests/experiments/cli/cli_support.hpp"

namespace lgvi::test {
namespace {

TEST(MergeSafety, CaseFileNamesMustBeNamesInsideTheirDirectory) {
  TempDir dir;
  const fs::path d = dir.work();
  using experiments::case_file_name_problem;
  EXPECT_EQ(case_file_name_problem(d, "a.csv"), "");
  EXPECT_EQ(case_file_name_problem(d, "sub/a.csv"), "");  // a missing directory is verify_files' business
  EXPECT_NE(case_file_name_problem(d, ""), "");
  EXPECT_NE(case_file_name_problem(d, "../a.csv").find("'..'"), std::string::npos);
  EXPECT_NE(case_file_name_problem(d, "sub/../../a.csv").find("'..'"), std::string::npos);
  EXPECT_NE(case_file_name_problem(d, "/etc/passwd").find("absolute"), std::string::npos);
  EXPECT_NE(case_file_name_problem(d, "./a.csv"), "");
  EXPECT_NE(case_file_name_problem(d, std::string("a.csv\0../x", 10)).find("NUL"), std::string::npos);
  fs::create_directory_symlink(dir.capture(), d / "link");
  EXPECT_NE(case_file_name_problem(d, "link/a.csv").find("symbolic link ('link')"), std::string::npos);
  write_text(dir.capture() / "b.csv", "x");
  fs::create_symlink(dir.capture() / "b.csv", d / "b.csv");
  EXPECT_NE(case_file_name_problem(d, "b.csv").find("symbolic link"), std::string::npos);
  EXPECT_EQ(case_file_name_problem(d, "b.csv", /*check_last=*/false), "");
}

/// Replaces the first `from` in `file` by `to`.
void edit_file(const fs::path& file, const std::string& from, const std::string& to) {
  std::string text = read_text(file);
  const std::size_t at = text.find(from);
  ASSERT_NE(at, std::string::npos) << from << " not in " << file;
  text.replace(at, from.size(), to);
  write_text(file, text);
}

TEST(MergeSafety, ADoctoredJournalCannotLeadOutsideTheShardOrTheOutput) {
  TempDir dir;
  for (const char* name : {"s00", "s01"}) {
    write_text(dir.scenes() / (std::string(name) + ".toml"), edited_scene("pendulum", "t_final = 20.0", "t_final = 0.1"));
  }
  const std::vector<std::string> base = {"--scenes-dir", dir.scenes().string(), "suite", "default"};
  for (int i = 0; i < 2; ++i) {
    std::vector<std::string> a = base;
    a.insert(a.end(), {"--out", "shard-" + std::to_string(i), "--shard", std::to_string(i) + "/2"});
    ASSERT_EQ(run_testbed(dir, a).exit_code, 0);
  }
  const fs::path shard = dir.work() / "shard-0";
  const fs::path journal = shard / "suite-journal.jsonl";
  const std::string original = read_text(journal);
  const std::string recorded = "\"path\":\"s00-symmetric.csv\"";
  ASSERT_NE(original.find(recorded), std::string::npos) << original.substr(0, 400);
  const std::string csv = read_text(shard / "s00-symmetric.csv");
  // Outside: files with the recorded bytes (so that only the name is wrong), and a directory.
  const fs::path outside = dir.capture() / "outside";
  fs::create_directories(outside);
  write_text(outside / "s00-symmetric.csv", csv);
  const fs::path escape = dir.work() / ".." / "escape.csv";  // shard-0/../../escape.csv, merged/../../escape.csv
  write_text(escape, csv);

  struct Doctoring {
    std::string path;          // recorded instead of s00-symmetric.csv
    std::function<void()> plant;
  };
  const std::vector<Doctoring> doctored = {
      {"../../escape.csv", [] {}},
      {(outside / "s00-symmetric.csv").string(), [] {}},
      {"sub/s00-symmetric.csv", [&] { fs::create_directory_symlink(outside, shard / "sub"); }},
      {"s00-symmetric.csv", [&] {  // the file itself a link (the journal unchanged)
         fs::rename(shard / "s00-symmetric.csv", dir.capture() / "kept.csv");
         fs::create_symlink(outside / "s00-symmetric.csv", shard / "s00-symmetric.csv");
       }},
  };
  for (const Doctoring& d : doctored) {
    SCOPED_TRACE(d.path);
    write_text(journal, original);
    if (d.path != "s00-symmetric.csv") edit_file(journal, recorded, "\"path\":\"" + d.path + "\"");
    d.plant();
    const CliResult r = run_testbed(dir, {"merge", "merged", "shard-0", "shard-1"});
    EXPECT_EQ(r.exit_code, 1) << r.err;
    ASSERT_EQ(r.err_lines().size(), 1u) << r.err;
    EXPECT_NE(r.err.find("error: " + (fs::path("shard-0") / "suite-journal.jsonl").string() + ": "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("case s00-symmetric: the file '" + d.path + "'"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir.work() / "merged"));
    EXPECT_EQ(read_text(escape), csv);
    std::error_code ec;
    fs::remove(shard / "sub", ec);
  }
  // Undone: the same shards merge.
  fs::remove(shard / "s00-symmetric.csv");
  fs::rename(dir.capture() / "kept.csv", shard / "s00-symmetric.csv");
  write_text(journal, original);
  const CliResult ok = run_testbed(dir, {"merge", "merged", "shard-0", "shard-1"});
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_EQ(read_text(dir.work() / "merged" / "s00-symmetric.csv"), csv);
}

}  // namespace
}  // namespace lgvi::test
