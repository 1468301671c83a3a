// The suite registry and the "all" meta-suite. A new suite (e.g. the optimal-control
// sensitivity and shooting suites) is a SuiteFactory returning its cases (any Job) and a
// renderer, listed once below.
#include <algorithm>

#include "experiments/suites/common.hpp"
#include "experiments/suites/study.hpp"

namespace lgvi::experiments {

namespace fs = std::filesystem;

const std::vector<SuiteEntry>& suite_registry() {
  static const std::vector<SuiteEntry> registry = {
      {"default", "every scene of the scenes directory with the symmetric and the printed LGVI",
       suites::default_suite},
      {"energy-drift", "energy error over 10^5 (quick) / 10^7 steps, every method: free body, pendulum, dumbbell",
       suites::energy_drift_suite},
      {"orthogonality", "||R^T R - I|| and quaternion norm error vs time, every method: free body, pendulum",
       suites::orthogonality_suite},
      {"momentum", "momentum maps vs time: pendulum, free body, connected bodies", suites::momentum_suite},
      {"work-precision", "final-state and energy error vs wall time and evaluations, sweeping h and rtol",
       suites::work_precision_suite},
      {"long-horizon", "energy, momentum, orthogonality error after 10^4 s (quick 10^3 s) vs cost, sweeping h and rtol",
       suites::long_horizon_suite},
      {"extremes", "where methods break: large h|Omega|, fast spin, near-flat inertia, tiny steps, gimbal lock",
       suites::extremes_suite},
      {"soak", "10^7 steps (quick 10^5) of the symmetric LGVI per system: conservation and peak resident memory",
       suites::soak_suite},
      {"sensitivity", "transition matrices: LGVI linearization and CVODES vs finite differences and each other, over T",
       suites::sensitivity_suite},
      {"shooting", "indirect optimal control: convergence histories and condition numbers, discrete vs continuous, "
                   "decomposed vs not", suites::shooting_suite},
      {"ocp-comparison", "every optimal control method on the paper's examples, 8 starts (quick 2): own and replayed "
                         "cost and violation against CPU time", suites::ocp_comparison_suite},
      {"ensemble-bodies", "200 random free bodies and 200 random heavy tops (quick 20 each): every metric's median, "
                          "quantiles and failures over the samples, banded work-precision figures",
       [](const SuiteParams& params) { return load_study(default_studies_dir() / "ensemble-bodies.toml", params); }},
      {"all", "every suite above, one subdirectory each (the README's main command runs it with --quick)",
       suites::all_suite},
  };
  return registry;
}

namespace suites {

Suite all_suite(const SuiteParams& params) {
  Suite all;
  all.name = "all";
  all.description = "every suite, one subdirectory each";
  std::vector<Suite> parts;
  for (const SuiteEntry& e : suite_registry()) {
    if (e.name == "all") continue;
    parts.push_back(e.make(params));
  }
  for (Suite& part : parts) {
    for (SuiteCase& c : part.cases) {
      c.id = part.name + "/" + c.id;
      c.group = part.name + "/" + c.group;
      all.cases.push_back(std::move(c));
    }
    for (const std::string& col : part.columns) {
      if (std::find(all.columns.begin(), all.columns.end(), col) == all.columns.end()) all.columns.push_back(col);
    }
  }
  // Each part renders its own rows into its subdirectory, with its own group names.
  all.render = [parts](const RenderContext& ctx, const std::vector<SummaryRow>& rows) {
    std::vector<fs::path> files;
    for (const Suite& part : parts) {
      if (!part.render) continue;
      const std::string prefix = part.name + "/";
      std::vector<SummaryRow> mine;
      for (const SummaryRow& r : rows) {
        if (!r.text("case").starts_with(prefix)) continue;
        mine.push_back(r.with("group", r.text("group").substr(std::min(prefix.size(), r.text("group").size()))));
      }
      if (mine.empty()) continue;
      RenderContext sub = ctx;
      sub.out_dir = ctx.out_dir / part.name;
      const std::vector<fs::path> more = part.render(sub, mine);
      files.insert(files.end(), more.begin(), more.end());
    }
    return files;
  };
  return all;
}

}  // namespace suites
}  // namespace lgvi::experiments
