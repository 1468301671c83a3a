#include "experiments/input/literature_references.hpp"

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string_view>

#include "experiments/input/toml_reader.hpp"

namespace lgvi::experiments {

namespace {

constexpr std::array<std::string_view, 8> kKeys = {"scene", "source",    "t",         "R",
                                                   "Omega", "computed_by", "agreement", "digits"};

std::string round_trip(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  std::string s = buf;
  // A TOML float needs a '.', an exponent or inf/nan.
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

std::string quoted(const std::string& s) {
  std::string q = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') q += '\\';
    q += c;
  }
  return q + "\"";
}

}  // namespace

std::vector<LiteratureReference> read_literature_references(const std::filesystem::path& file) {
  const std::string name = file.string();
  const std::string text = read_toml_file(file, "the literature references");
  const TomlReader r(name);
  const toml::table doc = r.parse(text, "literature references");
  r.check_keys(doc, "", {"problem"});
  const toml::array* problems = doc["problem"].as_array();
  if (problems == nullptr || problems->empty()) r.fail("problem", "must be a non-empty array of tables [[problem]]");
  std::vector<LiteratureReference> out;
  for (std::size_t i = 0; i < problems->size(); ++i) {
    const std::string prefix = "problem[" + std::to_string(i) + "]";
    const toml::table* t = problems->get(i)->as_table();
    if (t == nullptr) r.fail(prefix, "must be a table");
    r.check_keys(*t, prefix, std::span<const std::string_view>(kKeys));
    LiteratureReference ref;
    ref.scene = r.required(*t, "scene", prefix, &TomlReader::string);
    ref.source = r.required(*t, "source", prefix, &TomlReader::string);
    ref.t = r.required(*t, "t", prefix, &TomlReader::positive);
    ref.R = r.required(*t, "R", prefix, &TomlReader::mat3);
    ref.Omega = r.required(*t, "Omega", prefix, &TomlReader::vec3);
    ref.computed_by = r.required(*t, "computed_by", prefix, &TomlReader::string);
    ref.agreement = r.required(*t, "agreement", prefix, &TomlReader::number);
    ref.digits = static_cast<int>(r.required(*t, "digits", prefix, &TomlReader::integer));
    out.push_back(std::move(ref));
  }
  return out;
}

std::string literature_references_toml(const std::vector<LiteratureReference>& references, const std::string& header) {
  std::ostringstream s;
  std::istringstream lines(header);
  for (std::string line; std::getline(lines, line);) s << (line.empty() ? "#" : "# " + line) << "\n";
  for (const LiteratureReference& ref : references) {
    s << "\n[[problem]]\n";
    s << "scene = " << quoted(ref.scene) << "\n";
    s << "source = " << quoted(ref.source) << "\n";
    s << "t = " << round_trip(ref.t) << "\n";
    s << "R = [\n";
    for (int i = 0; i < 3; ++i) {
      s << "  [" << round_trip(ref.R(i, 0)) << ", " << round_trip(ref.R(i, 1)) << ", " << round_trip(ref.R(i, 2))
        << "],\n";
    }
    s << "]\n";
    s << "Omega = [" << round_trip(ref.Omega(0)) << ", " << round_trip(ref.Omega(1)) << ", " << round_trip(ref.Omega(2))
      << "]\n";
    s << "computed_by = " << quoted(ref.computed_by) << "\n";
    s << "agreement = " << round_trip(ref.agreement) << "\n";
    s << "digits = " << ref.digits << "\n";
  }
  return s.str();
}

}  // namespace lgvi::experiments
