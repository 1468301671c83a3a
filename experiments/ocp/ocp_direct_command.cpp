// `lgvi-testbed ocp SCENE` for a scene whose [ocp] method is direct (the paper's sections 4.1 and
// 4.2: ocp-cart-pendulum.toml, ocp-connected-bodies.toml): lgvi/ocp/direct.hpp. Writes, atomically, into --out DIR:
//   ocp-SYSTEM-history.csv     one row per SLSQP evaluation (cost, violation)
//   ocp-SYSTEM-trajectory.csv  t, the scene's state columns (experiments/recorder), controls
//   ocp-SYSTEM-summary.json    cost, violation, evaluations, gradients, wall time, status, knots
//   ocp-SYSTEM-knots.csv       t and the optimized knot values u1..u_nu, one row per knot (the
//                              circles of the paper's Figs. 4(b), 5(b))
// With --solver ddp (lgvi/ocp/ddp.hpp: free node controls, no spline) the history has one row per
// iLQR iteration and there is no knots file (the node controls are in the trajectory).
#include <cmath>
#include <filesystem>
#include <ostream>

#include "experiments/output/atomic_file.hpp"
#include "experiments/output/csv_writer.hpp"
#include "experiments/output/fields.hpp"
#include "experiments/output/json_writer.hpp"
#include "experiments/ocp/ocp_command.hpp"
#include "experiments/ocp/ocp_output.hpp"
#include "experiments/scene/ocp_scene.hpp"
#include "experiments/input/paper_values.hpp"
#include "experiments/methods/simulate.hpp"
#include "experiments/systems/systems.hpp"
#include "experiments/systems/ocp.hpp"
#include "lgvi/ocp/ddp.hpp"
#include "lgvi/ocp/direct.hpp"

namespace lgvi::experiments {

namespace fs = std::filesystem;

namespace {

constexpr int kMaxEvaluations = 3000;      // per start, SLSQP (the connected bodies' starts take 400..2500)
constexpr int kMaxIpoptIterations = 1000;  // per start (multiple shooting takes tens to hundreds)

using ocp_output::join;
using ocp_output::values;

template <class F>
std::string start_field(const ocp::DirectSummary& S, F f, const char* separator = " ") {
  std::string s;
  for (std::size_t i = 0; i < S.starts.size(); ++i) {
    if (i > 0) s += separator;
    s += f(S.starts[i]);
  }
  return s;
}

template <class B, class Model = typename B::DirectModel>
int solve_and_write(const typename Model::System& system, const typename Model::Transfer& problem,
                    const ocp::DirectOptions& options, const ocp_output::Run& run, const OcpCommand& cmd,
                    const std::string& command_line, std::ostream& out, std::ostream& err) {
  const ocp::DirectResult<Model> result = ocp::solve_direct(system, problem, options);
  const ocp::DirectSummary& S = result.summary;
  if (S.status == ocp::DirectStatus::InvalidInput) return ocp_output::invalid_input(cmd, S.message, err);
  const ocp_output::Files files = ocp_output::create_files(cmd, run.label);
  const fs::path& history = files.history;
  const fs::path& trajectory = files.trajectory;
  const fs::path knots_file = ocp_output_file(files.dir, run.label, "knots.csv");

  Eigen::VectorXd knot_times(S.knots);
  for (int i = 0; i < S.knots; ++i) knot_times(i) = problem.t_final * i / (S.knots - 1);
  const Eigen::VectorXd& r = S.residual;
  Fields f = {
      {"system", run.system},
      {"method", std::string(options.solver == ocp::DirectSolver::Slsqp
                                 ? "direct: cubic-spline controls, SLSQP (NLopt)"
                                 : "direct: cubic-spline controls, multiple shooting, IPOPT")},
      {"solver", std::string(ocp::to_string(options.solver))},
      {"hessian", std::string(options.solver == ocp::DirectSolver::Slsqp ? "" : ocp::to_string(options.ipopt_hessian))},
      {"state_guess", std::string(options.solver == ocp::DirectSolver::Slsqp ? "" : ocp::to_string(options.state_guess))},
      {"shooting_interval", std::int64_t{options.solver == ocp::DirectSolver::Slsqp ? 0 : options.shooting_interval}},
      {"form", std::string(to_string(options.form))},
      {"h", options.h},
      {"steps", static_cast<std::int64_t>(S.steps)},
      {"t_final", problem.t_final},
      {"W", ocp_output::weight_text(options.W)},
      {"knots", std::int64_t{S.knots}},
      {"spline", std::string(ocp::to_string(options.spline))},
      {"gradients", std::string(ocp::to_string(options.gradients))},
      {"status", std::string(ocp::to_string(S.status))},
      {"status_detail", S.brief()},
      {"nlopt_result", S.nlopt_result},
      {"converged", S.converged()},
      {"tolerance", options.tolerance},
      {"cost", S.cost},
      {"violation", S.violation},
      {"violation_norm", std::string(B::violation_norm)},
      {"constraint_violation", S.constraint_violation},
      {"constraints", std::int64_t{S.constraints}},
  };
  ocp_output::add_violation_parts<B>(f, r);
  ocp_output::add_replay_fields(f, system, problem,
                                result.controls.cols() == static_cast<Eigen::Index>(S.steps) + 1 ? Eigen::MatrixXd(result.controls)
                                                                                                : Eigen::MatrixXd(),
                                options.h, options.form, options.W);
  const Fields rest = {
      {"iterations", std::int64_t{S.iterations}},
      {"evaluations", std::int64_t{S.evaluations}},
      {"failed_simulations", std::int64_t{S.failed_simulations}},
      {"gradient_evaluations", std::int64_t{S.gradient_evaluations}},
      {"simulations", std::int64_t{S.simulations}},
      {"wall_seconds", S.wall_seconds},
      {"starts", std::int64_t(S.starts.size())},
      {"first_start", std::int64_t{options.first_start}},
      {"best_start", std::int64_t{S.best_start >= 0 ? S.starts[S.best_start].index : -1}},
      {"seed", static_cast<std::int64_t>(options.seed)},
      {"start_costs", start_field(S, [](const ocp::DirectStart& s) { return shortest(s.cost); })},
      {"start_violations", start_field(S, [](const ocp::DirectStart& s) { return shortest(s.violation); })},
      {"start_iterations", start_field(S, [](const ocp::DirectStart& s) { return std::to_string(s.iterations); })},
      {"start_seconds", start_field(S, [](const ocp::DirectStart& s) { return shortest(s.seconds); })},
      {"start_statuses", start_field(S, [](const ocp::DirectStart& s) { return std::string(ocp::to_string(s.status)); }, "; ")},
      {"knot_times", join(knot_times)},
      {"initial_knots", join(S.best_start >= 0 ? S.starts[S.best_start].initial_knots : S.initial_knots)},
      {"knot_values", join(S.knot_values)},
      {"knot_layout", std::string(B::knot_layout)},
  };
  f.insert(f.end(), rest.begin(), rest.end());
  if (run.paper != nullptr) {
    f.push_back({"paper_cost", run.paper->cost});
    f.push_back({"paper_violation", run.paper->terminal_violation});
  }
  const Fields files_fields = {
      {"history_csv", history.filename().string()},
      {"trajectory_csv", trajectory.filename().string()},
      {"knots_csv", knots_file.filename().string()},
      {"git_describe", std::string(git_describe())},
      {"command_line", command_line},
  };
  f.insert(f.end(), files_fields.begin(), files_fields.end());
  f.push_back({"run_id", files.run_id});

  {
    CsvWriter csv(history, {"start", "evaluation", "iteration", "gradient", "cost", "violation", "seconds"});
    int iteration = 0, start = -1;
    for (const ocp::DirectIteration& it : S.history) {
      if (it.start != start) iteration = 0;
      start = it.start;
      if (it.gradient) ++iteration;
      const double row[] = {double(it.start), double(it.evaluation), double(iteration), it.gradient ? 1.0 : 0.0,
                            it.cost, it.violation, it.seconds};
      csv.write_row(row);
    }
    csv.commit(f);
  }
  if (!result.states.empty()) {
    const ocp::DirectTranscription<Model> tr(system, problem, options);
    std::vector<std::string> columns = {"t"};
    B::state_columns(columns);
    for (int i = 1; i <= Model::nu; ++i) columns.push_back(std::string(1, 'u') + static_cast<char>('0' + i));
    columns.push_back("energy");
    CsvWriter csv(trajectory, columns);
    std::vector<double> row;
    for (std::size_t k = 0; k < result.states.size(); ++k) {
      row.clear();
      row.push_back(static_cast<double>(k) * options.h);
      B::state_row(row, tr.lgvi(), result.states[k]);
      for (int i = 0; i < Model::nu; ++i) row.push_back(result.controls(i, static_cast<Eigen::Index>(k)));
      row.push_back(B::energy(tr.lgvi(), result.states[k]));
      csv.write_row(row);
    }
    csv.commit(f);
  }
  if (S.knot_values.size() == static_cast<Eigen::Index>(Model::nu) * S.knots) {
    std::vector<std::string> cols = {"t"};
    for (int i = 1; i <= Model::nu; ++i) cols.push_back(std::string("u").append(std::to_string(i)));
    CsvWriter csv(knots_file, cols);
    std::vector<double> row;
    for (int j = 0; j < S.knots; ++j) {
      row.assign({knot_times(j)});
      for (int i = 0; i < Model::nu; ++i) row.push_back(S.knot_values(i * S.knots + j));  // knot_layout
      csv.write_row(row);
    }
    csv.commit(f);
  }
  // One object; the vectors as arrays of numbers (their text form stays in the CSVs' metadata).
  std::vector<double> start_costs, start_violations, start_iterations;
  for (const ocp::DirectStart& s : S.starts) {
    start_costs.push_back(s.cost);
    start_violations.push_back(s.violation);
    start_iterations.push_back(static_cast<double>(s.iterations));
  }
  write_json_object(files.summary, f,
                    {{"W", ocp_output::weight_values(options.W, B::nu)},
                     {"knot_times", values(knot_times)},
                     {"initial_knots", values(S.best_start >= 0 ? S.starts[S.best_start].initial_knots : S.initial_knots)},
                     {"knot_values", values(S.knot_values)},
                     {"start_costs", start_costs},
                     {"start_violations", start_violations},
                     {"start_iterations", start_iterations}});
  return ocp_output::finish(cmd, S, files, {history, trajectory, knots_file, files.summary}, out, err);
}

// --solver ddp: iLQR on the node controls (lgvi/ocp/ddp.hpp); the same history, trajectory and
// summary files, no knots file.
template <class B, class Model = typename B::DirectModel>
int solve_and_write_ddp(const typename Model::System& system, const typename Model::Transfer& problem,
                        const ocp::DdpOptions& options, const ocp_output::Run& run, const OcpCommand& cmd,
                        const std::string& command_line, std::ostream& out, std::ostream& err) {
  const ocp::DdpResult<Model> result = ocp::solve_ddp(system, problem, options);
  const ocp::DdpSummary& S = result.summary;
  if (S.status == ocp::DdpStatus::InvalidInput) return ocp_output::invalid_input(cmd, S.message, err);
  const ocp_output::Files files = ocp_output::create_files(cmd, run.label);
  const Eigen::VectorXd& r = S.residual;
  const auto per_start = [&](auto f, const char* separator = " ") {
    std::string s;
    for (std::size_t i = 0; i < S.starts.size(); ++i) s += (i > 0 ? separator : "") + f(S.starts[i]);
    return s;
  };
  Fields f = {
      {"system", run.system},
      {"method", std::string("direct: free node controls, iLQR/DDP with an augmented Lagrangian")},
      {"solver", std::string("ddp")},
      {"form", std::string(to_string(options.form))},
      {"h", options.h},
      {"steps", static_cast<std::int64_t>(S.steps)},
      {"t_final", problem.t_final},
      {"W", ocp_output::weight_text(options.W)},
      {"knots", std::int64_t{options.knots}},  // of the starts' splines only
      {"spline", std::string(ocp::to_string(options.spline))},
      {"status", std::string(ocp::to_string(S.status))},
      {"status_detail", S.brief()},
      {"converged", S.converged()},
      {"tolerance", options.tolerance},
      {"cost", S.cost},
      {"violation", S.violation},
      {"violation_norm", std::string(B::violation_norm)},
      {"constraints", std::int64_t{S.constraints}},
  };
  ocp_output::add_violation_parts<B>(f, r);
  ocp_output::add_replay_fields(f, system, problem,
                                result.controls.cols() == static_cast<Eigen::Index>(S.steps) + 1 ? Eigen::MatrixXd(result.controls)
                                                                                                : Eigen::MatrixXd(),
                                options.h, options.form, options.W);
  const Fields rest = {
      {"iterations", std::int64_t{S.iterations}},
      {"outer_iterations", std::int64_t{S.outer_iterations}},
      {"rollouts", static_cast<std::int64_t>(S.rollouts)},
      {"wall_seconds", S.wall_seconds},
      {"cpu_seconds", S.cpu_seconds},
      {"starts", std::int64_t(S.starts.size())},
      {"first_start", std::int64_t{options.first_start}},
      {"best_start", std::int64_t{S.best_start >= 0 ? S.starts[S.best_start].index : -1}},
      {"seed", static_cast<std::int64_t>(options.seed)},
      {"start_costs", per_start([](const ocp::DdpStart& s) { return shortest(s.cost); })},
      {"start_violations", per_start([](const ocp::DdpStart& s) { return shortest(s.violation); })},
      {"start_iterations", per_start([](const ocp::DdpStart& s) { return std::to_string(s.iterations); })},
      {"start_seconds", per_start([](const ocp::DdpStart& s) { return shortest(s.cpu_seconds); })},
      {"start_statuses", per_start([](const ocp::DdpStart& s) { return std::string(ocp::to_string(s.status)); }, "; ")},
      {"history_csv", files.history.filename().string()},
      {"trajectory_csv", files.trajectory.filename().string()},
      {"git_describe", std::string(git_describe())},
      {"command_line", command_line},
      {"run_id", files.run_id},
  };
  f.insert(f.end(), rest.begin(), rest.end());
  {
    CsvWriter csv(files.history, {"start", "iteration", "outer", "cost", "violation", "objective", "gradient",
                                  "expected", "alpha", "regularization", "penalty", "seconds"});
    for (const ocp::DdpIteration& it : S.history) {
      const double row[] = {double(it.start), double(it.iteration), double(it.outer), it.cost, it.violation,
                            it.objective,     it.gradient,          it.expected,      it.alpha, it.regularization,
                            it.penalty,       it.seconds};
      csv.write_row(row);
    }
    csv.commit(f);
  }
  {
    const ocp::Ddp<Model> ddp(system, problem, options);
    const auto& lgvi = ddp.transcription().lgvi();
    std::vector<std::string> columns = {"t"};
    B::state_columns(columns);
    for (int i = 1; i <= Model::nu; ++i) columns.push_back(std::string(1, 'u') + static_cast<char>('0' + i));
    columns.push_back("energy");
    CsvWriter csv(files.trajectory, columns);
    std::vector<double> row;
    for (std::size_t k = 0; k < result.states.size(); ++k) {
      row.clear();
      row.push_back(static_cast<double>(k) * options.h);
      B::state_row(row, lgvi, result.states[k]);
      for (int i = 0; i < Model::nu; ++i) row.push_back(result.controls(i, static_cast<Eigen::Index>(k)));
      row.push_back(B::energy(lgvi, result.states[k]));
      csv.write_row(row);
    }
    csv.commit(f);
  }
  std::vector<double> start_costs, start_violations, start_iterations;
  for (const ocp::DdpStart& s : S.starts) {
    start_costs.push_back(s.cost);
    start_violations.push_back(s.violation);
    start_iterations.push_back(static_cast<double>(s.iterations));
  }
  write_json_object(files.summary, f,
                    {{"W", ocp_output::weight_values(options.W, B::nu)},
                     {"start_costs", start_costs}, {"start_violations", start_violations},
                     {"start_iterations", start_iterations}});
  return ocp_output::finish(cmd, S, files, {files.history, files.trajectory, files.summary}, out, err);
}

}  // namespace

namespace {

template <class M>
int run_direct_for(const Scene& scene, const M& m, const OcpCommand& cmd, const std::string& command_line,
                   std::ostream& out, std::ostream& err) {
  using B = OcpBinding<M>;
  if constexpr (!B::direct) {
    throw InvalidInput("ocp.method", std::string("the ") + M::name + " has no direct method");
  } else {
    const OcpDefinition& d = *scene.ocp;
    ocp::DirectOptions options = d.direct;
    options.form = scene.form;
    options.h = scene.horizon.h;
    if (cmd.spline) {
      try {
        options.spline = ocp::parse_spline_end(*cmd.spline);
      } catch (const InvalidInput&) {
        throw InvalidInput("--spline", "must be 'not-a-knot' or 'natural' (got '" + *cmd.spline + "')");
      }
    }
    if (cmd.gradients) {
      try {
        options.gradients = ocp::parse_gradient_method(*cmd.gradients);
      } catch (const InvalidInput&) {
        throw InvalidInput("--gradients", "must be 'exact' or 'finite-difference' (got '" + *cmd.gradients + "')");
      }
    }
    using O = ocp::DirectOptions;
    if (cmd.knots) {
      const int knots = ocp_output::option_int(*cmd.knots, O::kKnots, "--knots");
      if (knots != options.knots && options.initial_knots.size() > 0) {
        throw InvalidInput("--knots", "the scene's ocp.direct.initial_knots are for " + std::to_string(options.knots) +
                                          " knots");
      }
      const std::size_t nodes = scene.horizon.steps + 1;
      if (static_cast<std::size_t>(knots) > nodes) {
        throw InvalidInput("--knots", "must be at most the grid's " + std::to_string(nodes) +
                                          " nodes (steps + 1; got " + std::to_string(knots) + ")");
      }
      options.knots = knots;
    }
    if (cmd.tolerance) options.tolerance = ocp_output::option_number(*cmd.tolerance, O::kTolerance, "--tolerance");
    if (cmd.starts) options.starts = ocp_output::option_int(*cmd.starts, O::kStarts, "--starts");
    if (cmd.seed) options.seed = static_cast<std::uint64_t>(ocp_output::option_int(*cmd.seed, O::kSeed, "--seed"));
    options.first_start = ocp_output::option_int(cmd.first_start, O::kFirstStart, "--first-start");
    if (cmd.solver && *cmd.solver == "ddp") {
      // iLQR on free node controls (lgvi/ocp/ddp.hpp): the same discrete problem and starts.
      const std::pair<bool, const char*> not_ddp[] = {{cmd.gradients.has_value(), "--gradients"},
                                                      {cmd.hessian.has_value(), "--hessian"},
                                                      {cmd.state_guess.has_value(), "--state-guess"},
                                                      {cmd.shooting_interval.has_value(), "--shooting-interval"}};
      for (const auto& [given, name] : not_ddp) {
        if (given) throw InvalidInput(name, "applies to --solver slsqp or ipopt only");
      }
      ocp::DdpOptions ddp;
      ddp.form = options.form;
      ddp.h = options.h;
      ddp.W = options.W;
      ddp.knots = options.knots;
      ddp.spline = options.spline;
      ddp.initial_knots = options.initial_knots;
      ddp.starts = options.starts;
      ddp.first_start = options.first_start;
      ddp.seed = options.seed;
      ddp.guess_scale = options.guess_scale;
      ddp.keep_redundant_constraint = options.keep_redundant_constraint;
      ddp.newton = options.newton;
      if (cmd.tolerance) ddp.tolerance = options.tolerance;  // else DDP's default, 1e-8
      if (cmd.max_iterations) {
        ddp.max_iterations =
            ocp_output::option_int(*cmd.max_iterations, ocp::DdpOptions::kMaxIterations, "--max-iterations");
      }
      ocp_output::validate_options(ddp, scene, "direct");
      const auto problem = B::transfer(m, std::get<typename M::State>(d.target), scene.horizon.t_final);
      const auto& system = ocp_output::with_sphere_radius(B::system(m), cmd.sphere_radius);
      return solve_and_write_ddp<B>(system, problem, ddp, ocp_output::Run::of(scene), cmd, command_line, out, err);
    }
    if (cmd.solver) {
      try {
        options.solver = ocp::parse_direct_solver(*cmd.solver);
      } catch (const InvalidInput&) {
        throw InvalidInput("--solver", "must be 'slsqp', 'ipopt', 'ddp' or 'collocation' (got '" + *cmd.solver + "')");
      }
    }
    const bool ipopt = options.solver == ocp::DirectSolver::IpoptMultipleShooting;
    // The IPOPT-only options are errors with SLSQP, as the [ocp.direct] keys are.
    if (cmd.hessian && !ipopt) throw InvalidInput("--hessian", "applies to --solver ipopt only");
    if (cmd.state_guess && !ipopt) throw InvalidInput("--state-guess", "applies to --solver ipopt only");
    if (cmd.shooting_interval) {
      if (!ipopt) throw InvalidInput("--shooting-interval", "applies to --solver ipopt only");
      options.shooting_interval =
          ocp_output::option_int(*cmd.shooting_interval, O::kShootingInterval, "--shooting-interval");
    }
    if (cmd.hessian) options.ipopt_hessian = ocp_output::option_hessian(*cmd.hessian);
    if (cmd.state_guess) {
      try {
        options.state_guess = ocp::parse_shooting_state_guess(*cmd.state_guess);
      } catch (const InvalidInput&) {
        throw InvalidInput("--state-guess", "must be 'simulated' or 'geodesic' (got '" + *cmd.state_guess + "')");
      }
    }
    if (cmd.max_iterations) {
      options.max_evaluations = ocp_output::option_int(*cmd.max_iterations, O::kMaxEvaluations, "--max-iterations");
    } else if (!d.max_evaluations_given) {
      options.max_evaluations = ipopt ? kMaxIpoptIterations : kMaxEvaluations;
    }
    ocp_output::validate_options(options, scene, "direct");
    const auto problem = B::transfer(m, std::get<typename M::State>(d.target), scene.horizon.t_final);
    const auto& system = ocp_output::with_sphere_radius(B::system(m), cmd.sphere_radius);
    return solve_and_write<B>(system, problem, options, ocp_output::Run::of(scene), cmd, command_line, out, err);
  }
}

}  // namespace

int ocp_output::run_direct(const Scene& scene, const OcpCommand& cmd, const std::string& command_line,
                           std::ostream& out, std::ostream& err) {
  return visit_binding(scene.model,
                       [&](auto, const auto& m) { return run_direct_for(scene, m, cmd, command_line, out, err); });
}

}  // namespace lgvi::experiments
