#include "experiments/input/paper_values.hpp"

#include <stdexcept>
#include <string_view>

#include "experiments/input/toml_reader.hpp"
#include "lgvi/inertia.hpp"

namespace lgvi::experiments {

namespace {

constexpr const char* kFile = "validation/paper_values.toml";

/// The number at `path` ("key.name", "key.name[0]"), if there: TomlReader's number rule.
std::optional<double> optional_number(const TomlReader& r, const toml::table& table, const std::string& path) {
  const toml::node* n = table.at_path(path).node();
  if (n == nullptr) return std::nullopt;
  return r.number(*n, path);
}

double required(const TomlReader& r, const toml::table& table, const std::string& path) {
  const toml::node* n = table.at_path(path).node();
  if (n == nullptr || !n->is_number()) r.fail(path, "missing or not a number");
  return r.number(*n, path);
}

PaperExample example(const TomlReader& r, const toml::table& table, const std::string& key,
                     const std::string& section) {
  PaperExample e;
  e.key = key;
  e.section = section;
  const toml::node* system = table.at_path(key + ".system").node();
  if (system == nullptr) r.fail(key + ".system", "is required");
  e.system = r.string(*system, key + ".system");
  e.cost = required(r, table, key + ".cost");
  e.terminal_violation = required(r, table, key + ".terminal_violation");
  e.outer_iterations_approx = optional_number(r, table, key + ".outer_iterations_approx");
  e.h = optional_number(r, table, key + ".h");
  e.horizon = optional_number(r, table, key + ".horizon");
  return e;
}

/// A defect of the embedded file is the build's: std::logic_error, "FILE: FIELD: reason" (a
/// syntax error without its line, "FILE: reason").
PaperValues parse() {
  const TomlReader r(kFile);
  toml::table table;
  try {
    table = r.parse(kPaperValuesToml, "paper values");
  } catch (const SceneError& e) {
    throw std::logic_error(std::string(kFile) + ": " + e.reason());
  }
  try {
    PaperValues p;
    p.dumbbell = example(r, table, "dumbbell_orbit_transfer", "3.1");
    p.pendulum = example(r, table, "pendulum_reorientation", "3.2");
    p.cart_pendulum = example(r, table, "cart_pendulum", "4.1");
    p.connected_bodies = example(r, table, "connected_bodies", "4.2");
    p.decomposed_condition_min = required(r, table, "pendulum_reorientation.decomposed_condition_number_range[0]");
    p.decomposed_condition_max = required(r, table, "pendulum_reorientation.decomposed_condition_number_range[1]");
    p.undecomposed_condition = required(r, table, "pendulum_reorientation.undecomposed_condition_number");
    return p;
  } catch (const SceneError& e) {
    throw std::logic_error(e.what());
  }
}

}  // namespace

const PaperExample& PaperValues::example(const std::string& system) const {
  for (const PaperExample* e : {&dumbbell, &pendulum, &cart_pendulum, &connected_bodies}) {
    if (e->system == system) return *e;
  }
  throw InvalidInput("system", "the paper has no optimal control example for '" + system + "'");
}

const PaperExample* PaperValues::find(const std::string& key) const {
  for (const PaperExample* e : {&dumbbell, &pendulum, &cart_pendulum, &connected_bodies}) {
    if (e->key == key) return e;
  }
  return nullptr;
}

std::string PaperValues::keys() const {
  std::string s;
  for (const PaperExample* e : {&dumbbell, &pendulum, &cart_pendulum, &connected_bodies}) {
    s += (s.empty() ? "" : ", ") + e->key;
  }
  return s;
}

const PaperValues& paper_values() {
  static const PaperValues values = parse();
  return values;
}

}  // namespace lgvi::experiments
