#include "experiments/json_writer.hpp"

#include "experiments/atomic_file.hpp"

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

}  // namespace lgvi::experiments
