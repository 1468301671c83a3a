// CSV results (DESIGN.md, output conventions): `# key: value` metadata lines, one header row,
// then data rows, each number in the shortest form that reads back to the same double
// (std::to_chars). The file is written under a temporary name and renamed onto the target at
// commit, so it appears complete or not at all.
//
// Rows are written once, into that temporary file, as they come. The metadata must come first,
// but part of it (a run's final status, its step counts) is known only at the end; so a writer
// made with the metadata known up front writes those lines at once, then reserves a block of
// bytes for the closing metadata, then the header, then the rows; commit() writes the closing
// lines into the block and fills the rest of it with one blank comment line ('#' and spaces).
// Closing metadata longer than the block (or a writer made without one) is written by copying
// the rows once more into a second temporary file behind the complete metadata.
//
// Rows are formatted into one buffer of kRowBufferSize bytes, allocated with the writer, and
// handed to the file when the next row might not fit (and at commit): one write per 64 KiB,
// nothing allocated per row. Numbers are written by write_shortest (shortest.hpp), byte for byte
// std::to_chars's text.
//
// A stream target ("-" for standard output, an existing FIFO or device: atomic_file.hpp) cannot
// seek back: with leading metadata, the rows stream out as they come and the closing metadata
// follows the last row as `# key: value` lines (a trailer); without, the rows are held in memory
// and written behind the complete metadata at commit.
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "experiments/output/atomic_file.hpp"
#include "experiments/output/fields.hpp"

namespace lgvi::experiments {

class CsvWriter {
 public:
  /// Bytes reserved for the closing metadata by default: a status line (the longest seen are
  /// solver failures with the solver's message, ~250 characters) and a few counts.
  static constexpr std::size_t kDefaultReserve = 512;
  /// Bytes of rows gathered before they are written.
  static constexpr std::size_t kRowBufferSize = std::size_t{1} << 16;

  /// All metadata at commit: the rows are copied once behind it then. For small outputs.
  /// Throws OutputError.
  CsvWriter(std::filesystem::path target, std::vector<std::string> columns);
  /// Metadata known up front (`leading`, written at once), `reserve` bytes for commit()'s closing
  /// metadata, then the header; the rows are written once. Throws OutputError.
  CsvWriter(std::filesystem::path target, std::vector<std::string> columns, const Fields& leading,
            std::size_t reserve = kDefaultReserve);
  /// Without commit: the temporary is removed; a stream target still receives the rows gathered
  /// (as it received every row before them).
  ~CsvWriter();
  CsvWriter(const CsvWriter&) = delete;
  CsvWriter& operator=(const CsvWriter&) = delete;

  const std::vector<std::string>& columns() const { return columns_; }
  /// Appends one data row. Precondition: values.size() == columns().size().
  void write_row(std::span<const double> values);
  std::size_t rows() const { return rows_; }

  /// Completes the metadata with `closing` (after the leading lines) and publishes the file
  /// atomically. Newlines inside metadata values are replaced by spaces (one line per key).
  /// Throws OutputError. Without a successful commit, the destructor leaves no file behind.
  void commit(const Fields& closing);

  const std::filesystem::path& target() const { return target_; }

 private:
  std::filesystem::path target_;
  std::vector<std::string> columns_;
  std::string leading_;        ///< the leading metadata lines
  AtomicFile file_;
  std::size_t reserve_ = 0;    ///< size of the reserved block (0: none, the header is not written yet)
  long reserve_offset_ = 0;    ///< where the block starts
  long rows_offset_ = 0;       ///< where the rows start
  std::size_t rows_ = 0;
  bool trailer_ = false;       ///< stream target with leading metadata: closing metadata after the rows
  bool buffered_ = false;      ///< stream target without: rows held in `buffer_` until commit
  std::string buffer_;
  std::unique_ptr<char[]> rows_buffer_;  ///< kRowBufferSize bytes: rows not yet handed on
  std::size_t pending_ = 0;              ///< bytes of rows in rows_buffer_

  void emit(std::string_view text);
  /// Hands the pending rows to the file (or buffer_). Throws OutputError.
  void drain();
};

/// The metadata lines of `fields`: "# key: value\n" each, newlines in keys and values replaced by
/// spaces.
std::string metadata_lines(const Fields& fields);

/// The cells of one row of a CSV the harness wrote (cells hold no commas: see csv_writer.cpp and
/// suite.cpp's cell()).
std::vector<std::string> split_csv_row(const std::string& line);

}  // namespace lgvi::experiments
