#include "experiments/csv_writer.hpp"

#include <array>
#include <cassert>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>

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

CsvWriter::CsvWriter(std::filesystem::path target, std::vector<std::string> columns)
    : target_(std::move(target)), columns_(std::move(columns)), spool_(target_) {}

void CsvWriter::write_row(std::span<const double> values) {
  assert(values.size() == columns_.size());
  // One buffer per row; 25 characters hold any %.17g double plus the separator.
  std::array<char, 64 * 26> line;
  char* p = line.data();
  char* const end = line.data() + line.size();
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (end - p < 26) {  // very wide rows: flush the partial line
      spool_.write(std::string_view(line.data(), static_cast<std::size_t>(p - line.data())));
      p = line.data();
    }
    if (i > 0) *p++ = ',';
    p = std::to_chars(p, end, values[i], std::chars_format::general, 17).ptr;
  }
  *p++ = '\n';
  spool_.write(std::string_view(line.data(), static_cast<std::size_t>(p - line.data())));
  ++rows_;
}

void CsvWriter::commit(const Fields& metadata) {
  spool_.flush();
  AtomicFile out(target_);
  std::string head;
  for (const Field& f : metadata) head += "# " + one_line(f.key) + ": " + one_line(to_text(f.value)) + "\n";
  for (std::size_t i = 0; i < columns_.size(); ++i) head += (i > 0 ? "," : "") + columns_[i];
  head += "\n";
  out.write(head);

  std::unique_ptr<std::FILE, int (*)(std::FILE*)> in(std::fopen(spool_.temp_path().c_str(), "rb"), &std::fclose);
  if (!in) throw OutputError(target_.string() + ": cannot reread the spooled rows: " + std::strerror(errno));
  std::array<char, 1 << 16> buf;
  std::size_t n = 0;
  while ((n = std::fread(buf.data(), 1, buf.size(), in.get())) > 0) out.write(std::string_view(buf.data(), n));
  if (std::ferror(in.get())) throw OutputError(target_.string() + ": cannot reread the spooled rows");
  out.commit();
  spool_.discard();
}

}  // namespace lgvi::experiments
