// What the two `ocp` commands share (experiments/ocp/ocp_command.cpp, the indirect method;
// experiments/ocp/ocp_direct_command.cpp, the direct method): the validation of the options both read,
// the output directory and the ocp-SYSTEM-* file names in it, the summary's vector fields, and the
// lines printed at the end with the exit status. Internal to those two files, not part of the CLI's
// interface (experiments/ocp/ocp_command.hpp).
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <vector>
#include <optional>
#include <ostream>
#include <string>
#include <system_error>
#include <utility>

#include "baselines/ocp_replay.hpp"
#include "experiments/output/atomic_file.hpp"
#include "experiments/output/fields.hpp"
#include "experiments/ocp/ocp_command.hpp"
#include "experiments/scene/ocp_scene.hpp"
#include "experiments/input/paper_values.hpp"
#include "lgvi/lgvi.hpp"
#include "lgvi/ocp/direct.hpp"
#include "lgvi/systems/dumbbell.hpp"

namespace lgvi::experiments::ocp_output {

/// v's entries in shortest round-trip form, separated by single spaces (a summary field).
inline std::string join(const Eigen::VectorXd& v) {
  std::string s;
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    if (i > 0) s += ' ';
    s += shortest(v(i));
  }
  return s;
}

/// v's entries as a JSON array of the summary (write_json_object).
inline std::vector<double> values(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

/// A new run id: time (ns since the epoch, hex), process id and 32 random bits. Every file of a
/// run carries it (`run_id`), so that a reader can tell one run's files (verify_ocp_run).
std::string new_run_id();
/// --form (given): "printed" or "symmetric". Throws InvalidInput naming --form.
inline LgviForm parse_form(const OcpCommand& cmd) {
  try {
    return parse_lgvi_form(cmd.form.value_or(""));
  } catch (const InvalidInput&) {
    throw InvalidInput("--form", "must be 'symmetric' or 'printed' (got '" + cmd.form.value_or("") + "')");
  }
}

/// What a run's files are named by and compared with: the scene's label (ocp_label), its system
/// and the paper's example named by its ocp.paper (null: none).
struct Run {
  std::string label;
  std::string system;
  const PaperExample* paper = nullptr;
  static Run of(const Scene& scene) {
    return {ocp_label(scene), scene.system(),
            scene.ocp->paper.empty() ? nullptr : paper_values().find(scene.ocp->paper)};
  }
};

/// The summary's "W": "identity" when W is empty or the identity, else its entries row by row.
inline std::string weight_text(const Eigen::MatrixXd& W) {
  if (W.size() == 0 || W.isIdentity(0.0)) return "identity";
  const Eigen::MatrixXd Wt = W.transpose();  // row by row
  return join(Eigen::Map<const Eigen::VectorXd>(Wt.data(), Wt.size()));
}

/// The summary JSON's "W": its n x n entries row by row (the identity's when W is empty).
inline std::vector<double> weight_values(const Eigen::MatrixXd& W, int n) {
  const Eigen::MatrixXd full = W.size() == 0 ? Eigen::MatrixXd::Identity(n, n) : W;
  const Eigen::MatrixXd Wt = full.transpose();  // row by row
  return {Wt.data(), Wt.data() + Wt.size()};
}

/// The range of --h, --t-final and --sphere-radius: a positive number, at most the scene files'
/// largest magnitude (lgvi/range.hpp); a horizon or step the scene cannot take is then the scene's
/// error (integration.h (--h): ...).
inline constexpr Range kPositiveOption = Range::above(0, kMaxMagnitude);

/// A given integer option checked against `range` (the options struct's, which the [ocp] table's
/// key is read against): its value as an int. Throws InvalidInput naming the option,
/// "--starts: must be an integer in [1, 10000] (got 0)".
inline int option_int(long long value, const Range& range, const char* option) {
  range.require(static_cast<double>(value), option);
  return static_cast<int>(value);
}
/// A given number option checked against `range`.
inline double option_number(double value, const Range& range, const char* option) {
  range.require(value, option);
  return value;
}
/// --hessian's value (ipopt and collocation). Throws InvalidInput naming the option.
inline ocp::IpoptHessian option_hessian(const std::string& value) {
  try {
    return ocp::parse_ipopt_hessian(value);
  } catch (const InvalidInput&) {
    throw InvalidInput("--hessian", "must be 'limited-memory', 'cost' or 'exact' (got '" + value + "')");
  }
}

/// The options struct's own check after the command's values replaced the scene's
/// (ShootingOptions::validate, DirectOptions::validate; each given option was checked against the
/// same range when it was read): a failure names the scene file and the [ocp] table's key.
template <class Options>
void validate_options(const Options& options, const Scene& scene, const std::string& table) {
  try {
    options.validate();
  } catch (const InvalidInput& e) {
    const std::string what = e.what();
    throw SceneError(scene.file.string(), "ocp." + table + "." + e.field(),
                     what.substr(std::min(what.size(), e.field().size() + 2)));
  }
}

/// --sphere-radius: the dumbbell with the spheres' radius r (unset: unchanged). Throws
/// InvalidInput naming --sphere-radius for a bad radius: outside kPositiveOption, or one that
/// gives no valid inertia.
inline DumbbellSpacecraft with_sphere_radius(const DumbbellSpacecraft& d, const std::optional<double>& r) {
  if (!r) return d;
  kPositiveOption.require(*r, "--sphere-radius");
  try {
    return DumbbellSpacecraft(d.mass, d.mu, d.rho, *r);
  } catch (const InvalidInput& e) {
    throw InvalidInput("--sphere-radius", e.what());
  }
}
/// Any other system has no sphere radius: r must not be given.
template <class System>
const System& with_sphere_radius(const System& s, const std::optional<double>& r) {
  if (r) throw InvalidInput("--sphere-radius", "applies to scenes with a sphere radius (the dumbbell's) only");
  return s;
}

/// The terminal violation's parts (OcpBinding<M>::violation_parts: name, offset, size), each the
/// norm of its segment of the residual r; with no residual (r empty: no sweep completed), the
/// parts take `without_residual` when given (the indirect summary's whole violation), else none.
template <class B>
void add_violation_parts(Fields& f, const Eigen::VectorXd& r, std::optional<double> without_residual = std::nullopt) {
  if (r.size() == 0 && !without_residual) return;
  for (const auto& p : B::violation_parts) {
    f.push_back({p.name, r.size() > 0 ? r.segment(p.offset, p.size).norm() : *without_residual});
  }
}

/// The replayed yardstick of a solved answer (baselines/ocp_replay.hpp): its node controls u
/// (n_u x (N + 1), column j at t_j = j h) replayed on the quaternion model by gsl-rk8pd at
/// rtol = atol = 1e-13, interpreted as the form's kicks apply them, appended as the summary's
/// replay (what was run), replay_interpolation, replayed_cost, replayed_violation (the norm of
/// violation_norm), replayed_quaternion_drift, replay_seconds, replay_cpu_seconds (the calling thread's) and replay_status ("ok" or why not;
/// then those numbers are left out, never NaN). u empty (no run of the method completed): not replayed.
template <class System, class Problem>
void add_replay_fields(Fields& f, const System& system, const Problem& problem, const Eigen::MatrixXd& u, double h,
                       LgviForm form, const Eigen::MatrixXd& W) {
  const baselines::ReplayOptions options;
  baselines::ReplayControls c;
  c.u = u;
  c.h = h;
  c.interpolation = baselines::replay_interpolation(form);
  c.W = W;
  baselines::ReplayResult r;
  std::string status;
  if (u.cols() < 2) {
    status = "not replayed: no control history";
  } else {
    try {
      r = baselines::replay(system, problem, c, options);
      status = r.ok ? "ok" : r.message;
    } catch (const InvalidInput& e) {
      status = std::string("not replayed: ") + e.what();
    }
  }
  const bool ok = r.ok;
  const Fields replay = {
      {"replay", options.method + ", rtol = atol = " + shortest(options.rtol) + ", quaternion model, controls " +
                     baselines::to_string(c.interpolation) + " between the nodes"},
      {"replay_interpolation", std::string(baselines::to_string(c.interpolation))},
      {"replay_status", status},
  };
  f.insert(f.end(), replay.begin(), replay.end());
  if (ok) {  // a failed replay has no numbers (its status says why); none is written as NaN
    const Fields numbers = {{"replayed_cost", r.cost},
                            {"replayed_violation", r.violation},
                            {"replayed_quaternion_drift", r.quaternion_drift},
                            {"replay_seconds", r.seconds},
                            {"replay_cpu_seconds", r.cpu_seconds}};
    f.insert(f.end(), numbers.begin(), numbers.end());
  }
}

/// The node controls of a vector of them as columns.
template <class Vec>
Eigen::MatrixXd control_columns(const std::vector<Vec>& controls) {
  Eigen::MatrixXd u(Vec::RowsAtCompileTime, static_cast<Eigen::Index>(controls.size()));
  for (std::size_t j = 0; j < controls.size(); ++j) u.col(static_cast<Eigen::Index>(j)) = controls[j];
  return u;
}

/// The direct method on the scene's problem (experiments/ocp/ocp_direct_command.cpp); the same files,
/// exit statuses and errors as run_ocp_command.
int run_direct(const Scene& scene, const OcpCommand& cmd, const std::string& command_line, std::ostream& out,
               std::ostream& err);

/// --solver collocation on the scene's problem (experiments/ocp/ocp_collocation_command.cpp): the
/// continuous transcription of lgvi/ocp/collocation.hpp, whatever the scene's ocp.method; the
/// same files (history: one row per IPOPT iteration), exit statuses and errors as run_ocp_command.
int run_collocation(const Scene& scene, const OcpCommand& cmd, const std::string& command_line, std::ostream& out,
                    std::ostream& err);

/// --h and --steps exclude each other; each given one, and --t-final, in its range (--steps:
/// kOcpSteps, the [ocp] scenes' step cap). Throws InvalidInput naming the option.
inline void check_step_options(const OcpCommand& cmd) {
  if (cmd.h && cmd.steps) throw InvalidInput("--h", "give either --h or --steps, not both");
  if (cmd.h) kPositiveOption.require(*cmd.h, "--h");
  if (cmd.t_final) kPositiveOption.require(*cmd.t_final, "--t-final");
  if (cmd.steps) kOcpSteps.require(static_cast<double>(*cmd.steps), "--steps");
}

/// The output directory of one run and the three files every `ocp` run writes in it
/// (ocp_output_file names them). The summary is written last: it marks the run complete.
struct Files {
  std::string run_id = new_run_id();  ///< recorded in every file of the run
  std::filesystem::path dir;         ///< --out
  std::filesystem::path history;     ///< ocp-SYSTEM-history.csv
  std::filesystem::path trajectory;  ///< ocp-SYSTEM-trajectory.csv
  std::filesystem::path summary;     ///< ocp-SYSTEM-summary.json
};

/// Creates --out (with its parents) and names the files after `label`. Throws OutputError when
/// the directory cannot be created.
inline Files create_files(const OcpCommand& cmd, const std::string& label) {
  Files f;
  f.dir = cmd.out;
  std::error_code ec;
  std::filesystem::create_directories(f.dir, ec);
  if (ec) throw OutputError(f.dir.string() + ": cannot create the output directory: " + ec.message());
  f.history = ocp_output_file(f.dir, label, "history.csv");
  f.trajectory = ocp_output_file(f.dir, label, "trajectory.csv");
  f.summary = ocp_output_file(f.dir, label, "summary.json");
  return f;
}

/// The solver rejected its input: one "error: ocp SYSTEM: MESSAGE" line on err, or, when the
/// field the solver names ("globalization: ...", "knots: ...") was set by a command-line option,
/// "error: --globalization: ..." naming the option. Returns the exit status 1.
inline int invalid_input(const OcpCommand& cmd, const std::string& message, std::ostream& err) {
  const std::pair<const char*, std::pair<const char*, bool>> options[] = {
      {"globalization", {"--globalization", cmd.globalization.has_value()}},
      {"merit", {"--merit", cmd.merit.has_value()}},
      {"knots", {"--knots", cmd.knots.has_value()}},
      {"shooting_interval", {"--shooting-interval", cmd.shooting_interval.has_value()}},
      {"initial_multiplier", {"--guess", !cmd.guess.empty()}},
      {"h", {cmd.steps ? "--steps" : "--h", cmd.h.has_value() || cmd.steps.has_value()}},
  };
  for (const auto& [field, option] : options) {
    const std::string prefix = std::string(field) + ": ";
    if (option.second && message.rfind(prefix, 0) == 0) {
      err << "error: " << option.first << ": " << message.substr(prefix.size()) << "\n" << std::flush;
      return 1;
    }
  }
  err << "error: ocp " << cmd.system << ": " << message << "\n" << std::flush;
  return 1;
}

/// After the files are written: the summary's brief() line and "wrote FILE, FILE, ..." (the files
/// in the order given) on out. Returns the exit status: 0 converged; otherwise 2, after an
/// "error: ocp SYSTEM: ... (results written to DIR)" line on err. Summary: the method's summary
/// (ocp::ShootingSummary, ocp::DirectSummary), with brief() and converged().
template <class Summary>
int finish(const OcpCommand& cmd, const Summary& S, const Files& files,
           std::initializer_list<std::filesystem::path> written, std::ostream& out, std::ostream& err) {
  out << "ocp " << cmd.system << ": " << S.brief() << "\n";
  out << "wrote ";
  const char* separator = "";
  for (const std::filesystem::path& file : written) {
    out << separator << file.string();
    separator = ", ";
  }
  out << "\n";
  if (!S.converged()) {
    err << "error: ocp " << cmd.system << ": " << S.brief() << " (results written to " << files.dir.string()
        << ")\n"
        << std::flush;
    return 2;
  }
  return 0;
}

}  // namespace lgvi::experiments::ocp_output
