#include "experiments/output/data_dir.hpp"

#include <optional>

namespace lgvi::experiments {

namespace fs = std::filesystem;

namespace {

fs::path& data_root() {
  static fs::path root;
  return root;
}

/// <data root>/<installed>, else <directory of the running executable>/LGVI_DATA_FROM_BINDIR/<installed>,
/// when it exists.
std::optional<fs::path> installed_dir(std::string_view installed) {
  std::error_code ec;
  if (!data_root().empty()) {
    const fs::path in_root = data_root() / installed;
    if (fs::is_directory(in_root, ec)) return in_root.lexically_normal();
  }
  // Linux: the running executable, whatever the current directory or argv[0].
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path beside = exe.parent_path() / LGVI_DATA_FROM_BINDIR / installed;
    if (fs::is_directory(beside, ec)) return beside.lexically_normal();
  }
  return std::nullopt;
}

}  // namespace

std::filesystem::path data_dir(std::string_view installed, std::string_view in_source) {
  if (std::optional<fs::path> dir = installed_dir(installed)) return *dir;
  return fs::path(LGVI_SOURCE_DIR) / in_source;
}

bool data_dir_is_installed(std::string_view installed) { return installed_dir(installed).has_value(); }

void set_data_root(const std::filesystem::path& root) { data_root() = root; }

}  // namespace lgvi::experiments
