// Rendering figures with gnuplot: one script per figure kind in experiments/plots/, run as
//   gnuplot -c SCRIPT OUT.png TITLE XLABEL YLABEL in1.csv label1 [in2.csv label2 ...]
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace lgvi::experiments {

/// The gnuplot scripts compiled in: <source>/experiments/plots.
std::filesystem::path default_plots_dir();
/// The gnuplot executable found at configure time.
std::string default_gnuplot();

/// One curve: a CSV written by lgvi-testbed and its legend entry.
struct Curve {
  std::filesystem::path csv;
  std::string label;
};

/// Runs `gnuplot -c script OUT title xlabel ylabel csv1 label1 ...` with OUT a temporary next to
/// `png`, renamed onto `png` when gnuplot succeeded and wrote a non-empty file. gnuplot's stdout
/// is discarded; its stderr is kept for the error message. Throws OutputError (first line of
/// gnuplot's stderr) on failure, leaving no file.
void render_plot(const std::string& gnuplot, const std::filesystem::path& script,
                 const std::filesystem::path& png, const std::string& title, const std::string& xlabel,
                 const std::string& ylabel, const std::vector<Curve>& curves);

/// Runs `gnuplot -c script OUT args...` the same way (OUT a temporary renamed onto `png`).
/// gnuplot -c passes at most 9 arguments: scripts with many curves take a curve-list file.
/// Throws OutputError.
void run_gnuplot_script(const std::string& gnuplot, const std::filesystem::path& script,
                        const std::filesystem::path& png, const std::vector<std::string>& args);

}  // namespace lgvi::experiments
