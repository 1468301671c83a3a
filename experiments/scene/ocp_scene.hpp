// A scene's [ocp] table: the optimal control problem of the scene's system, in one record.
// The initial state is the scene's [initial], the horizon and step its [integration] (h,
// t_final, form); [ocp] adds the terminal state, the weight W, the method and its settings.
// Every key with type, units, default and range: experiments/scenes/README.md ("Optimal
// control"). The per-system part (which methods, the number of controls, the lgvi/ocp problem
// record) is the system's ocp binding (experiments/systems/ocp.hpp).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <Eigen/Dense>

#include "experiments/scene/scene.hpp"
#include "experiments/input/scene_reader.hpp"
#include "lgvi/ocp/direct.hpp"
#include "lgvi/ocp/indirect.hpp"

namespace lgvi::experiments {

/// The steps (t_final / h) of a scene with an [ocp] table, whichever way h and t_final are given
/// (the file, `ocp --h`, `--steps`, `--t-final`, Python): at most the solvers' kMaxOcpSteps
/// (lgvi/range.hpp; 10^7 steps took 3.8 GB and wrote a 4.3 GB CSV).
inline constexpr Range kOcpSteps = Range::integers(1, kMaxOcpSteps);

enum class OcpMethod { Indirect, Direct };
const char* to_string(OcpMethod m);

/// The [ocp] table, validated. The solver options carry every setting of the file (their h and
/// form are filled from the scene's [integration] when the problem is solved).
struct OcpDefinition {
  OcpMethod method = OcpMethod::Indirect;
  /// The table of validation/paper_values.toml the run is compared with ("pendulum_reorientation");
  /// empty: none.
  std::string paper;
  /// The target (terminal) state, the system's state record (the keys of its [initial]).
  std::variant<AttitudeInitial, RigidBodyInitial, CartPendulumInitial, ConnectedBodiesInitial> target;
  ocp::ShootingOptions indirect;  ///< method indirect: W, initial_multiplier, globalization, ...
  ocp::DirectOptions direct;      ///< method direct: W, knots, spline, starts, solver, ...
  bool max_evaluations_given = false;  ///< direct: else the solver's default (slsqp 3000, ipopt 1000)

  /// W as given (n_u x n_u), empty when the file gives none (identity).
  const Eigen::MatrixXd& W() const { return method == OcpMethod::Indirect ? indirect.W : direct.W; }
};

/// Reads and validates the scene's [ocp] table for its model (parameters: the scene's
/// [parameters], for reading the target state by the system's binding). Throws SceneError naming
/// the file, the field ("ocp.W") and the reason.
std::shared_ptr<const OcpDefinition> read_ocp_table(const SceneReader& r, const Model& model,
                                                     const SceneTable& parameters, const SceneTable& ocp);

/// The scene file of an `ocp` argument: a path (contains '/' or ends in ".toml") as given; a name
/// NAME as scenes_dir/ocp-NAME.toml when that exists (the shipped examples: `ocp pendulum` is
/// ocp-pendulum.toml), else resolve_scene(NAME). Throws SceneError for an unknown name.
std::filesystem::path resolve_ocp_scene(const std::string& name_or_path, const std::filesystem::path& scenes_dir);

/// Checks a weight W: finite, symmetric (to 1e-12 of its largest entry) and positive definite
/// (smallest eigenvalue above 1e-14 of the largest). Throws InvalidInput(field, reason).
void check_weight(const Eigen::MatrixXd& W, const std::string& field);

/// W from n values (its diagonal) or n^2 (the matrix row by row), checked by check_weight.
/// Throws InvalidInput naming `field` for another count or a W that is not SPD.
Eigen::MatrixXd weight_matrix(const std::vector<double>& values, int n, const std::string& field);

/// The label of a scene's ocp output files: its name without a leading "ocp-" (ocp-pendulum.toml
/// writes ocp-pendulum-*.csv).
std::string ocp_label(const Scene& scene);

}  // namespace lgvi::experiments
