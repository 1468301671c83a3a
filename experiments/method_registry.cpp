// The method registry: every method the harness runs, registered once. A new method is its file
// (a Method and its MethodInfo, e.g. experiments/lgvi_method.cpp) plus one line below.
#include "experiments/method.hpp"

namespace lgvi::experiments {

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

std::unique_ptr<Method> make_method(const std::string& name) { return make_method(name, MethodOptions{}); }

std::unique_ptr<Method> make_method(const std::string& name, const MethodOptions& options) {
  return method_info(name).make(options);
}

}  // namespace lgvi::experiments
