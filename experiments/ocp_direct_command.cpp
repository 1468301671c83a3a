// `lgvi-testbed ocp cart-pendulum|connected-bodies`: the direct method of sections 4.1 and 4.2
// (lgvi/ocp/direct.hpp). Writes, atomically, into --out DIR:
//   ocp-SYSTEM-history.csv     one row per SLSQP evaluation (cost, violation)
//   ocp-SYSTEM-trajectory.csv  t, the scene's state columns (experiments/recorder), controls
//   ocp-SYSTEM-summary.json    cost, violation, evaluations, gradients, wall time, status, knots
//   ocp-SYSTEM-knots.csv       t and the optimized knot values u1..u_nu, one row per knot (the
//                              circles of the paper's Figs. 4(b), 5(b))
#include <cmath>
#include <filesystem>
#include <ostream>

#include "experiments/atomic_file.hpp"
#include "experiments/csv_writer.hpp"
#include "experiments/fields.hpp"
#include "experiments/json_writer.hpp"
#include "experiments/ocp_command.hpp"
#include "experiments/ocp_output.hpp"
#include "experiments/paper_values.hpp"
#include "experiments/simulate.hpp"
#include "lgvi/ocp/direct.hpp"

namespace lgvi::experiments {

namespace fs = std::filesystem;

namespace {

constexpr double kPaperStep = 0.01;  // both sections (validation/paper_values.toml)
// Default multistart (README "Direct method"): the cart-pendulum converges from the default
// guess; the connected bodies' landscape has many local optima (costs 0.54 to 90 found).
constexpr int kCartPendulumStarts = 1;
constexpr int kConnectedBodiesStarts = 8;
constexpr int kMaxEvaluations = 3000;  // per start; the connected bodies' starts take 400..2500
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

void append_matrix(std::vector<double>& row, const Mat3& R) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) row.push_back(R(i, j));
}

std::vector<std::string> trajectory_columns(bool cart, int nu) {
  std::vector<std::string> c = {"t"};
  const auto matrix = [&](const std::string& name) {
    for (char i = '1'; i <= '3'; ++i)
      for (char j = '1'; j <= '3'; ++j) c.push_back(name + i + j);
  };
  const auto vector = [&](const std::string& name) {
    for (char i = '1'; i <= '3'; ++i) c.push_back(name + i);
  };
  if (cart) {
    matrix("R");
    vector("Omega");
    for (const char* name : {"x", "y", "xdot", "ydot"}) c.push_back(name);
  } else {
    matrix("R1_");
    matrix("R2_");
    vector("Omega1_");
    vector("Omega2_");
  }
  for (int i = 1; i <= nu; ++i) c.push_back(std::string(1, 'u') + static_cast<char>('0' + i));
  c.push_back("energy");
  return c;
}

void state_row(std::vector<double>& row, const CartPendulumLgvi& lgvi, const CartPendulumState& s) {
  Vec3 Omega;
  Vec2 q_dot;
  lgvi.velocities(s, Omega, q_dot);
  append_matrix(row, s.R);
  for (int i = 0; i < 3; ++i) row.push_back(Omega(i));
  row.insert(row.end(), {s.q.x(), s.q.y(), q_dot.x(), q_dot.y()});
}
double energy(const CartPendulumLgvi& lgvi, const CartPendulumState& s) {
  Vec3 Omega;
  Vec2 q_dot;
  lgvi.velocities(s, Omega, q_dot);
  return lgvi.system().energy(s.R, Omega, q_dot);
}
void state_row(std::vector<double>& row, const ConnectedBodiesLgvi& lgvi, const ConnectedBodiesState& s) {
  Vec3 Omega1, Omega2;
  lgvi.velocities(s, Omega1, Omega2);
  append_matrix(row, s.R1);
  append_matrix(row, s.R2);
  for (int i = 0; i < 3; ++i) row.push_back(Omega1(i));
  for (int i = 0; i < 3; ++i) row.push_back(Omega2(i));
}
double energy(const ConnectedBodiesLgvi& lgvi, const ConnectedBodiesState& s) {
  Vec3 Omega1, Omega2;
  lgvi.velocities(s, Omega1, Omega2);
  return lgvi.system().energy(s.R1, s.R2, Omega1, Omega2);
}

template <class Model>
int solve_and_write(const typename Model::System& system, const typename Model::Transfer& problem,
                    const ocp::DirectOptions& options, const PaperExample& paper, const OcpCommand& cmd,
                    const std::string& command_line, std::ostream& out, std::ostream& err) {
  const ocp::DirectResult<Model> result = ocp::solve_direct(system, problem, options);
  const ocp::DirectSummary& S = result.summary;
  if (S.status == ocp::DirectStatus::InvalidInput) return ocp_output::invalid_input(cmd, S.message, err);
  const ocp_output::Files files = ocp_output::create_files(cmd);
  const fs::path& history = files.history;
  const fs::path& trajectory = files.trajectory;
  const fs::path knots_file = ocp_output_file(files.dir, cmd.system, "knots.csv");
  constexpr bool cart = Model::nu == 2;

  Eigen::VectorXd knot_times(S.knots);
  for (int i = 0; i < S.knots; ++i) knot_times(i) = problem.t_final * i / (S.knots - 1);
  const Eigen::VectorXd& r = S.residual;
  const bool have_r = r.size() > 0;
  Fields f = {
      {"system", cmd.system},
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
      {"W", std::string("identity")},
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
      {"violation_norm",
       std::string(cart ? "2-norm of [log(R_N^T R_f)^vee; q_N - q_f; Omega_N - Omega_f; qdot_N - qdot_f]"
                        : "2-norm of [log(R1_N^T R1_f)^vee; log(R2_N^T R2_f)^vee; Omega1_N - Omega1_f; "
                          "Omega2_N - Omega2_f] (Omega2 not among the SLSQP constraints)")},
      {"constraint_violation", S.constraint_violation},
      {"constraints", std::int64_t{S.constraints}},
  };
  if (have_r) {
    if constexpr (cart) {
      f.push_back({"violation_rotation", r.head(3).norm()});
      f.push_back({"violation_position", r.segment(3, 2).norm()});
      f.push_back({"violation_angular_velocity", r.segment(5, 3).norm()});
      f.push_back({"violation_velocity", r.segment(8, 2).norm()});
    } else {
      f.push_back({"violation_rotation1", r.head(3).norm()});
      f.push_back({"violation_rotation2", r.segment(3, 3).norm()});
      f.push_back({"violation_angular_velocity1", r.segment(6, 3).norm()});
      f.push_back({"violation_angular_velocity2", r.segment(9, 3).norm()});
    }
  }
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
      {"knot_layout", std::string(cart ? "u_x at the knots, then u_y" : "u_1 at the knots, then u_2, then u_3")},
      {"paper_cost", paper.cost},
      {"paper_violation", paper.terminal_violation},
      {"history_csv", history.filename().string()},
      {"trajectory_csv", trajectory.filename().string()},
      {"knots_csv", knots_file.filename().string()},
      {"git_describe", std::string(git_describe())},
      {"command_line", command_line},
  };
  f.insert(f.end(), rest.begin(), rest.end());
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
    CsvWriter csv(trajectory, trajectory_columns(cart, Model::nu));
    std::vector<double> row;
    for (std::size_t k = 0; k < result.states.size(); ++k) {
      row.clear();
      row.push_back(static_cast<double>(k) * options.h);
      state_row(row, tr.lgvi(), result.states[k]);
      for (int i = 0; i < Model::nu; ++i) row.push_back(result.controls(i, static_cast<Eigen::Index>(k)));
      row.push_back(energy(tr.lgvi(), result.states[k]));
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
                    {{"knot_times", values(knot_times)},
                     {"initial_knots", values(S.best_start >= 0 ? S.starts[S.best_start].initial_knots : S.initial_knots)},
                     {"knot_values", values(S.knot_values)},
                     {"start_costs", start_costs},
                     {"start_violations", start_violations},
                     {"start_iterations", start_iterations}});
  return ocp_output::finish(cmd, S, files, {history, trajectory, knots_file, files.summary}, out, err);
}

}  // namespace

int run_ocp_direct_command(const OcpCommand& cmd, const std::string& command_line, std::ostream& out,
                           std::ostream& err) {
  ocp::DirectOptions options;
  options.form = ocp_output::parse_form(cmd);
  try {
    options.spline = ocp::parse_spline_end(cmd.spline);
  } catch (const InvalidInput&) {
    throw InvalidInput("--spline", "must be 'not-a-knot' or 'natural' (got '" + cmd.spline + "')");
  }
  try {
    options.gradients = ocp::parse_gradient_method(cmd.gradients);
  } catch (const InvalidInput&) {
    throw InvalidInput("--gradients", "must be 'exact' or 'finite-difference' (got '" + cmd.gradients + "')");
  }
  if (cmd.no_decomposition) throw InvalidInput("--no-decomposition", "applies to the pendulum only");
  if (cmd.sphere_radius != 0.0) throw InvalidInput("--sphere-radius", "applies to the dumbbell only");
  if (cmd.merit != "velocity") throw InvalidInput("--merit", "applies to the indirect method only");
  ocp_output::check_step_options(cmd);
  if (cmd.max_iterations < 0) throw InvalidInput("--max-iterations", "must be >= 1");
  if (cmd.knots < 3) throw InvalidInput("--knots", "must be >= 3");
  if (!(cmd.tolerance > 0.0) || !std::isfinite(cmd.tolerance)) throw InvalidInput("--tolerance", "must be > 0");
  if (cmd.starts < 0) throw InvalidInput("--starts", "must be >= 1");
  if (cmd.seed < 0) throw InvalidInput("--seed", "must be >= 0");
  options.knots = cmd.knots;
  options.seed = static_cast<std::uint64_t>(cmd.seed);
  if (cmd.first_start < 0) throw InvalidInput("--first-start", "must be >= 0");
  options.first_start = cmd.first_start;
  options.tolerance = cmd.tolerance;
  try {
    options.solver = ocp::parse_direct_solver(cmd.solver);
  } catch (const InvalidInput&) {
    throw InvalidInput("--solver", "must be 'slsqp' or 'ipopt' (got '" + cmd.solver + "')");
  }
  if (cmd.shooting_interval < 0) throw InvalidInput("--shooting-interval", "must be >= 1");
  if (cmd.shooting_interval > 0 && options.solver != ocp::DirectSolver::IpoptMultipleShooting) {
    throw InvalidInput("--shooting-interval", "applies to --solver ipopt only");
  }
  if (cmd.shooting_interval > 0) options.shooting_interval = cmd.shooting_interval;
  try {
    options.ipopt_hessian = ocp::parse_ipopt_hessian(cmd.hessian);
  } catch (const InvalidInput&) {
    throw InvalidInput("--hessian", "must be 'limited-memory', 'cost' or 'exact' (got '" + cmd.hessian + "')");
  }
  try {
    options.state_guess = ocp::parse_shooting_state_guess(cmd.state_guess);
  } catch (const InvalidInput&) {
    throw InvalidInput("--state-guess", "must be 'simulated' or 'geodesic' (got '" + cmd.state_guess + "')");
  }
  const int default_cap = options.solver == ocp::DirectSolver::Slsqp ? kMaxEvaluations : kMaxIpoptIterations;
  options.max_evaluations = cmd.max_iterations > 0 ? cmd.max_iterations : default_cap;
  const bool cart = cmd.system == "cart-pendulum";
  options.starts = cmd.starts > 0 ? cmd.starts : cart ? kCartPendulumStarts : kConnectedBodiesStarts;
  ocp::CartPendulumTransfer cart_problem = ocp::CartPendulumTransfer::paper();
  ocp::ConnectedBodiesTransfer bodies_problem = ocp::ConnectedBodiesTransfer::paper();
  double& t_final = cart ? cart_problem.t_final : bodies_problem.t_final;
  if (cmd.t_final != 0.0) {
    require_positive(cmd.t_final, "--t-final");
    t_final = cmd.t_final;
  }
  if (cmd.h != 0.0) {
    require_positive(cmd.h, "--h");
    options.h = cmd.h;
  } else if (cmd.steps > 0) {
    options.h = t_final / static_cast<double>(cmd.steps);
  } else {
    options.h = kPaperStep;
  }
  const int n = (cart ? 2 : 3) * cmd.knots;
  if (!cmd.guess.empty()) {
    if (static_cast<int>(cmd.guess.size()) != n) {
      throw InvalidInput("--guess", "needs " + std::to_string(n) + " knot values for the " + cmd.system + " (got " +
                                        std::to_string(cmd.guess.size()) + ")");
    }
    options.initial_knots = Eigen::Map<const Eigen::VectorXd>(cmd.guess.data(), n);
  }
  if (cart) {
    return solve_and_write<ocp::CartPendulumDirectModel>(CartPendulum::paper(), cart_problem, options,
                                                         paper_values().cart_pendulum, cmd, command_line, out, err);
  }
  return solve_and_write<ocp::ConnectedBodiesDirectModel>(ConnectedBodies::paper(), bodies_problem, options,
                                                          paper_values().connected_bodies, cmd, command_line, out, err);
}

}  // namespace lgvi::experiments
