// The method registry: every method the harness runs, registered once. A new method is its file
// in experiments/methods/ (its Method, or a one-step scheme run by one_step.hpp's driver, and a
// function returning its MethodInfo with its traits) plus its declaration and one line below;
// the room's CMake library compiles every .cpp of the folder.
#include "experiments/methods/method.hpp"

#include <algorithm>
#include <string_view>
#include <utility>

namespace lgvi::experiments {

// The registrations, one per method file.
MethodInfo lgvi_method_info();                                          // lgvi_method.cpp
MethodInfo composed_lgvi_method_info(const char* scheme);               // lgvi_method.cpp
MethodInfo lie_group_method_info(const std::string& name);              // lie_group_methods.cpp
MethodInfo symplectic_method_info(const std::string& name);             // symplectic_methods.cpp
MethodInfo baseline_method_info(const baselines::SolverInfo& solver);  // baseline_method.cpp

const std::vector<MethodInfo>& method_registry() {
  static const std::vector<MethodInfo> registry = [] {
    std::vector<MethodInfo> r;
    r.push_back(lgvi_method_info());
    for (const char* scheme : {"yoshida4", "suzuki4", "yoshida6", "kahan-li6"}) {
      r.push_back(composed_lgvi_method_info(scheme));
    }
    for (const char* name : {"lie-euler", "rkmk2", "rkmk4", "cg3", "cg4", "cf4", "rkmk45"}) {
      r.push_back(lie_group_method_info(name));
    }
    for (const char* name : {"splitting-dlm", "splitting-exact", "nosquish", "rattle"}) {
      r.push_back(symplectic_method_info(name));
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

namespace {

/// The boolean traits a query may name, and how each reads a MethodInfo.
const std::vector<std::pair<std::string_view, bool (*)(const MethodInfo&)>>& named_traits() {
  static const std::vector<std::pair<std::string_view, bool (*)(const MethodInfo&)>> traits = {
      {"symmetric", [](const MethodInfo& m) { return m.symmetric; }},
      {"variational", [](const MethodInfo& m) { return m.variational; }},
      {"symplectic", [](const MethodInfo& m) { return m.symplectic; }},
      {"stays_on_group", [](const MethodInfo& m) { return m.stays_on_group; }},
      {"preserves_momentum_map", [](const MethodInfo& m) { return m.preserves_momentum_map; }},
      {"on_group", [](const MethodInfo& m) { return m.on_group(); }},
      {"fixed_step", [](const MethodInfo& m) { return m.fixed_step(); }},
      {"adaptive", [](const MethodInfo& m) { return m.adaptive(); }},
  };
  return traits;
}

}  // namespace

std::vector<const MethodInfo*> methods_matching(std::string_view query) {
  struct Term {
    bool (*trait)(const MethodInfo&);
    bool negated;
  };
  std::vector<Term> terms;
  std::string_view rest = query;
  while (true) {
    const std::size_t and_at = rest.find(" and ");
    std::string_view word = rest.substr(0, and_at);
    bool negated = false;
    if (word.substr(0, 4) == "not ") {
      negated = true;
      word.remove_prefix(4);
    }
    const auto& traits = named_traits();
    const auto it = std::find_if(traits.begin(), traits.end(), [&](const auto& t) { return t.first == word; });
    if (it == traits.end()) {
      std::string known;
      for (const auto& t : traits) known += (known.empty() ? "" : ", ") + std::string(t.first);
      throw InvalidInput("methods", "unknown trait '" + std::string(word) + "' in '" + std::string(query) +
                                        "' (known: " + known + "; join them with \" and \", negate with \"not \")");
    }
    terms.push_back({it->second, negated});
    if (and_at == std::string_view::npos) break;
    rest.remove_prefix(and_at + 5);
  }
  return methods_where([&](const MethodInfo& m) {
    return std::all_of(terms.begin(), terms.end(), [&](const Term& t) { return t.trait(m) != t.negated; });
  });
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
