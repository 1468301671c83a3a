// "default": every scene of the scenes directory with the symmetric and the printed LGVI, at
// the scene's own step and horizon; per scene, figures of the energy, orthogonality and
// momentum errors of both forms.
#include "experiments/output/atomic_file.hpp"
#include "experiments/output/plot.hpp"
#include "experiments/scene/scene.hpp"
#include "experiments/suites/common.hpp"

namespace lgvi::experiments::suites {

namespace fs = std::filesystem;

Suite default_suite(const SuiteParams& params) {
  Suite s;
  s.name = "default";
  s.description = "every scene of the scenes directory with the symmetric and the printed LGVI";
  s.columns = simulation_columns();
  s.columns.push_back("momentum_map");
  const MethodSpec lgvi("lgvi");
  for (const std::string& scene : scene_names(params.scenes_dir)) {
    // An optimal control problem (a scene with an [ocp] table) is run by `ocp`, not simulated here.
    if (load_scene(params.scenes_dir / (scene + ".toml")).ocp) continue;
    for (const LgviForm form : {LgviForm::Symmetric, LgviForm::Printed}) {
      SimulateSpec spec;
      spec.scene = scene;
      spec.overrides.form = form;
      SuiteCase c = simulate_case(scene + "-" + to_string(form), scene, spec, lgvi, Expectation::Complete);
      for (Field& f : c.labels) {
        if (f.key == "label") f.value = "LGVI (" + std::string(to_string(form)) + ")";
      }
      s.cases.push_back(std::move(c));
    }
  }
  s.render = [](const RenderContext& ctx, const std::vector<SummaryRow>& rows) {
    std::vector<fs::path> files;
    for (const auto& [scene, group] : by_group(rows)) {
      const SummaryRow& first = *group.front();
      const SystemLabels labels = system_labels(first.text("system"));
      const std::string suffix = ", h = " + title_number(first, "h");
      const struct {
        const char* column;
        const char* kind;
        std::string title;
        std::string ylabel;
      } figures[] = {
          {"energy_error", "energy", scene + ": energy error" + suffix, labels.energy},
          {"orthogonality_error", "orthogonality", scene + ": orthogonality error" + suffix, "||R^T R - I||_F"},
          {"momentum_error", "momentum", scene + ": " + first.text("momentum_map") + " error" + suffix, labels.momentum},
      };
      for (const auto& f : figures) {
        files.push_back(plot_time_series(ctx, scene + "-" + f.kind, f.title, f.ylabel, f.column, false, group));
      }
    }
    return files;
  };
  return s;
}

}  // namespace lgvi::experiments::suites
