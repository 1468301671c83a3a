#include "experiments/data_dir.hpp"

namespace lgvi::experiments {

namespace fs = std::filesystem;

std::filesystem::path data_dir(std::string_view installed, std::string_view in_source) {
  std::error_code ec;
  // Linux: the running executable, whatever the current directory or argv[0].
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path beside = exe.parent_path() / LGVI_DATA_FROM_BINDIR / installed;
    if (fs::is_directory(beside, ec)) return beside.lexically_normal();
  }
  return fs::path(LGVI_SOURCE_DIR) / in_source;
}

}  // namespace lgvi::experiments
