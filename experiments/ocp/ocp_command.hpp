// `lgvi-testbed ocp FILE.toml|NAME`: the optimal control problem of a scene's [ocp] table
// (experiments/scene/ocp_scene.hpp), by the indirect discrete optimal control of sections 3.1 and 3.2
// (lgvi/ocp/indirect.hpp) or the direct method of sections 4.1 and 4.2 (lgvi/ocp/direct.hpp).
// The paper's four examples are the shipped scenes experiments/scenes/ocp-{dumbbell, pendulum,
// cart-pendulum, connected-bodies}.toml (`ocp pendulum`). Writes, atomically, into --out DIR
// (SYSTEM: the scene's label, ocp_label):
//   ocp-SYSTEM-history.csv     one row per outer Newton-Armijo iteration
//   ocp-SYSTEM-trajectory.csv  t, state, controls, multipliers at every node
//   ocp-SYSTEM-summary.json    cost, violation, iterations, condition numbers, wall time, status
// Every file carries the run's `run_id`; the summary is written last (verify_ocp_run).
#pragma once

#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace lgvi::experiments {

/// The options of the `ocp` subcommand, filled by CLI11 (and by Python's solve_ocp). The problem
/// is a scene file with an [ocp] table (experiments/scene/ocp_scene.hpp); an option given here
/// replaces the scene's value, an unset one leaves it. Every value given is checked by
/// run_ocp_command against its stated range, the one the [ocp] table's key has (the options
/// structs' Ranges, lgvi/ocp/indirect.hpp and direct.hpp), an error naming the option and the
/// range: `--max-iterations: must be an integer in [1, 1000000] (got 0)`.
struct OcpCommand {
  /// A scene with an [ocp] table: a path, a name NAME of experiments/scenes/ocp-NAME.toml (the
  /// paper's examples: "dumbbell", "pendulum", "cart-pendulum", "connected-bodies"), or a scene
  /// name (resolve_ocp_scene).
  std::string system;
  /// A scene made in memory (Python) in place of `system`'s file; `system` then only names it in
  /// messages. Parsed again from its text with the overrides below.
  std::shared_ptr<const Scene> scene;
  /// Replaces [ocp] W: n_u values (the diagonal) or n_u^2 (the matrix row by row), checked as the
  /// file's W (symmetric positive definite); empty: the scene's.
  std::vector<double> weight;
  std::optional<std::string> form;  ///< replaces [integration] form
  std::optional<double> h;          ///< replaces [integration] h; (0, 1e100]
  std::optional<long long> steps;   ///< instead of h: h = t_final / steps; [1, 10^6] (kOcpSteps)
  bool no_decomposition = false;
  std::optional<std::string> merit;
  std::optional<std::string> globalization;  ///< indirect: "newton-armijo", "levenberg-marquardt", "homotopy", "continuation"
  std::optional<double> lm_damping;          ///< indirect, levenberg-marquardt: initial damping mu_0
  std::optional<long long> nonmonotone_memory;  ///< indirect: Armijo test against the max merit of this many points
  std::vector<double> guess;  ///< lambda_0; empty: the scene's
  std::optional<long long> max_iterations;  ///< indirect max_iterations, direct max_evaluations
  std::optional<double> t_final;            ///< replaces [integration] t_final; (0, 1e100]
  std::optional<double> sphere_radius;      ///< dumbbell only
  std::string out = "results/ocp";
  // Direct method (experiments/ocp/ocp_direct_command.cpp).
  std::optional<long long> knots;         ///< per control component
  std::optional<std::string> spline;      ///< "not-a-knot" or "natural"
  std::optional<std::string> gradients;   ///< "exact" or "finite-difference"
  std::optional<double> tolerance;        ///< on the terminal violation
  std::optional<long long> starts;        ///< multistart
  std::optional<long long> seed;          ///< of the random starts
  long long first_start = 0;              ///< run starts first_start .. first_start + starts - 1 (0: the default guess first)
  std::optional<std::string> solver;      ///< "slsqp", "ipopt" (multiple shooting) or "ddp" (lgvi/ocp/README.md)
  std::optional<std::string> hessian;     ///< ipopt: "limited-memory", "cost" or "exact"
  std::optional<std::string> state_guess; ///< ipopt: "geodesic" or "simulated" (initial shooting states)
  std::optional<long long> shooting_interval;  ///< ipopt: steps per shooting segment
  std::optional<long long> intervals;     ///< collocation: mesh intervals (lgvi/ocp/collocation.hpp)
};

/// Registers the `ocp` subcommand on `app`, binding its options to `options` (which must outlive
/// parsing). Returns the subcommand, whose parsed() says whether it was chosen.
CLI::App* add_ocp_command(CLI::App& app, OcpCommand& options);

/// True when the scene `ocp NAME` runs (a path or a name, resolve_ocp_scene) is solved by the
/// direct method (its [ocp] method). Throws SceneError for a missing or bad scene.
bool is_direct_system(const std::string& name_or_path);

/// The file `ocp NAME --out dir` writes for `what` ("history.csv", "trajectory.csv",
/// "summary.json"; the direct method also "knots.csv"): dir/ocp-LABEL-what, LABEL the scene's
/// name without a leading "ocp-" (ocp_label: `ocp pendulum` writes ocp-pendulum-*).
std::filesystem::path ocp_output_file(const std::filesystem::path& dir, const std::string& label,
                                      const std::string& what);

/// Checks that the ocp-SYSTEM-* files in `dir` are those of one complete run: the summary (written
/// last) exists and each CSV present carries the summary's run_id. Throws OutputError naming the
/// file and both runs otherwise (a run killed between its files; experiments/ocp/ocp_run_files.cpp).
void verify_ocp_run(const std::filesystem::path& dir, const std::string& system);

/// Runs it: solves, writes the three files, prints the summary line to `out`. Returns the exit
/// status: 0 converged, 2 not converged (files written; the status says why), 1 bad input
/// (one "error:" line on `err`). Throws OutputError when files cannot be written.
int run_ocp_command(const OcpCommand& options, const std::string& command_line, std::ostream& out,
                    std::ostream& err);


}  // namespace lgvi::experiments
