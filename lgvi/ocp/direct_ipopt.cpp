// IPOPT on the multiple-shooting transcription of the direct problem (direct_ipopt.hpp).
#include "lgvi/ocp/direct_ipopt.hpp"

#include <IpIpoptApplication.hpp>
#include <IpTNLP.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace lgvi::ocp::detail {

namespace {

std::string ipopt_name(Ipopt::ApplicationReturnStatus s) {
  using namespace Ipopt;
  switch (s) {
    case Solve_Succeeded: return "Solve_Succeeded";
    case Solved_To_Acceptable_Level: return "Solved_To_Acceptable_Level";
    case Infeasible_Problem_Detected: return "Infeasible_Problem_Detected";
    case Search_Direction_Becomes_Too_Small: return "Search_Direction_Becomes_Too_Small";
    case Diverging_Iterates: return "Diverging_Iterates";
    case User_Requested_Stop: return "User_Requested_Stop";
    case Feasible_Point_Found: return "Feasible_Point_Found";
    case Maximum_Iterations_Exceeded: return "Maximum_Iterations_Exceeded";
    case Restoration_Failed: return "Restoration_Failed";
    case Error_In_Step_Computation: return "Error_In_Step_Computation";
    case Maximum_CpuTime_Exceeded: return "Maximum_CpuTime_Exceeded";
    case Not_Enough_Degrees_Of_Freedom: return "Not_Enough_Degrees_Of_Freedom";
    case Invalid_Problem_Definition: return "Invalid_Problem_Definition";
    case Invalid_Option: return "Invalid_Option";
    case Invalid_Number_Detected: return "Invalid_Number_Detected";
    default: return "IPOPT_STATUS_" + std::to_string(static_cast<int>(s));
  }
}

// The TNLP: IPOPT asks for f, grad f, g and the Jacobian at the same point in separate calls;
// one evaluate_shooting serves them all (cached by the point; gradients computed on demand).
template <class Model>
class ShootingNlp : public Ipopt::TNLP {
 public:
  using Transcription = DirectTranscription<Model>;
  ShootingNlp(const Transcription& tr, const typename Transcription::ShootingNodes& nodes, const Eigen::VectorXd& c0,
              IpoptHessian hessian, double cost_scale, int start_index, DirectSummary& S, std::chrono::steady_clock::time_point start)
      : tr_(tr), nodes_(nodes), hessian_(hessian), cost_scale_(cost_scale), start_index_(start_index), S_(S), start_(start) {
    x0_ = Eigen::VectorXd::Zero(tr.shooting_variables(nodes));
    x0_.head(tr.parameters()) = c0;
    x_final_ = x0_;
    tr.shooting_structure(nodes, rows_, cols_);
    const Eigen::MatrixXd& Sm = tr.sampling();
    gram_ = Eigen::MatrixXd::Zero(Sm.cols(), Sm.cols());
    for (Eigen::Index k = 0; k < Sm.rows(); ++k) gram_ += tr.node_weight(k) * Sm.row(k).transpose() * Sm.row(k);
  }

  bool get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac_g, Ipopt::Index& nnz_h_lag,
                    IndexStyleEnum& index_style) override {
    n = tr_.shooting_variables(nodes_);
    m = tr_.shooting_constraints(nodes_);
    nnz_jac_g = static_cast<Ipopt::Index>(rows_.size());
    const int np = tr_.parameters();
    nnz_h_lag = hessian_ == IpoptHessian::LimitedMemory ? 0 : np * (np + 1) / 2;
    index_style = C_STYLE;
    return true;
  }
  bool get_bounds_info(Ipopt::Index n, Ipopt::Number* x_l, Ipopt::Number* x_u, Ipopt::Index m, Ipopt::Number* g_l,
                       Ipopt::Number* g_u) override {
    for (Ipopt::Index i = 0; i < n; ++i) {
      x_l[i] = -1e19;  // IPOPT's "no bound"
      x_u[i] = 1e19;
    }
    for (Ipopt::Index i = 0; i < m; ++i) g_l[i] = g_u[i] = 0.0;
    return true;
  }
  bool get_starting_point(Ipopt::Index n, bool init_x, Ipopt::Number* x, bool, Ipopt::Number*, Ipopt::Number*,
                          Ipopt::Index, bool init_lambda, Ipopt::Number*) override {
    if (!init_x || init_lambda) return false;
    Eigen::Map<Eigen::VectorXd>(x, n) = x0_;
    return true;
  }
  bool eval_f(Ipopt::Index n, const Ipopt::Number* x, bool, Ipopt::Number& f) override {
    if (!ensure(n, x, false)) return false;
    f = e_.cost / cost_scale_;
    return true;
  }
  bool eval_grad_f(Ipopt::Index n, const Ipopt::Number* x, bool, Ipopt::Number* g) override {
    if (!ensure(n, x, true)) return false;
    Eigen::Map<Eigen::VectorXd>(g, n) = e_.cost_gradient / cost_scale_;
    return true;
  }
  bool eval_g(Ipopt::Index n, const Ipopt::Number* x, bool, Ipopt::Index m, Ipopt::Number* g) override {
    if (!ensure(n, x, false)) return false;
    Eigen::Map<Eigen::VectorXd>(g, m) = e_.constraints;
    return true;
  }
  bool eval_jac_g(Ipopt::Index n, const Ipopt::Number* x, bool, Ipopt::Index, Ipopt::Index nele, Ipopt::Index* iRow,
                  Ipopt::Index* jCol, Ipopt::Number* values) override {
    if (values == nullptr) {
      for (Ipopt::Index i = 0; i < nele; ++i) {
        iRow[i] = rows_[static_cast<std::size_t>(i)];
        jCol[i] = cols_[static_cast<std::size_t>(i)];
      }
      return true;
    }
    if (!ensure(n, x, true)) return false;
    std::copy(e_.jacobian_values.begin(), e_.jacobian_values.end(), values);
    return true;
  }
  // IpoptHessian::CostOnly: the cost's Hessian (constant: J is quadratic in the knots,
  // d2J/dc_(a,i) dc_(b,j) = W_ab sum_k w_k S_ki S_kj) without the constraints' curvature, a
  // generalized Gauss-Newton model; lower triangle of the knot block, the state block zero.
  bool eval_h(Ipopt::Index, const Ipopt::Number*, bool, Ipopt::Number obj_factor, Ipopt::Index,
              const Ipopt::Number*, bool, Ipopt::Index, Ipopt::Index* iRow, Ipopt::Index* jCol,
              Ipopt::Number* values) override {
    if (hessian_ == IpoptHessian::LimitedMemory) return false;
    const int np = tr_.parameters(), knots = tr_.knots();
    Ipopt::Index e = 0;
    for (int r = 0; r < np; ++r) {
      for (int q = 0; q <= r; ++q, ++e) {
        if (values == nullptr) {
          iRow[e] = r;
          jCol[e] = q;
        } else {
          values[e] = obj_factor / cost_scale_ * tr_.weight()(r / knots, q / knots) * gram_(r % knots, q % knots);
        }
      }
    }
    return true;
  }
  bool intermediate_callback(Ipopt::AlgorithmMode, Ipopt::Index iter, Ipopt::Number obj, Ipopt::Number inf_pr,
                             Ipopt::Number, Ipopt::Number, Ipopt::Number, Ipopt::Number, Ipopt::Number,
                             Ipopt::Number, Ipopt::Index, const Ipopt::IpoptData*,
                             Ipopt::IpoptCalculatedQuantities*) override {
    iterations_ = iter;
    DirectIteration it;
    it.evaluation = static_cast<int>(S_.history.size()) + 1;
    it.start = start_index_;
    it.gradient = true;
    it.cost = obj * cost_scale_;
    it.violation = inf_pr;  // IPOPT's max-norm of the (unscaled) constraints
    it.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    S_.history.push_back(it);
    return true;
  }
  void finalize_solution(Ipopt::SolverReturn, Ipopt::Index n, const Ipopt::Number* x, const Ipopt::Number*,
                         const Ipopt::Number*, Ipopt::Index, const Ipopt::Number*, const Ipopt::Number*, Ipopt::Number,
                         const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    x_final_ = Eigen::Map<const Eigen::VectorXd>(x, n);
  }

  const Eigen::VectorXd& solution() const { return x_final_; }
  int iterations() const { return iterations_; }

 private:
  bool ensure(Ipopt::Index n, const Ipopt::Number* xp, bool gradients) {
    const Eigen::Map<const Eigen::VectorXd> xm(xp, n);
    const bool same = have_ && x_ == xm;
    if (same && (have_gradients_ || !gradients)) return e_.ok;
    x_ = xm;
    have_ = true;
    have_gradients_ = gradients;
    ++S_.simulations;
    if (gradients) ++S_.gradient_evaluations;
    if (!tr_.evaluate_shooting(nodes_, x_, gradients, e_)) {
      ++S_.failed_simulations;
      char buf[512];
      std::snprintf(buf, sizeof buf, "rotation update failed at step %zu (t = %.6g): %s", e_.failed_step,
                    static_cast<double>(e_.failed_step) * tr_.h(), e_.failure.brief().c_str());
      S_.last_failure = buf;
      return false;
    }
    return true;
  }

  const Transcription& tr_;
  const typename Transcription::ShootingNodes& nodes_;
  IpoptHessian hessian_;
  double cost_scale_;
  Eigen::MatrixXd gram_;  ///< S^T diag(w) S
  int start_index_;
  DirectSummary& S_;
  std::chrono::steady_clock::time_point start_;
  std::vector<int> rows_, cols_;
  Eigen::VectorXd x0_, x_final_, x_;
  bool have_ = false, have_gradients_ = false;
  typename Transcription::ShootingEvaluation e_;
  int iterations_ = 0;
};

}  // namespace

template <class Model>
IpoptOutcome run_ipopt(const DirectTranscription<Model>& tr, const DirectOptions& options, int start_index,
                       double cost_scale, Eigen::VectorXd& c, DirectSummary& S,
                       std::chrono::steady_clock::time_point start) {
  IpoptOutcome out;
  typename DirectTranscription<Model>::ShootingNodes nodes;
  typename DirectTranscription<Model>::Evaluation guess;
  // The state variables start at the references (zero chart offsets): the simulation of the guess
  // control or the geodesic between the boundary states (options.state_guess).
  if (!tr.shooting_nodes(c, options.shooting_interval, options.state_guess, nodes, guess)) {
    ++S.failed_simulations;
    S.last_failure = tr.failure_message(guess);
    out.code = "guess_simulation_failed";
    return out;
  }
  if (options.state_guess == ShootingStateGuess::Simulated) ++S.simulations;
  Ipopt::SmartPtr<ShootingNlp<Model>> nlp = new ShootingNlp<Model>(tr, nodes, c, options.ipopt_hessian, cost_scale, start_index, S, start);
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  Ipopt::OptionsList& o = *app->Options();
  o.SetIntegerValue("print_level", 0);
  o.SetStringValue("sb", "yes");  // no banner
  o.SetStringValue("hessian_approximation",
                   options.ipopt_hessian == IpoptHessian::LimitedMemory ? "limited-memory" : "exact");
  o.SetIntegerValue("max_iter", options.max_evaluations);
  // Feasibility: IPOPT's test is the max-norm of the unscaled constraints. The reported
  // violation is the 2-norm of the terminal residual after re-simulating the knots in one sweep
  // (defects amplified through the remaining segments): the bound is a tenth of the tolerance
  // spread over the rows, the rest is left to the feasibility polish in solve().
  o.SetNumericValue("constr_viol_tol", 0.1 * options.tolerance / std::sqrt(double(tr.constraints())));
  o.SetNumericValue("tol", 1e-9);
  o.SetNumericValue("acceptable_tol", 1e-6);
  o.SetNumericValue("acceptable_constr_viol_tol", 0.1 * options.tolerance / std::sqrt(double(tr.constraints())));
  if (app->Initialize() != Ipopt::Solve_Succeeded) {
    out.code = "ipopt_initialize_failed";
    return out;
  }
  const Ipopt::ApplicationReturnStatus status = app->OptimizeTNLP(nlp);
  out.code = ipopt_name(status);
  out.success = status == Ipopt::Solve_Succeeded || status == Ipopt::Solved_To_Acceptable_Level;
  out.iteration_limit = status == Ipopt::Maximum_Iterations_Exceeded;
  out.iterations = nlp->iterations();
  c = nlp->solution().head(tr.parameters());
  return out;
}

template IpoptOutcome run_ipopt<CartPendulumDirectModel>(const DirectTranscription<CartPendulumDirectModel>&,
                                                         const DirectOptions&, int, double, Eigen::VectorXd&,
                                                         DirectSummary&, std::chrono::steady_clock::time_point);
template IpoptOutcome run_ipopt<ConnectedBodiesDirectModel>(const DirectTranscription<ConnectedBodiesDirectModel>&,
                                                            const DirectOptions&, int, double, Eigen::VectorXd&,
                                                            DirectSummary&, std::chrono::steady_clock::time_point);

}  // namespace lgvi::ocp::detail
