// The method registry: every method the harness runs, registered once. A new method is its file
// in experiments/methods/ (its Method, or a one-step scheme run by one_step.hpp's driver, and a
// function returning its MethodInfo with its traits) plus its declaration and one line below;
// the room's CMake library compiles every .cpp of the folder.
#include "experiments/methods/method.hpp"

#include <algorithm>

namespace lgvi::experiments {

// The registrations, one per method file.
MethodInfo lgvi_method_info();                                          // lgvi_method.cpp
MethodInfo composed_lgvi_method_info(const char* scheme);               // lgvi_method.cpp
MethodInfo baseline_method_info(const baselines::SolverInfo& solver);  // baseline_method.cpp

const std::vector<MethodInfo>& method_registry() {
  static const std::vector<MethodInfo> registry = [] {
    std::vector<MethodInfo> r;
    r.push_back(lgvi_method_info());
    for (const char* scheme : {"yoshida4", "suzuki4", "yoshida6", "kahan-li6"}) {
      r.push_back(composed_lgvi_method_info(scheme));
    }
    for (const baselines::SolverInfo& solver : baselines::solver_list()) r.push_back(baseline_method_info(solver));
    return r;
  }();
  return registry;
}

const MethodInfo& method_info(const std::string& name) {
  for (const MethodInfo& m : method_registry()) {
    if (m.name == name) return m;
  }
  std::string known;
  for (const MethodInfo& m : method_registry()) known += (known.empty() ? "" : ", ") + m.name;
  throw InvalidInput("method", "unknown method '" + name + "' (known: " + known + ")");
}

std::vector<std::string> method_names() {
  std::vector<std::string> names;
  for (const MethodInfo& m : method_registry()) names.push_back(m.name);
  return names;
}

std::vector<const MethodInfo*> methods_where(const std::function<bool(const MethodInfo&)>& trait) {
  std::vector<const MethodInfo*> picked;
  for (const MethodInfo& m : method_registry()) {
    if (trait(m)) picked.push_back(&m);
  }
  return picked;
}

bool MethodInfo::applies_to(const std::string& system) const {
  return systems.empty() || std::find(systems.begin(), systems.end(), system) != systems.end();
}

void refuse_options(const std::string& method, const MethodOptions& options) {
  if (options.model) throw InvalidInput("model", method + " works on the Lie group itself: it takes no coordinate model");
  if (options.rtol || options.atol) {
    throw InvalidInput(options.rtol ? "rtol" : "atol", method + " is a fixed-step method (h from the scene)");
  }
  if (options.rotation_update) throw InvalidInput("rotation_update", method + " has no rotation update (LGVI only)");
}

std::unique_ptr<Method> make_method(const std::string& name) { return make_method(name, MethodOptions{}); }

std::unique_ptr<Method> make_method(const std::string& name, const MethodOptions& options) {
  return method_info(name).make(options);
}

}  // namespace lgvi::experiments
