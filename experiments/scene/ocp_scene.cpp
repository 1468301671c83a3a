#include "experiments/scene/ocp_scene.hpp"

#include <cmath>
#include <cstdio>
#include <type_traits>

#include "experiments/input/paper_values.hpp"
#include "experiments/systems/systems.hpp"
#include "experiments/systems/ocp.hpp"

namespace lgvi::experiments {

namespace fs = std::filesystem;

namespace {

/// The [ocp.indirect] / [ocp.direct] key of an options struct's member as validate() names it:
/// "lm_initial_damping" is lm_damping, "initial_multiplier[2]" multiplier_guess, ...
std::string ocp_table_key(const std::string& member) {
  const std::string name = member.substr(0, member.find('['));
  if (name == "lm_initial_damping") return "lm_damping";
  if (name == "initial_multiplier") return "multiplier_guess";
  if (name == "ipopt_hessian") return "hessian";
  return name;
}

std::string list_text(std::initializer_list<const char*> names) {
  std::string s;
  for (const char* n : names) s += (s.empty() ? "'" : ", '") + std::string(n) + "'";
  return s;
}

/// A string value of t among `allowed`, else `fallback` when absent.
std::string choice(const SceneReader& r, const SceneTable& t, std::string_view key,
                   std::initializer_list<const char*> allowed, const char* fallback) {
  if (!r.has(t, key)) return fallback;
  const std::string value = r.string(t, key);
  for (const char* a : allowed) {
    if (value == a) return value;
  }
  r.fail(t.path() + "." + std::string(key), "must be one of " + list_text(allowed) + " (got '" + value + "')");
}

/// An integer value of t in `range` (the options struct's, lgvi/ocp), else `fallback` when absent.
std::int64_t ranged_integer(const SceneReader& r, const SceneTable& t, std::string_view key, const Range& range,
                            std::int64_t fallback) {
  if (!r.has(t, key)) return fallback;
  const std::int64_t v = r.integer(t, key);
  const std::string problem = range.problem(static_cast<double>(v));
  if (!problem.empty()) r.fail(t.path() + "." + std::string(key), problem);
  return v;
}

int ranged_int(const SceneReader& r, const SceneTable& t, std::string_view key, const Range& range, int fallback) {
  return static_cast<int>(ranged_integer(r, t, key, range, fallback));  // the ranges lie within int's
}

/// A number of t in `range`, else `fallback` when absent.
double ranged_number(const SceneReader& r, const SceneTable& t, std::string_view key, const Range& range,
                     double fallback) {
  if (!r.has(t, key)) return fallback;
  const double v = r.number(t, key);
  const std::string problem = range.problem(v);
  if (!problem.empty()) r.fail(t.path() + "." + std::string(key), problem);
  return v;
}

/// The options' own check (ShootingOptions::validate, DirectOptions::validate: the ranges the
/// keys were read against, and what they say of the values together), a failure named as the
/// table's key ("ocp.indirect.lm_damping" for the member lm_initial_damping).
template <class Options>
void validate_table(const SceneReader& r, const SceneTable& t, const Options& o) {
  try {
    o.validate();
  } catch (const InvalidInput& e) {
    const std::string what = e.what();
    r.fail(t.path() + "." + ocp_table_key(e.field()), what.substr(std::min(what.size(), e.field().size() + 2)));
  }
}

}  // namespace

void check_weight(const Eigen::MatrixXd& W, const std::string& field) {
  const Eigen::Index n = W.rows();
  if (!W.allFinite()) throw InvalidInput(field, "has a non-finite entry (must be symmetric positive definite)");
  const double scale = W.cwiseAbs().maxCoeff();
  if (scale == 0.0) throw InvalidInput(field, "is zero (must be symmetric positive definite)");
  if ((W - W.transpose()).cwiseAbs().maxCoeff() > 1e-12 * scale) {
    throw InvalidInput(field, "is not symmetric (must be symmetric positive definite)");
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (W + W.transpose()), Eigen::EigenvaluesOnly);
  if (!(eig.eigenvalues()(0) > 1e-14 * eig.eigenvalues()(n - 1))) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.3g", eig.eigenvalues()(0));
    throw InvalidInput(field, std::string("is not positive definite (smallest eigenvalue ") + buf + ")");
  }
}

Eigen::MatrixXd weight_matrix(const std::vector<double>& values, int n, const std::string& field) {
  const auto count = static_cast<int>(values.size());
  Eigen::MatrixXd W;
  if (count == n) {
    W = Eigen::Map<const Eigen::VectorXd>(values.data(), n).asDiagonal();
  } else if (count == n * n) {
    W = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(values.data(), n, n);
  } else {
    throw InvalidInput(field, "needs " + std::to_string(n) + " values (the diagonal) or " + std::to_string(n * n) +
                                  " (the matrix row by row) for this system's " + std::to_string(n) +
                                  " controls (got " + std::to_string(count) + ")");
  }
  check_weight(W, field);
  return W;
}

namespace {

/// W: an n x n matrix, symmetric (to 1e-12 of its largest entry) and positive definite (smallest
/// eigenvalue above 1e-14 of the largest: the indirect method inverts W, eq. 17, and the direct
/// method's cost must bound every control). The solvers check the same (lgvi/ocp); here the file
/// and field are named.
Eigen::MatrixXd read_weight(const SceneReader& r, const SceneTable& ocp, int n) {
  if (!r.has(ocp, "W")) return {};
  const Eigen::MatrixXd W = r.matrix(ocp, "W", n);
  try {
    check_weight(W, "ocp.W");
  } catch (const InvalidInput& e) {
    const std::string what = e.what();
    r.fail("ocp.W", what.substr(std::min(what.size(), e.field().size() + 2)));
  }
  return W;
}

ocp::ShootingOptions read_indirect(const SceneReader& r, const std::optional<SceneTable>& t, int multipliers) {
  ocp::ShootingOptions o;
  o.max_iterations = 300;
  o.initial_multiplier = Eigen::VectorXd::Zero(multipliers);
  if (!t) return o;
  r.check_keys(*t, {"multiplier_guess", "globalization", "lm_damping", "nonmonotone_memory", "merit", "decomposition",
                    "max_iterations", "tolerance"});
  using O = ocp::ShootingOptions;
  if (r.has(*t, "multiplier_guess")) o.initial_multiplier = r.vector(*t, "multiplier_guess", multipliers);
  o.globalization = ocp::parse_globalization(
      choice(r, *t, "globalization", {"newton-armijo", "levenberg-marquardt", "homotopy", "continuation"}, "newton-armijo"));
  o.lm_initial_damping = ranged_number(r, *t, "lm_damping", O::kLmInitialDamping, o.lm_initial_damping);
  o.nonmonotone_memory = ranged_int(r, *t, "nonmonotone_memory", O::kNonmonotoneMemory, o.nonmonotone_memory);
  o.merit = ocp::parse_merit(choice(r, *t, "merit", {"velocity", "momentum"}, "velocity"));
  if (r.has(*t, "decomposition")) o.decomposition = r.boolean(*t, "decomposition");
  o.max_iterations = ranged_int(r, *t, "max_iterations", O::kMaxIterations, o.max_iterations);
  o.tolerance = ranged_number(r, *t, "tolerance", O::kTolerance, o.tolerance);
  validate_table(r, *t, o);
  return o;
}

ocp::DirectOptions read_direct(const SceneReader& r, const std::optional<SceneTable>& t, int nu, bool& cap_given) {
  ocp::DirectOptions o;
  cap_given = false;
  if (!t) return o;
  r.check_keys(*t, {"knots", "spline", "gradients", "tolerance", "starts", "seed", "solver", "max_evaluations",
                    "initial_knots", "hessian", "state_guess", "shooting_interval"});
  using O = ocp::DirectOptions;
  o.knots = ranged_int(r, *t, "knots", O::kKnots, o.knots);
  o.spline = ocp::parse_spline_end(choice(r, *t, "spline", {"not-a-knot", "natural"}, "not-a-knot"));
  o.gradients = ocp::parse_gradient_method(choice(r, *t, "gradients", {"exact", "finite-difference"}, "exact"));
  o.tolerance = ranged_number(r, *t, "tolerance", O::kTolerance, o.tolerance);
  o.starts = ranged_int(r, *t, "starts", O::kStarts, o.starts);
  o.seed = static_cast<std::uint64_t>(ranged_integer(r, *t, "seed", O::kSeed, static_cast<std::int64_t>(o.seed)));
  o.solver = ocp::parse_direct_solver(choice(r, *t, "solver", {"slsqp", "ipopt"}, "slsqp"));
  cap_given = r.has(*t, "max_evaluations");
  o.max_evaluations = ranged_int(r, *t, "max_evaluations", O::kMaxEvaluations, o.max_evaluations);
  if (r.has(*t, "initial_knots")) o.initial_knots = r.vector(*t, "initial_knots", nu * o.knots);
  const bool ipopt = o.solver == ocp::DirectSolver::IpoptMultipleShooting;
  for (const char* key : {"hessian", "state_guess", "shooting_interval"}) {
    if (!ipopt && r.has(*t, key)) r.fail(t->path() + "." + key, "applies to solver = 'ipopt' only");
  }
  o.ipopt_hessian = ocp::parse_ipopt_hessian(choice(r, *t, "hessian", {"limited-memory", "cost", "exact"}, "limited-memory"));
  o.state_guess = ocp::parse_shooting_state_guess(choice(r, *t, "state_guess", {"geodesic", "simulated"}, "geodesic"));
  o.shooting_interval = ranged_int(r, *t, "shooting_interval", O::kShootingInterval, o.shooting_interval);
  validate_table(r, *t, o);
  return o;
}

template <class M>
std::shared_ptr<const OcpDefinition> read_for(const SceneReader& r, const SceneTable& parameters,
                                              const SceneTable& ocp) {
  using B = OcpBinding<M>;
  r.check_keys(ocp, {"method", "paper", "W", "target", "indirect", "direct"});
  if (!B::indirect && !B::direct) {
    r.fail("ocp", std::string("the ") + M::name + " has no optimal control method (systems with one: " +
                      "experiments/scenes/README.md, \"Optimal control\")");
  }
  auto d = std::make_shared<OcpDefinition>();
  const std::string method = r.string(ocp, "method");
  if (method == "indirect" && B::indirect) {
    d->method = OcpMethod::Indirect;
  } else if (method == "direct" && B::direct) {
    d->method = OcpMethod::Direct;
  } else {
    r.fail("ocp.method", "must be " + std::string(B::indirect ? "'indirect'" : "'direct'") + " for the " + M::name +
                             " (got '" + method + "')");
  }
  const char* other = d->method == OcpMethod::Indirect ? "direct" : "indirect";
  if (r.has(ocp, other)) r.fail(std::string("ocp.") + other, std::string("is the ") + other + " method's table; ocp.method is '" + method + "'");
  if (r.has(ocp, "paper")) {
    d->paper = r.string(ocp, "paper");
    if (!paper_values().find(d->paper)) {
      r.fail("ocp.paper", "unknown example '" + d->paper + "' (expected a table of validation/paper_values.toml: " +
                              paper_values().keys() + ")");
    }
  }
  const Eigen::MatrixXd W = read_weight(r, ocp, B::nu);
  const std::optional<SceneTable> target = r.table(ocp, "target", true);
  {
    // The target has the keys and checks of the system's [initial] (its binding reads it).
    SystemBinding<M>::check_keys(r, parameters, *target);
    try {
      d->target = SystemBinding<M>::read(r, parameters, *target, std::nullopt).initial;
    } catch (const SceneError& e) {
      // make_state's complaints name "initial.<field>": they are about the target here.
      if (e.field().rfind("initial", 0) != 0) throw;
      throw SceneError(e.file(), "ocp.target" + e.field().substr(7), e.reason());
    }
  }
  if (d->method == OcpMethod::Indirect) {
    if constexpr (B::indirect) {
      d->indirect = read_indirect(r, r.table(ocp, "indirect", false), 2 * B::IndirectModel::nq);
    }
    d->indirect.W = W;
  } else {
    d->direct = read_direct(r, r.table(ocp, "direct", false), B::nu, d->max_evaluations_given);
    d->direct.W = W;
  }
  return d;
}

}  // namespace

const char* to_string(OcpMethod m) { return m == OcpMethod::Indirect ? "indirect" : "direct"; }

std::shared_ptr<const OcpDefinition> read_ocp_table(const SceneReader& r, const Model& model,
                                                     const SceneTable& parameters, const SceneTable& ocp) {
  return std::visit(
      [&](const auto& m) {
        using B = OcpBinding<std::decay_t<decltype(m)>>;
        // A scene the system's optimal control model does not describe (its binding says).
        if constexpr (requires { B::check_scene(r, m); }) B::check_scene(r, m);
        return read_for<std::decay_t<decltype(m)>>(r, parameters, ocp);
      },
      model);
}

fs::path resolve_ocp_scene(const std::string& name_or_path, const fs::path& scenes_dir) {
  const bool is_path = name_or_path.find('/') != std::string::npos ||
                       (name_or_path.size() > 5 && name_or_path.ends_with(".toml"));
  if (!is_path && !name_or_path.empty()) {
    const fs::path example = scenes_dir / ("ocp-" + name_or_path + ".toml");
    std::error_code ec;
    if (fs::is_regular_file(example, ec)) return example;
  }
  return resolve_scene(name_or_path, scenes_dir);
}

std::string ocp_label(const Scene& scene) {
  return scene.name.rfind("ocp-", 0) == 0 ? scene.name.substr(4) : scene.name;
}

}  // namespace lgvi::experiments
