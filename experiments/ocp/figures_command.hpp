// `lgvi-testbed figures`: the paper's Figs. 2-5, regenerated from the optimal control runs.
//   Fig. 2  dumbbell spacecraft, indirect method (section 3.1)
//   Fig. 3  3D pendulum, indirect method (section 3.2)
//   Fig. 4  3D pendulum on a cart, direct method (section 4.1)
//   Fig. 5  two connected rigid bodies, direct method (section 4.2)
// Each figure has four panels: (a) the maneuver, (b) the controls (with the knots for the
// direct method), (c) the convergence of the solver on semilog axes (with the condition numbers
// for the indirect method), (d) the angular velocities. The panels are drawn by
// the system's script (OcpBinding<M>::figure_script: experiments/plots/fig_SYSTEM.gp) from the
// files `lgvi-testbed ocp SCENE` writes. `figures SCENE.toml ...` draws any scene with an [ocp]
// table the same way (a user's own problem: fig-LABEL.png, titled by its description, its cost
// and violation beside the paper's when it names an example).
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace lgvi::experiments {

/// The options of the `figures` subcommand, filled by CLI11.
struct FiguresCommand {
  std::string out = "results/figures";  ///< where the ocp files and the figures go
  /// Empty: solve the optimal control problems first (`ocp SYSTEM` with its defaults, into
  /// `out`). Otherwise a directory holding the ocp-SYSTEM-*.csv files of earlier runs.
  std::string from;
  /// Scenes with an [ocp] table (paths, or names as `ocp` takes them); empty: the paper's four.
  std::vector<std::string> scenes;
  std::vector<std::string> only;  ///< of the paper's examples, the systems to draw; empty: all four
  std::string format = "png";     ///< the figures' file format: png, pdf or svg
  std::string plots_dir;
  std::string gnuplot;
};

/// The systems in figure order with their figure numbers: {"dumbbell", 2}, {"pendulum", 3}, ...
std::vector<std::pair<std::string, int>> figure_systems();

/// Registers the `figures` subcommand on `app`, binding its options to `options`.
CLI::App* add_figures_command(CLI::App& app, FiguresCommand& options);

/// Solves (unless options.from is set) and draws OUT/figN-SYSTEM.png (.pdf, .svg: options.format)
/// for each chosen example of the paper, or OUT/fig-LABEL.png for each scene named (LABEL:
/// ocp_label). Returns 0 when every solve converged and every figure was drawn; 2
/// when a solve did not converge (its figure is still drawn from the files it wrote, which say
/// why); 1 on bad input (one "error:" line on `err`: a --format other than png, pdf, svg; scenes
/// and --only together). Throws OutputError when a file cannot be read or written.
int run_figures_command(const FiguresCommand& options, const std::string& command_line, std::ostream& out,
                        std::ostream& err);

}  // namespace lgvi::experiments
