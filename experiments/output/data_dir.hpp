// Where the CLI's data lives: the scenes, the plot scripts and the accepted metrics.
#pragma once

#include <filesystem>
#include <string_view>

namespace lgvi::experiments {

/// The directory holding `installed` (e.g. "scenes"): <root>/<installed> when set_data_root(root)
/// was called and that exists (the installed Python package, whose process is the interpreter);
/// else beside an installed lgvi-testbed,
/// <directory of the running executable>/LGVI_DATA_FROM_BINDIR/<installed>, when it exists, so
/// that an installed prefix can be moved; otherwise the source tree's <in_source> (the build
/// tree's executable, or an installation without its data).
std::filesystem::path data_dir(std::string_view installed, std::string_view in_source);

/// True when data_dir(installed, ...) is an installation's directory (beside the executable),
/// false when it is the source tree's: an installation's data is not the user's to rewrite.
bool data_dir_is_installed(std::string_view installed);

/// Makes data_dir look in `root` first (an installed package's data folder). Call before any
/// thread reads data_dir (the Python package calls it when imported).
void set_data_root(const std::filesystem::path& root);

}  // namespace lgvi::experiments
