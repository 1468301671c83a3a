#include "experiments/output/json_writer.hpp"

#include <algorithm>
#include <cmath>

#include "experiments/output/atomic_file.hpp"

namespace lgvi::experiments {

void write_json_summary(const std::filesystem::path& target, const std::vector<Fields>& runs) {
  AtomicFile out(target);
  out.write("[\n");
  for (std::size_t i = 0; i < runs.size(); ++i) {
    out.write(to_json(runs[i]));
    out.write(i + 1 < runs.size() ? ",\n" : "\n");
  }
  out.write("]\n");
  out.commit();
}

void write_json_object(const std::filesystem::path& target, const Fields& fields,
                       const std::vector<std::pair<std::string, std::vector<double>>>& arrays) {
  AtomicFile out(target);
  out.write("{\n");
  for (std::size_t i = 0; i < fields.size(); ++i) {
    const Field& f = fields[i];
    std::string line;
    const auto array = std::find_if(arrays.begin(), arrays.end(), [&f](const auto& a) { return a.first == f.key; });
    if (array != arrays.end()) {
      // The key as to_json writes it (escaped), then the numbers.
      line = to_json({{f.key, std::int64_t{0}}});
      line = line.substr(1, line.rfind(':')) + " [";
      for (std::size_t k = 0; k < array->second.size(); ++k) {
        const double x = array->second[k];
        line += (k > 0 ? ", " : "") + (std::isfinite(x) ? shortest(x) : std::string("null"));
      }
      line += "]";
    } else {
      line = to_json({f});
      line = line.substr(1, line.size() - 2);  // the object's one member, without its braces
    }
    out.write("  " + line + (i + 1 < fields.size() ? ",\n" : "\n"));
  }
  out.write("}\n");
  out.commit();
}

}  // namespace lgvi::experiments
