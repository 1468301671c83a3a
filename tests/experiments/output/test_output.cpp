// Atomic output: CSV writer, JSON summary, temporaries never left behind.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <charconv>
#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "experiments/cli/cli_support.hpp"
#include "experiments/output/atomic_file.hpp"
#include "experiments/output/csv_writer.hpp"
#include "experiments/output/json_writer.hpp"
#include "test_support.hpp"

namespace lgvi::experiments {
namespace {

using test::TempDir;

TEST(CsvWriter, LeavesNoFileWithoutCommit) {
  TempDir dir;
  {
    CsvWriter csv(dir.work() / "out.csv", {"t", "x"});
    const double row[] = {0.0, 1.0};
    csv.write_row(row);
    EXPECT_EQ(dir.work_entries().size(), 1u);  // the spool exists while writing...
  }
  EXPECT_TRUE(dir.work_entries().empty());  // ...and is gone with the writer, no out.csv
}

TEST(CsvWriter, WritesMetadataHeaderAndFullPrecisionRows) {
  TempDir dir;
  const auto target = dir.work() / "out.csv";
  CsvWriter csv(target, {"t", "x"});
  const double third = 1.0 / 3.0;
  const double rows[][2] = {{0.0, third}, {0.1, -1e-300}, {0.2, 6.02214076e23}};
  for (const auto& r : rows) csv.write_row(r);
  EXPECT_FALSE(std::filesystem::exists(target));
  csv.commit({{"scene", std::string("demo")}, {"h", 0.1}, {"steps", std::int64_t{2}},
              {"command_line", std::string("a\nb")}});
  const std::string text = test::read_text(target);
  EXPECT_EQ(text.substr(0, text.find("0,")),
            "# scene: demo\n# h: 0.10000000000000001\n# steps: 2\n# command_line: a b\nt,x\n");
  const test::CsvParts parts = test::read_csv(target);
  ASSERT_EQ(parts.rows.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(parts.rows[i][1], rows[i][1]);  // the shortest round-trip form reads back exactly
  }
  EXPECT_NE(text.find("\n0,0.3333333333333333\n0.1,-1e-300\n0.2,6.02214076e+23\n"), std::string::npos) << text;
  EXPECT_EQ(dir.work_entries(), std::vector<std::string>{"out.csv"});
}

/// `rows` rows of `columns` numbers of every magnitude and length (seeded), and the text the
/// writer made of them before its own formatter: std::to_chars each, ',' between, '\n' after.
struct RowsAndText {
  std::vector<std::vector<double>> rows;
  std::string text;
};
RowsAndText rows_and_text(std::size_t rows, std::size_t columns, std::uint64_t salt) {
  std::mt19937_64 rng = test::make_rng(salt);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-30, 30);
  RowsAndText out;
  for (std::size_t r = 0; r < rows; ++r) {
    std::vector<double> row(columns);
    for (std::size_t i = 0; i < columns; ++i) {
      switch (i % 4) {
        case 0: row[i] = 1e-3 * static_cast<double>(r); break;                     // a time
        case 1: row[i] = unit(rng); break;                                          // an attitude entry
        case 2: row[i] = unit(rng) * std::pow(10.0, exponent(rng)); break;          // any magnitude
        default: row[i] = static_cast<double>(static_cast<int>(rng() % 7)); break;  // a count
      }
    }
    for (std::size_t i = 0; i < columns; ++i) {
      char buf[32];
      out.text.append(buf, std::to_chars(buf, buf + sizeof buf, row[i]).ptr);
      out.text += i + 1 < columns ? ',' : '\n';
    }
    out.rows.push_back(std::move(row));
  }
  return out;
}

TEST(CsvWriter, RowsAreTheBytesOfToCharsAcrossTheRowBuffer) {
  // 6000 rows of 25 numbers (~2.6 MB, many times CsvWriter::kRowBufferSize): the rows are
  // std::to_chars's text, in order, whichever writer and however the buffer is cut.
  const RowsAndText data = rows_and_text(6000, 25, 1);
  ASSERT_GT(data.text.size(), 8 * CsvWriter::kRowBufferSize);
  const std::vector<std::string> columns(25, "c");
  const std::string header = "c,c,c,c,c,c,c,c,c,c,c,c,c,c,c,c,c,c,c,c,c,c,c,c,c\n";
  for (const bool leading : {false, true}) {
    TempDir dir;
    const auto target = dir.work() / "out.csv";
    std::optional<CsvWriter> csv;
    if (leading) {
      csv.emplace(target, columns, Fields{{"scene", std::string("demo")}}, 32);
    } else {
      csv.emplace(target, columns);
    }
    for (const auto& row : data.rows) csv->write_row(row);
    csv->commit({{"status", std::string("completed")}});
    const std::string text = test::read_text(target);
    const std::string meta = leading ? "# scene: demo\n# status: completed\n#" + std::string(32 - 20 - 2, ' ') + "\n"
                                     : "# status: completed\n";
    EXPECT_EQ(text.substr(0, meta.size() + header.size()), meta + header) << leading;
    EXPECT_TRUE(text.substr(meta.size() + header.size()) == data.text) << leading;  // no 2.6 MB diff printed
    const test::CsvParts parts = test::read_csv(target);
    ASSERT_EQ(parts.rows.size(), data.rows.size());
    for (std::size_t r = 0; r < data.rows.size(); r += 997) {
      for (std::size_t i = 0; i < 25; ++i) EXPECT_EQ(parts.rows[r][i], data.rows[r][i]);  // reads back exactly
    }
  }
}

TEST(CsvWriter, ARowWiderThanTheRowBufferIsWrittenWhole) {
  const std::size_t columns = CsvWriter::kRowBufferSize / 10;  // up to 25 bytes each: 2.5 buffers
  const RowsAndText data = rows_and_text(3, columns, 2);
  TempDir dir;
  const auto target = dir.work() / "wide.csv";
  CsvWriter csv(target, std::vector<std::string>(columns, "c"), {}, 2);
  for (const auto& row : data.rows) csv.write_row(row);
  csv.commit({});
  const std::string text = test::read_text(target);
  EXPECT_TRUE(text.substr(2 + 2 * columns) == data.text);  // past the block "#\n" and the header
  EXPECT_EQ(test::read_csv(target).rows.size(), 3u);
}

TEST(CsvWriter, AStreamTargetReceivesEveryRowWithTheTrailer) {
  // A descriptor name is a stream target (atomic_file.hpp): with leading metadata the rows go
  // out as the buffer fills and the closing metadata follows them; without, all at commit. A
  // writer destroyed without commit still sends the rows it gathered.
  const RowsAndText data = rows_and_text(3000, 25, 3);
  for (const int variant : {0, 1, 2}) {  // leading metadata; none; leading, never committed
    TempDir dir;
    const auto file = dir.work() / "stream.csv";
    test::write_text(file, "");
    const int fd = ::open(file.c_str(), O_WRONLY | O_APPEND);
    ASSERT_GE(fd, 0);
    {
      const std::filesystem::path name = "/proc/self/fd/" + std::to_string(fd);
      std::optional<CsvWriter> csv;
      if (variant == 1) {
        csv.emplace(name, std::vector<std::string>{"t", "x"});
      } else {
        csv.emplace(name, std::vector<std::string>(25, "c"), Fields{{"scene", std::string("demo")}});
      }
      for (const auto& row : data.rows) {
        csv->write_row(variant == 1 ? std::span<const double>(row).first(2) : std::span<const double>(row));
      }
      if (variant != 2) csv->commit({{"status", std::string("completed")}});
    }
    ::close(fd);
    const std::string text = test::read_text(file);
    if (variant == 1) {
      EXPECT_EQ(text.substr(0, 24), "# status: completed\nt,x\n");
      EXPECT_EQ(test::read_csv(file).rows.size(), data.rows.size());
    } else {
      const std::string head = "# scene: demo\nc,c,c,c,c,c,c,c,c,c,c,c,c,c,c,c,c,c,c,c,c,c,c,c,c\n";
      const std::string tail = variant == 0 ? "# status: completed\n" : "";
      EXPECT_TRUE(text == head + data.text + tail) << variant;
    }
    EXPECT_EQ(dir.work_entries(), std::vector<std::string>{"stream.csv"});
  }
}

TEST(CsvWriter, AWriterDestroyedMidRunLeavesNoFile) {
  // Rows beyond the buffer were written to the temporary already: it is removed all the same.
  const RowsAndText data = rows_and_text(3000, 25, 4);
  TempDir dir;
  {
    CsvWriter csv(dir.work() / "out.csv", std::vector<std::string>(25, "c"), {{"scene", std::string("demo")}});
    for (const auto& row : data.rows) csv.write_row(row);
    ASSERT_EQ(dir.work_entries().size(), 1u);
    EXPECT_GT(std::filesystem::file_size(dir.work() / dir.work_entries().front()), CsvWriter::kRowBufferSize);
  }
  EXPECT_TRUE(dir.work_entries().empty());
}

/// Inode of the only file in `dir` (the writer's temporary while it writes).
ino_t only_inode(const TempDir& dir) {
  const std::vector<std::string> names = dir.work_entries();
  EXPECT_EQ(names.size(), 1u);
  struct stat st {};
  EXPECT_EQ(::stat((dir.work() / names.front()).c_str(), &st), 0);
  return st.st_ino;
}

TEST(CsvWriter, LeadingMetadataAndAReservedBlockWriteTheRowsOnce) {
  // Metadata known up front is written at once, the closing metadata into the reserved block:
  // the file the rows were written to is the file published (same inode), nothing is copied.
  TempDir dir;
  const auto target = dir.work() / "out.csv";
  CsvWriter csv(target, {"t", "x"}, {{"scene", std::string("demo")}, {"h", 0.1}}, 64);
  for (int k = 0; k < 1000; ++k) {
    const double row[] = {0.1 * k, 1.0 / (k + 1)};
    csv.write_row(row);
  }
  const ino_t written = only_inode(dir);
  csv.commit({{"status", std::string("completed")}, {"output_rows", std::int64_t{1000}}});
  EXPECT_EQ(only_inode(dir), written);
  const std::string text = test::read_text(target);
  const std::string closing = "# status: completed\n# output_rows: 1000\n";
  EXPECT_EQ(text.substr(0, text.find("t,x\n")),
            "# scene: demo\n# h: 0.10000000000000001\n" + closing + "#" + std::string(64 - closing.size() - 2, ' ') +
                "\n");
  const test::CsvParts parts = test::read_csv(target);
  EXPECT_EQ(parts.meta("status"), "completed");
  EXPECT_EQ(parts.meta("output_rows"), "1000");
  ASSERT_EQ(parts.rows.size(), 1000u);
  EXPECT_EQ(parts.rows[999][1], 1.0 / 1000);
}

TEST(CsvWriter, ClosingMetadataLongerThanTheBlockIsCopiedBehindIt) {
  TempDir dir;
  const auto target = dir.work() / "out.csv";
  CsvWriter csv(target, {"t"}, {{"scene", std::string("demo")}}, 16);
  const double row[] = {0.5};
  csv.write_row(row);
  const ino_t written = only_inode(dir);
  const std::string status(100, 's');
  csv.commit({{"status", status}});
  EXPECT_NE(only_inode(dir), written);  // a second file: the rows were copied
  EXPECT_EQ(test::read_text(target), "# scene: demo\n# status: " + status + "\nt\n0.5\n");
}

TEST(CsvWriter, ClosingMetadataThatFillsTheBlockExactly) {
  const std::string closing = "# k: v\n";  // 7 bytes
  for (const std::size_t reserve : {closing.size(), closing.size() + 1, closing.size() + 2}) {
    TempDir dir;
    const auto target = dir.work() / "out.csv";
    CsvWriter csv(target, {"t"}, {}, reserve);
    const ino_t written = only_inode(dir);
    csv.commit({{"k", std::string("v")}});
    // One byte left cannot hold a blank comment line ("#\n"): then the rows are copied.
    const bool in_block = reserve != closing.size() + 1;
    EXPECT_EQ(only_inode(dir) == written, in_block) << reserve;
    EXPECT_EQ(test::read_text(target), closing + (reserve == closing.size() + 2 ? "#\n" : "") + "t\n") << reserve;
  }
}

TEST(CsvWriter, CommitReplacesAnExistingFile) {
  TempDir dir;
  const auto target = dir.work() / "out.csv";
  test::write_text(target, "old");
  CsvWriter csv(target, {"t"});
  EXPECT_EQ(test::read_text(target), "old");  // untouched until commit
  csv.commit({});
  EXPECT_EQ(test::read_text(target), "t\n");
}

TEST(CsvWriter, UnwritableDirectoryThrowsAndLeavesNothing) {
  TempDir dir;
  EXPECT_THROW(CsvWriter(dir.work() / "missing" / "out.csv", {"t"}), OutputError);
  EXPECT_TRUE(dir.work_entries().empty());
}

TEST(CsvWriter, FailedRenameLeavesNoTemporary) {
  TempDir dir;
  {
    CsvWriter csv(dir.work() / "taken.csv", {"t"});
    // The name becomes a directory while the file is written: the rename fails.
    std::filesystem::create_directory(dir.work() / "taken.csv");
    EXPECT_THROW(csv.commit({}), OutputError);
  }
  EXPECT_EQ(dir.work_entries(), std::vector<std::string>{"taken.csv"});
}

TEST(AtomicFile, RefusesADirectoryUpFront) {
  TempDir dir;
  std::filesystem::create_directory(dir.work() / "taken.csv");
  EXPECT_THROW(AtomicFile(dir.work() / "taken.csv"), OutputError);
  EXPECT_EQ(dir.work_entries(), std::vector<std::string>{"taken.csv"});
}

TEST(AtomicFile, DestroyedWithoutCommitLeavesNothing) {
  TempDir dir;
  {
    AtomicFile f(dir.work() / "a.json");
    f.write("partial");
  }
  EXPECT_TRUE(dir.work_entries().empty());
}

TEST(AtomicFile, AFailedWriteThrowsAtOnceNotAtCommit) {
  // /dev/full fails every write with ENOSPC, as a full disk does; a character device is written
  // in place. A block larger than any stdio buffer reaches the device within write().
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full on this machine";
  AtomicFile f("/dev/full");
  const std::string block(std::size_t{1} << 20, 'x');
  try {
    f.write(block);
    ADD_FAILURE() << "a write to /dev/full did not throw";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("/dev/full: write error"), std::string::npos) << e.what();
  }
}

TEST(JsonSummary, OneObjectPerLineAndNullForNonFinite) {
  TempDir dir;
  const auto target = dir.work() / "summary.json";
  write_json_summary(target, {{{"scene", std::string("a\"b")}, {"x", 0.1}, {"n", std::int64_t{3}}},
                              {{"bad", std::numeric_limits<double>::quiet_NaN()}, {"ok", true}}});
  EXPECT_EQ(test::read_text(target),
            "[\n{\"scene\": \"a\\\"b\", \"x\": 0.1, \"n\": 3},\n{\"bad\": null, \"ok\": true}\n]\n");
}

TEST(FieldText, DoublesRoundTrip) {
  EXPECT_EQ(to_text(FieldValue{0.1}), "0.10000000000000001");
  EXPECT_EQ(to_text(FieldValue{std::int64_t{-4}}), "-4");
  EXPECT_EQ(shortest(0.1), "0.1");
}

}  // namespace
}  // namespace lgvi::experiments
