#include "experiments/scene/scene.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <memory>
#include <mutex>
#include <set>
#include <span>
#include <sstream>
#include <vector>

#include <toml++/toml.h>

#include "experiments/output/csv_writer.hpp"
#include "experiments/output/data_dir.hpp"
#include "experiments/scene/ocp_scene.hpp"
#include "experiments/scene/scene_table.hpp"
#include "experiments/input/scene_reader.hpp"
#include "experiments/input/toml_reader.hpp"
#include "experiments/systems/systems.hpp"
#include "lgvi/range.hpp"
#include "lgvi/so3.hpp"

namespace lgvi::experiments {

namespace fs = std::filesystem;

namespace {

/// The model of binding B's system from the scene's tables, checking every table's keys before
/// reading any value (a misspelt key is the likeliest cause of a missing one).
template <class B>
Model read_system(const SceneReader& r, const SceneTable& parameters, const SceneTable& initial,
                  const SceneTable& integration, const std::optional<SceneTable>& control) {
  B::check_keys(r, parameters, initial);
  r.check_keys(integration, {"h", "t_final", "form", "output_every", "last_step"});
  if (control) B::check_control_keys(r, *control);
  return B::read(r, parameters, initial, control);
}

/// The model of the scene's `system` (the name of a Model alternative), read by its binding.
Model read_model(const SceneReader& r, const std::string& system, const SceneTable& parameters,
                 const SceneTable& initial, const SceneTable& integration, const std::optional<SceneTable>& control) {
  std::optional<Model> model;
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    const auto try_one = [&]<class M>(std::type_identity<M>) {
      if (!model && system == M::name) {
        model.emplace(read_system<SystemBinding<M>>(r, parameters, initial, integration, control));
      }
    };
    (try_one(std::type_identity<std::variant_alternative_t<I, Model>>{}), ...);
  }(std::make_index_sequence<std::variant_size_v<Model>>{});
  if (!model) r.fail("system", "unknown system '" + system + "'");  // parse_scene checked the name
  return std::move(*model);
}

}  // namespace

LastStep parse_last_step(const std::string& name) {
  if (name == "error") return LastStep::Error;
  if (name == "shorter") return LastStep::Shorter;
  throw InvalidInput("last_step", "unknown value '" + name + "' (expected \"error\" or \"shorter\")");
}

Horizon make_horizon(double h, double t_final, std::int64_t output_every, LastStep last_step) {
  require_positive(h, "h");
  require_positive(t_final, "t_final");
  const double n = t_final / h;
  if (!(n <= kMaxSteps)) {  // lgvi/range.hpp
    throw InvalidInput("t_final", "needs too many steps (t_final / h = " + format_number(n) +
                                      ", limit " + format_number(kMaxSteps) + ")");
  }
  double steps = std::round(n);
  const bool whole = std::abs(steps * h - t_final) <= 1e-9 * t_final;
  const bool shorter = !whole && last_step == LastStep::Shorter;
  if (shorter) steps = std::floor(n);
  if (steps < 1.0) {
    throw InvalidInput("t_final", "is shorter than one step (t_final = " + format_number(t_final) +
                                      ", h = " + format_number(h) + ")");
  }
  if (!whole && !shorter) {
    throw InvalidInput("t_final", "is not a whole number of steps of h = " + format_number(h) +
                                      " (t_final / h = " + format_number(n) + ")");
  }
  // floor(n) whole steps end short of t_final by more than the tolerance (else `whole`): the
  // last step t_final - floor(n) h lies in (1e-9 t_final, h).
  if (shorter) steps += 1.0;
  // Bounded by the step limit: a larger K writes the same two rows (first and last) as K = steps,
  // and next_written + K stays far from overflow.
  if (output_every < 1 || static_cast<double>(output_every) > kMaxSteps) {
    throw InvalidInput("output_every", "must be an integer >= 1 and <= " + format_number(kMaxSteps) + " (got " +
                                           std::to_string(output_every) + ")");
  }
  Horizon horizon;
  horizon.h = h;
  horizon.t_final = t_final;
  horizon.steps = static_cast<std::size_t>(steps);
  horizon.output_every = static_cast<std::size_t>(output_every);
  horizon.shorter_last_step = shorter;
  return horizon;
}

Scene parse_scene(std::string_view toml_text, const fs::path& file, const SceneOverrides& overrides) {
  const toml::table doc = TomlReader(file.string()).parse(toml_text, "scene");
  return parse_scene_table(doc, toml_text, file, overrides);
}

Scene parse_scene_table(const toml::table& doc, std::string_view toml_text, const fs::path& file,
                        const SceneOverrides& overrides) {
  const std::string file_name = file.string();
  const TomlReader r(file_name);

  // Unknown keys first, everywhere: a misspelt key is the likeliest cause of a missing one.
  r.check_keys(doc, "", {"system", "description", "parameters", "initial", "integration", "control", "ocp"});
  const std::string system = r.required(doc, "system", "", &TomlReader::string);
  std::string known;
  bool is_known = false;
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    for (const std::string_view name : {std::string_view(std::variant_alternative_t<I, Model>::name)...}) {
      known += (known.empty() ? "" : ", ") + std::string(name);
      is_known = is_known || system == name;
    }
  }(std::make_index_sequence<std::variant_size_v<Model>>{});
  if (!is_known) r.fail("system", "unknown system '" + system + "' (expected one of: " + known + ")");
  const toml::table* parameters = r.table(doc, "parameters", "", true);
  const toml::table* initial = r.table(doc, "initial", "", true);
  const toml::table* integration = r.table(doc, "integration", "", true);
  const toml::table* control = r.table(doc, "control", "", false);
  const toml::table* ocp = r.table(doc, "ocp", "", false);

  // The system's tables, read by its binding (keys first, everywhere).
  const SceneReader reader(file_name);
  std::optional<SceneTable> control_table;
  if (control != nullptr) control_table = SceneTableAccess::make(*control, "control");
  Scene scene{file.stem().string(), file, "",
              read_model(reader, system, SceneTableAccess::make(*parameters, "parameters"),
                         SceneTableAccess::make(*initial, "initial"), SceneTableAccess::make(*integration, "integration"),
                         control_table),
              Horizon{}, LgviForm::Symmetric, nullptr, {}};
  if (const toml::node* d = doc.get("description")) scene.description = r.string(*d, "description");

  // [integration], with the command-line overrides named in messages.
  double h = r.required(*integration, "h", "integration", &TomlReader::number);
  double t_final = r.required(*integration, "t_final", "integration", &TomlReader::number);
  std::int64_t every = 1;
  if (const toml::node* e = integration->get("output_every")) every = r.integer(*e, "integration.output_every");
  if (const toml::node* f = integration->get("form")) {
    const std::string form = r.string(*f, "integration.form");
    scene.form = r.physics("integration.", [&] { return parse_lgvi_form(form); });
  }
  if (const toml::node* l = integration->get("last_step")) {
    const std::string last_step = r.string(*l, "integration.last_step");
    scene.last_step = r.physics("integration.", [&] { return parse_last_step(last_step); });
  }
  if (overrides.h) h = *overrides.h;
  if (overrides.t_final) t_final = *overrides.t_final;
  if (overrides.output_every) every = *overrides.output_every;
  if (overrides.form) scene.form = *overrides.form;
  try {
    scene.horizon = make_horizon(h, t_final, every, scene.last_step);
  } catch (const InvalidInput& e) {
    std::vector<std::string> notes;  // which values came from the command line
    if (e.field() == "h" && overrides.h) notes.push_back("--h");
    if (e.field() == "t_final" && overrides.t_final) notes.push_back("--t-final");
    if (e.field() == "t_final" && overrides.h) notes.push_back("h from --h");
    if (e.field() == "output_every" && overrides.output_every) notes.push_back("--every");
    std::string field = "integration." + e.field();
    for (std::size_t i = 0; i < notes.size(); ++i) field += (i == 0 ? " (" : ", ") + notes[i];
    if (!notes.empty()) field += ")";
    r.fail(field, reason_of(e));
  }
  if (ocp != nullptr) {
    if (scene.horizon.shorter_last_step) {
      r.fail("integration.last_step", "\"shorter\" is not allowed with [ocp]: the optimal control problem needs "
                                      "t_final a whole number of steps of h");
    }
    if (!kOcpSteps.contains(static_cast<double>(scene.horizon.steps))) {
      // Named by the value that set the number of steps: t_final when only it came from the
      // command line, else h (with the option that gave it).
      const std::string field = overrides.t_final && !overrides.h ? "integration.t_final (--t-final)"
                                : overrides.h                     ? "integration.h (--h)"
                                                                  : "integration.h";
      r.fail(field, "gives " + std::to_string(scene.horizon.steps) + " steps (t_final / h, t_final = " +
                        format_number(scene.horizon.t_final) + ", h = " + format_number(scene.horizon.h) +
                        "); a scene with [ocp] takes at most " + Range::text(kOcpSteps.hi) +
                        " (its solvers keep every step's state and sensitivities)");
    }
    scene.ocp = read_ocp_table(reader, scene.model, SceneTableAccess::make(*parameters, "parameters"),
                               SceneTableAccess::make(*ocp, "ocp"));
  }
  // A file cut short can be another valid scene: "t_final = 50.0" cut to "t_final = 5", or a
  // file without its last tables ([control] is optional). The defence (README, "File-level
  // rules"): a cut inside a line leaves a last line without its newline, warned about here; a
  // refusal would break hand-written files saved without one. A cut at a line boundary drops the
  // last line: the shipped scenes end with a required key (integration.t_final), so that is an
  // error. Reporting absent optional tables was not chosen: 11 of the 13 shipped scenes have no
  // [control] and would print a line on every run, and absent optional keys (form,
  // output_every, phase) would still pass unreported; an optional end marker cannot be told
  // missing from a file written without one.
  scene.inputs = reader.inputs();
  if (toml_text.empty()) return scene;  // a table made in memory (an ensemble's sample)
  if (const auto warning = truncation_warning(toml_text, file_name)) scene.warnings.push_back(*warning);
  scene.text = std::make_shared<const std::string>(toml_text);
  return scene;
}

Scene parse_scene_file(const fs::path& file, const SceneOverrides& overrides) {
  // A regular file of at most 1 MiB: a FIFO or a device (/dev/zero) is refused, not read.
  return parse_scene(read_toml_file(file, "the scene file"), file, overrides);
}

Scene load_scene(const fs::path& file, const SceneOverrides& overrides) {
  Scene scene = parse_scene_file(file, overrides);
  warn_once(file, scene.warnings);
  return scene;
}

fs::path default_scenes_dir() { return data_dir("scenes", "experiments/scenes"); }

std::vector<std::string> scene_names(const fs::path& scenes_dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (fs::directory_iterator it(scenes_dir, ec), end; !ec && it != end; it.increment(ec)) {
    if (it->path().extension() == ".toml" && it->is_regular_file(ec)) names.push_back(it->path().stem().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

fs::path resolve_scene(const std::string& name_or_path, const fs::path& scenes_dir) {
  const bool is_path = name_or_path.find('/') != std::string::npos ||
                       (name_or_path.size() > 5 && name_or_path.ends_with(".toml"));
  if (is_path) return name_or_path;
  const fs::path file = scenes_dir / (name_or_path + ".toml");
  std::error_code ec;
  if (!name_or_path.empty() && fs::is_regular_file(file, ec)) return file;
  std::string known;
  for (const std::string& n : scene_names(scenes_dir)) known += (known.empty() ? "" : ", ") + n;
  throw SceneError(name_or_path, "",
                   "unknown scene; known scenes: " + (known.empty() ? std::string("(none)") : known) +
                       " (in " + scenes_dir.string() + "); or give the path of a .toml file");
}

}  // namespace lgvi::experiments
