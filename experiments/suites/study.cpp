#include "experiments/suites/study.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <optional>
#include <set>

#include <toml++/toml.h>

#include "baselines/tolerance.hpp"
#include "experiments/output/data_dir.hpp"
#include "experiments/systems/exact_reference.hpp"
#include "experiments/scene/scene.hpp"
#include "experiments/input/toml_reader.hpp"
#include "experiments/suites/journal.hpp"
#include "experiments/suites/common.hpp"
#include "experiments/suites/ensemble.hpp"
#include "experiments/suites/ensemble_statistics.hpp"
#include "experiments/systems/systems.hpp"

namespace lgvi::experiments {

namespace fs = std::filesystem;
using suites::MethodSpec;

namespace {

/// Keys a study's top level may hold; all but name, description and quick may also be in [quick].
constexpr std::string_view kTopKeys[] = {"name",    "description",      "scenes", "methods", "h",
                                         "steps",   "tolerances",       "horizons", "reference", "metrics",
                                         "samples", "adaptive_samples", "probes", "ensemble", "quick"};
constexpr std::string_view kQuickKeys[] = {"scenes",  "methods",          "h",      "steps",   "tolerances", "horizons",
                                           "reference", "metrics",        "samples", "adaptive_samples", "probes",
                                           "ensemble"};
constexpr std::string_view kSceneKeys[] = {"scene", "horizons", "h", "steps", "tolerances", "ensemble"};
constexpr std::string_view kMethodKeys[] = {"method", "model", "where"};
/// samples and adaptive_samples: rows per run, at most 10^7 (a case's CSV of 10^7 rows is about
/// 2 GB; adaptive_samples = 10^13, a grid of more steps than a horizon may have, was refused
/// naming the scene file's "integration.t_final (--t-final, h from --h)" instead of this key).
constexpr Range kStudySamples = Range::integers(1, 1e7);
constexpr std::string_view kReferenceKeys[] = {"kind", "method", "model", "h", "steps", "rtol"};

std::string join(std::span<const std::string_view> items) {
  std::string s;
  for (const std::string_view i : items) s += (s.empty() ? "" : ", ") + std::string(i);
  return s;
}

/// The study's TOML tree with its [quick] overlay; the value rules are TomlReader's (a wrong
/// type named by its kind only).
class StudyReader : public TomlReader {
 public:
  StudyReader(std::string file, const toml::table& doc, const toml::table* quick)
      : TomlReader(std::move(file), TypeDescription::Kind), doc_(doc), quick_(quick) {}

  /// A top-level value with its field name: from [quick] when the quick form is run and the
  /// table has it, else from the top level; node is null when neither has it.
  struct Value {
    const toml::node* node = nullptr;
    std::string field;
  };
  Value get(std::string_view key) const {
    if (quick_ != nullptr) {
      if (const toml::node* n = quick_->get(key)) return {n, "quick." + std::string(key)};
    }
    return {doc_.get(key), std::string(key)};
  }

 private:
  const toml::table& doc_;
  const toml::table* quick_;
};

/// The fixed-step sweep: steps h, or numbers of steps over the horizon (h = T / n); neither: the
/// scene's own h.
struct FixedSweep {
  std::vector<double> h;
  std::vector<std::int64_t> steps;
  std::string field;  ///< where it was given
};

struct SceneEntry {
  std::string arg;   ///< SimulateSpec::scene: a name in the scenes directory or a path
  std::string name;  ///< the scene's name (file stem): case ids, groups, the "scene" column
  std::optional<Scene> scene;  ///< as its file says (loaded by read_scene)
  std::string field;
  std::vector<double> horizons;
  std::string horizons_field;
  FixedSweep fixed;
  std::vector<double> tolerances;
  std::string tolerances_field;
  const toml::node* ensemble = nullptr;  ///< the scene table's own [ensemble] keys
  std::string ensemble_field;
};

struct Reference {
  /// ExactOrNone: the exact solution where the scene has one, no reference elsewhere (its
  /// cases then have no final-state or phase error).
  enum class Kind { None, Exact, ExactOrNone, ExactOrRun, Run } kind = Kind::None;
  std::string method;
  MethodOptions options;
  std::optional<double> h;
  std::optional<std::int64_t> steps;
  std::string field = "reference";
};

/// A tolerance: a number in the adaptive methods' range (baselines/tolerance.hpp), the check
/// `simulate --rtol` and make_method apply.
double read_tolerance(const StudyReader& r, const toml::node& n, const std::string& field) {
  const double x = r.finite_number(n, field);
  try {
    baselines::check_tolerance(x, field);
  } catch (const InvalidInput& e) {
    r.fail(field, reason_of(e));
  }
  return x;
}

/// A sweep of tolerances (read_tolerance), without repeats.
std::vector<double> tolerance_sweep(const StudyReader& r, const toml::node& n, const std::string& field) {
  std::vector<double> v;
  const toml::array& a = r.sweep(n, field);
  for (std::size_t i = 0; i < a.size(); ++i) {
    const std::string f = field + "[" + std::to_string(i) + "]";
    const double x = read_tolerance(r, *a.get(i), f);
    if (std::find(v.begin(), v.end(), x) != v.end()) r.fail(f, "repeats " + format_number(x));
    v.push_back(x);
  }
  return v;
}

FixedSweep read_fixed_sweep(const StudyReader& r, const toml::node* h, const std::string& h_field,
                            const toml::node* steps, const std::string& steps_field) {
  FixedSweep s;
  if (h != nullptr && steps != nullptr) {
    r.fail(steps_field, "give the fixed steps as h or as steps (numbers of steps per horizon), not both");
  }
  if (h != nullptr) {
    s.h = r.positive_sweep(*h, h_field);
    s.field = h_field;
  }
  if (steps != nullptr) {
    s.steps = r.count_sweep(*steps, steps_field);
    s.field = steps_field;
  }
  return s;
}

/// A method by name with an optional model (a baseline's defaults to kDefaultCoordinateModel), checked by
/// building it; errors name name_field or model_field.
MethodSpec make_study_method(const StudyReader& r, const std::string& name, const std::string& name_field,
                             std::optional<std::string> model, const std::string& model_field) {
  const MethodInfo* info = nullptr;
  try {
    info = &method_info(name);
  } catch (const InvalidInput& e) {
    r.fail(name_field, reason_of(e));
  }
  if (!model && !info->on_group()) model = kDefaultCoordinateModel;  // named in the case ids
  MethodSpec spec(name, model);
  MethodOptions check = spec.options();
  if (!info->fixed_step()) check.rtol = 1e-6;
  try {
    (void)info->make(check);
  } catch (const InvalidInput& e) {
    r.fail(e.field() == "model" ? model_field : name_field, reason_of(e));
  }
  return spec;
}

/// A method entry: "name", {method = "name", model = "..."}, or {where = "trait query"}: every
/// registered method whose traits match (methods_matching, e.g. "on_group and not variational",
/// the Lie group methods), each with its default model.
std::vector<MethodSpec> read_methods(const StudyReader& r, const toml::node& n, const std::string& field) {
  if (n.is_string()) return {make_study_method(r, r.string(n, field), field, std::nullopt, field)};
  const toml::table* t = n.as_table();
  if (t == nullptr) {
    r.fail(field, std::string("must be a method name or a table {method, model} (got ") + r.describe(n) + ")");
  }
  r.check_keys(*t, field, kMethodKeys);
  if (const toml::node* w = t->get("where")) {
    for (const char* key : {"method", "model"}) {
      if (t->get(key) != nullptr) r.fail(field + "." + key, "does not go with 'where' (a trait query names its methods)");
    }
    const std::string query = r.string(*w, field + ".where");
    std::vector<const MethodInfo*> matched;
    try {
      matched = methods_matching(query);
    } catch (const InvalidInput& e) {
      r.fail(field + ".where", reason_of(e));
    }
    if (matched.empty()) r.fail(field + ".where", "'" + query + "' matches no method");
    std::vector<MethodSpec> specs;
    for (const MethodInfo* info : matched) {
      specs.push_back(make_study_method(r, info->name, field + ".where", std::nullopt, field + ".where"));
    }
    return specs;
  }
  const toml::node* m = t->get("method");
  if (m == nullptr) r.fail(field + ".method", "is required (a method name; see 'lgvi-testbed simulate --help')");
  std::optional<std::string> model;
  if (const toml::node* mo = t->get("model")) model = r.string(*mo, field + ".model");
  return {make_study_method(r, r.string(*m, field + ".method"), field + ".method", model, field + ".model")};
}

Reference read_reference(const StudyReader& r) {
  Reference ref;
  const auto [node, field] = r.get("reference");
  ref.field = field;
  if (node == nullptr) return ref;
  const auto kind_of = [&](const std::string& text, const std::string& f, bool table) {
    if (text == "none") return Reference::Kind::None;
    if (text == "exact") return Reference::Kind::Exact;
    if (text == "exact-or-none") return Reference::Kind::ExactOrNone;
    if (table && text == "run") return Reference::Kind::Run;
    if (table && text == "exact-or-run") return Reference::Kind::ExactOrRun;
    r.fail(f, "unknown reference '" + text + "' (expected " +
                  (table ? "\"run\", \"exact-or-run\", \"exact\", \"exact-or-none\" or \"none\""
                         : "\"exact\", \"exact-or-none\", \"none\" or a table {method, h | steps | rtol}") +
                  ")");
  };
  if (node->is_string()) {
    ref.kind = kind_of(r.string(*node, field), field, false);
    return ref;
  }
  const toml::table* t = node->as_table();
  if (t == nullptr) {
    r.fail(field, std::string("must be \"exact\", \"exact-or-none\", \"none\" or a table (got ") + r.describe(*node) + ")");
  }
  r.check_keys(*t, field, kReferenceKeys);
  ref.kind = Reference::Kind::Run;
  if (const toml::node* k = t->get("kind")) ref.kind = kind_of(r.string(*k, field + ".kind"), field + ".kind", true);
  const bool runs = ref.kind == Reference::Kind::Run || ref.kind == Reference::Kind::ExactOrRun;
  if (!runs) {
    for (const char* key : {"method", "model", "h", "steps", "rtol"}) {
      if (t->get(key) != nullptr) r.fail(field + "." + key, "applies to a reference run only (kind \"run\" or \"exact-or-run\")");
    }
    return ref;
  }
  const toml::node* m = t->get("method");
  if (m == nullptr) r.fail(field + ".method", "is required (the method of the reference run)");
  std::optional<std::string> model;
  if (const toml::node* mo = t->get("model")) model = r.string(*mo, field + ".model");
  const MethodSpec spec =
      make_study_method(r, r.string(*m, field + ".method"), field + ".method", model, field + ".model");
  ref.method = spec.method;
  ref.options = spec.options();
  const toml::node* h = t->get("h");
  const toml::node* steps = t->get("steps");
  const toml::node* rtol = t->get("rtol");
  if (spec.fixed_step()) {
    if (rtol != nullptr) r.fail(field + ".rtol", "applies to an adaptive method; " + spec.method + " steps with h or steps");
    if (h != nullptr && steps != nullptr) r.fail(field + ".steps", "give h or steps, not both");
    if (h == nullptr && steps == nullptr) r.fail(field + ".h", "is required for the fixed-step " + spec.method + " (or steps)");
    if (h != nullptr) ref.h = r.positive(*h, field + ".h");
    if (steps != nullptr) ref.steps = r.integer_at_least(*steps, field + ".steps", 1);
  } else {
    if (h != nullptr || steps != nullptr) {
      r.fail(field + (h != nullptr ? ".h" : ".steps"), "applies to a fixed-step method; " + spec.method + " takes rtol");
    }
    if (rtol == nullptr) r.fail(field + ".rtol", "is required for the adaptive " + spec.method);
    ref.options.rtol = read_tolerance(r, *rtol, field + ".rtol");
  }
  return ref;
}

/// Where a scene argument of the study points: a path (contains '/' or ends in .toml), relative
/// to the study file's directory, or a name in the scenes directory.
std::string scene_argument(const std::string& arg, const fs::path& study_file) {
  const bool is_path = arg.find('/') != std::string::npos || (arg.size() > 5 && arg.ends_with(".toml"));
  if (!is_path) return arg;
  fs::path p(arg);
  if (p.is_relative()) p = (study_file.parent_path() / p).lexically_normal();
  std::string s = p.string();
  // A path without a '/' (study in the current directory) must still read as a path.
  if (s.find('/') == std::string::npos) s = "./" + s;
  return s;
}

SceneEntry read_scene(const StudyReader& r, const toml::node& n, const std::string& field, const fs::path& study_file,
                      const fs::path& scenes_dir) {
  SceneEntry e;
  e.field = field;
  const toml::table* t = n.as_table();
  std::string arg;
  std::string arg_field = field;
  if (n.is_string()) {
    arg = r.string(n, field);
  } else if (t != nullptr) {
    r.check_keys(*t, field, kSceneKeys);
    const toml::node* s = t->get("scene");
    if (s == nullptr) r.fail(field + ".scene", "is required (a scene name or the path of a scene file)");
    arg_field = field + ".scene";
    arg = r.string(*s, arg_field);
  } else {
    r.fail(field, std::string("must be a scene name, a path or a table {scene, horizons, h, steps, tolerances} (got ") +
                      r.describe(n) + ")");
  }
  if (arg.empty()) r.fail(arg_field, "is empty (a scene name or the path of a scene file)");
  e.arg = scene_argument(arg, study_file);
  fs::path file;
  try {
    file = resolve_scene(e.arg, scenes_dir);
  } catch (const SceneError& err) {
    r.fail(arg_field, "'" + arg + "': " + err.reason());
  }
  try {
    e.scene.emplace(load_scene(file));
  } catch (const SceneError& err) {
    r.fail(arg_field, err.what());  // "SCENE_FILE: FIELD: reason" of the scene file itself
  }
  e.name = e.scene->name;
  if (t != nullptr) {
    if (const toml::node* h = t->get("horizons")) {
      e.horizons_field = field + ".horizons";
      e.horizons = r.positive_sweep(*h, e.horizons_field);
    }
    e.fixed = read_fixed_sweep(r, t->get("h"), field + ".h", t->get("steps"), field + ".steps");
    if (const toml::node* tol = t->get("tolerances")) {
      e.tolerances_field = field + ".tolerances";
      e.tolerances = tolerance_sweep(r, *tol, e.tolerances_field);
    }
    e.ensemble = t->get("ensemble");
    e.ensemble_field = field + ".ensemble";
  }
  return e;
}

/// "%g" of a step (case ids).
std::string tag_g(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

/// "%.0e" of a tolerance (case ids).
std::string tag_e(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.0e", x);
  return buf;
}

bool has(const std::vector<std::string>& v, std::string_view x) { return std::find(v.begin(), v.end(), x) != v.end(); }

/// Levels of the cheapest-method tables.
const std::vector<double> kLevels(std::begin(kStudyLevels), std::end(kStudyLevels));

/// Each method's finest run of a group: of its completed runs (one curve label: method, model
/// and form), the one with the most evaluations (the smallest step or tightest tolerance).
std::vector<const SummaryRow*> finest_run_per_method(const std::vector<const SummaryRow*>& members) {
  std::vector<const SummaryRow*> finest;
  for (const SummaryRow* r : members) {
    if (r->text("status") != "completed" || r->text("csv_path").empty()) continue;
    const auto same = std::find_if(finest.begin(), finest.end(),
                                   [&](const SummaryRow* f) { return f->text("label") == r->text("label"); });
    if (same == finest.end()) {
      finest.push_back(r);
    } else if (r->number("evaluations").value_or(0.0) > (*same)->number("evaluations").value_or(0.0)) {
      *same = r;
    }
  }
  return finest;
}

/// Per group (scene and horizon): each metric against integrator time (metric "time") and
/// against evaluations, log-log, one curve per method; the errors over time of each method's
/// finest run (energy, momentum map, orthogonality: those of the metrics named); a table of the
/// cheapest method per level of each error metric.
SuiteRenderer study_renderer(std::string name, std::vector<std::string> metrics) {
  return [name, metrics](const RenderContext& ctx, const std::vector<SummaryRow>& rows) {
    std::vector<fs::path> files;
    const auto groups = suites::by_group(rows);
    const bool timed = has(metrics, "time");
    const std::string time_label = "integrator wall time per run [s] (min of repeated serial runs)";
    const std::string evaluations_label = "evaluations (baselines: RHS calls; LGVI: substeps)";
    for (const auto& [group, members] : groups) {
      const SummaryRow& first = *members.front();
      const std::string horizon = "T = " + suites::title_number(first, "t_final");
      for (const StudyMetricView& m : kStudyMetricViews) {
        if (!has(metrics, m.metric)) continue;
        std::string title = group + ": " + m.what + " over " + horizon + " vs cost";
        if (std::string_view(m.metric) == "final-error") title += " (reference: " + first.text("reference") + ")";
        std::vector<std::pair<std::string, std::string>> axes;
        if (timed) axes.emplace_back("integrator_seconds_min", "time");
        axes.emplace_back("evaluations", "evaluations");
        for (const auto& [x, suffix] : axes) {
          const fs::path png = suites::plot_xy(ctx, group + "-" + m.file + "-" + suffix, title,
                                               x == "evaluations" ? evaluations_label : time_label, m.ylabel,
                                               suites::curves_by_label(members, x, m.column));
          if (!png.empty()) files.push_back(png);
        }
      }
      const std::vector<const SummaryRow*> finest = finest_run_per_method(members);
      const SystemLabels labels = system_labels(first.text("system"));
      const struct {
        const char* metric;
        const char* column;
        const char* kind;
        std::string what;
        std::string ylabel;
      } series[] = {
          {"energy", "energy_error", "energy-over-time", "energy error", labels.energy},
          {"momentum", "momentum_error", "momentum-over-time", first.text("momentum_map") + " error", labels.momentum},
          {"orthogonality", "orthogonality_error", "orthogonality-over-time", "orthogonality error", "||R^T R - I||_F"},
      };
      for (const auto& f : series) {
        if (!has(metrics, f.metric) || finest.empty()) continue;
        const fs::path png = suites::plot_time_series(ctx, group + "-" + f.kind,
                                                      group + ": " + f.what + " over time, each method's finest run",
                                                      f.ylabel, f.column, false, finest);
        if (!png.empty()) files.push_back(png);
      }
    }
    std::string table = "# " + name + ": cheapest method per accuracy level\n\n"
                        "Per scene and horizon, among the completed runs whose error is at most the level: the one "
                        "with the least integrator time per run (wall time excluding recording, the minimum over "
                        "repeated serial runs; only with the metric \"time\") and the one with the fewest "
                        "evaluations (RHS calls for the baselines, substeps for the LGVI). Errors are maxima over "
                        "the written samples; the final-state error is against the reference named in "
                        "summary.csv.\n";
    bool any = false;
    for (const StudyMetricView& m : kStudyMetricViews) {
      if (!has(metrics, m.metric) || std::string_view(m.metric) == "orthogonality") continue;
      table += std::string("\n## ") + m.what + "\n\n" + suites::cheapest_table(groups, m.column, m.what, kLevels);
      any = true;
    }
    if (any) files.push_back(suites::write_text_file(ctx, name + "-table.md", table));
    return files;
  };
}

/// The study file's text: a regular file of at most 1 MiB (read_toml_file). Throws SceneError.
std::string read_study_file(const fs::path& file) { return read_toml_file(file, "the study file"); }

}  // namespace

fs::path default_studies_dir() { return data_dir("studies", "experiments/studies"); }

Suite load_study(const fs::path& file, const SuiteParams& params) {
  Suite s = parse_study(read_study_file(file), file, params);
  warn_once(file, s.warnings);
  return s;
}

Suite parse_study(std::string_view toml_text, const fs::path& file, const SuiteParams& params) {
  const std::string file_name = file.string();
  const toml::table doc = TomlReader(file_name, TypeDescription::Kind).parse(toml_text, "study");
  const StudyReader top(file_name, doc, nullptr);
  top.check_keys(doc, "", kTopKeys);
  const toml::table* quick = nullptr;
  if (const toml::node* q = doc.get("quick")) {
    quick = q->as_table();
    if (quick == nullptr) top.fail("quick", std::string("must be a table (got ") + top.describe(*q) + ")");
    top.check_keys(*quick, "quick", kQuickKeys);
  }
  const StudyReader r(file_name, doc, params.quick ? quick : nullptr);

  Suite s;
  s.name = file.stem().string();
  if (const toml::node* n = doc.get("name")) s.name = r.string(*n, "name");
  if (s.name.empty() || s.name.find_first_of("/\\\n\r\t") != std::string::npos) {
    r.fail("name", "must be a non-empty name without '/' or control characters (got '" + s.name + "')");
  }
  if (const toml::node* n = doc.get("description")) s.description = r.string(*n, "description");

  // Methods.
  std::vector<MethodSpec> fixed_methods;
  std::vector<MethodSpec> adaptive_methods;
  {
    const auto [node, field] = r.get("methods");
    if (node == nullptr) r.fail("methods", "is required (a list of method names, e.g. [\"lgvi\", \"cvode-bdf\"])");
    const toml::array& a = r.sweep(*node, field);
    std::set<std::string> seen;
    for (std::size_t i = 0; i < a.size(); ++i) {
      const std::string f = field + "[" + std::to_string(i) + "]";
      for (MethodSpec& m : read_methods(r, *a.get(i), f)) {
        if (!seen.insert(m.id()).second) r.fail(f, "lists " + m.id() + " twice");
        (m.fixed_step() ? fixed_methods : adaptive_methods).push_back(std::move(m));
      }
    }
  }

  // Reference and metrics.
  const Reference reference = read_reference(r);
  std::vector<std::string> metrics;
  {
    const auto [node, field] = r.get("metrics");
    if (node == nullptr) {
      for (const std::string_view m : kStudyMetrics) {
        if (m != "final-error" || reference.kind != Reference::Kind::None) metrics.emplace_back(m);
      }
    } else {
      const toml::array& a = r.sweep(*node, field);
      for (std::size_t i = 0; i < a.size(); ++i) {
        const std::string f = field + "[" + std::to_string(i) + "]";
        const std::string m = r.string(*a.get(i), f);
        if (std::find(std::begin(kStudyMetrics), std::end(kStudyMetrics), m) == std::end(kStudyMetrics)) {
          r.fail(f, "unknown metric '" + m + "' (expected one of: " + join(kStudyMetrics) + ")");
        }
        if (has(metrics, m)) r.fail(f, "lists '" + m + "' twice");
        metrics.push_back(m);
      }
      if (has(metrics, "final-error") && reference.kind == Reference::Kind::None) {
        r.fail(field, "final-error needs a reference (reference is \"none\": give \"exact\" or a reference run)");
      }
    }
  }

  // Sweeps and sampling shared by the scenes.
  const auto [horizons, horizons_field] = [&] {
    const auto [node, field] = r.get("horizons");
    return std::make_pair(node == nullptr ? std::vector<double>{} : r.positive_sweep(*node, field), field);
  }();
  const std::vector<double> tolerances = [&] {
    const auto [node, field] = r.get("tolerances");
    return node == nullptr ? std::vector<double>{} : tolerance_sweep(r, *node, field);
  }();
  const auto h_value = r.get("h");
  const auto steps_value = r.get("steps");
  const FixedSweep fixed = read_fixed_sweep(r, h_value.node, h_value.field, steps_value.node, steps_value.field);
  // An integer key in its range; the message says what the value is for and what is allowed.
  const auto integer_key = [&](std::string_view key, std::int64_t fallback, const Range& range, const char* what) {
    const auto [node, field] = r.get(key);
    if (node == nullptr) return fallback;
    const std::int64_t v = r.integer(*node, field);
    if (!range.contains(static_cast<double>(v))) r.fail(field, range.problem(static_cast<double>(v)) + ": " + what);
    return v;
  };
  const std::int64_t samples =
      integer_key("samples", 100, kStudySamples, "the rows written per fixed-step run (every K-th step, K = steps / samples)");
  const std::int64_t adaptive_samples = integer_key(
      "adaptive_samples", samples, kStudySamples,
      "the intervals of the adaptive runs' output grid (its step is T / adaptive_samples; one row per grid time)");
  const auto probes = static_cast<std::size_t>(integer_key(
      "probes", 0, Range::integers(0, 1000), "how many of the largest h of each fixed-step sweep are probes"));

  // Scenes, each loaded (its own errors name its file).
  std::vector<SceneEntry> scenes;
  {
    const auto [node, field] = r.get("scenes");
    if (node == nullptr) r.fail("scenes", "is required (a list of scene names or paths, e.g. [\"free-body\"])");
    const toml::array& a = r.sweep(*node, field);
    for (std::size_t i = 0; i < a.size(); ++i) {
      scenes.push_back(read_scene(r, *a.get(i), field + "[" + std::to_string(i) + "]", file, params.scenes_dir));
    }
  }
  // The files the cases come from, in the resume fingerprint (suite_journal.hpp): this file's
  // bytes, each scene file's bytes and those of the files the scenes read (control samples),
  // named by file name (where they lie is in this file and the scenes).
  s.inputs.push_back({"the study file " + file.filename().string(), text_fnv1a64(std::string(toml_text))});
  const auto add_input = [&](const SuiteInput& in) {
    const bool seen = std::any_of(s.inputs.begin(), s.inputs.end(), [&](const SuiteInput& x) {
      return x.what == in.what && x.digest == in.digest;
    });
    if (!seen) s.inputs.push_back(in);
  };
  for (const SceneEntry& e : scenes) {
    add_input({"the scene file " + e.scene->file.filename().string(), file_fnv1a64(e.scene->file)});
    for (const fs::path& p : e.scene->inputs) {
      add_input({"the control samples file " + p.filename().string(), file_fnv1a64(p)});
    }
  }

  if (!adaptive_methods.empty()) {
    for (const SceneEntry& e : scenes) {
      if (e.tolerances.empty() && tolerances.empty()) {
        r.fail("tolerances", "is required: the study has adaptive methods (" + adaptive_methods.front().method +
                                 "); give rtol values, e.g. [1e-6, 1e-8, 1e-10]");
      }
    }
  }

  s.columns = suites::simulation_columns();
  const bool timed = has(metrics, "time");
  if (timed) s.columns.insert(s.columns.end(), suites::timing_columns().begin(), suites::timing_columns().end());
  if (has(metrics, "momentum")) s.columns.push_back("momentum_map");

  // Ensembles: the top level's [ensemble], quick.ensemble's keys over it in the quick form, a
  // scene table's own keys over both; each scene's laws checked against its file.
  struct SceneEnsemble {
    std::optional<EnsembleLaws> laws;
    std::shared_ptr<const toml::table> doc;  ///< the scene file's table
  };
  std::vector<SceneEnsemble> ensembles;
  std::optional<std::int64_t> ensemble_samples;  // the fewest samples of a scene (--sample's range)
  for (const SceneEntry& e : scenes) {
    SceneEnsemble se;
    const std::vector<EnsembleLayer> layers = {
        {doc.get("ensemble"), "ensemble"},
        {params.quick && quick != nullptr ? quick->get("ensemble") : nullptr, "quick.ensemble"},
        {e.ensemble, e.ensemble_field}};
    if (std::any_of(layers.begin(), layers.end(), [](const EnsembleLayer& l) { return l.node != nullptr; })) {
      se.laws = read_ensemble(r, layers);
      se.doc = std::make_shared<const toml::table>(TomlReader(e.scene->file.string()).parse(*e.scene->text, "scene"));
      check_ensemble(r, *se.laws, *e.scene, *se.doc);
      ensemble_samples = std::min(ensemble_samples.value_or(se.laws->samples), se.laws->samples);
      if (!has(s.columns, "sample")) {
        s.columns.push_back("sample");
        s.columns.push_back("sample_seed");
      }
      for (const std::string& c : drawn_columns(*se.laws)) {
        if (!has(s.columns, c)) s.columns.push_back(c);
      }
    }
    ensembles.push_back(std::move(se));
  }
  if (params.sample) {
    if (!ensemble_samples) throw InvalidInput("--sample", "the study " + file_name + " has no [ensemble]");
    if (static_cast<std::int64_t>(*params.sample) >= *ensemble_samples) {
      throw InvalidInput("--sample", "must be a sample of the study: an integer in [0, " +
                                         std::to_string(*ensemble_samples - 1) + "] (got " +
                                         std::to_string(*params.sample) + ")");
    }
  }

  std::set<std::string> ids;
  std::set<std::string> applied;  // the methods with a case
  for (std::size_t scene_index = 0; scene_index < scenes.size(); ++scene_index) {
    const SceneEntry& e = scenes[scene_index];
    const SceneEnsemble& ensemble = ensembles[scene_index];
    if (reference.kind == Reference::Kind::Exact) {
      std::string why_not;
      if (!ExactReference::of(e.scene->model, &why_not)) {
        r.fail(reference.field, "exact: scene '" + e.name + "' (" + e.scene->system() + ") has no exact solution (" +
                                    why_not + "); give a reference run, kind \"exact-or-run\", or \"none\"");
      }
    }
    const std::vector<double>& scene_horizons = !e.horizons.empty() ? e.horizons
                                                : !horizons.empty() ? horizons
                                                                    : std::vector<double>{e.scene->horizon.t_final};
    const std::string& scene_horizons_field = !e.horizons.empty() ? e.horizons_field : horizons_field;
    const FixedSweep& sweep = !e.fixed.field.empty() ? e.fixed : fixed;
    const std::vector<double>& scene_tolerances = !e.tolerances.empty() ? e.tolerances : tolerances;

    // The samples of this scene: all of them, only --sample's, or one nominal run.
    std::vector<std::shared_ptr<const EnsembleSample>> draws;
    if (ensemble.laws) {
      const auto first = params.sample ? *params.sample : std::size_t{0};
      const auto end = params.sample ? first + 1 : static_cast<std::size_t>(ensemble.laws->samples);
      for (std::size_t k = first; k < end; ++k) {
        draws.push_back(std::make_shared<const EnsembleSample>(ensemble.doc, *ensemble.laws, *e.scene, k));
      }
    } else {
      draws.push_back(nullptr);
    }
    for (const double T : scene_horizons) {
      for (const std::shared_ptr<const EnsembleSample>& sample : draws) {
        const std::string group = scene_horizons.size() > 1 ? e.name + "-T" + tag_g(T) : e.name;
        const std::string id_prefix = group + "-" + (sample ? "s" + std::to_string(sample->index()) + "-" : "");
        // A horizon and step the harness accepts (a whole number of steps), named in the study.
        const auto horizon_of = [&](double h, const std::string& field) {
          try {
            return make_horizon(h, T, 1, e.scene->last_step);
          } catch (const InvalidInput& err) {
            r.fail(field, "horizon T = " + format_number(T) + " of scene '" + e.name + "' with h = " + format_number(h) +
                              ": " + reason_of(err) +
                              (field == scene_horizons_field ? "" : " (horizons from " + (scene_horizons_field.empty() ? std::string("the scene file") : scene_horizons_field) + ")"));
          }
        };

        std::shared_ptr<const ReferenceRun> ref;
        const bool exact_here = reference.kind != Reference::Kind::ExactOrNone || ExactReference::of(e.scene->model);
        if (reference.kind != Reference::Kind::None && exact_here) {
          SimulateSpec spec;
          spec.scene = e.arg;
          spec.sample = sample;
          spec.overrides.t_final = T;
          spec.method = reference.method.empty() ? "lgvi" : reference.method;
          spec.options = reference.options;
          if (reference.kind == Reference::Kind::Exact || reference.kind == Reference::Kind::ExactOrNone ||
              spec.options.rtol) {
            spec.overrides.h = T;  // one output interval: only the final state is compared
            spec.overrides.output_every = 1;
          } else {
            const double h = reference.steps ? T / static_cast<double>(*reference.steps) : *reference.h;
            const Horizon hz = horizon_of(h, reference.field + (reference.steps ? ".steps" : ".h"));
            spec.overrides.h = h;
            spec.overrides.output_every = static_cast<std::int64_t>(hz.steps);
          }
          ref = reference.kind == Reference::Kind::Run ? std::make_shared<const ReferenceRun>(spec)
                                                       : ReferenceRun::exact_or_run(spec, params.scenes_dir);
        }

        // The fixed steps of this horizon with their case-id tags, largest h first for the probes.
        struct Step {
          double h;
          std::size_t steps;
          std::string tag;
        };
        std::vector<Step> steps;
        if (!sweep.steps.empty()) {
          for (const std::int64_t n : sweep.steps) {
            const double h = T / static_cast<double>(n);
            (void)horizon_of(h, sweep.field);
            steps.push_back({h, static_cast<std::size_t>(n), "n" + std::to_string(n)});
          }
        } else {
          const std::vector<double> hs = !sweep.h.empty() ? sweep.h : std::vector<double>{e.scene->horizon.h};
          const std::string field = !sweep.h.empty() ? sweep.field : scene_horizons_field;
          for (const double h : hs) {
            const Horizon hz = horizon_of(h, field.empty() ? e.field : field);
            steps.push_back({h, hz.steps, "h" + tag_g(h)});
          }
        }
        std::vector<double> by_size;
        for (const Step& st : steps) by_size.push_back(st.h);
        std::sort(by_size.rbegin(), by_size.rend());
        const auto is_probe = [&](double h) {
          const auto rank = static_cast<std::size_t>(std::find(by_size.begin(), by_size.end(), h) - by_size.begin());
          return rank < probes;
        };

        const auto add = [&](SuiteCase c) {
          if (!ids.insert(c.id).second) {
            r.fail(e.field, "makes the case '" + c.id + "' twice (a scene and horizon listed twice?)");
          }
          for (Field& f : c.labels) {
            if (f.key == "scene") f.value = e.name;
          }
          if (sample) c.labels.insert(c.labels.end(), sample->fields().begin(), sample->fields().end());
          c.group = group;
          s.cases.push_back(std::move(c));
        };
        // A method applies to the systems its traits name (a splitting: the separable ones); it
        // is left out of the other scenes, and refused below if it applies to none.
        const std::string system = e.scene->system();
        for (const MethodSpec& m : fixed_methods) {
          if (!m.info->applies_to(system)) continue;
          applied.insert(m.method);
          // A first-order method (Lie-Euler: explicit, its energy grows by (1 + h^2 |Omega|^2)^(1/2)
          // a step on these undamped systems) may overflow on a long horizon at any step: a probe
          // at every step.
          const bool first_order = m.info->order == 1;
          for (const Step& st : steps) {
            SimulateSpec spec;
            spec.scene = e.arg;
            spec.sample = sample;
            spec.overrides.t_final = T;
            spec.overrides.h = st.h;
            spec.overrides.output_every =
                static_cast<std::int64_t>(std::max<std::size_t>(1, st.steps / static_cast<std::size_t>(samples)));
            spec.timed = timed;
            add(suites::simulate_case(id_prefix + m.id() + "-" + st.tag, group, spec, m,
                                      is_probe(st.h) || first_order ? Expectation::Either : Expectation::Complete,
                                      ref));
          }
        }
        for (MethodSpec m : adaptive_methods) {
          if (!m.info->applies_to(system)) continue;
          applied.insert(m.method);
          for (const double rtol : scene_tolerances) {
            m.rtol = rtol;
            SimulateSpec spec;
            spec.scene = e.arg;
            spec.sample = sample;
            spec.overrides.t_final = T;
            spec.overrides.h = T / static_cast<double>(adaptive_samples);  // the output grid
            spec.overrides.output_every = 1;
            spec.timed = timed;
            add(suites::simulate_case(id_prefix + m.id() + "-rtol" + tag_e(rtol), group, spec, m, Expectation::Complete,
                                      ref));
          }
        }
      }
    }
  }
  for (const std::vector<MethodSpec>* list : {&fixed_methods, &adaptive_methods}) {
    for (const MethodSpec& m : *list) {
      if (applied.contains(m.method)) continue;
      std::string systems;
      for (const std::string& name : m.info->systems) systems += (systems.empty() ? "" : ", ") + name;
      r.fail("methods", m.method + " applies to none of the study's scenes (its systems: " + systems + ")");
    }
  }
  if (s.cases.empty()) r.fail("methods", "the study has no cases");
  // A file cut short, by the scene files' rule (toml_text.hpp): a last line without its newline
  // is warned about; a cut at a line boundary is refused by the shipped studies' order (their
  // last line is a required key; experiments/studies/README.md, "A file cut short").
  if (const auto warning = truncation_warning(toml_text, file_name)) s.warnings.push_back(*warning);
  s.render = ensemble_samples ? ensemble_renderer(s.name, metrics) : study_renderer(s.name, metrics);
  return s;
}

}  // namespace lgvi::experiments
