// `lgvi-testbed ocp dumbbell|pendulum`: the indirect discrete optimal control of sections 3.1
// and 3.2 (lgvi/ocp/indirect.hpp); `ocp cart-pendulum|connected-bodies`: the direct method of
// sections 4.1 and 4.2 (lgvi/ocp/direct.hpp). Writes, atomically, into --out DIR:
//   ocp-SYSTEM-history.csv     one row per outer Newton-Armijo iteration
//   ocp-SYSTEM-trajectory.csv  t, state, controls, multipliers at every node
//   ocp-SYSTEM-summary.json    cost, violation, iterations, condition numbers, wall time, status
// Every file carries the run's `run_id`; the summary is written last (verify_ocp_run).
#pragma once

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

namespace CLI {
class App;
class Validator;
}

namespace lgvi::experiments {

/// The options of the `ocp` subcommand, filled by CLI11.
struct OcpCommand {
  std::string system;       ///< "dumbbell", "pendulum", "cart-pendulum" or "connected-bodies"
  std::string form = "printed";
  double h = 0.0;           ///< 0: the default step (see ocp_command.cpp)
  long long steps = 0;      ///< alternative to h: t_final / steps
  bool no_decomposition = false;
  std::string merit = "velocity";
  std::string globalization = "newton-armijo";  ///< indirect: or "levenberg-marquardt", "homotopy", "continuation"
  double lm_damping = 1e-3;          ///< indirect, levenberg-marquardt: initial damping mu_0
  int nonmonotone_memory = 1;        ///< indirect: Armijo test against the max merit of this many points
  std::vector<double> guess;  ///< lambda_0; empty: the documented default
  int max_iterations = 0;      ///< 0: the method's default (indirect 300, direct 3000)
  double t_final = 0.0;        ///< 0: the paper's horizon
  double sphere_radius = 0.0;  ///< dumbbell only; 0: DumbbellSpacecraft::paper()'s 0.05
  std::string out = "results/ocp";
  // Direct method (cart-pendulum, connected-bodies; experiments/ocp_direct_command.cpp).
  int knots = 7;                        ///< per control component
  std::string spline = "not-a-knot";    ///< or "natural"
  std::string gradients = "exact";      ///< or "finite-difference"
  double tolerance = 1e-10;             ///< on the terminal violation
  int starts = 0;                       ///< multistart; 0: the system's default (README)
  long long seed = 1;                   ///< of the random starts
  int first_start = 0;                  ///< run starts first_start .. first_start + starts - 1
  std::string solver = "slsqp";         ///< or "ipopt" (multiple shooting; lgvi/ocp/README.md)
  std::string hessian = "limited-memory";  ///< ipopt: or "cost", "exact"
  std::string state_guess = "geodesic";  ///< ipopt: or "simulated" (initial shooting states)
  int shooting_interval = 0;            ///< ipopt: steps per shooting segment; 0: the default (40)
};

/// An option check: the value is a number in [lo, hi] (finite), else "must be a number in RANGE
/// (got TEXT)" with `range` as the text of the range ("(0, 1e6]"). For CLI11's check().
CLI::Validator number_in(double lo, double hi, bool lo_open, const std::string& range);

/// Registers the `ocp` subcommand on `app`, binding its options to `options` (which must outlive
/// parsing). Returns the subcommand, whose parsed() says whether it was chosen.
CLI::App* add_ocp_command(CLI::App& app, OcpCommand& options);

/// True for the systems the direct method solves (cart-pendulum, connected-bodies); the others
/// (pendulum, dumbbell) are solved by indirect shooting.
bool is_direct_system(const std::string& system);

/// The file `ocp SYSTEM --out dir` writes for `what` ("history.csv", "trajectory.csv",
/// "summary.json"; the direct method also "knots.csv"): dir/ocp-SYSTEM-what.
std::filesystem::path ocp_output_file(const std::filesystem::path& dir, const std::string& system,
                                      const std::string& what);

/// Checks that the ocp-SYSTEM-* files in `dir` are those of one complete run: the summary (written
/// last) exists and each CSV present carries the summary's run_id. Throws OutputError naming the
/// file and both runs otherwise (a run killed between its files; experiments/ocp_run_files.cpp).
void verify_ocp_run(const std::filesystem::path& dir, const std::string& system);

/// Runs it: solves, writes the three files, prints the summary line to `out`. Returns the exit
/// status: 0 converged, 2 not converged (files written; the status says why), 1 bad input
/// (one "error:" line on `err`). Throws OutputError when files cannot be written.
int run_ocp_command(const OcpCommand& options, const std::string& command_line, std::ostream& out,
                    std::ostream& err);

/// The direct method's part of run_ocp_command (systems cart-pendulum and connected-bodies): SLSQP
/// on spline knots. Same files, exit statuses and errors.
int run_ocp_direct_command(const OcpCommand& options, const std::string& command_line, std::ostream& out,
                           std::ostream& err);

}  // namespace lgvi::experiments
