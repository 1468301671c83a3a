// The files of one `ocp` run as one unit: a run id in each of them, the summary written last,
// checked on read (verify_ocp_run). A run killed or failing between its files leaves files of
// two runs side by side; the ids tell them apart.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>

#include <nlohmann/json.hpp>

#include "experiments/output/atomic_file.hpp"
#include "experiments/ocp/ocp_command.hpp"
#include "experiments/ocp/ocp_output.hpp"

namespace lgvi::experiments {

namespace fs = std::filesystem;

namespace {

/// The run_id metadata line of a CSV (`# run_id: ID`, before its header); "" when it has none.
std::string csv_run_id(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  const std::string key = "# run_id: ";
  while (std::getline(in, line) && line.starts_with("#")) {
    if (line.starts_with(key)) return line.substr(key.size());
  }
  return "";
}

}  // namespace

std::string ocp_output::new_run_id() {
  const auto now = std::chrono::system_clock::now().time_since_epoch();
  const long long ns = std::chrono::duration_cast<std::chrono::nanoseconds>(now).count();
  std::random_device device;
  char text[64];
  std::snprintf(text, sizeof text, "%llx-%ld-%08x", ns, static_cast<long>(::getpid()),
                static_cast<unsigned>(device()));
  return text;
}

void verify_ocp_run(const fs::path& dir, const std::string& system) {
  const fs::path summary = ocp_output_file(dir, system, "summary.json");
  const std::string rerun = "; run `lgvi-testbed ocp " + system + "` again";
  std::ifstream in(summary);
  if (!in) {
    throw OutputError(summary.string() + ": not found: the run that wrote this directory's ocp-" + system +
                      " files did not finish" + rerun);
  }
  const nlohmann::json parsed = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (!parsed.is_object() || !parsed.contains("run_id") || !parsed["run_id"].is_string()) {
    throw OutputError(summary.string() + ": no run_id (written by an older version, or not an ocp summary)" + rerun);
  }
  const std::string id = parsed["run_id"].get<std::string>();
  for (const char* what : {"history.csv", "trajectory.csv", "knots.csv"}) {
    const fs::path file = ocp_output_file(dir, system, what);
    std::error_code ec;
    if (!fs::exists(file, ec)) continue;
    const std::string file_id = csv_run_id(file);
    if (file_id == id) continue;
    throw OutputError(file.string() + ": from " + (file_id.empty() ? "a run without a run id" : "run " + file_id) +
                      ", but " + summary.filename().string() + " is from run " + id +
                      ": an interrupted run left files of two runs" + rerun);
  }
}

}  // namespace lgvi::experiments
