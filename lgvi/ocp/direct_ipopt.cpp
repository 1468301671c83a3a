// IPOPT on the multiple-shooting transcription of the direct problem (direct_ipopt.hpp).
#include "lgvi/ocp/direct_ipopt.hpp"

#include <IpIpoptApplication.hpp>
#include <IpTNLP.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

namespace lgvi::ocp::detail {

std::string ipopt_name(int status) {
  const auto s = static_cast<Ipopt::ApplicationReturnStatus>(status);
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

namespace {


// The TNLP: IPOPT asks for f, grad f, g and the Jacobian at the same point in separate calls;
// one evaluate_shooting serves them all (cached by the point; gradients added on demand along the
// stored states, see ensure).
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
    if (hessian_ == IpoptHessian::Exact) build_hessian_structure();
  }

  bool get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac_g, Ipopt::Index& nnz_h_lag,
                    IndexStyleEnum& index_style) override {
    n = tr_.shooting_variables(nodes_);
    m = tr_.shooting_constraints(nodes_);
    nnz_jac_g = static_cast<Ipopt::Index>(rows_.size());
    const int np = tr_.parameters();
    nnz_h_lag = hessian_ == IpoptHessian::LimitedMemory ? 0
                : hessian_ == IpoptHessian::CostOnly    ? np * (np + 1) / 2
                                                        : static_cast<Ipopt::Index>(h_rows_.size());
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
  bool eval_h(Ipopt::Index n, const Ipopt::Number* x, bool, Ipopt::Number obj_factor, Ipopt::Index m,
              const Ipopt::Number* lambda, bool, Ipopt::Index, Ipopt::Index* iRow, Ipopt::Index* jCol,
              Ipopt::Number* values) override {
    if (hessian_ == IpoptHessian::LimitedMemory) return false;
    if (hessian_ == IpoptHessian::Exact) {
      if (values == nullptr) {
        std::copy(h_rows_.begin(), h_rows_.end(), iRow);
        std::copy(h_cols_.begin(), h_cols_.end(), jCol);
        return true;
      }
      return lagrangian_hessian(n, x, obj_factor, m, lambda, values);
    }
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
  // IPOPT evaluates f and g at a trial point first and asks for the gradients there only once
  // the point is accepted: the values' run stores its states, and the gradients are then the step
  // linearizations along them (no rotation update solved twice). Evaluating the gradients with
  // every trial point instead costs more: a gradient sweep is ~4x a value sweep (benchmark
  // ShootingJacobian), the linearizations ~3 of those 4, wasted at every rejected trial.
  bool ensure(Ipopt::Index n, const Ipopt::Number* xp, bool gradients) {
    const Eigen::Map<const Eigen::VectorXd> xm(xp, n);
    const bool same = have_ && x_ == xm;
    if (same && (have_gradients_ || !gradients)) return e_.ok;
    if (same && e_.ok) {
      tr_.shooting_gradients(nodes_, x_, e_);
      have_gradients_ = true;
      ++S_.gradient_evaluations;
      return true;
    }
    x_ = xm;
    have_ = true;
    have_gradients_ = gradients;
    ++S_.simulations;
    if (gradients) ++S_.gradient_evaluations;
    if (!tr_.evaluate_shooting(nodes_, x_, gradients, e_)) {
      ++S_.failed_simulations;
      S_.last_failure = step_failure_message(e_.failed_step, static_cast<double>(e_.failed_step) * tr_.h(),
                                             e_.failure, e_.non_finite, 6);
      return false;
    }
    return true;
  }

  // --- IpoptHessian::Exact ----------------------------------------------------------------
  // Structure: (p, q), p >= q, whenever a constraint row involves both columns, and the knot
  // block (the cost). Colouring (Curtis, Powell, Reid 1974, applied to the symmetric case by
  // symmetry): each knot column is its own group (the knots enter every row); state columns share
  // a group when no state row of the Hessian has a non-zero in two of them; the knot rows of the
  // state columns are then read from the knot columns' differences (H symmetric).
  void build_hessian_structure() {
    const int n = tr_.shooting_variables(nodes_), np = tr_.parameters();
    std::vector<std::vector<int>> row_columns(static_cast<std::size_t>(tr_.shooting_constraints(nodes_)));
    for (std::size_t k = 0; k < rows_.size(); ++k) row_columns[static_cast<std::size_t>(rows_[k])].push_back(cols_[k]);
    adjacency_.assign(static_cast<std::size_t>(n), {});
    for (int p = 0; p < np; ++p) {
      for (int q = 0; q < np; ++q) adjacency_[static_cast<std::size_t>(p)].push_back(q);
    }
    for (const std::vector<int>& columns : row_columns) {
      for (int p : columns) {
        for (int q : columns) adjacency_[static_cast<std::size_t>(p)].push_back(q);
      }
    }
    for (std::vector<int>& a : adjacency_) {
      std::sort(a.begin(), a.end());
      a.erase(std::unique(a.begin(), a.end()), a.end());
    }
    for (int p = 0; p < n; ++p) {
      for (int q : adjacency_[static_cast<std::size_t>(p)]) {
        if (q > p) break;
        h_rows_.push_back(p);
        h_cols_.push_back(q);
      }
    }
    colour_.assign(static_cast<std::size_t>(n), -1);
    int colours = 0;
    for (int p = 0; p < np; ++p) colour_[static_cast<std::size_t>(p)] = colours++;
    const int first_state_colour = colours;
    std::vector<int> forbidden_by(static_cast<std::size_t>(n) + 1, -1);
    for (int p = np; p < n; ++p) {
      for (int r : adjacency_[static_cast<std::size_t>(p)]) {
        if (r < np) continue;  // knot rows come from the knot columns
        for (int q : adjacency_[static_cast<std::size_t>(r)]) {
          if (q >= np && colour_[static_cast<std::size_t>(q)] >= 0) forbidden_by[colour_[static_cast<std::size_t>(q)]] = p;
        }
      }
      int c = first_state_colour;
      while (forbidden_by[static_cast<std::size_t>(c)] == p) ++c;
      colour_[static_cast<std::size_t>(p)] = c;
      colours = std::max(colours, c + 1);
    }
    colours_ = colours;
  }
  static int entry_index(const std::vector<int>& rows, const std::vector<int>& cols, int p, int q) {
    // (p, q) with p >= q; the structure is sorted by p, then q.
    const auto lo = std::lower_bound(rows.begin(), rows.end(), p);
    const auto hi = std::upper_bound(lo, rows.end(), p);
    const auto at = std::lower_bound(cols.begin() + (lo - rows.begin()), cols.begin() + (hi - rows.begin()), q);
    return static_cast<int>(at - cols.begin());
  }
  /// grad_x (sigma J / cost_scale + y^T g) of an evaluation with gradients.
  Eigen::VectorXd lagrangian_gradient(const typename Transcription::ShootingEvaluation& e, double sigma,
                                      const Eigen::Map<const Eigen::VectorXd>& y) const {
    Eigen::VectorXd g = sigma / cost_scale_ * e.cost_gradient;
    for (std::size_t k = 0; k < rows_.size(); ++k) g(cols_[k]) += e.jacobian_values[k] * y(rows_[k]);
    return g;
  }
  // Forward differences of the Lagrangian's exact gradient, one sweep with gradients per colour.
  // Step: the error is delta/2 |d3L| (truncation) + 2 eps_g |grad L| / delta (the exact gradient's
  // round-off, eps_g a few eps); for unit-scaled variables (knots in N or N m, chart coordinates in
  // rad and the state units) the balance is delta ~ sqrt(eps) max(1, |x_j|), leaving a relative
  // Hessian error ~ sqrt(eps) ~ 1e-8: enough for IPOPT's Newton steps (superlinear convergence).
  bool lagrangian_hessian(Ipopt::Index n, const Ipopt::Number* xp, double sigma, Ipopt::Index m,
                          const Ipopt::Number* lambda, Ipopt::Number* values) {
    if (!ensure(n, xp, true)) return false;
    const Eigen::Map<const Eigen::VectorXd> y(lambda, m);
    const Eigen::VectorXd base = lagrangian_gradient(e_, sigma, y);
    const Eigen::VectorXd x = x_;
    const int np = tr_.parameters();
    std::vector<double> sum(h_rows_.size(), 0.0);
    std::vector<int> count(h_rows_.size(), 0);
    Eigen::VectorXd step(n);
    for (int c = 0; c < colours_; ++c) {
      Eigen::VectorXd xc = x;
      step.setZero();
      for (int j = 0; j < n; ++j) {
        if (colour_[static_cast<std::size_t>(j)] != c) continue;
        step(j) = std::sqrt(std::numeric_limits<double>::epsilon()) * std::max(1.0, std::abs(x(j)));
        xc(j) += step(j);
      }
      ++S_.simulations;
      ++S_.gradient_evaluations;
      if (!tr_.evaluate_shooting(nodes_, xc, true, perturbed_)) {
        ++S_.failed_simulations;
        return false;
      }
      const Eigen::VectorXd diff = lagrangian_gradient(perturbed_, sigma, y) - base;
      for (int j = 0; j < n; ++j) {
        if (colour_[static_cast<std::size_t>(j)] != c) continue;
        for (int r : adjacency_[static_cast<std::size_t>(j)]) {
          if (j >= np && r < np) continue;  // a knot row of a state group: shared, taken from the knot column
          const int e = r >= j ? entry_index(h_rows_, h_cols_, r, j) : entry_index(h_rows_, h_cols_, j, r);
          sum[static_cast<std::size_t>(e)] += diff(r) / step(j);
          ++count[static_cast<std::size_t>(e)];
        }
      }
    }
    for (std::size_t e = 0; e < sum.size(); ++e) values[e] = count[e] > 0 ? sum[e] / count[e] : 0.0;
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
  // IpoptHessian::Exact: structure (lower triangle, sorted by row then column), the columns each
  // column's Hessian entries lie in, the colour groups and the perturbed evaluation's buffer.
  std::vector<int> h_rows_, h_cols_, colour_;
  std::vector<std::vector<int>> adjacency_;
  int colours_ = 0;
  typename Transcription::ShootingEvaluation perturbed_;
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
  // L-BFGS in the KKT system: IPOPT's default (Sherman-Morrison) re-solves the augmented system
  // once per low-rank column after each update, each a MUMPS call whose fixed per-call cost
  // dominates on these few-hundred-row systems; "extended" adds the low-rank terms as rows and
  // columns of one system factored once (the same model, other rounding: iterates differ in the
  // last bits). Connected bodies, 8 starts (lgvi-direct-benchmarks): 7.37 -> 5.92 s CPU, 933 ->
  // 926 iterations, the same optima (lgvi/ocp/README.md).
  if (options.ipopt_hessian == IpoptHessian::LimitedMemory) o.SetStringValue("limited_memory_aug_solver", "extended");
  // No second-order corrections: a rejected trial point's correction costs a simulation of
  // every segment, along a linearization of the defects that the chaotic flow makes poor (in the
  // 8 starts below, 15 corrections ended in a failed rotation update). Connected bodies, 8 starts
  // (lgvi-direct-benchmarks, one run each, with the reverse sweeps): 5.09 -> 4.18 s CPU, 924 ->
  // 870 iterations, 2199 -> 1899 simulations, 8/8 feasible, best 0.065091 either way; seeds 2-4
  // (CLI): 18-20% less CPU, 8/8 feasible, the same best; cart-pendulum 36 -> 34 iterations, 281.2317.
  o.SetIntegerValue("max_soc", 0);
  o.SetIntegerValue("max_iter", options.max_evaluations);
  // Feasibility: IPOPT's test is the max-norm of the unscaled constraints. The reported
  // violation is the 2-norm of the terminal residual after re-simulating the knots in one sweep
  // (defects amplified through the remaining segments): the bound is a tenth of the tolerance
  // spread over the rows, the rest is left to the feasibility polish in solve().
  o.SetNumericValue("constr_viol_tol", 0.1 * options.tolerance / std::sqrt(double(tr.constraints())));
  o.SetNumericValue("tol", 1e-9);
  o.SetNumericValue("acceptable_tol", 1e-6);
  o.SetNumericValue("acceptable_constr_viol_tol", 0.1 * options.tolerance / std::sqrt(double(tr.constraints())));
  // No options file: IPOPT would otherwise read an ipopt.opt in the working directory, and a
  // stray one would change the results without a trace in the summary or the resume fingerprint.
  if (app->Initialize(std::string()) != Ipopt::Solve_Succeeded) {
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
