// Where the CLI's data lives: the scenes, the plot scripts and the accepted metrics.
#pragma once

#include <filesystem>
#include <string_view>

namespace lgvi::experiments {

/// The directory holding `installed` (e.g. "scenes") beside an installed lgvi-testbed:
/// <directory of the running executable>/LGVI_DATA_FROM_BINDIR/<installed>, when it exists, so
/// that an installed prefix can be moved; otherwise the source tree's <in_source> (the build
/// tree's executable, or an installation without its data).
std::filesystem::path data_dir(std::string_view installed, std::string_view in_source);

}  // namespace lgvi::experiments
