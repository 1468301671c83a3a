#include "experiments/output/csv_writer.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cassert>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>

#include "experiments/output/shortest.hpp"

namespace lgvi::experiments {

namespace {

std::string one_line(std::string s) {
  for (char& c : s) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  return s;
}

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(c));
          out += buf;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

}  // namespace

std::string shortest(double x) {
  std::array<char, 32> buf;
  const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), x);
  return std::string(buf.data(), r.ptr);
}

std::string to_text(const FieldValue& value) {
  struct Visitor {
    std::string operator()(const std::string& s) const { return s; }
    std::string operator()(double x) const {
      std::array<char, 32> buf;
      const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), x, std::chars_format::general, 17);
      return std::string(buf.data(), r.ptr);
    }
    std::string operator()(std::int64_t i) const { return std::to_string(i); }
    std::string operator()(bool b) const { return b ? "true" : "false"; }
  };
  return std::visit(Visitor{}, value);
}

std::string to_json(const Fields& fields) {
  struct Visitor {
    std::string operator()(const std::string& s) const { return json_string(s); }
    std::string operator()(double x) const { return std::isfinite(x) ? shortest(x) : "null"; }
    std::string operator()(std::int64_t i) const { return std::to_string(i); }
    std::string operator()(bool b) const { return b ? "true" : "false"; }
  };
  std::string out = "{";
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (i > 0) out += ", ";
    out += json_string(fields[i].key) + ": " + std::visit(Visitor{}, fields[i].value);
  }
  return out + "}";
}

std::string metadata_lines(const Fields& fields) {
  std::string text;
  for (const Field& f : fields) text += "# " + one_line(f.key) + ": " + one_line(to_text(f.value)) + "\n";
  return text;
}

std::vector<std::string> split_csv_row(const std::string& line) {
  std::vector<std::string> cells;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    cells.push_back(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) return cells;
    start = comma + 1;
  }
}

namespace {

std::string header_line(const std::vector<std::string>& columns) {
  std::string line;
  for (std::size_t i = 0; i < columns.size(); ++i) line += (i > 0 ? "," : "") + columns[i];
  return line + "\n";
}

/// A blank comment line of exactly `size` >= 2 bytes: '#', spaces, newline.
std::string padding_line(std::size_t size) {
  std::string line(1, '#');  // appended, not "#" + std::string: GCC 12 warns falsely (-Wrestrict)
  line.append(size - 2, ' ');
  return line + '\n';
}

}  // namespace

CsvWriter::CsvWriter(std::filesystem::path target, std::vector<std::string> columns)
    : target_(std::move(target)), columns_(std::move(columns)), file_(target_), buffered_(file_.is_stream()),
      rows_buffer_(new char[kRowBufferSize]) {}

CsvWriter::CsvWriter(std::filesystem::path target, std::vector<std::string> columns, const Fields& leading,
                     std::size_t reserve)
    : target_(std::move(target)), columns_(std::move(columns)), leading_(metadata_lines(leading)), file_(target_),
      reserve_(std::max<std::size_t>(reserve, 2)), rows_buffer_(new char[kRowBufferSize]) {
  const std::string header = header_line(columns_);
  file_.write(leading_);
  if (file_.is_stream()) {  // no block to come back to: the closing lines go after the rows
    trailer_ = true;
    reserve_ = 0;
    file_.write(header);
    return;
  }
  file_.write(padding_line(reserve_));  // replaced at commit
  file_.write(header);
  reserve_offset_ = static_cast<long>(leading_.size());
  rows_offset_ = reserve_offset_ + static_cast<long>(reserve_ + header.size());
}

CsvWriter::~CsvWriter() {
  if (!file_.is_stream() || buffered_) return;  // the temporary goes (AtomicFile), or nothing was sent yet
  try {
    drain();
  } catch (const OutputError&) {  // best effort: a destructor has no one to tell
  }
}

void CsvWriter::emit(std::string_view text) {
  if (buffered_) {
    buffer_.append(text);
  } else {
    file_.write(text);
  }
}

void CsvWriter::drain() {
  if (pending_ == 0) return;
  const std::size_t n = pending_;
  pending_ = 0;
  emit(std::string_view(rows_buffer_.get(), n));
}

void CsvWriter::write_row(std::span<const double> values) {
  assert(values.size() == columns_.size());
  // Room for the row at its longest: each number and its separator, the scratch of the last
  // number (write_shortest), the newline.
  const std::size_t longest = values.size() * (kShortestMaxChars + 1) + kShortestRoom + 1;
  if (kRowBufferSize - pending_ < longest) drain();
  char* const begin = rows_buffer_.get();
  char* p = begin + pending_;
  if (longest <= kRowBufferSize) {
    p = write_csv_numbers(p, values);
  } else {  // a row wider than the buffer (over 2,500 columns): handed on in parts
    for (const double x : values) {
      if (static_cast<std::size_t>(begin + kRowBufferSize - p) < kShortestRoom + 1) {
        pending_ = static_cast<std::size_t>(p - begin);
        drain();
        p = begin;
      }
      p = write_shortest(p, x);
      *p++ = ',';
    }
    p[-1] = '\n';  // the last separator (the row has numbers: it is wide)
  }
  pending_ = static_cast<std::size_t>(p - begin);
  ++rows_;
}

void CsvWriter::commit(const Fields& closing) {
  drain();
  const std::string closing_text = metadata_lines(closing);
  if (trailer_) {
    file_.write(closing_text);
    file_.commit();
    return;
  }
  if (buffered_) {
    file_.write(leading_ + closing_text + header_line(columns_));
    file_.write(buffer_);
    file_.commit();
    return;
  }
  if (reserve_ > 0 && (closing_text.size() == reserve_ || closing_text.size() + 2 <= reserve_)) {
    // Into the reserved block: the rows stay where they are.
    file_.flush();
    if (std::fseek(file_.stream(), reserve_offset_, SEEK_SET) != 0) {
      throw OutputError(target_.string() + ": cannot seek in the temporary file: " + std::strerror(errno));
    }
    file_.write(closing_text);
    if (closing_text.size() < reserve_) file_.write(padding_line(reserve_ - closing_text.size()));
    file_.commit();
    return;
  }
  // The metadata does not fit (or no block was reserved): a second file, the rows copied once.
  file_.flush();
  AtomicFile out(target_);
  out.write(leading_ + closing_text + header_line(columns_));
  // Through the temporary's own descriptor (never reopened by name).
  const int in = ::fileno(file_.stream());
  std::array<char, 1 << 16> buf;
  for (off_t at = static_cast<off_t>(rows_offset_);;) {
    const ssize_t n = ::pread(in, buf.data(), buf.size(), at);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw OutputError(target_.string() + ": cannot reread the rows: " + std::strerror(errno));
    if (n == 0) break;
    out.write(std::string_view(buf.data(), static_cast<std::size_t>(n)));
    at += n;
  }
  out.commit();
  file_.discard();
}

}  // namespace lgvi::experiments
