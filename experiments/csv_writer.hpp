// CSV results (DESIGN.md, output conventions): `# key: value` metadata lines, one header row,
// then data rows at full precision (%.17g). Rows are streamed to a spool file as they come,
// the metadata (which includes the run's final status) is written at commit, and the finished
// file appears atomically under its name.
#pragma once

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "experiments/atomic_file.hpp"
#include "experiments/fields.hpp"

namespace lgvi::experiments {

class CsvWriter {
 public:
  /// Opens the spool next to `target`. Throws OutputError.
  CsvWriter(std::filesystem::path target, std::vector<std::string> columns);

  const std::vector<std::string>& columns() const { return columns_; }
  /// Appends one data row. Precondition: values.size() == columns().size().
  void write_row(std::span<const double> values);
  std::size_t rows() const { return rows_; }

  /// Writes metadata, header and the spooled rows to `target` atomically and removes the
  /// spool. Newlines inside metadata values are replaced by spaces (one line per key). Throws
  /// OutputError. Without a successful commit, the destructor leaves no file behind.
  void commit(const Fields& metadata);

  const std::filesystem::path& target() const { return target_; }

 private:
  std::filesystem::path target_;
  std::vector<std::string> columns_;
  AtomicFile spool_;
  std::size_t rows_ = 0;
};

}  // namespace lgvi::experiments
