#include "experiments/ocp_command.hpp"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <ostream>
#include <sstream>

#include "experiments/atomic_file.hpp"
#include "experiments/csv_writer.hpp"
#include "experiments/fields.hpp"
#include "experiments/json_writer.hpp"
#include "experiments/ocp_output.hpp"
#include "experiments/paper_values.hpp"
#include "experiments/simulate.hpp"
#include "lgvi/ocp/indirect.hpp"

namespace lgvi::experiments {

namespace fs = std::filesystem;

namespace {

// Defaults, documented in the README ("Indirect optimal control"):
//  - form printed: the paper states its discrete optimal control problem (eqs. 14-19, 24-28)
//    for the printed LGVI (eqs. 8-12, 21-23); --form symmetric solves the symmetric one.
//  - steps: the pendulum's h = 0.001 is the paper's; the dumbbell's step is not printed, we use
//    the same number of steps, 1000 (h = pi/2000 over the quarter orbit T = pi/2).
//  - the initial multiplier guesses carry no information about the answer: the dumbbell starts
//    from lambda_0 = 0 (the uncontrolled motion); the pendulum from all ones (lambda_0 = 0 is a
//    degenerate guess there: at rest with u = 0 the linearization cannot rotate about the
//    vertical, the shape block is singular).
constexpr double kPendulumStep = 1e-3;
constexpr long long kDumbbellSteps = 1000;


using ocp_output::join;
using ocp_output::values;

std::vector<std::string> multiplier_columns(bool translation) {
  std::vector<std::string> c;
  const char* blocks_t[] = {"lambda_R", "lambda_x", "lambda_Pi", "lambda_p"};
  const char* blocks_r[] = {"lambda_R", "lambda_Pi"};
  if (translation) {
    for (const char* b : blocks_t)
      for (int i = 1; i <= 3; ++i) c.push_back(std::string(b) + std::to_string(i));
  } else {
    for (const char* b : blocks_r)
      for (int i = 1; i <= 3; ++i) c.push_back(std::string(b) + std::to_string(i));
  }
  return c;
}

void write_history(const fs::path& file, const ocp::ShootingSummary& S, const Fields& metadata) {
  CsvWriter csv(file, {"iteration", "violation", "cost", "step_length", "backtracks", "cond_sensitivity",
                       "cond_inverted", "step_norm", "group_residual", "group_block", "sweeps", "seconds"});
  for (const ocp::IterationRecord& r : S.history) {
    const double row[] = {double(r.iteration), r.violation, r.cost, r.step_length, double(r.backtracks),
                          r.cond_sensitivity, r.cond_inverted, r.step_norm, r.group_residual, r.group_block,
                          double(r.sweeps), r.seconds};
    csv.write_row(row);
  }
  csv.commit(metadata);
}

template <class Model>
void write_trajectory(const fs::path& file, const ocp::ShootingResult<Model>& result,
                      const ocp::StateMultiplierFlow<Model>& flow, const Fields& metadata) {
  std::vector<std::string> cols = {"t"};
  for (int i = 1; i <= 3; ++i)
    for (int j = 1; j <= 3; ++j) cols.push_back("R" + std::to_string(i) + std::to_string(j));
  if constexpr (Model::has_translation) {
    for (int i = 1; i <= 3; ++i) cols.push_back("x" + std::to_string(i));
  }
  for (int i = 1; i <= 3; ++i) cols.push_back("Omega" + std::to_string(i));
  if constexpr (Model::has_translation) {
    for (int i = 1; i <= 3; ++i) cols.push_back("v" + std::to_string(i));
    for (int i = 1; i <= 3; ++i) cols.push_back("um" + std::to_string(i));
    for (int i = 1; i <= 3; ++i) cols.push_back("uf" + std::to_string(i));
  } else {
    for (int i = 1; i <= 3; ++i) cols.push_back("u" + std::to_string(i));
  }
  for (const std::string& c : multiplier_columns(Model::has_translation)) cols.push_back(c);
  CsvWriter csv(file, cols);
  const auto& sw = result.sweep;
  std::vector<double> row;
  for (std::size_t k = 0; k < sw.states.size(); ++k) {
    const auto& s = sw.states[k];
    row.clear();
    row.push_back(static_cast<double>(k) * flow.h());
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) row.push_back(s.R(i, j));
    if constexpr (Model::has_translation) {
      for (int i = 0; i < 3; ++i) row.push_back(s.x(i));
    }
    const Vec3 Omega = flow.lgvi().omega(s);
    for (int i = 0; i < 3; ++i) row.push_back(Omega(i));
    if constexpr (Model::has_translation) {
      for (int i = 0; i < 3; ++i) row.push_back(s.v(i));
    }
    const typename Model::VecU u = k < sw.controls.size() ? sw.controls[k] : Model::VecU::Zero();
    for (int i = 0; i < Model::nu; ++i) row.push_back(u(i));
    const typename Model::VecS l = k < sw.multipliers.size() ? sw.multipliers[k] : Model::VecS::Zero();
    for (int i = 0; i < 2 * Model::nq; ++i) row.push_back(l(i));
    csv.write_row(row);
  }
  csv.commit(metadata);
}

template <class Model>
int solve_and_write(const typename Model::System& system, const ocp::TransferProblem& problem,
                    const ocp::ShootingOptions& options, const PaperExample& paper, const OcpCommand& cmd,
                    const std::string& command_line, std::ostream& out, std::ostream& err) {
  const ocp::ShootingResult<Model> result = ocp::solve_indirect(system, problem, options);
  const ocp::ShootingSummary& S = result.summary;
  if (S.status == ocp::ShootingStatus::InvalidInput) return ocp_output::invalid_input(cmd, S.message, err);
  const ocp_output::Files files = ocp_output::create_files(cmd);
  const fs::path& history = files.history;
  const fs::path& trajectory = files.trajectory;

  // Violation by parts (the norm is the 2-norm of all of them, see lgvi/ocp/indirect.hpp).
  const Eigen::VectorXd& r = S.residual;
  const bool have_r = r.size() > 0;
  const int nq = Model::nq;
  Fields f = {
      {"system", cmd.system},
      {"method", std::string("indirect shooting (Newton-Armijo on lambda_0)")},
      {"form", std::string(to_string(options.form))},
      {"h", options.h},
      {"steps", static_cast<std::int64_t>(S.steps)},
      {"t_final", problem.t_final},
      {"W", std::string("identity")},
      {"inertia_diagonal", join(system.inertia.J.diagonal())},
      {"decomposition", S.decomposition},
      {"merit", std::string(ocp::to_string(options.merit))},
      {"globalization", std::string(ocp::to_string(options.globalization))},
      {"nonmonotone_memory", static_cast<std::int64_t>(options.nonmonotone_memory)},
      {"status", std::string(ocp::to_string(S.status))},
      {"status_detail", S.brief()},
      {"converged", S.converged()},
      {"cost", S.cost},
      {"violation", S.violation},
      {"violation_norm", std::string(Model::has_translation
                                         ? "2-norm of [log(R_f^T R_N)^vee; x_N - x_f; Omega_N - Omega_f; v_N - v_f]"
                                         : "2-norm of [log(R_f^T R_N)^vee; Omega_N - Omega_f]")},
      {"violation_rotation", have_r ? r.head(3).norm() : S.violation},
  };
  if constexpr (Model::has_translation) {
    f.push_back({"violation_position", have_r ? r.segment(3, 3).norm() : S.violation});
  }
  f.push_back({"violation_angular_velocity", have_r ? r.segment(nq, 3).norm() : S.violation});
  if constexpr (Model::has_translation) {
    f.push_back({"violation_velocity", have_r ? r.segment(nq + 3, 3).norm() : S.violation});
  }
  if constexpr (Model::has_translation) {
    // The dumbbell's cost split into the moment and force controls (W = I).
    double moment = 0.0, force = 0.0;
    const auto [c0, c1] = impulse_weights(options.form, options.h);
    const auto& u = result.sweep.controls;
    for (std::size_t j = 0; j < u.size(); ++j) {
      const double w = j == 0 ? c0 : j == S.steps ? c1 : c0 + c1;
      moment += 0.5 * w * u[j].template head<3>().squaredNorm();
      force += 0.5 * w * u[j].template tail<3>().squaredNorm();
    }
    f.push_back({"cost_moment", moment});
    f.push_back({"cost_force", force});
  }
  const Fields rest = {
      {"outer_iterations", std::int64_t{S.iterations}},
      {"inner_iterations", std::int64_t{S.inner_iterations}},
      {"sweeps", std::int64_t{S.sweeps}},
      {"cond_min", S.cond_min},
      {"cond_max", S.cond_max},
      {"cond_full_min", S.cond_full_min},
      {"cond_full_max", S.cond_full_max},
      {"wall_seconds", S.wall_seconds},
      {"multiplier_guess", join(S.multiplier_guess)},
      {"multiplier", join(S.multiplier)},
      {"paper_cost", paper.cost},
      {"paper_violation", paper.terminal_violation},
      {"paper_iterations", static_cast<std::int64_t>(paper.outer_iterations_approx.value_or(0.0))},
      {"history_csv", history.filename().string()},
      {"trajectory_csv", trajectory.filename().string()},
      {"git_describe", std::string(git_describe())},
      {"command_line", command_line},
  };
  f.insert(f.end(), rest.begin(), rest.end());
  f.push_back({"run_id", files.run_id});

  write_history(history, S, f);
  if (!result.sweep.states.empty()) {
    const ocp::StateMultiplierFlow<Model> flow(system, problem, options.form, options.h, options.W, options.rotation);
    write_trajectory<Model>(trajectory, result, flow, f);
  }
  // One object; the vectors as arrays of numbers (their text form stays in the CSVs' metadata).
  write_json_object(files.summary, f,
                    {{"inertia_diagonal", values(system.inertia.J.diagonal())},
                     {"multiplier_guess", values(S.multiplier_guess)},
                     {"multiplier", values(S.multiplier)}});
  return ocp_output::finish(cmd, S, files, {history, trajectory, files.summary}, out, err);
}

}  // namespace

CLI::Validator number_in(double lo, double hi, bool lo_open, const std::string& range) {
  return CLI::Validator(
      [lo, hi, lo_open, range](std::string& text) -> std::string {
        char* end = nullptr;
        const double x = std::strtod(text.c_str(), &end);
        const bool parsed = !text.empty() && end == text.c_str() + text.size();
        if (parsed && std::isfinite(x) && (lo_open ? x > lo : x >= lo) && x <= hi) return "";
        return "must be a number in " + range + " (got '" + text + "')";
      },
      range);
}

CLI::App* add_ocp_command(CLI::App& app, OcpCommand& o) {
  CLI::App* cmd = app.add_subcommand(
      "ocp", "Discrete optimal control: indirect (sec. 3.1, 3.2; Newton-Armijo shooting on the initial multiplier) or direct (sec. 4.1, 4.2; spline knots by SLSQP); "
             "writes the iteration history, the trajectory and a JSON summary");
  cmd->add_option("SYSTEM", o.system, "dumbbell (orbit transfer, sec. 3.1) | pendulum (180 deg about the vertical, sec. 3.2) | "
                                "cart-pendulum (sec. 4.1) | connected-bodies (sec. 4.2): the last two by the direct method")
      ->required()
      ->check(CLI::IsMember({"dumbbell", "pendulum", "cart-pendulum", "connected-bodies"}));
  cmd->add_option("--form", o.form, "LGVI form: printed (the paper's eqs.; default) | symmetric")->capture_default_str();
  // Given options are checked when given (0 used to mean "the default" silently).
  cmd->add_option("--h", o.h, "Time step (the horizon must be a whole number of steps; default: pendulum 0.001, "
                              "dumbbell pi/2000)")
      ->check(number_in(0.0, 1e100, true, "(0, 1e100]"));
  // At most 10^6 steps: the shooting keeps every step's state and sensitivities (1e8 steps ended
  // in std::bad_alloc); the paper's problems take 1000.
  cmd->add_option("--steps", o.steps, "Number of steps (instead of --h), 1 .. 1000000")
      ->check(number_in(1.0, 1e6, false, "[1, 1000000]"));
  cmd->add_flag("--no-decomposition", o.no_decomposition,
                "Pendulum: invert the full (rank-deficient) sensitivity instead of its shape block");
  cmd->add_option("--merit", o.merit, "Line-search merit: velocity (default) | momentum")->capture_default_str();
  cmd->add_option("--globalization", o.globalization,
                  "Indirect method: newton-armijo (the paper's; default) | levenberg-marquardt | homotopy "
                  "(Newton homotopy path following, then Newton-Armijo) | continuation (the same path, Hermite "
                  "predictor, Broyden corrector, Jacobians at path points only, then Newton-Armijo)")
      ->capture_default_str();
  cmd->add_option("--lm-damping", o.lm_damping, "Levenberg-Marquardt: initial damping mu_0 (relative to diag(J^T J))")
      ->capture_default_str();
  cmd->add_option("--nonmonotone-memory", o.nonmonotone_memory,
                  "Newton-Armijo / homotopy end game: Armijo test against the largest merit of the last M "
                  "accepted points (1: monotone)")
      ->capture_default_str();
  cmd->add_option("--guess", o.guess, "Initial multiplier lambda_0, comma-separated (6 pendulum, 12 dumbbell values)")
      ->delimiter(',');
  cmd->add_option("--max-iterations", o.max_iterations,
                  "Indirect: outer Newton iterations (default 300); direct: SLSQP evaluations per start (default 3000)");
  cmd->add_option("--t-final", o.t_final, "Horizon (default: the paper's, pendulum 1, dumbbell pi/2)")
      ->check(number_in(0.0, 1e100, true, "(0, 1e100]"));
  cmd->add_option("--sphere-radius", o.sphere_radius,
                  "Dumbbell: radius of the two spheres (sets the rod-axis inertia; default 0.05, README)");
  cmd->add_option("--out", o.out, "Output directory")->capture_default_str();
  cmd->add_option("--knots", o.knots, "Direct method: spline knots per control component")->capture_default_str();
  cmd->add_option("--spline", o.spline, "Direct method: spline end condition, not-a-knot | natural")
      ->capture_default_str();
  cmd->add_option("--gradients", o.gradients, "Direct method: exact | finite-difference")->capture_default_str();
  cmd->add_option("--tolerance", o.tolerance, "Direct method: bound on the terminal violation")->capture_default_str();
  cmd->add_option("--starts", o.starts,
                  "Direct method: SLSQP starts (the default guess, then seeded random knots); default: "
                  "cart-pendulum 1, connected-bodies 8");
  cmd->add_option("--solver", o.solver,
                  "Direct method: slsqp (the paper's single shooting; default) | ipopt (multiple shooting)")
      ->capture_default_str();
  cmd->add_option("--hessian", o.hessian,
                  "Direct method, --solver ipopt: limited-memory (L-BFGS) | cost (the cost's exact Hessian, "
                  "constraint curvature left out) | exact (Hessian of the Lagrangian by forward differences of its "
                  "exact gradient, columns grouped by colour)")
      ->capture_default_str();
  cmd->add_option("--state-guess", o.state_guess,
                  "Direct method, --solver ipopt: initial states, geodesic (between the boundary states) | "
                  "simulated (the guess control's run)")
      ->capture_default_str();
  cmd->add_option("--shooting-interval", o.shooting_interval,
                  "Direct method, --solver ipopt: LGVI steps per shooting segment (1: every state a variable; "
                  "default 40)");
  cmd->add_option("--seed", o.seed, "Direct method: seed of the random starts")->capture_default_str();
  cmd->add_option("--first-start", o.first_start,
                  "Direct method: number of the first start run (0 = the default guess; K > 0 the K-th "
                  "seeded random start), so one start of a multistart can be rerun alone")
      ->capture_default_str();
  // An option of the other method is an error, not silently ignored.
  cmd->parse_complete_callback([cmd]() {
    const std::string system = cmd->get_option("SYSTEM")->as<std::string>();
    const bool direct = is_direct_system(system);
    for (const char* name : {"--knots", "--spline", "--gradients", "--tolerance", "--starts", "--solver", "--hessian",
                             "--state-guess", "--shooting-interval", "--seed", "--first-start"}) {
      if (!direct && cmd->count(name) > 0) {
        throw CLI::ValidationError(name, "applies to the direct method only (cart-pendulum, connected-bodies), not to " +
                                             system);
      }
    }
    for (const char* name : {"--no-decomposition", "--merit", "--globalization", "--lm-damping", "--nonmonotone-memory", "--guess",
                             "--sphere-radius"}) {
      if (direct && cmd->count(name) > 0) {
        throw CLI::ValidationError(name, "applies to the indirect method only (pendulum, dumbbell), not to " + system);
      }
    }
  });
  return cmd;
}

bool is_direct_system(const std::string& system) {
  return system == "cart-pendulum" || system == "connected-bodies";
}

fs::path ocp_output_file(const fs::path& dir, const std::string& system, const std::string& what) {
  // Appends only: GCC 12 warns falsely (-Wrestrict) on "literal" + std::string.
  std::string name = "ocp-";
  name.append(system).append("-").append(what);
  return dir / name;
}

int run_ocp_command(const OcpCommand& cmd, const std::string& command_line, std::ostream& out, std::ostream& err) {
  if (is_direct_system(cmd.system)) {
    return run_ocp_direct_command(cmd, command_line, out, err);
  }
  ocp::ShootingOptions options;
  options.form = ocp_output::parse_form(cmd);
  try {
    options.merit = ocp::parse_merit(cmd.merit);
  } catch (const InvalidInput&) {
    throw InvalidInput("--merit", "must be 'velocity' or 'momentum' (got '" + cmd.merit + "')");
  }
  ocp_output::check_step_options(cmd);
  if (cmd.max_iterations < 0) throw InvalidInput("--max-iterations", "must be >= 0");
  options.decomposition = !cmd.no_decomposition;
  try {
    options.globalization = ocp::parse_globalization(cmd.globalization);
  } catch (const InvalidInput&) {
    throw InvalidInput("--globalization",
                       "must be 'newton-armijo', 'levenberg-marquardt', 'homotopy' or 'continuation' (got '" +
                           cmd.globalization + "')");
  }
  if (!(cmd.lm_damping > 0.0) || !std::isfinite(cmd.lm_damping)) throw InvalidInput("--lm-damping", "must be > 0");
  options.lm_initial_damping = cmd.lm_damping;
  if (cmd.nonmonotone_memory < 1) throw InvalidInput("--nonmonotone-memory", "must be >= 1");
  options.nonmonotone_memory = cmd.nonmonotone_memory;
  options.max_iterations = cmd.max_iterations > 0 ? cmd.max_iterations : 300;
  const bool pendulum = cmd.system == "pendulum";
  ocp::TransferProblem problem =
      pendulum ? ocp::TransferProblem::pendulum_paper() : ocp::TransferProblem::dumbbell_paper();
  if (cmd.t_final != 0.0) {
    require_positive(cmd.t_final, "--t-final");
    problem.t_final = cmd.t_final;
  }
  if (cmd.sphere_radius != 0.0 && pendulum) throw InvalidInput("--sphere-radius", "applies to the dumbbell only");
  if (cmd.h != 0.0) {
    options.h = cmd.h;
  } else if (cmd.steps > 0) {
    options.h = problem.t_final / static_cast<double>(cmd.steps);
  } else {
    options.h = pendulum ? kPendulumStep : problem.t_final / static_cast<double>(kDumbbellSteps);
  }
  const int n = pendulum ? 6 : 12;
  if (!cmd.guess.empty()) {
    if (static_cast<int>(cmd.guess.size()) != n) {
      throw InvalidInput("--guess", "needs " + std::to_string(n) + " values for the " + cmd.system + " (got " +
                                        std::to_string(cmd.guess.size()) + ")");
    }
    options.initial_multiplier = Eigen::Map<const Eigen::VectorXd>(cmd.guess.data(), n);
  } else {
    options.initial_multiplier = pendulum ? Eigen::VectorXd::Ones(n) : Eigen::VectorXd::Zero(n);
  }
  if (pendulum) {
    return solve_and_write<ocp::PendulumModel>(Pendulum3D::paper(), problem, options, paper_values().pendulum, cmd,
                                               command_line, out, err);
  }
  DumbbellSpacecraft dumbbell = DumbbellSpacecraft::paper();
  if (cmd.sphere_radius != 0.0) {
    try {
      dumbbell = DumbbellSpacecraft(dumbbell.mass, dumbbell.mu, dumbbell.rho, cmd.sphere_radius);
    } catch (const InvalidInput& e) {
      throw InvalidInput("--sphere-radius", e.what());
    }
  }
  return solve_and_write<ocp::DumbbellModel>(dumbbell, problem, options, paper_values().dumbbell, cmd, command_line, out, err);
}

}  // namespace lgvi::experiments
