#include "experiments/ocp/ocp_command.hpp"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <ostream>
#include <sstream>

#include "experiments/output/atomic_file.hpp"
#include "experiments/output/csv_writer.hpp"
#include "experiments/output/fields.hpp"
#include "experiments/output/json_writer.hpp"
#include "experiments/ocp/ocp_output.hpp"
#include "experiments/scene/ocp_scene.hpp"
#include "experiments/input/paper_values.hpp"
#include "experiments/methods/simulate.hpp"
#include "experiments/systems/systems.hpp"
#include "experiments/systems/ocp.hpp"
#include "lgvi/ocp/collocation.hpp"
#include "lgvi/ocp/indirect.hpp"

namespace lgvi::experiments {

namespace fs = std::filesystem;

namespace {

using ocp_output::join;
using ocp_output::values;

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

/// t, the state, the controls and the multipliers at each step (the binding B names the columns).
template <class B, class Model = typename B::IndirectModel>
void write_trajectory(const fs::path& file, const ocp::ShootingResult<Model>& result,
                      const ocp::StateMultiplierFlow<Model>& flow, const Fields& metadata) {
  std::vector<std::string> cols = {"t"};
  B::state_columns(cols);
  B::control_columns(cols);
  B::multiplier_columns(cols);
  CsvWriter csv(file, cols);
  const auto& sw = result.sweep;
  std::vector<double> row;
  for (std::size_t k = 0; k < sw.states.size(); ++k) {
    const auto& s = sw.states[k];
    row.clear();
    row.push_back(static_cast<double>(k) * flow.h());
    B::state_row(row, flow.lgvi(), s);
    const typename Model::VecU u = k < sw.controls.size() ? sw.controls[k] : Model::VecU::Zero();
    for (int i = 0; i < Model::nu; ++i) row.push_back(u(i));
    const typename Model::VecS l = k < sw.multipliers.size() ? sw.multipliers[k] : Model::VecS::Zero();
    for (int i = 0; i < 2 * Model::nq; ++i) row.push_back(l(i));
    csv.write_row(row);
  }
  csv.commit(metadata);
}

template <class B, class Model = typename B::IndirectModel>
int solve_and_write(const typename Model::System& system, const ocp::TransferProblem& problem,
                    const ocp::ShootingOptions& options, const ocp_output::Run& run, const OcpCommand& cmd,
                    const std::string& command_line, std::ostream& out, std::ostream& err) {
  const ocp::ShootingResult<Model> result = ocp::solve_indirect(system, problem, options);
  const ocp::ShootingSummary& S = result.summary;
  if (S.status == ocp::ShootingStatus::InvalidInput) return ocp_output::invalid_input(cmd, S.message, err);
  const ocp_output::Files files = ocp_output::create_files(cmd, run.label);
  const fs::path& history = files.history;
  const fs::path& trajectory = files.trajectory;

  // Violation by parts (the norm is the 2-norm of all of them, see lgvi/ocp/indirect.hpp).
  const Eigen::VectorXd& r = S.residual;
  Fields f = {
      {"system", run.system},
      {"method", std::string("indirect shooting (Newton-Armijo on lambda_0)")},
      {"form", std::string(to_string(options.form))},
      {"h", options.h},
      {"steps", static_cast<std::int64_t>(S.steps)},
      {"t_final", problem.t_final},
      {"W", ocp_output::weight_text(options.W)},
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
      {"violation_norm", std::string(B::violation_norm)},
  };
  ocp_output::add_violation_parts<B>(f, r, S.violation);
  // The replayed yardstick of the final sweep's controls (the whole sweep only).
  const bool complete = result.sweep.controls.size() == S.steps + 1;
  ocp_output::add_replay_fields(f, system, problem,
                                complete ? ocp_output::control_columns(result.sweep.controls) : Eigen::MatrixXd(),
                                options.h, options.form, options.W);
  // The cost by the control's parts (W = I; with another W the split of u^T W u is not defined
  // and the parts are left out).
  if (ocp_output::weight_text(options.W) == "identity") {
    B::cost_parts(options.form, options.h, S.steps, result.sweep.controls, f);
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
  };
  f.insert(f.end(), rest.begin(), rest.end());
  if (run.paper != nullptr) {
    f.push_back({"paper_cost", run.paper->cost});
    f.push_back({"paper_violation", run.paper->terminal_violation});
    f.push_back({"paper_iterations", static_cast<std::int64_t>(run.paper->outer_iterations_approx.value_or(0.0))});
  }
  const Fields files_fields = {
      {"history_csv", history.filename().string()},
      {"trajectory_csv", trajectory.filename().string()},
      {"git_describe", std::string(git_describe())},
      {"command_line", command_line},
  };
  f.insert(f.end(), files_fields.begin(), files_fields.end());
  f.push_back({"run_id", files.run_id});

  write_history(history, S, f);
  if (!result.sweep.states.empty()) {
    const ocp::StateMultiplierFlow<Model> flow(system, problem, options.form, options.h, options.W, options.rotation);
    write_trajectory<B>(trajectory, result, flow, f);
  }
  // One object; the vectors as arrays of numbers (their text form stays in the CSVs' metadata).
  write_json_object(files.summary, f,
                    {{"W", ocp_output::weight_values(options.W, B::nu)},
                     {"inertia_diagonal", values(system.inertia.J.diagonal())},
                     {"multiplier_guess", values(S.multiplier_guess)},
                     {"multiplier", values(S.multiplier)}});
  return ocp_output::finish(cmd, S, files, {history, trajectory, files.summary}, out, err);
}

}  // namespace

namespace {

/// An integer option may be written as a number with an exponent ("1e8"): the text of an
/// integral value is rewritten as the integer, so that its range is what the error names
/// ("--steps: must be an integer in [1, 1000000] (got 100000000)"), not CLI11's conversion.
CLI::Validator integer_text() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        char* end = nullptr;
        const double x = std::strtod(text.c_str(), &end);
        if (!text.empty() && end == text.c_str() + text.size() && std::isfinite(x) && x == std::floor(x) &&
            std::abs(x) < 9e18) {
          text = std::to_string(static_cast<long long>(x));
        }
        return "";
      },
      "INT");
}

}  // namespace

CLI::App* add_ocp_command(CLI::App& app, OcpCommand& o) {
  CLI::App* cmd = app.add_subcommand(
      "ocp", "Discrete optimal control of a scene's [ocp] problem: indirect (sec. 3.1, 3.2; Newton-Armijo shooting on "
             "the initial multiplier) or direct (sec. 4.1, 4.2; spline knots by SLSQP); writes the iteration history, "
             "the trajectory and a JSON summary");
  cmd->add_option("SCENE", o.system,
                  "A scene file with an [ocp] table (experiments/scenes/README.md), or a name: the paper's examples "
                  "dumbbell (sec. 3.1), pendulum (sec. 3.2), cart-pendulum (sec. 4.1), connected-bodies (sec. 4.2) "
                  "run experiments/scenes/ocp-NAME.toml")
      ->required();
  cmd->add_option("--form", o.form, "LGVI form: printed | symmetric (default: the scene's [integration] form)");
  // Every option given is checked against its stated range by run_ocp_command (which Python's
  // solve_ocp runs too), not here: the ranges are the [ocp] table's (the options structs',
  // lgvi/ocp), an error names the option. A 0 is a value like any other (it used to mean "the
  // scene's" silently).
  cmd->add_option("--h", o.h, "Time step, in (0, 1e100] (the horizon must be a whole number of steps, at most "
                              "1000000; default: the scene's)");
  cmd->add_option("--steps", o.steps, "Number of steps (instead of --h), in [1, 1000000]")
      ->transform(integer_text());
  cmd->add_flag("--no-decomposition", o.no_decomposition,
                "Indirect: invert the full (rank-deficient) sensitivity instead of its shape block");
  cmd->add_option("--merit", o.merit, "Indirect: line-search merit, velocity | momentum");
  cmd->add_option("--globalization", o.globalization,
                  "Indirect method: newton-armijo (the paper's) | levenberg-marquardt | homotopy "
                  "(Newton homotopy path following, then Newton-Armijo) | continuation (the same path, Hermite "
                  "predictor, Broyden corrector, Jacobians at path points only, then Newton-Armijo)");
  cmd->add_option("--lm-damping", o.lm_damping,
                  "Levenberg-Marquardt: initial damping mu_0 (relative to diag(J^T J)), in " +
                      ocp::ShootingOptions::kLmInitialDamping.text());
  cmd->add_option("--nonmonotone-memory", o.nonmonotone_memory,
                  "Newton-Armijo / homotopy end game: Armijo test against the largest merit of the last M "
                  "accepted points (1: monotone), in " + ocp::ShootingOptions::kNonmonotoneMemory.text())
      ->transform(integer_text());
  cmd->add_option("--guess", o.guess,
                  "Indirect: initial multiplier lambda_0, comma-separated (2 n_q values: 6 pendulum and free body, "
                  "12 dumbbell; each 0 or of magnitude in [1e-100, 1e100])")
      ->delimiter(',');
  cmd->add_option("--weight", o.weight,
                  "Replaces the scene's [ocp] W: n_u values (the diagonal) or n_u^2 (the matrix row by row), "
                  "comma-separated; symmetric positive definite (n_u: 3 pendulum and free body, 6 dumbbell, 2 cart-pendulum, 3 connected bodies)")
      ->delimiter(',');
  cmd->add_option("--max-iterations", o.max_iterations,
                  "Indirect: outer Newton iterations, in " + ocp::ShootingOptions::kMaxIterations.text() +
                      "; direct: SLSQP evaluations (IPOPT iterations) per start, in " +
                      ocp::DirectOptions::kMaxEvaluations.text())
      ->transform(integer_text());
  cmd->add_option("--t-final", o.t_final, "Horizon, in (0, 1e100] (default: the scene's; the step stays the scene's h)");
  cmd->add_option("--sphere-radius", o.sphere_radius,
                  "Dumbbell: radius of the two spheres, in (0, 1e100] (sets the rod-axis inertia; default: the scene's)");
  cmd->add_option("--out", o.out, "Output directory")->capture_default_str();
  cmd->add_option("--knots", o.knots,
                  "Direct method: spline knots per control component, in " + ocp::DirectOptions::kKnots.text() +
                      " (at most the grid's nodes)")
      ->transform(integer_text());
  cmd->add_option("--spline", o.spline, "Direct method: spline end condition, not-a-knot | natural");
  cmd->add_option("--gradients", o.gradients, "Direct method: exact | finite-difference");
  cmd->add_option("--tolerance", o.tolerance,
                  "Direct method: bound on the terminal violation, in " + ocp::DirectOptions::kTolerance.text());
  cmd->add_option("--starts", o.starts,
                  "Direct method: SLSQP starts (the default guess, then seeded random knots), in " +
                      ocp::DirectOptions::kStarts.text())
      ->transform(integer_text());
  cmd->add_option("--solver", o.solver,
                  "Direct method: slsqp (the paper's single shooting) | ipopt (multiple shooting) | ddp (iLQR on free "
                  "node controls, augmented Lagrangian); any scene: collocation (Hermite-Simpson on the continuous "
                  "quaternion model, IPOPT; every system with an optimal control problem)");
  cmd->add_option("--intervals", o.intervals,
                  "--solver collocation: mesh intervals, in " + ocp::CollocationOptions::kIntervals.text() +
                      " (default 100)")
      ->transform(integer_text());
  cmd->add_option("--hessian", o.hessian,
                  "--solver ipopt and collocation: limited-memory (L-BFGS; ipopt's default) | cost (the cost's exact "
                  "Hessian, constraint curvature left out) | exact (Hessian of the Lagrangian: ipopt by forward "
                  "differences of its exact gradient, columns grouped by colour; collocation's default, by central "
                  "differences of the rate's exact Jacobian at each collocation point)");
  cmd->add_option("--state-guess", o.state_guess,
                  "Direct method, --solver ipopt: initial states, geodesic (between the boundary states) | "
                  "simulated (the guess control's run)");
  cmd->add_option("--shooting-interval", o.shooting_interval,
                  "Direct method, --solver ipopt: LGVI steps per shooting segment (1: every state a variable; "
                  "default 40), in " + ocp::DirectOptions::kShootingInterval.text())
      ->transform(integer_text());
  cmd->add_option("--seed", o.seed, "Direct method: seed of the random starts, in " + ocp::DirectOptions::kSeed.text())
      ->transform(integer_text());
  cmd->add_option("--first-start", o.first_start,
                  "Direct method: number of the first start run (0 = the default guess; K > 0 the K-th "
                  "seeded random start), so one start of a multistart can be rerun alone; in " +
                      ocp::DirectOptions::kFirstStart.text())
      ->transform(integer_text())
      ->capture_default_str();
  return cmd;
}

bool is_direct_system(const std::string& name_or_path) {
  const Scene scene = load_scene(resolve_ocp_scene(name_or_path, default_scenes_dir()));
  return scene.ocp && scene.ocp->method == OcpMethod::Direct;
}

fs::path ocp_output_file(const fs::path& dir, const std::string& label, const std::string& what) {
  // Appends only: GCC 12 warns falsely (-Wrestrict) on "literal" + std::string.
  std::string name = "ocp-";
  name.append(label).append("-").append(what);
  return dir / name;
}

namespace {

/// An option of the other method is an error, not silently ignored.
void check_method_options(const OcpCommand& cmd, OcpMethod method) {
  const std::string scene_text = " (the scene's ocp.method is '" + std::string(to_string(method)) + "')";
  if (method == OcpMethod::Indirect) {
    const std::pair<const char*, bool> direct_only[] = {
        {"--knots", cmd.knots.has_value()},        {"--spline", cmd.spline.has_value()},
        {"--gradients", cmd.gradients.has_value()}, {"--tolerance", cmd.tolerance.has_value()},
        {"--starts", cmd.starts.has_value()},      {"--solver", cmd.solver.has_value()},
        {"--hessian", cmd.hessian.has_value()},    {"--state-guess", cmd.state_guess.has_value()},
        {"--shooting-interval", cmd.shooting_interval.has_value()}, {"--seed", cmd.seed.has_value()},
        {"--first-start", cmd.first_start != 0}};
    for (const auto& [name, given] : direct_only) {
      if (given) throw InvalidInput(name, "applies to the direct method only, not to " + cmd.system + scene_text);
    }
  } else {
    const std::pair<const char*, bool> indirect_only[] = {
        {"--no-decomposition", cmd.no_decomposition}, {"--merit", cmd.merit.has_value()},
        {"--globalization", cmd.globalization.has_value()}, {"--lm-damping", cmd.lm_damping.has_value()},
        {"--nonmonotone-memory", cmd.nonmonotone_memory.has_value()}, {"--guess", !cmd.guess.empty()}};
    for (const auto& [name, given] : indirect_only) {
      if (given) throw InvalidInput(name, "applies to the indirect method only, not to " + cmd.system + scene_text);
    }
  }
}

/// The indirect method on the scene's problem, with the command's replacements.
template <class M>
int run_indirect(const Scene& scene, const M& m, const OcpCommand& cmd, const std::string& command_line,
                 std::ostream& out, std::ostream& err) {
  using B = OcpBinding<M>;
  if constexpr (!B::indirect) {
    throw InvalidInput("ocp.method", std::string("the ") + M::name + " has no indirect method");
  } else {
    const OcpDefinition& d = *scene.ocp;
    ocp::ShootingOptions options = d.indirect;
    options.form = scene.form;
    options.h = scene.horizon.h;
    if (cmd.merit) {
      try {
        options.merit = ocp::parse_merit(*cmd.merit);
      } catch (const InvalidInput&) {
        throw InvalidInput("--merit", "must be 'velocity' or 'momentum' (got '" + *cmd.merit + "')");
      }
    }
    using O = ocp::ShootingOptions;
    if (cmd.no_decomposition) options.decomposition = false;
    if (cmd.globalization) {
      try {
        options.globalization = ocp::parse_globalization(*cmd.globalization);
      } catch (const InvalidInput&) {
        throw InvalidInput("--globalization", "must be 'newton-armijo', 'levenberg-marquardt', 'homotopy' or 'continuation' (got '" +
                                                  *cmd.globalization + "')");
      }
    }
    if (cmd.lm_damping) {
      options.lm_initial_damping = ocp_output::option_number(*cmd.lm_damping, O::kLmInitialDamping, "--lm-damping");
    }
    if (cmd.nonmonotone_memory) {
      options.nonmonotone_memory =
          ocp_output::option_int(*cmd.nonmonotone_memory, O::kNonmonotoneMemory, "--nonmonotone-memory");
    }
    if (cmd.max_iterations) {
      options.max_iterations = ocp_output::option_int(*cmd.max_iterations, O::kMaxIterations, "--max-iterations");
    }
    const int n = 2 * B::IndirectModel::nq;
    if (!cmd.guess.empty()) {
      if (static_cast<int>(cmd.guess.size()) != n) {
        throw InvalidInput("--guess", "needs " + std::to_string(n) + " values for the " + scene.system() + " (got " +
                                          std::to_string(cmd.guess.size()) + ")");
      }
      for (const double x : cmd.guess) require_admissible(x, "--guess");
      options.initial_multiplier = Eigen::Map<const Eigen::VectorXd>(cmd.guess.data(), n);
    }
    ocp_output::validate_options(options, scene, "indirect");
    const ocp::TransferProblem problem =
        B::transfer(m, std::get<typename M::State>(d.target), scene.horizon.t_final);
    const auto system = ocp_output::with_sphere_radius(B::system(m), cmd.sphere_radius);
    return solve_and_write<B>(system, problem, options, ocp_output::Run::of(scene), cmd,
                                                      command_line, out, err);
  }
}

}  // namespace

int run_ocp_command(const OcpCommand& cmd, const std::string& command_line, std::ostream& out, std::ostream& err) {
  const fs::path file = cmd.scene ? cmd.scene->file : resolve_ocp_scene(cmd.system, default_scenes_dir());
  const auto load = [&](const SceneOverrides& overrides) {
    return cmd.scene ? parse_scene(*cmd.scene->text, cmd.scene->file, overrides) : load_scene(file, overrides);
  };
  ocp_output::check_step_options(cmd);
  SceneOverrides overrides;
  if (cmd.form) overrides.form = ocp_output::parse_form(cmd);
  overrides.t_final = cmd.t_final;
  overrides.h = cmd.h;
  // With --steps and --t-final the step is known at once (the scene's h over the new horizon
  // may be more steps than an [ocp] scene takes); with --steps alone, from the scene's horizon.
  if (cmd.steps && cmd.t_final) overrides.h = *cmd.t_final / static_cast<double>(*cmd.steps);
  Scene scene = load(overrides);
  if (cmd.steps && !cmd.t_final) {
    overrides.h = scene.horizon.t_final / static_cast<double>(*cmd.steps);
    scene = load(overrides);
  }
  if (!scene.ocp) {
    throw SceneError(file.string(), "ocp",
                     "is required (the optimal control problem: an [ocp] table, experiments/scenes/README.md)");
  }
  if (!cmd.weight.empty()) {
    auto replaced = std::make_shared<OcpDefinition>(*scene.ocp);
    const int nu = visit_binding(scene.model, [](auto, const auto& m) {
      return OcpBinding<std::decay_t<decltype(m)>>::nu;
    });
    const Eigen::MatrixXd W = weight_matrix(cmd.weight, nu, "--weight");
    replaced->indirect.W = W;
    replaced->direct.W = W;
    scene.ocp = std::move(replaced);
  }
  if (cmd.solver && *cmd.solver == "collocation") return ocp_output::run_collocation(scene, cmd, command_line, out, err);
  if (cmd.intervals) throw InvalidInput("--intervals", "applies to --solver collocation only");
  check_method_options(cmd, scene.ocp->method);
  return visit_binding(scene.model, [&](auto, const auto& m) {
    return scene.ocp->method == OcpMethod::Indirect ? run_indirect(scene, m, cmd, command_line, out, err)
                                                    : ocp_output::run_direct(scene, cmd, command_line, out, err);
  });
}

}  // namespace lgvi::experiments
