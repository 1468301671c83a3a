#include "experiments/input/paper_values.hpp"

#include <stdexcept>
#include <string_view>

#include <toml++/toml.h>

#include "lgvi/inertia.hpp"

namespace lgvi::experiments {

namespace {

constexpr const char* kFile = "validation/paper_values.toml";

double required(const toml::table& table, const std::string& path) {
  const std::optional<double> v = table.at_path(path).value<double>();
  if (!v) throw std::logic_error(std::string(kFile) + ": " + path + ": missing or not a number");
  return *v;
}

std::optional<double> optional_number(const toml::table& table, const std::string& path) {
  return table.at_path(path).value<double>();
}

PaperExample example(const toml::table& table, const std::string& key, const std::string& section) {
  PaperExample e;
  e.key = key;
  e.section = section;
  e.cost = required(table, key + ".cost");
  e.terminal_violation = required(table, key + ".terminal_violation");
  e.outer_iterations_approx = optional_number(table, key + ".outer_iterations_approx");
  e.h = optional_number(table, key + ".h");
  e.horizon = optional_number(table, key + ".horizon");
  return e;
}

PaperValues parse() {
  toml::table table;
  try {
    table = toml::parse(std::string_view(kPaperValuesToml), std::string_view(kFile));
  } catch (const toml::parse_error& e) {
    throw std::logic_error(std::string(kFile) + ": " + std::string(e.description()));
  }
  PaperValues p;
  p.dumbbell = example(table, "dumbbell_orbit_transfer", "3.1");
  p.pendulum = example(table, "pendulum_reorientation", "3.2");
  p.cart_pendulum = example(table, "cart_pendulum", "4.1");
  p.connected_bodies = example(table, "connected_bodies", "4.2");
  p.decomposed_condition_min = required(table, "pendulum_reorientation.decomposed_condition_number_range[0]");
  p.decomposed_condition_max = required(table, "pendulum_reorientation.decomposed_condition_number_range[1]");
  p.undecomposed_condition = required(table, "pendulum_reorientation.undecomposed_condition_number");
  return p;
}

}  // namespace

const PaperExample& PaperValues::example(const std::string& system) const {
  if (system == "pendulum") return pendulum;
  if (system == "dumbbell") return dumbbell;
  if (system == "cart-pendulum") return cart_pendulum;
  if (system == "connected-bodies") return connected_bodies;
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
