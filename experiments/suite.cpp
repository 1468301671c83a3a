#include "experiments/suite.hpp"

#include <map>

#include "experiments/json_writer.hpp"
#include "experiments/plot.hpp"
#include "experiments/scene.hpp"

namespace lgvi::experiments {

namespace fs = std::filesystem;

namespace {

/// Axis labels in the units of the scene's system (gnuplot enhanced text).
struct Labels {
  std::string time;
  std::string energy;
  std::string momentum;
};

Labels labels_for(const Model& model) {
  if (std::holds_alternative<DumbbellModel>(model)) {
    return {"time [normalized: orbit period 2π]", "|E - E_0| [normalized]",
            "|H - H_0| [normalized],  H = x × m v + R J Ω"};
  }
  if (std::holds_alternative<CartPendulumModel>(model)) {
    return {"time [s]", "|E - E_0| [J]", "|e_3^T R Π + x p_y - y p_x - (...)_0| [kg m^2/s]"};
  }
  if (std::holds_alternative<ConnectedBodiesModel>(model)) {
    return {"time [s]", "|E - E_0| [J]", "|R_1 Π_1 + R_2 Π_2 - (...)_0| [kg m^2/s]"};
  }
  if (std::holds_alternative<PendulumModel>(model)) {
    return {"time [s]", "|E - E_0| [J]", "|e_3^T R J Ω - (e_3^T R J Ω)_0| [kg m^2/s]"};
  }
  return {"time [s]", "|E - E_0| [J]", "|R J Ω - (R J Ω)_0| [kg m^2/s]"};
}

std::string format_h(double h) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", h);
  return buf;
}

}  // namespace

std::string SuiteCase::id() const { return scene + "-" + to_string(form); }

bool SuiteResult::all_ok() const {
  for (const RunSummary& r : runs) {
    if (!r.stats.ok()) return false;
  }
  return true;
}

std::vector<std::pair<std::string, std::string>> suite_list() {
  return {{"default", "every scene of the scenes directory with the symmetric and the printed LGVI"}};
}

Suite make_suite(const std::string& name, const fs::path& scenes_dir) {
  if (name == "default") {
    Suite s{name, suite_list()[0].second, {}};
    for (const std::string& scene : scene_names(scenes_dir)) {
      for (const LgviForm form : {LgviForm::Symmetric, LgviForm::Printed}) s.cases.push_back({scene, "lgvi", form});
    }
    if (s.cases.empty()) throw InvalidInput("suite", "no scenes in " + scenes_dir.string());
    return s;
  }
  std::string known;
  for (const auto& [n, d] : suite_list()) known += (known.empty() ? "" : ", ") + n;
  throw InvalidInput("suite", "unknown suite '" + name + "' (known: " + known + ")");
}

SuiteResult run_suite(const Suite& suite, const SuiteOptions& options, std::ostream& progress) {
  // Every scene is loaded and validated before anything runs or is written.
  std::vector<Scene> scenes;
  for (const SuiteCase& c : suite.cases) {
    SceneOverrides o;
    o.form = c.form;
    scenes.push_back(load_scene(resolve_scene(c.scene, options.scenes_dir), o));
  }
  std::vector<std::unique_ptr<Method>> methods;
  for (const SuiteCase& c : suite.cases) methods.push_back(make_method(c.method));

  std::error_code ec;
  fs::create_directories(options.out_dir, ec);
  if (ec) throw OutputError(options.out_dir.string() + ": cannot create the output directory: " + ec.message());

  SuiteResult result;
  std::vector<Fields> summaries;
  for (std::size_t i = 0; i < suite.cases.size(); ++i) {
    const SuiteCase& c = suite.cases[i];
    const fs::path csv = options.out_dir / (c.id() + ".csv");
    RunSummary r = simulate(scenes[i], *methods[i], {csv, options.command_line});
    progress << "[" << i + 1 << "/" << suite.cases.size() << "] " << c.id() << ": " << r.stats.brief() << "\n"
             << std::flush;
    summaries.push_back(r.to_fields());
    result.runs.push_back(std::move(r));
  }
  const fs::path summary = options.out_dir / "summary.json";
  write_json_summary(summary, summaries);
  progress << "wrote " << summary.string() << "\n";
  if (!options.plots) return result;

  // One figure per (scene, kind), with every case of that scene as a curve.
  std::map<std::string, std::vector<std::size_t>> by_scene;
  std::vector<std::string> order;
  for (std::size_t i = 0; i < suite.cases.size(); ++i) {
    if (by_scene.find(suite.cases[i].scene) == by_scene.end()) order.push_back(suite.cases[i].scene);
    by_scene[suite.cases[i].scene].push_back(i);
  }
  for (const std::string& name : order) {
    const std::vector<std::size_t>& cases = by_scene[name];
    const Scene& scene = scenes[cases.front()];
    const Labels labels = labels_for(scene.model);
    std::vector<Curve> curves;
    for (const std::size_t i : cases) {
      curves.push_back({result.runs[i].csv, "LGVI (" + std::string(to_string(suite.cases[i].form)) + ")"});
    }
    const std::string suffix = ", h = " + format_h(scene.horizon.h);
    const struct {
      const char* script;
      const char* kind;
      std::string title;
      std::string ylabel;
    } figures[] = {
        {"energy_error.gp", "energy", name + ": energy error" + suffix, labels.energy},
        {"orthogonality.gp", "orthogonality", name + ": orthogonality error" + suffix, "||R^T R - I||_F"},
        {"momentum.gp", "momentum", name + ": " + momentum_map(scene.model).description + " error" + suffix,
         labels.momentum},
    };
    for (const auto& f : figures) {
      const fs::path png = options.out_dir / (name + "-" + f.kind + ".png");
      render_plot(options.gnuplot, options.plots_dir / f.script, png, f.title, labels.time, f.ylabel, curves);
      result.plots.push_back(png);
    }
  }
  progress << "wrote " << result.plots.size() << " plots in " << options.out_dir.string() << "\n";
  return result;
}

}  // namespace lgvi::experiments
