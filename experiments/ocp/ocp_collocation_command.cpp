// `lgvi-testbed ocp SCENE --solver collocation`: the scene's transfer solved as the continuous
// problem by Hermite-Simpson collocation of the quaternion model (lgvi/ocp/collocation.hpp), for
// every system with an optimal control problem (pendulum, free body, dumbbell, cart-pendulum,
// connected bodies). Writes, atomically, into --out DIR:
//   ocp-LABEL-history.csv     one row per IPOPT iteration (cost, constraint infeasibility)
//   ocp-LABEL-trajectory.csv  at the mesh nodes: the attitude systems t, R, Omega, q, |q| - 1, u;
//                             the others t, the state y (OcpBinding::collocation_columns: the
//                             quaternions, positions, velocities or momenta), max | |q| - 1 |, u
//   ocp-LABEL-summary.json    cost, violation (the system's norm), max defect, |q| drift,
//                             iterations, CPU time, and the replayed yardstick of the controls
//                             (the quadratic through each interval's node, midpoint and node controls)
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <ostream>
#include <type_traits>

#include "experiments/input/paper_values.hpp"
#include "experiments/methods/simulate.hpp"
#include "experiments/ocp/ocp_command.hpp"
#include "experiments/ocp/ocp_output.hpp"
#include "experiments/output/csv_writer.hpp"
#include "experiments/output/fields.hpp"
#include "experiments/output/json_writer.hpp"
#include "experiments/scene/ocp_scene.hpp"
#include "experiments/systems/ocp.hpp"
#include "experiments/systems/systems.hpp"
#include "lgvi/ocp/collocation.hpp"

namespace lgvi::experiments {

namespace {

constexpr int kDefaultIntervals = 100;

/// The options of the discrete methods are errors with collocation, not silently ignored.
void check_collocation_options(const OcpCommand& cmd) {
  const std::pair<const char*, bool> other[] = {
      {"--form", cmd.form.has_value()},
      {"--h", cmd.h.has_value()},
      {"--steps", cmd.steps.has_value()},
      {"--no-decomposition", cmd.no_decomposition},
      {"--merit", cmd.merit.has_value()},
      {"--globalization", cmd.globalization.has_value()},
      {"--lm-damping", cmd.lm_damping.has_value()},
      {"--nonmonotone-memory", cmd.nonmonotone_memory.has_value()},
      {"--guess", !cmd.guess.empty()},
      {"--knots", cmd.knots.has_value()},
      {"--spline", cmd.spline.has_value()},
      {"--gradients", cmd.gradients.has_value()},
      {"--starts", cmd.starts.has_value()},
      {"--seed", cmd.seed.has_value()},
      {"--first-start", cmd.first_start != 0},
      {"--state-guess", cmd.state_guess.has_value()},
      {"--shooting-interval", cmd.shooting_interval.has_value()},
  };
  for (const auto& [name, given] : other) {
    if (given) {
      throw InvalidInput(name, std::string("does not apply to --solver collocation (its mesh is --intervals; it "
                                           "transcribes the continuous model, not the LGVI)"));
    }
  }
}

template <class M>
int collocation_for(const Scene& scene, const M& m, const OcpCommand& cmd, const std::string& command_line,
                    std::ostream& out, std::ostream& err) {
  using B = OcpBinding<M>;
  if constexpr (!B::collocation) {
    throw InvalidInput("--solver", std::string("collocation is not implemented for the ") + M::name);
  } else {
    const OcpDefinition& d = *scene.ocp;
    using O = ocp::CollocationOptions;
    O options;
    options.W = d.W();
    options.intervals =
        cmd.intervals ? ocp_output::option_int(*cmd.intervals, O::kIntervals, "--intervals") : kDefaultIntervals;
    if (cmd.tolerance) options.tolerance = ocp_output::option_number(*cmd.tolerance, O::kTolerance, "--tolerance");
    if (cmd.max_iterations) {
      options.max_iterations = ocp_output::option_int(*cmd.max_iterations, O::kMaxIterations, "--max-iterations");
    }
    if (cmd.hessian) options.hessian = ocp_output::option_hessian(*cmd.hessian);
    const auto problem = B::transfer(m, std::get<typename M::State>(d.target), scene.horizon.t_final);
    const auto& system = ocp_output::with_sphere_radius(B::system(m), cmd.sphere_radius);
    const ocp::CollocationResult result = ocp::solve_collocation(system, problem, options);
    const ocp::CollocationSummary& S = result.summary;
    if (S.status == ocp::CollocationStatus::InvalidInput) return ocp_output::invalid_input(cmd, S.message, err);
    const ocp_output::Run run = ocp_output::Run::of(scene);
    const ocp_output::Files files = ocp_output::create_files(cmd, run.label);
    Fields f = {
        {"system", run.system},
        {"method", std::string("continuous: Hermite-Simpson collocation of the quaternion model, IPOPT (") +
                       (options.hessian == ocp::IpoptHessian::LimitedMemory ? "L-BFGS"
                        : options.hessian == ocp::IpoptHessian::Exact       ? "exact Hessian"
                                                                             : "the cost's Hessian") +
                       ")"},
        {"hessian", std::string(ocp::to_string(options.hessian))},
        {"solver", std::string("collocation")},
        {"intervals", std::int64_t{S.intervals}},
        {"h", result.h},
        {"t_final", problem.t_final},
        {"W", ocp_output::weight_text(options.W)},
        {"status", std::string(ocp::to_string(S.status))},
        {"status_detail", S.brief()},
        {"converged", S.converged()},
        {"tolerance", options.tolerance},
        {"cost", S.cost},
        {"violation", S.violation},
        {"violation_norm", std::string(B::violation_norm)},
    };
    ocp_output::add_violation_parts<B>(f, S.residual);
    {
      // The collocation's own control: the quadratic through node, midpoint and node.
      baselines::ReplayControls c;
      c.u = result.controls;
      c.h = result.h;
      c.interpolation = baselines::ReplayInterpolation::PiecewiseQuadratic;
      c.W = options.W;
      const baselines::ReplayOptions ro;
      baselines::ReplayResult rr;
      std::string status = "not replayed: no solution";
      if (result.controls.cols() >= 3) {
        rr = baselines::replay(system, problem, c, ro);
        status = rr.ok ? "ok" : rr.message;
      }
      const Fields replay = {
          {"replay", ro.method + ", rtol = atol = " + shortest(ro.rtol) +
                         ", quaternion model, controls piecewise-quadratic between the nodes"},
          {"replay_interpolation", std::string(baselines::to_string(c.interpolation))},
          {"replay_status", status},
      };
      f.insert(f.end(), replay.begin(), replay.end());
      if (rr.ok) {  // a failed replay has no numbers (its status says why)
        const Fields numbers = {{"replayed_cost", rr.cost},
                                {"replayed_violation", rr.violation},
                                {"replayed_quaternion_drift", rr.quaternion_drift},
                                {"replay_seconds", rr.seconds},
                                {"replay_cpu_seconds", rr.cpu_seconds}};
        f.insert(f.end(), numbers.begin(), numbers.end());
      }
    }
    const Fields rest = {
        {"max_defect", S.max_defect},
        {"quaternion_drift", S.quaternion_drift},
        {"max_normal_rate", S.max_normal_rate},
        {"ipopt_status", S.ipopt_status},
        {"iterations", std::int64_t{S.iterations}},
        {"variables", std::int64_t{S.variables}},
        {"constraints", std::int64_t{S.constraints}},
        {"jacobian_nonzeros", std::int64_t{S.jacobian_nonzeros}},
        {"hessian_nonzeros", std::int64_t{S.hessian_nonzeros}},
        {"wall_seconds", S.wall_seconds},
        {"cpu_seconds", S.cpu_seconds},
    };
    f.insert(f.end(), rest.begin(), rest.end());
    if (run.paper != nullptr) {
      f.push_back({"paper_cost", run.paper->cost});
      f.push_back({"paper_violation", run.paper->terminal_violation});
    }
    const Fields files_fields = {
        {"history_csv", files.history.filename().string()},
        {"trajectory_csv", files.trajectory.filename().string()},
        {"git_describe", std::string(git_describe())},
        {"command_line", command_line},
        {"run_id", files.run_id},
    };
    f.insert(f.end(), files_fields.begin(), files_fields.end());
    {
      CsvWriter csv(files.history, {"iteration", "cost", "infeasibility"});
      for (std::size_t i = 0; i < result.history_cost.size(); ++i) {
        const double row[] = {double(i), result.history_cost[i], result.history_infeasibility[i]};
        csv.write_row(row);
      }
      csv.commit(f);
    }
    if constexpr (requires { B::collocation_columns; }) {
      // t, y, max | |q_i| - 1 |, u at the nodes
      const int ny = static_cast<int>(B::collocation_columns.size()) - B::nu;  // (no solution: no rows)
      std::vector<std::string> cols = {"t"};
      for (int i = 0; i < ny; ++i) cols.push_back(B::collocation_columns[static_cast<std::size_t>(i)]);
      cols.push_back("quaternion_norm_error");
      for (std::size_t i = static_cast<std::size_t>(ny); i < B::collocation_columns.size(); ++i) {
        cols.push_back(B::collocation_columns[i]);
      }
      CsvWriter csv(files.trajectory, cols);
      std::vector<double> row;
      for (Eigen::Index k = 0; k < result.states.cols(); ++k) {
        row.assign({static_cast<double>(k) * result.h});
        double drift = 0.0;
        for (int i = 0; i < ny; ++i) row.push_back(result.states(i, k));
        for (int i = 0; i < B::collocation_quaternions; ++i) {  // the quaternions come first in y
          drift = std::max(drift, std::abs(result.states.col(k).segment<4>(4 * i).norm() - 1.0));
        }
        row.push_back(drift);
        for (Eigen::Index i = 0; i < result.controls.rows(); ++i) row.push_back(result.controls(i, 2 * k));
        csv.write_row(row);
      }
      csv.commit(f);
    } else {
      std::vector<std::string> cols = {"t"};
      for (char i = '1'; i <= '3'; ++i)
        for (char j = '1'; j <= '3'; ++j) cols.push_back(std::string("R") + i + j);
      for (const char* name : {"Omega1", "Omega2", "Omega3", "q0", "q1", "q2", "q3", "quaternion_norm_error", "u1",
                               "u2", "u3"}) {
        cols.push_back(name);
      }
      CsvWriter csv(files.trajectory, cols);
      std::vector<double> row;
      for (Eigen::Index k = 0; k < result.states.cols(); ++k) {
        const Eigen::Vector4d q = result.states.col(k).head<4>();
        const Eigen::Quaterniond e(q(0), q(1), q(2), q(3));
        const Mat3 R = e.normalized().toRotationMatrix();
        row.assign({static_cast<double>(k) * result.h});
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) row.push_back(R(i, j));
        for (int i = 4; i < 7; ++i) row.push_back(result.states(i, k));
        for (int i = 0; i < 4; ++i) row.push_back(q(i));
        row.push_back(q.norm() - 1.0);
        for (int i = 0; i < 3; ++i) row.push_back(result.controls(i, 2 * k));
        csv.write_row(row);
      }
      csv.commit(f);
    }
    write_json_object(files.summary, f, {{"W", ocp_output::weight_values(options.W, B::nu)}});
    return ocp_output::finish(cmd, S, files, {files.history, files.trajectory, files.summary}, out, err);
  }
}

}  // namespace

int ocp_output::run_collocation(const Scene& scene, const OcpCommand& cmd, const std::string& command_line,
                                std::ostream& out, std::ostream& err) {
  check_collocation_options(cmd);
  return visit_binding(scene.model,
                       [&](auto, const auto& m) { return collocation_for(scene, m, cmd, command_line, out, err); });
}

}  // namespace lgvi::experiments
