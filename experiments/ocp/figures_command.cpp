#include "experiments/ocp/figures_command.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <ostream>

#include <nlohmann/json.hpp>

#include "experiments/output/atomic_file.hpp"
#include "experiments/ocp/ocp_command.hpp"
#include "experiments/scene/ocp_scene.hpp"
#include "experiments/input/paper_values.hpp"
#include "experiments/output/plot.hpp"
#include "experiments/systems/ocp.hpp"
#include "experiments/systems/systems.hpp"

namespace lgvi::experiments {

namespace fs = std::filesystem;

namespace {

/// "Fig. N: " (a paper's figure, number > 0) and the scene's description (the ocp scenes
/// describe their problem and method), or its file's name when it has none.
std::string figure_title(const Scene& scene, int number) {
  const std::string what = scene.description.empty() ? scene.file.filename().string() : scene.description;
  if (number <= 0) return what;
  // Appends only: GCC 12 warns falsely (-Wrestrict) on "literal" + std::string.
  std::string n = "Fig. ";
  n.append(std::to_string(number)).append(": ");
  return n + what;
}

/// Characters per title line: the titles are set in 6 pt (ocp_figure.gp), about 4 pt a character
/// (measured on the PNG), on a 3.5 in (252 pt) figure: 63 fit; 60 leave a margin on both sides.
constexpr std::size_t kTitleWidth = 60;

std::string number_text(double x, int digits) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*g", digits, x);
  return buf;
}

/// What a figure's title and panels take from the run's summary JSON (an object, or an array
/// of one): the cost and terminal violation ("-" when absent) and, for a multistart run, the
/// start shown and the number of starts (-1 and 0 when absent).
struct RunValues {
  std::string cost = "-";
  std::string violation = "-";
  long best_start = -1;
  long starts = 0;
};

RunValues run_values(const fs::path& summary_file) {
  RunValues v;
  std::ifstream in(summary_file);
  if (!in) return v;
  const nlohmann::json parsed = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  const nlohmann::json& j = parsed.is_array() && !parsed.empty() ? parsed.front() : parsed;
  if (!j.is_object()) return v;
  if (j.contains("cost") && j["cost"].is_number()) v.cost = number_text(j["cost"].get<double>(), 6);
  if (j.contains("violation") && j["violation"].is_number()) v.violation = number_text(j["violation"].get<double>(), 3);
  if (j.contains("best_start") && j["best_start"].is_number_integer() && j.contains("starts") &&
      j["starts"].is_number_integer()) {
    const long best = j["best_start"].get<long>();
    const long starts = j["starts"].get<long>();
    if (best >= 0 && best < starts) {
      v.best_start = best;
      v.starts = starts;
    }
  }
  return v;
}

/// Last title line: the run's cost and terminal violation, then the paper's when the scene names
/// its example (validation/paper_values.toml). Without a readable summary, "-" for the run's.
std::string figure_values(const Scene& scene, const RunValues& run) {
  if (scene.ocp->paper.empty()) return "cost " + run.cost + ", violation " + run.violation;
  const PaperExample* example = paper_values().find(scene.ocp->paper);
  if (example == nullptr) throw InvalidInput(scene.file.string(), "ocp.paper: names no example of the paper");
  const PaperExample& paper = *example;
  return "cost " + run.cost + ", violation " + run.violation + " (paper: " + number_text(paper.cost, 6) +
         ", " + number_text(paper.terminal_violation, 3) + ")";
}

fs::path require_file(const fs::path& file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) {
    throw OutputError(file.string() + ": not found (run `lgvi-testbed ocp` first, or drop --from)");
  }
  return file;
}

}  // namespace

std::vector<std::pair<std::string, int>> figure_systems() {
  return {{"dumbbell", 2}, {"pendulum", 3}, {"cart-pendulum", 4}, {"connected-bodies", 5}};
}

CLI::App* add_figures_command(CLI::App& app, FiguresCommand& o) {
  CLI::App* cmd = app.add_subcommand(
      "figures", "Draw the paper's Figs. 2-5 from its four optimal control examples, or the solution of any [ocp] scene");
  cmd->add_option("scenes", o.scenes,
                  "Scenes with an [ocp] table to solve and draw (a path, or a name as `ocp` takes it); none: the "
                  "paper's four examples");
  cmd->add_option("--out", o.out, "Output directory of the ocp files and the figures")->capture_default_str();
  cmd->add_option("--from", o.from,
                  "Draw from the ocp-SYSTEM-*.csv files in this directory instead of solving again");
  std::vector<std::string> names;
  for (const auto& [name, number] : figure_systems()) names.push_back(name);
  cmd->add_option("--only", o.only, "Examples to draw: dumbbell, pendulum, cart-pendulum, connected-bodies")
      ->check(CLI::IsMember(names));
  cmd->add_option("--format", o.format, "Figure file formats: png, pdf, svg or a list (png,pdf)")->capture_default_str();
  o.plots_dir = default_plots_dir().string();
  o.gnuplot = default_gnuplot();
  cmd->add_option("--plots-dir", o.plots_dir, "Directory of the gnuplot scripts")->capture_default_str();
  cmd->add_option("--gnuplot", o.gnuplot, "gnuplot executable")->capture_default_str();
  return cmd;
}

int run_figures_command(const FiguresCommand& o, const std::string& command_line, std::ostream& out,
                        std::ostream& err) {
  std::vector<FigureFormat> formats;
  try {
    formats = figure_formats_named("--format", o.format);
  } catch (const InvalidInput& e) {
    err << "error: " << e.what() << "\n" << std::flush;
    return 1;
  }
  const fs::path out_dir(o.out);
  const fs::path data_dir = o.from.empty() ? out_dir : fs::path(o.from);
  if (!o.from.empty()) {
    std::error_code ec;
    if (!fs::is_directory(data_dir, ec)) {
      err << "error: --from: " << data_dir.string() << ": not a directory\n" << std::flush;
      return 1;
    }
  }
  // What to draw: the scenes named, else the paper's four examples (--only: some of them).
  struct Drawing {
    std::string argument;  ///< the scene as `ocp` takes it (a name or a path)
    int number;            ///< the paper's figure number; 0 for another scene
  };
  std::vector<Drawing> drawings;
  if (!o.scenes.empty()) {
    if (!o.only.empty()) {
      err << "error: --only: chooses among the paper's examples; with scenes named, name only those\n" << std::flush;
      return 1;
    }
    for (const std::string& s : o.scenes) drawings.push_back({s, 0});
  } else {
    for (const auto& [system, number] : figure_systems()) {
      if (o.only.empty() || std::find(o.only.begin(), o.only.end(), system) != o.only.end()) {
        drawings.push_back({system, number});
      }
    }
  }

  // Every scene read and checked before anything is written.
  std::vector<Scene> scenes;
  for (const Drawing& d : drawings) {
    scenes.push_back(load_scene(resolve_ocp_scene(d.argument, default_scenes_dir())));
    if (!scenes.back().ocp) {
      throw SceneError(scenes.back().file.string(), "ocp",
                       "is required (the figure's optimal control problem: an [ocp] table, experiments/scenes/README.md)");
    }
  }
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec) throw OutputError(out_dir.string() + ": cannot create the output directory: " + ec.message());

  int status = 0;
  for (std::size_t i = 0; i < drawings.size(); ++i) {
    const Drawing& d = drawings[i];
    const Scene& scene = scenes[i];
    const std::string label = ocp_label(scene);
    // A scene named by its file is drawn as the paper's figure when it is one of its examples.
    int number = d.number;
    for (const auto& [system, n] : figure_systems()) {
      if (number == 0 && label == system && scene.ocp->paper != "") number = n;
    }
    if (o.from.empty()) {
      OcpCommand ocp;
      ocp.system = d.argument;
      ocp.out = out_dir.string();
      const int code = run_ocp_command(ocp, command_line, out, err);
      if (code == 1) return 1;
      if (code != 0) status = 2;  // not converged: the files say why; the figure shows it
    }
    // One column wide (experiments/plots/ocp_figure.gp): lines of at most kTitleWidth characters.
    const RunValues run = run_values(ocp_output_file(data_dir, label, "summary.json"));
    const std::string title = wrap_text(figure_title(scene, number), kTitleWidth) + "\n" +
                              wrap_text(figure_values(scene, run), kTitleWidth);
    std::vector<std::string> args = {title,
                                     gnuplot_path(require_file(ocp_output_file(data_dir, label, "trajectory.csv"))),
                                     gnuplot_path(require_file(ocp_output_file(data_dir, label, "history.csv")))};
    if (scene.ocp->method == OcpMethod::Direct) {
      args.push_back(gnuplot_path(require_file(ocp_output_file(data_dir, label, "knots.csv"))));
      // The convergence panel draws the start whose solution the figure shows.
      if (run.best_start >= 0) {
        args.push_back(std::to_string(run.best_start));
        args.push_back(std::to_string(run.starts));
      }
    }
    verify_ocp_run(data_dir, label);  // the files above are one run's
    const std::string script = visit_binding(scene.model, [](auto, const auto& m) -> std::string {
      return OcpBinding<std::decay_t<decltype(m)>>::figure_script;
    });
    for (const FigureFormat format : formats) {
      std::string name = "fig";
      if (number > 0) name.append(std::to_string(number));
      name.append("-").append(label).append(figure_extension(format));
      const fs::path figure = out_dir / name;
      run_gnuplot_script(o.gnuplot, fs::path(o.plots_dir) / script, figure, args);
      out << "wrote " << figure.string() << "\n" << std::flush;
    }
  }
  return status;
}

}  // namespace lgvi::experiments
