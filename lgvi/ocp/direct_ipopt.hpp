// Internal to the direct method: one IPOPT run on the multiple-shooting transcription
// (DirectTranscription::evaluate_shooting). Only direct.cpp includes this; IPOPT's own headers
// stay in direct_ipopt.cpp.
#pragma once

#include <chrono>
#include <string>

#include <Eigen/Dense>

#include "lgvi/ocp/direct.hpp"

namespace lgvi::ocp::detail {

/// IPOPT's return status (Ipopt::ApplicationReturnStatus) by name, "Solve_Succeeded"; the
/// multiple shooting's and the collocation's summaries both use it.
std::string ipopt_name(int status);

struct IpoptOutcome {
  std::string code;              ///< IPOPT's ApplicationReturnStatus by name, e.g. "Solve_Succeeded"
  bool success = false;          ///< Solve_Succeeded or Solved_To_Acceptable_Level
  bool iteration_limit = false;  ///< Maximum_Iterations_Exceeded
  int iterations = 0;            ///< IPOPT iterations
};

/// Solves the multiple-shooting transcription from the knot values c (updated to the returned
/// knots) with shooting nodes every options.shooting_interval steps, the state variables started
/// at the simulation of c. Limited-memory (L-BFGS) Hessian of the Lagrangian, exact sparse
/// constraint Jacobian. Counts into S (simulations, gradient evaluations, history); a failed
/// simulation of a trial point is reported to IPOPT as an evaluation error (it then cuts the
/// step) and kept in S.last_failure. cost_scale: the objective handed to IPOPT is J / cost_scale.
template <class Model>
IpoptOutcome run_ipopt(const DirectTranscription<Model>& tr, const DirectOptions& options, int start_index,
                       double cost_scale, Eigen::VectorXd& c, DirectSummary& S,
                       std::chrono::steady_clock::time_point start);

}  // namespace lgvi::ocp::detail
