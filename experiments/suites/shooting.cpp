// "shooting": convergence histories and condition numbers of the indirect optimal-control
// solvers on the paper's transfers (the shipped scenes experiments/scenes/ocp-pendulum.toml,
// ocp-dumbbell.toml, ocp-cart-pendulum.toml; the system's part is its ocp binding,
// experiments/systems/ocp.hpp):
//   discrete    Newton-Armijo shooting on the initial multiplier of the discrete necessary
//               conditions (lgvi/ocp/indirect.hpp), symmetric and printed LGVI, with and
//               without the pendulum's symmetry decomposition;
//   continuous  the same shooting on the initial costate of the continuous necessary
//               conditions, integrated by CVODES (baselines/pontryagin.hpp), from the discrete
//               solver's documented guess (all ones), from zero, and from the discrete solution
//               (continuous_costate_from_discrete); the dumbbell's from its discrete symmetric
//               solution, with the comparison (cost, multipliers, violations) in the table;
//   globalizations  the dumbbell's discrete shooting by Newton-Armijo, the Newton homotopy, the
//               continuation (Hermite predictor, Broyden corrector), Levenberg-Marquardt and the
//               non-monotone momentum-merit Armijo test;
//   direct      spline controls + SLSQP on the cart-pendulum transfer of section 4.1
//               (lgvi/ocp/direct.hpp; one start from the default guess): its SQP iterates' history
//               (no Newton matrix, so no condition numbers).
// Expected outcomes (the harness's expectations, measured in lgvi/ocp/README.md and
// tests/baselines/test_pontryagin.cpp): without the decomposition the full sensitivity of the
// pendulum has rank 5 (the vertical momentum is conserved for every control; condition ~1e30
// discrete, ~1/rtol or worse continuous) and the line search fails; from lambda(0) = 0 the
// pendulum stays at rest with u = 0 and the linearization cannot turn it about the vertical.
// Those cases must fail; the others must converge.
//
// Per case: <id>.csv, the iteration history (one row per outer iteration, at its start: violation,
// cost, accepted step length, backtracks, condition numbers of the full sensitivity and of the
// matrix inverted, Newton step norm, cumulative sweeps/integrations and seconds), plus, when the
// last iteration accepted and evaluated a step, a final row for the end point (step length,
// backtracks, condition numbers and step norm nan: no Newton system is formed there). Summary: status, cost, violation, iterations, condition
// ranges, wall time.
#include <algorithm>
#include <cmath>
#include <limits>

#include "baselines/pontryagin.hpp"
#include "experiments/output/csv_writer.hpp"
#include "experiments/scene/ocp_scene.hpp"
#include "experiments/methods/simulate.hpp"
#include "experiments/suites/common.hpp"
#include "experiments/systems/systems.hpp"
#include "experiments/systems/ocp.hpp"
#include "lgvi/ocp/direct.hpp"
#include "lgvi/ocp/indirect.hpp"

namespace lgvi::experiments::suites {

namespace fs = std::filesystem;

namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

enum class Solver { Discrete, Continuous, Direct };
enum class Guess { Ones, Zero, DiscreteSolution };

const char* guess_name(Guess g) {
  switch (g) {
    case Guess::Ones: return "ones";
    case Guess::Zero: return "zero";
    case Guess::DiscreteSolution: return "discrete-solution";
  }
  return "?";
}

/// The shipped ocp scene of an example (`ocp NAME`: experiments/scenes/ocp-NAME.toml).
Scene example_scene(const std::string& example) {
  return load_scene(resolve_ocp_scene(example, default_scenes_dir()));
}

/// Whether the example's indirect model has a symmetry (the decomposition applies).
bool has_symmetry(const std::string& example) {
  const Scene scene = example_scene(example);
  return visit_binding(scene.model, [](auto, const auto& m) {
    using B = OcpBinding<std::decay_t<decltype(m)>>;
    if constexpr (B::indirect) {
      return B::IndirectModel::has_symmetry;
    } else {
      return false;
    }
  });
}

/// The violation axis label of the example's system (its ocp binding).
std::string violation_label(const std::string& example) {
  const Scene scene = example_scene(example);
  return visit_binding(scene.model, [](auto, const auto& m) {
    return std::string(OcpBinding<std::decay_t<decltype(m)>>::violation_label);
  });
}

struct ShootingSpec {
  std::string system;  ///< the example (an ocp scene, `ocp NAME`): "pendulum", "dumbbell" (indirect), "cart-pendulum" (direct)
  bool symmetric = false;  ///< the example's indirect model has a symmetry (set by the suite from the binding)
  Solver solver = Solver::Discrete;
  LgviForm form = LgviForm::Symmetric;  ///< discrete; and of the discrete solution a continuous run starts from
  std::size_t steps = 1000;             ///< discrete (and the discrete solution's)
  double rtol = 1e-10;                  ///< continuous
  bool decomposition = true;
  Guess guess = Guess::Ones;
  int max_iterations = 100;
  ocp::Globalization globalization = ocp::Globalization::NewtonArmijo;  ///< discrete
  ocp::Merit merit = ocp::Merit::Velocity;                              ///< discrete
  int nonmonotone_memory = 1;                                           ///< discrete
  /// The discrete solution a continuous run starts from (Guess::DiscreteSolution): its guess and
  /// globalization.
  Guess start_guess = Guess::Ones;
  ocp::Globalization start_globalization = ocp::Globalization::NewtonArmijo;

  /// Legend text; no commas (labels are summary.csv cells).
  std::string label() const {
    if (solver == Solver::Direct) return "direct SLSQP on splines N = " + std::to_string(steps) + "; default guess";
    std::string l = solver == Solver::Discrete
                        ? std::string("discrete ") + (form == LgviForm::Symmetric ? "symmetric" : "printed") +
                              " LGVI N = " + std::to_string(steps)
                        : "continuous CVODES rtol " + shortest(rtol);
    if (symmetric) l += decomposition ? "; decomposed" : "; not decomposed";
    if (globalization == ocp::Globalization::LevenbergMarquardt) l += "; Levenberg-Marquardt";
    if (globalization == ocp::Globalization::Homotopy) l += "; Newton homotopy";
    if (globalization == ocp::Globalization::Continuation) l += "; continuation";
    if (merit == ocp::Merit::Momentum) l += "; momentum merit";
    if (nonmonotone_memory > 1) l += "; non-monotone " + std::to_string(nonmonotone_memory);
    return l + "; from " + guess_name(guess);
  }
  std::string id() const {
    if (solver == Solver::Direct) return system + "-direct-n" + std::to_string(steps);
    std::string i = system + "-" + (solver == Solver::Discrete ? "discrete-" : "continuous-");
    if (solver == Solver::Discrete) {
      i += std::string(form == LgviForm::Symmetric ? "symmetric" : "printed") + "-n" + std::to_string(steps) + "-";
    } else {
      char buf[32];
      std::snprintf(buf, sizeof buf, "rtol%.0e-", rtol);
      i += buf;
    }
    if (symmetric) i += decomposition ? "decomposed-" : "full-";
    if (globalization == ocp::Globalization::LevenbergMarquardt) i += "lm-";
    if (globalization == ocp::Globalization::Homotopy) i += "homotopy-";
    if (globalization == ocp::Globalization::Continuation) i += "continuation-";
    if (merit == ocp::Merit::Momentum) i += "momentum-";
    if (nonmonotone_memory > 1) i += "nm" + std::to_string(nonmonotone_memory) + "-";
    return i + guess_name(guess);
  }
};

ocp::ShootingOptions discrete_options(const ShootingSpec& s, const ocp::TransferProblem& problem, int n) {
  ocp::ShootingOptions o;
  o.form = s.form;
  o.h = problem.t_final / static_cast<double>(s.steps);
  o.decomposition = s.decomposition;
  o.max_iterations = s.max_iterations;
  o.globalization = s.globalization;
  o.merit = s.merit;
  o.nonmonotone_memory = s.nonmonotone_memory;
  o.initial_multiplier = s.guess == Guess::Ones ? Eigen::VectorXd::Ones(n) : Eigen::VectorXd::Zero(n);
  return o;
}

/// Writes the history CSV; returns the number of rows.
std::size_t write_history(const fs::path& file, const ocp::ShootingSummary& S, const Fields& metadata,
                          const std::string& count_name) {
  CsvWriter csv(file, {"iteration", "violation", "cost", "step_length", "backtracks", "cond_sensitivity",
                       "cond_inverted", "step_norm", count_name, "seconds"});
  for (const ocp::IterationRecord& r : S.history) {
    const double row[] = {double(r.iteration), r.violation,        r.cost,      r.step_length,   double(r.backtracks),
                          r.cond_sensitivity,  r.cond_inverted,    r.step_norm, double(r.sweeps), r.seconds};
    csv.write_row(row);
  }
  // The end point, when it is a new point (the last iteration accepted a step and evaluated it).
  if (S.history.empty() || (S.history.back().step_length > 0.0 && S.violation != S.history.back().violation)) {
    const double it = S.history.empty() ? 0.0 : S.history.back().iteration + 1.0;
    const double row[] = {it, S.violation, S.cost, kNan, kNan, kNan, kNan, kNan, double(S.sweeps), S.wall_seconds};
    csv.write_row(row);
  }
  csv.commit(metadata);
  return csv.rows();
}

/// The direct method's history: one row per SQP iterate (gradient evaluation) of the reported
/// start, its evaluation index as the count; step lengths and condition numbers do not exist.
void write_direct_history(const fs::path& file, const ocp::DirectSummary& S, const Fields& metadata) {
  CsvWriter csv(file, {"iteration", "violation", "cost", "step_length", "backtracks", "cond_sensitivity",
                       "cond_inverted", "step_norm", "evaluations", "seconds"});
  int iterate = 0;
  for (const ocp::DirectIteration& r : S.history) {
    if (!r.gradient || S.best_start < 0 || r.start != S.starts[S.best_start].index) continue;
    const double row[] = {double(iterate++), r.violation, r.cost, kNan, kNan, kNan, kNan, kNan,
                          double(r.evaluation), r.seconds};
    csv.write_row(row);
  }
  csv.commit(metadata);
}

class ShootingJob final : public Job {
 public:
  explicit ShootingJob(ShootingSpec spec) : spec_(std::move(spec)) {}

  void validate(const fs::path&) const override {
    const Scene scene = example_scene(spec_.system);  // SceneError for an unknown example
    if (!scene.ocp || (spec_.solver == Solver::Direct) != (scene.ocp->method == OcpMethod::Direct)) {
      throw InvalidInput("system", "shooting cases: an ocp scene solved by the " +
                                       std::string(spec_.solver == Solver::Direct ? "direct" : "indirect") +
                                       " method; got '" + spec_.system + "'");
    }
    if (spec_.steps == 0 || !(spec_.rtol > 0.0)) throw InvalidInput("shooting", "steps and rtol must be positive");
  }

 private:
  template <class B, class M>
  JobResult run_indirect(const JobContext& ctx, const Scene& scene, const M& m) const {
    using Model = typename B::IndirectModel;
    const int n = 2 * Model::nq;
    const ocp::TransferProblem problem =
        B::transfer(m, std::get<typename M::State>(scene.ocp->target), scene.horizon.t_final);
    Fields f = {{"system", spec_.system},
                {"label", spec_.label()},
                {"solver", std::string(spec_.solver == Solver::Discrete ? "discrete" : "continuous")},
                {"decomposition", spec_.decomposition},
                {"globalization", std::string(ocp::to_string(spec_.globalization))},
                {"merit", std::string(ocp::to_string(spec_.merit))},
                {"nonmonotone_memory", static_cast<std::int64_t>(spec_.nonmonotone_memory)},
                {"guess", std::string(guess_name(spec_.guess))},
                {"t_final", problem.t_final}};
    ocp::ShootingSummary S;
    std::string count_name = "sweeps";
    std::optional<ocp::ShootingSummary> start;  // the discrete solution a continuous run starts from
    if (spec_.solver == Solver::Discrete) {
      ocp::ShootingOptions o = discrete_options(spec_, problem, n);
      o.W = scene.ocp->indirect.W;
      f.push_back({"form", std::string(to_string(spec_.form))});
      f.push_back({"h", o.h});
      f.push_back({"steps", static_cast<std::int64_t>(spec_.steps)});
      S = ocp::solve_indirect(B::system(m), problem, o).summary;
      f.push_back({"tolerance", o.tolerance});
    } else if constexpr (!B::continuous) {
      throw InvalidInput("solver", "'" + spec_.system + "' has no continuous (Pontryagin) shooting");
    } else {
      baselines::ContinuousShootingOptions o;
      o.integration.rtol = spec_.rtol;
      o.decomposition = spec_.decomposition;
      o.max_iterations = spec_.max_iterations;
      if (spec_.guess == Guess::Ones) {
        o.initial_costate = Eigen::VectorXd::Ones(n);
      } else if (spec_.guess == Guess::DiscreteSolution) {
        // The discrete solution of the same form and N, from the case's start guess by its start
        // globalization (the pendulum: all ones, Newton-Armijo; the dumbbell: zero, the Newton
        // homotopy, which reaches Newton-Armijo's extremal, 1.3906 symmetric; the continuation
        // reaches the same extremal but stalls at 1.6e-12 on the symmetric form).
        ShootingSpec d = spec_;
        d.solver = Solver::Discrete;
        d.guess = spec_.start_guess;
        d.decomposition = true;
        d.globalization = spec_.start_globalization;
        ocp::ShootingOptions od = discrete_options(d, problem, n);
        od.W = scene.ocp->indirect.W;
        start = ocp::solve_indirect(B::system(m), problem, od).summary;
        if (!start->converged()) {
          return {false, "start-failed", "the discrete solution to start from: " + start->brief(), f};
        }
        // The discrete lambda_0 on the continuous costate's coordinates (baselines/pontryagin.hpp).
        o.initial_costate = B::continuous_costate(start->multiplier);
        f.push_back({"start", d.label() + ": " + start->brief()});
      }
      const auto record = [&](const auto& r) {
        S = r.summary;
        f.push_back({"rtol", spec_.rtol});
        f.push_back({"tolerance", r.tolerance});
        f.push_back({"integrations", static_cast<std::int64_t>(r.integrations)});
        f.push_back({"integration_steps", static_cast<std::int64_t>(r.integration_steps)});
        f.push_back({"rhs_evaluations", static_cast<std::int64_t>(r.rhs_evaluations)});
      };
      record(B::solve_continuous(m, problem, o));
      count_name = "integrations";
      if (start && S.multiplier.size() == start->multiplier.size()) {
        // Continuous against discrete: cost, initial multipliers (a symmetric system's arbitrary
        // component along its symmetry direction v_g = dC(s_0) removed from both), terminal violations.
        Eigen::VectorXd dl = S.multiplier - start->multiplier;
        Eigen::VectorXd lc = S.multiplier;
        if constexpr (Model::has_symmetry) {
          const ocp::StateMultiplierFlow<Model> flow(B::system(m), problem, spec_.form,
                                                     problem.t_final / static_cast<double>(spec_.steps),
                                                     scene.ocp->indirect.W);
          const Eigen::VectorXd v_g = Model::conserved_gradient(flow.initial_state()).normalized();
          dl -= v_g * v_g.dot(dl);
          lc -= v_g * v_g.dot(lc);
        }
        f.push_back({"discrete_cost", start->cost});
        f.push_back({"discrete_violation", start->violation});
        f.push_back({"discrete_iterations", static_cast<std::int64_t>(start->iterations)});
        f.push_back({"cost_difference", S.cost - start->cost});
        f.push_back({"multiplier_difference", dl.norm() / std::max(lc.norm(), 1e-300)});
      }
    }
    f.push_back({"cost", S.cost});
    f.push_back({"violation", S.violation});
    f.push_back({"iterations", static_cast<std::int64_t>(S.iterations)});
    f.push_back({"inner_iterations", static_cast<std::int64_t>(S.inner_iterations)});
    f.push_back({"sweeps", static_cast<std::int64_t>(S.sweeps)});
    f.push_back({"cond_min", S.cond_min});
    f.push_back({"cond_max", S.cond_max});
    f.push_back({"cond_full_min", S.cond_full_min});
    f.push_back({"cond_full_max", S.cond_full_max});
    f.push_back({"first_cond_full", S.history.empty() ? kNan : S.history.front().cond_sensitivity});
    f.push_back({"wall_seconds", S.wall_seconds});
    f.push_back({"shooting_status", std::string(to_string(S.status))});
    f.push_back({"csv_path", ctx.case_id + ".csv"});

    Fields meta = {{"suite", std::string("shooting")}, {"status", std::string(to_string(S.status))},
                   {"message", S.message}};
    meta.insert(meta.end(), f.begin(), f.end());
    meta.push_back({"git_describe", std::string(git_describe())});
    meta.push_back({"command_line", ctx.command_line});
    write_history(ctx.out_dir / (ctx.case_id + ".csv"), S, meta, count_name);

    JobResult out;
    out.completed = S.converged();
    out.status = S.converged() ? "completed" : to_string(S.status);
    out.detail = S.brief();  // names the failure and its message
    out.fields = std::move(f);
    return out;
  }

  template <class B, class M>
  JobResult run_direct(const JobContext& ctx, const Scene& scene, const M& m) const {
    const auto problem = B::transfer(m, std::get<typename M::State>(scene.ocp->target), scene.horizon.t_final);
    ocp::DirectOptions o;
    o.h = problem.t_final / static_cast<double>(spec_.steps);
    o.starts = 1;
    o.W = scene.ocp->direct.W;
    const ocp::DirectSummary S = ocp::solve_direct(B::system(m), problem, o).summary;
    Fields f = {{"system", spec_.system},
                {"label", spec_.label()},
                {"solver", std::string("direct")},
                {"guess", std::string("default")},
                {"t_final", problem.t_final},
                {"form", std::string(to_string(o.form))},
                {"h", o.h},
                {"steps", static_cast<std::int64_t>(spec_.steps)},
                {"tolerance", o.tolerance},
                {"cost", S.cost},
                {"violation", S.violation},
                {"iterations", static_cast<std::int64_t>(S.iterations)},
                {"inner_iterations", static_cast<std::int64_t>(S.evaluations - S.iterations)},
                {"sweeps", static_cast<std::int64_t>(S.simulations)},
                {"wall_seconds", S.wall_seconds},
                {"shooting_status", std::string(to_string(S.status))},
                {"csv_path", ctx.case_id + ".csv"}};
    Fields meta = {{"suite", std::string("shooting")}, {"status", std::string(to_string(S.status))},
                   {"message", S.message}, {"nlopt_result", S.nlopt_result}};
    meta.insert(meta.end(), f.begin(), f.end());
    meta.push_back({"git_describe", std::string(git_describe())});
    meta.push_back({"command_line", ctx.command_line});
    write_direct_history(ctx.out_dir / (ctx.case_id + ".csv"), S, meta);
    return {S.converged(), S.converged() ? "completed" : to_string(S.status), S.brief(), std::move(f)};
  }

  ShootingSpec spec_;

 public:
  // Defined after the member templates it calls: clang 14 does not instantiate member templates
  // first used in a generic lambda ahead of their definition (an undefined reference at link).
  JobResult run(const JobContext& ctx) const override {
    const Scene scene = example_scene(spec_.system);
    return visit_binding(scene.model, [&](auto, const auto& m) -> JobResult {
      using B = OcpBinding<std::decay_t<decltype(m)>>;
      if constexpr (B::direct) {
        return run_direct<B>(ctx, scene, m);
      } else if constexpr (B::indirect) {
        return run_indirect<B>(ctx, scene, m);
      } else {
        throw InvalidInput("system", "'" + spec_.system + "' has no optimal control method");
      }
    });
  }
};

}  // namespace

Suite shooting_suite(const SuiteParams& params) {
  Suite s;
  s.name = "shooting";
  s.description = "convergence histories and condition numbers of the indirect solvers: discrete vs continuous, "
                  "decomposed vs not";
  s.columns = {"system",     "label",     "solver",        "form",          "h",
               "steps",      "rtol",      "decomposition", "guess",         "shooting_status",
               "cost",       "violation", "tolerance",     "iterations",    "inner_iterations",
               "sweeps",     "integrations", "cond_min",   "cond_max",      "cond_full_min",
               "cond_full_max", "first_cond_full", "wall_seconds", "globalization", "discrete_cost",
               "discrete_violation", "discrete_iterations", "cost_difference", "multiplier_difference", "csv_path"};
  const bool quick = params.quick;
  const auto add = [&](ShootingSpec spec, Expectation e) {
    spec.symmetric = has_symmetry(spec.system);
    SuiteCase c;
    c.id = spec.id();
    c.group = spec.system;
    c.labels = {{"system", spec.system}, {"label", spec.label()}};
    c.expect = e;
    c.job = std::make_shared<ShootingJob>(spec);
    s.cases.push_back(std::move(c));
  };

  // Pendulum, the paper's h = 0.001 (1000 steps).
  std::vector<LgviForm> forms = {LgviForm::Symmetric};
  if (!quick) forms.push_back(LgviForm::Printed);
  for (const LgviForm form : forms) {
    for (const bool decomposition : {true, false}) {
      ShootingSpec d;
      d.system = "pendulum";
      d.form = form;
      d.decomposition = decomposition;
      add(d, decomposition ? Expectation::Complete : Expectation::Fail);
    }
  }
  {
    ShootingSpec c;
    c.system = "pendulum";
    c.solver = Solver::Continuous;
    add(c, Expectation::Complete);
    c.guess = Guess::Zero;
    add(c, Expectation::Fail);
    c.guess = Guess::DiscreteSolution;
    add(c, Expectation::Complete);
    c.guess = Guess::Ones;
    c.decomposition = false;
    add(c, Expectation::Fail);
    if (!quick) {
      c.decomposition = true;
      c.rtol = 1e-8;
      add(c, Expectation::Complete);
    }
  }
  // Direct: the cart-pendulum of section 4.1 (~220 SQP iterations, 0.4 s).
  {
    ShootingSpec d;
    d.system = "cart-pendulum";
    d.solver = Solver::Direct;
    d.steps = 200;  // h = 0.01, the method's default
    add(d, Expectation::Complete);
  }
  // Dumbbell (no symmetry; lgvi/ocp/README.md). Discrete, printed form, from the uncontrolled
  // motion (zero multiplier): 100 steps by Newton-Armijo (0.4 s), and the command's default 1000
  // steps by the globalizations side by side: Newton-Armijo (the paper's, ~180 outer iterations,
  // extremal 1.3909), the Newton homotopy (the same extremal, ~70), the continuation (the same
  // extremal, ~35, within the target of 40), Levenberg-Marquardt (extremal 1.427, ~130) and the
  // non-monotone Armijo test on the momentum merit (extremal 1.427, ~25). Continuous (CVODES,
  // baselines/pontryagin.hpp): from the discrete symmetric N = 1000 solution, compared with it
  // (cost, multipliers, violations).
  {
    ShootingSpec d;
    d.system = "dumbbell";
    d.form = LgviForm::Printed;
    d.steps = 100;
    d.guess = Guess::Zero;
    d.max_iterations = 300;
    add(d, Expectation::Either);  // converged, or stalled at the round-off floor (README)
    d.steps = 1000;
    add(d, Expectation::Either);
    d.globalization = ocp::Globalization::Homotopy;
    add(d, Expectation::Either);
    d.globalization = ocp::Globalization::Continuation;
    add(d, Expectation::Either);
    d.globalization = ocp::Globalization::LevenbergMarquardt;
    add(d, Expectation::Either);
    d.globalization = ocp::Globalization::NewtonArmijo;
    d.merit = ocp::Merit::Momentum;
    d.nonmonotone_memory = 5;
    add(d, Expectation::Either);
    if (!quick) {
      d.form = LgviForm::Symmetric;
      d.merit = ocp::Merit::Velocity;
      d.nonmonotone_memory = 1;
      d.globalization = ocp::Globalization::Continuation;
      add(d, Expectation::Either);
    }
    ShootingSpec c;
    c.system = "dumbbell";
    c.solver = Solver::Continuous;
    c.form = LgviForm::Symmetric;
    c.steps = 1000;
    c.max_iterations = 300;
    // rtol 1e-12: the dumbbell's continuous residual has a noise floor of ~1e-8 (measured: the
    // shooting stops at 3.6e-8 at rtol 1e-10, 9.2e-9 at 1e-12, above the default tolerance
    // 1e2 rtol), so the case is a probe (either outcome); the comparison with the discrete solution
    // (cost O(h^2), multipliers) is the point.
    c.rtol = 1e-12;
    c.guess = Guess::DiscreteSolution;
    c.start_guess = Guess::Zero;
    c.start_globalization = ocp::Globalization::Homotopy;
    add(c, Expectation::Either);
  }

  s.render = [](const RenderContext& ctx, const std::vector<SummaryRow>& rows) {
    std::vector<fs::path> files;
    for (const auto& [system, members] : by_group(rows)) {
      files.push_back(plot_iterations(ctx, system + "-violation",
                                      system + ": terminal violation against the outer iteration",
                                      violation_label(system),
                                      "violation", members));
      const bool has_conditions = std::any_of(members.begin(), members.end(),
                                              [](const SummaryRow* r) { return r->number("cond_max").has_value(); });
      if (!has_conditions) continue;  // the direct method forms no Newton matrix
      files.push_back(plot_iterations(ctx, system + "-cond-inverted",
                                      system + ": condition number of the Newton matrix inverted (shape block when "
                                               "decomposed)",
                                      "2-norm condition number", "cond_inverted", members));
      files.push_back(plot_iterations(ctx, system + "-cond-full",
                                      system + ": condition number of the full sensitivity dr/dλ_0",
                                      "2-norm condition number", "cond_sensitivity", members));
    }
    std::string table =
        "# Shooting: indirect optimal-control solvers\n\n"
        "Violation: |r| at the end; iterations: outer (inner = backtracks; direct: SQP iterates (inner = "
        "line-search trials)); sweeps: discrete sweeps, CVODES integrations or LGVI simulations (direct); cond: 2-norm condition number of the matrix inverted (range over iterations) and of the "
        "full sensitivity.\n\n"
        "| system | solver | expected | status | as expected | cost | violation | outer/inner | sweeps | cond "
        "(inverted) | cond (full) | seconds |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const SummaryRow& r : rows) {
      const auto num = [&](const char* c) { return r.number(c) ? fmt(*r.number(c)) : std::string(); };
      const auto range = [&](const char* lo, const char* hi) {
        return r.number(lo) && r.number(hi) ? fmt(*r.number(lo)) + ".." + fmt(*r.number(hi)) : std::string();
      };
      char cost[32] = "";
      if (r.number("cost")) std::snprintf(cost, sizeof cost, "%.7g", *r.number("cost"));
      const std::string sweeps = r.text("integrations").empty() ? r.text("sweeps") : r.text("integrations");
      table += "| " + r.text("group") + " | " + r.text("label") + " | " + r.text("expected") + " | " +
               r.text("status") + " | " + r.text("as_expected") + " | " + cost + " | " + num("violation") +
               " | " + r.text("iterations") + "/" + r.text("inner_iterations") + " | " + sweeps + " | " +
               range("cond_min", "cond_max") + " | " + range("cond_full_min", "cond_full_max") + " | " +
               num("wall_seconds") + " |\n";
    }
    // Continuous against the discrete solution it started from (same extremal): the cost differs by
    // the discretization error (O(h^2) for the symmetric form), the initial multipliers by O(h^2) too.
    std::string comparison;
    for (const SummaryRow& r : rows) {
      if (!r.number("discrete_cost")) continue;
      const auto num = [&](const char* c) { return r.number(c) ? fmt(*r.number(c)) : std::string(); };
      char costs[96];
      std::snprintf(costs, sizeof costs, "%.9g | %.9g", r.number("cost").value_or(kNan), *r.number("discrete_cost"));
      comparison += "| " + r.text("group") + " | " + r.text("label") + " | " + costs + " | " + num("cost_difference") +
                    " | " + num("multiplier_difference") + " | " + num("violation") + " | " +
                    num("discrete_violation") + " |\n";
    }
    if (!comparison.empty()) {
      table += "\nContinuous (CVODES) against the discrete solution it started from: cost, relative difference "
               "of the initial multipliers |lambda(0) - lambda_0| / |lambda(0)| (pendulum: symmetry direction "
               "removed), terminal violations.\n\n| system | continuous case | cost (continuous) | cost (discrete) "
               "| difference | multipliers (rel.) | violation (continuous) | violation (discrete) |\n"
               "|---|---|---|---|---|---|---|---|\n" +
               comparison;
    }
    files.push_back(write_text_file(ctx, "shooting-table.md", table));
    return files;
  };
  return s;
}

}  // namespace lgvi::experiments::suites
