// "ocp-comparison": the paper's central claim, that formulating the optimal control problem as a
// discrete-time one on the LGVI and applying standard computational methods has important
// advantages over constructing the continuous-time necessary conditions, measured. Every optimal
// control method of the testbed runs on each of the paper's examples that has an [ocp] scene
// (experiments/scenes/ocp-{pendulum,dumbbell,cart-pendulum,connected-bodies}.toml), and every
// answer is graded twice: by the method's own figures and by the replayed yardstick (its control
// history integrated on the continuous quaternion model by gsl-rk8pd at rtol 1e-13,
// baselines/ocp_replay.hpp), which judges discrete and continuous answers alike. Methods (ids are
// the palette's names, experiments/output/palette.cpp):
//   indirect-shooting    the discrete necessary conditions, Newton-Armijo on lambda_0 (sec. 3;
//                        lgvi/ocp/indirect.hpp, `ocp NAME`)
//   continuous-indirect  the continuous necessary conditions, the same shooting on lambda(0),
//                        CVODES at rtol 1e-10 (baselines/pontryagin.hpp); its own violation is
//                        already the continuous problem's (not replayed: no node controls)
//   slsqp                spline controls, single shooting, SLSQP (sec. 4; `ocp NAME --solver slsqp`)
//   ipopt                spline controls, multiple shooting, IPOPT (`--solver ipopt`)
//   ddp                  free node controls, iLQR with an augmented Lagrangian (lgvi/ocp/ddp.hpp)
//   collocation          Hermite-Simpson collocation of the continuous quaternion model, IPOPT
//                        (lgvi/ocp/collocation.hpp, `--solver collocation`, K = 100 intervals)
// A method that does not apply to an example (its ocp binding, experiments/systems/ocp.hpp, has no
// such solver) is one case with status "n/a" and the reason: the table names every gap.
//
// Starts, one case each (run in parallel by the suite's runner, resumable and shardable):
//   start 0   the method's documented guess: the scene's ocp.indirect.multiplier_guess, the
//             direct methods' default knots, collocation's slew guess;
//   start k   direct methods: the k-th seeded random start of the scene's multistart
//             (`--starts 1 --first-start k`, the scene's seed); indirect methods: the scene's
//             guess plus a uniform perturbation in [-1, 1] per entry times max(1, |guess|_inf)
//             (std::mt19937_64 seeded with k; random_multiplier); the continuous shooting takes
//             the same vectors as the discrete one (as the shooting suite does); collocation has
//             one start (its guess is deterministic and it defines no random one).
// Full form: 8 starts at the scene's h (collocation K = 100), and start 0 at h x 2 and h / 2
// (collocation K = 50 and 200) for the change with h. Quick form: 2 starts, the scene's h.
//
// IPOPT cases (ipopt, collocation) run one at a time (MUMPS is not thread-safe); the others in
// parallel.
// Cost: the CPU time of the calling thread (CLOCK_THREAD_CPUTIME_ID) over the whole in-process
// `ocp` run minus the replay's own CPU time (replay_cpu_seconds), measured in the run while the
// other worker thread runs another case on the other core. It includes writing the run's three
// files (~1 us per CSV row: at most 4 ms of the connected bodies' 401-node trajectory).
//
// Per case: the `ocp` run's files in <case id>/ (summary JSON, history, trajectory); summary:
// status, own cost and violation, replayed cost and violation, iterations, CPU time. Rendered:
// per example the replayed violation and the replayed cost against CPU time (one point per
// start, one colour per method), ocp-comparison-table.md and .csv (per example, variant and
// method: starts, converged, failed starts by status, the best converged start's figures,
// median iterations and CPU time per start, CPU time per iteration).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <mutex>
#include <random>
#include <sstream>

#include <nlohmann/json.hpp>

#include "baselines/pontryagin.hpp"
#include "experiments/ocp/ocp_command.hpp"
#include "experiments/output/json_writer.hpp"
#include "experiments/scene/ocp_scene.hpp"
#include "experiments/suites/common.hpp"
#include "experiments/systems/ocp.hpp"
#include "experiments/systems/systems.hpp"

namespace lgvi::experiments::suites {

namespace fs = std::filesystem;

namespace {

constexpr double kNoValue = std::numeric_limits<double>::quiet_NaN();

enum class OcpSolver { Indirect, ContinuousIndirect, Slsqp, Ipopt, Ddp, Collocation };

constexpr OcpSolver kSolvers[] = {OcpSolver::Indirect, OcpSolver::ContinuousIndirect, OcpSolver::Slsqp,
                                  OcpSolver::Ipopt,    OcpSolver::Ddp,                OcpSolver::Collocation};

/// The method's id: its palette name and file-name part.
const char* solver_id(OcpSolver s) {
  switch (s) {
    case OcpSolver::Indirect: return "indirect-shooting";
    case OcpSolver::ContinuousIndirect: return "continuous-indirect";
    case OcpSolver::Slsqp: return "slsqp";
    case OcpSolver::Ipopt: return "ipopt";
    case OcpSolver::Ddp: return "ddp";
    case OcpSolver::Collocation: return "collocation";
  }
  return "?";
}

/// Legend and table text (no commas: summary.csv cells).
const char* solver_label(OcpSolver s) {
  switch (s) {
    case OcpSolver::Indirect: return "discrete indirect shooting (LGVI)";
    case OcpSolver::ContinuousIndirect: return "continuous indirect (CVODES; own figures)";
    case OcpSolver::Slsqp: return "SLSQP single shooting (LGVI)";
    case OcpSolver::Ipopt: return "IPOPT multiple shooting (LGVI)";
    case OcpSolver::Ddp: return "DDP (LGVI; node controls)";
    case OcpSolver::Collocation: return "Hermite-Simpson collocation";
  }
  return "?";
}

/// The paper's examples, `ocp NAME`.
constexpr const char* kExamples[] = {"pendulum", "dumbbell", "cart-pendulum", "connected-bodies"};

/// Variants of the discretization: the scene's h (collocation K = 100), h x 2 (K = 50), h / 2 (K = 200).
enum class Grid { Nominal, Coarse, Fine };
const char* variant_name(Grid v) {
  switch (v) {
    case Grid::Nominal: return "h";
    case Grid::Coarse: return "2h";
    case Grid::Fine: return "h/2";
  }
  return "?";
}
const char* variant_id(Grid v) {
  switch (v) {
    case Grid::Nominal: return "";
    case Grid::Coarse: return "-coarse";
    case Grid::Fine: return "-fine";
  }
  return "?";
}
constexpr int kCollocationIntervals = 100;  // the command's default

Scene comparison_scene(const std::string& example, const fs::path& scenes_dir) {
  return load_scene(resolve_ocp_scene(example, scenes_dir));
}

/// Why `solver` does not apply to the example's system ("" when it does), from its ocp binding.
std::string not_applicable(const Scene& scene, OcpSolver solver) {
  return visit_binding(scene.model, [&](auto, const auto& m) -> std::string {
    using M = std::decay_t<decltype(m)>;
    using B = OcpBinding<M>;
    const std::string system = M::name;
    switch (solver) {
      case OcpSolver::Indirect:
        return B::indirect ? "" : "the " + system + " has no discrete necessary conditions in lgvi/ocp (direct only)";
      case OcpSolver::ContinuousIndirect:
        if constexpr (B::indirect) {
          if (B::continuous) return "";
        }
        return "the " + system + " has no continuous necessary conditions in baselines/pontryagin.hpp";
      case OcpSolver::Slsqp:
      case OcpSolver::Ipopt:
      case OcpSolver::Ddp:
        return B::direct ? "" : "the " + system + " has no direct (spline or node control) transcription in lgvi/ocp";
      case OcpSolver::Collocation:
        if (!B::collocation) return "the " + system + " has no collocation of its continuous model in lgvi/ocp/collocation.hpp";
        return "";
    }
    return "?";
  });
}

/// Start k > 0 of the indirect methods: guess + U[-1, 1]^n max(1, |guess|_inf), std::mt19937_64(k).
Eigen::VectorXd random_multiplier(const Eigen::VectorXd& guess, int start) {
  if (start == 0) return guess;
  std::mt19937_64 rng(static_cast<std::uint64_t>(start));
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double scale = std::max(1.0, guess.size() > 0 ? guess.cwiseAbs().maxCoeff() : 0.0);
  Eigen::VectorXd lambda = guess;
  for (Eigen::Index i = 0; i < lambda.size(); ++i) lambda(i) += scale * u(rng);
  return lambda;
}

struct ComparisonSpec {
  std::string example;
  OcpSolver solver = OcpSolver::Indirect;
  int start = 0;
  Grid variant = Grid::Nominal;
  std::string not_applicable;  ///< the reason; "" when the method applies

  std::string id() const {
    return example + "-" + solver_id(solver) + variant_id(variant) +
           (not_applicable.empty() ? "-s" + std::to_string(start) : std::string("-na"));
  }
};

std::mutex& ipopt_mutex() {
  static std::mutex m;
  return m;
}

double json_number(const nlohmann::json& j, const char* key) {
  return j.is_object() && j.contains(key) && j[key].is_number() ? j[key].get<double>() : kNoValue;
}
std::string json_text(const nlohmann::json& j, const char* key) {
  return j.is_object() && j.contains(key) && j[key].is_string() ? j[key].get<std::string>() : std::string();
}

class ComparisonJob final : public Job {
 public:
  explicit ComparisonJob(ComparisonSpec spec) : spec_(std::move(spec)) {}

  void validate(const fs::path& scenes_dir) const override {
    const Scene scene = comparison_scene(spec_.example, scenes_dir);  // SceneError for a missing example
    if (!scene.ocp) throw InvalidInput("system", "ocp-comparison: '" + spec_.example + "' has no [ocp] table");
  }

  double expected_cost(const fs::path&) const override {
    // Relative run times measured on the quick form (docs/suites.md): the connected bodies' DDP
    // and SLSQP starts take seconds, the pendulum's tens of milliseconds.
    if (!spec_.not_applicable.empty()) return 0.01;
    return spec_.example == "connected-bodies" ? 20.0 : spec_.example == "dumbbell" ? 5.0 : 1.0;
  }

 private:
  Fields base_fields() const {
    return {{"system", spec_.example},
            {"method", std::string(solver_id(spec_.solver))},
            {"label", std::string(solver_label(spec_.solver))},
            {"variant", std::string(variant_name(spec_.variant))},
            {"start", static_cast<std::int64_t>(spec_.start)}};
  }

  /// Steps of the variant (the scene's N, 2N or N/2); unset for the scene's own.
  std::optional<long long> steps(const Scene& scene) const {
    const auto n = static_cast<long long>(scene.horizon.steps);
    switch (spec_.variant) {
      case Grid::Nominal: return std::nullopt;
      case Grid::Coarse: return n / 2;
      case Grid::Fine: return 2 * n;
    }
    return std::nullopt;
  }

  JobResult run_command(const JobContext& ctx, const Scene& scene) const {
    OcpCommand cmd;
    cmd.system = scene.file.string();
    cmd.out = (ctx.out_dir / ctx.case_id).string();
    switch (spec_.solver) {
      case OcpSolver::Indirect: {
        const Eigen::VectorXd lambda = random_multiplier(scene.ocp->indirect.initial_multiplier, spec_.start);
        if (spec_.start > 0) cmd.guess.assign(lambda.data(), lambda.data() + lambda.size());
        cmd.steps = steps(scene);
        break;
      }
      case OcpSolver::Slsqp:
      case OcpSolver::Ipopt:
      case OcpSolver::Ddp:
        cmd.solver = solver_id(spec_.solver);
        cmd.starts = 1;
        cmd.first_start = spec_.start;
        cmd.steps = steps(scene);
        break;
      case OcpSolver::Collocation:
        cmd.solver = "collocation";
        cmd.intervals = spec_.variant == Grid::Coarse ? kCollocationIntervals / 2
                        : spec_.variant == Grid::Fine ? 2 * kCollocationIntervals
                                                         : kCollocationIntervals;
        break;
      case OcpSolver::ContinuousIndirect: break;  // not a command (run_continuous)
    }
    std::ostringstream out, err;
    // IPOPT's linear solver MUMPS keeps global state: two solves at once on two threads abort
    // ("PB allocation in DMUMPS_LOAD_INIT", measured), so the IPOPT methods run one at a time.
    const bool ipopt = spec_.solver == OcpSolver::Ipopt || spec_.solver == OcpSolver::Collocation;
    std::unique_lock<std::mutex> one_ipopt(ipopt_mutex(), std::defer_lock);
    if (ipopt) one_ipopt.lock();
    const double cpu0 = thread_cpu_seconds();
    const int code = run_ocp_command(cmd, ctx.command_line, out, err);
    const double cpu = thread_cpu_seconds() - cpu0;
    if (ipopt) one_ipopt.unlock();
    const std::string label = ocp_label(scene);
    const fs::path summary = ocp_output_file(cmd.out, label, "summary.json");
    nlohmann::json j;
    {
      std::ifstream in(summary);
      if (in) j = nlohmann::json::parse(in, nullptr, false);
    }
    if (!j.is_object()) {
      // Bad input (exit 1) writes nothing: the command's error line is the detail.
      return {false, "invalid-input", "ocp exit " + std::to_string(code) + ": " + err.str(), base_fields()};
    }
    Fields f = base_fields();
    const bool indirect = spec_.solver == OcpSolver::Indirect;
    const double replay_cpu = json_number(j, "replay_cpu_seconds");
    const Fields numbers = {
        {"h", json_number(j, "h")},
        {"steps", json_number(j, "steps")},
        {"intervals", json_number(j, "intervals")},
        {"form", json_text(j, "form")},
        {"solver_status", json_text(j, "status")},
        {"cost", json_number(j, "cost")},
        {"violation", json_number(j, "violation")},
        {"replayed_cost", json_number(j, "replayed_cost")},
        {"replayed_violation", json_number(j, "replayed_violation")},
        {"replayed_quaternion_drift", json_number(j, "replayed_quaternion_drift")},
        {"replay_status", json_text(j, "replay_status")},
        {"iterations", json_number(j, indirect ? "outer_iterations" : "iterations")},
        {"cpu_seconds", cpu - (std::isfinite(replay_cpu) ? replay_cpu : 0.0)},
        {"replay_cpu_seconds", replay_cpu},
        {"summary_path", ctx.case_id + "/" + summary.filename().string()},
        {"history_path", ctx.case_id + "/" + ocp_output_file(cmd.out, label, "history.csv").filename().string()},
        {"trajectory_path",
         ctx.case_id + "/" + ocp_output_file(cmd.out, label, "trajectory.csv").filename().string()},
    };
    f.insert(f.end(), numbers.begin(), numbers.end());
    if (fs::exists(ocp_output_file(cmd.out, label, "knots.csv"))) {
      f.push_back({"knots_path", ctx.case_id + "/" + ocp_output_file(cmd.out, label, "knots.csv").filename().string()});
    }
    const bool converged = j.value("converged", false);
    return {converged, converged ? "completed" : json_text(j, "status"), json_text(j, "status_detail"), std::move(f)};
  }

  template <class B, class M>
  JobResult run_continuous(const Scene& scene, const M& m) const {
    if constexpr (!B::indirect) {
      throw InvalidInput("method", "'" + spec_.example + "' has no necessary conditions");
    } else if constexpr (!B::continuous) {
      throw InvalidInput("method", "'" + spec_.example + "' has no continuous necessary conditions");
    } else {
      const auto problem = B::transfer(m, std::get<typename M::State>(scene.ocp->target), scene.horizon.t_final);
      baselines::ContinuousShootingOptions o;
      o.W = scene.ocp->indirect.W;
      o.initial_costate = random_multiplier(scene.ocp->indirect.initial_multiplier, spec_.start);
      o.max_iterations = scene.ocp->indirect.max_iterations;
      const double cpu0 = thread_cpu_seconds();
      const auto r = B::solve_continuous(m, problem, o);
      const double cpu = thread_cpu_seconds() - cpu0;
      const ocp::ShootingSummary& S = r.summary;
      Fields f = base_fields();
      const Fields numbers = {
          {"rtol", r.rtol},
          {"solver_status", std::string(ocp::to_string(S.status))},
          {"cost", S.cost},
          {"violation", S.violation},
          {"replay_status", std::string("not replayed: the continuous extremal, its own violation and cost are "
                                        "the continuous problem's (CVODES at rtol ") +
                                shortest(r.rtol) + ")"},
          {"iterations", static_cast<std::int64_t>(S.iterations)},
          {"integrations", static_cast<std::int64_t>(r.integrations)},
          {"cpu_seconds", cpu},
      };
      f.insert(f.end(), numbers.begin(), numbers.end());
      return {S.converged(), S.converged() ? "completed" : to_string(S.status), S.brief(), std::move(f)};
    }
  }

  ComparisonSpec spec_;

 public:
  JobResult run(const JobContext& ctx) const override {
    if (!spec_.not_applicable.empty()) {
      Fields f = base_fields();
      f.push_back({"replay_status", std::string("n/a")});
      return {false, "n/a", spec_.not_applicable, std::move(f)};
    }
    const Scene scene = comparison_scene(spec_.example, ctx.scenes_dir);
    if (spec_.solver != OcpSolver::ContinuousIndirect) return run_command(ctx, scene);
    return visit_binding(scene.model, [&](auto, const auto& m) -> JobResult {
      return run_continuous<OcpBinding<std::decay_t<decltype(m)>>>(scene, m);
    });
  }
};

// --- rendering -------------------------------------------------------------------------------------

/// The rows of one example, variant and method, with their aggregate.
struct Aggregate {
  std::string example, variant, method, label;
  std::string not_applicable;  ///< the n/a row's reason
  std::size_t starts = 0, converged = 0;
  std::map<std::string, std::size_t> failed;  ///< status -> starts
  const SummaryRow* best = nullptr;           ///< the converged start of least own cost
  double median_iterations = kNoValue, median_cpu = kNoValue, total_cpu = 0.0, cpu_per_iteration = kNoValue;
};

double median_of(std::vector<double> v) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  if (v.empty()) return kNoValue;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::vector<Aggregate> aggregate(const std::vector<SummaryRow>& rows) {
  std::vector<Aggregate> out;
  std::map<std::string, std::vector<const SummaryRow*>> members;
  for (const SummaryRow& r : rows) {
    const std::string key = r.text("system") + "|" + r.text("variant") + "|" + r.text("method");
    if (members.find(key) == members.end()) {
      Aggregate a;
      a.example = r.text("system");
      a.variant = r.text("variant");
      a.method = r.text("method");
      a.label = r.text("label");
      out.push_back(a);
    }
    members[key].push_back(&r);
  }
  for (Aggregate& a : out) {
    std::vector<double> iterations, cpu, per_iteration;
    for (const SummaryRow* r : members[a.example + "|" + a.variant + "|" + a.method]) {
      if (r->text("status") == "n/a") {
        a.not_applicable = r->text("detail");
        continue;
      }
      ++a.starts;
      if (r->text("status") == "completed") {
        ++a.converged;
        if (!a.best || r->number("cost").value_or(kNoValue) < a.best->number("cost").value_or(kNoValue)) a.best = r;
      } else {
        ++a.failed[r->text("status")];
      }
      const double it = r->number("iterations").value_or(kNoValue), c = r->number("cpu_seconds").value_or(kNoValue);
      iterations.push_back(it);
      cpu.push_back(c);
      if (std::isfinite(c)) a.total_cpu += c;
      if (it > 0.0) per_iteration.push_back(c / it);
    }
    a.median_iterations = median_of(iterations);
    a.median_cpu = median_of(cpu);
    a.cpu_per_iteration = median_of(per_iteration);
  }
  return out;
}

std::string number_text(const SummaryRow* r, const char* column, const char* format = "%.3g") {
  if (!r || !r->number(column)) return "";
  char buf[48];
  std::snprintf(buf, sizeof buf, format, *r->number(column));
  return buf;
}
std::string number_text(double x, const char* format = "%.3g") {
  if (!std::isfinite(x)) return "";
  char buf[48];
  std::snprintf(buf, sizeof buf, format, x);
  return buf;
}
std::string failed_text(const Aggregate& a) {
  std::string s;
  for (const auto& [status, n] : a.failed) s += (s.empty() ? "" : "; ") + std::to_string(n) + " " + status;
  return s;
}

/// The figure's y: the replayed figure, or the method's own where it is not replayed (the
/// continuous shooting, whose own figures are the continuous problem's).
std::optional<double> yardstick(const SummaryRow& r, const std::string& what) {
  if (const auto y = r.number("replayed_" + what)) return y;
  if (r.text("method") == solver_id(OcpSolver::ContinuousIndirect)) return r.number(what);
  return std::nullopt;
}

}  // namespace

Suite ocp_comparison_suite(const SuiteParams& params) {
  Suite s;
  s.name = "ocp-comparison";
  s.description = "every optimal control method on the paper's examples: own and replayed cost and violation "
                  "against CPU time";
  s.columns = {"system",         "method",        "label",           "variant",        "start",
               "h",              "steps",         "intervals",       "rtol",           "solver_status",
               "cost",           "violation",     "replayed_cost",   "replayed_violation",
               "replayed_quaternion_drift",       "replay_status",   "iterations",     "cpu_seconds",
               "replay_cpu_seconds", "summary_path", "history_path", "trajectory_path", "knots_path"};
  const int starts = params.quick ? 2 : 8;
  for (const char* example : kExamples) {
    const Scene scene = comparison_scene(example, params.scenes_dir);
    for (const OcpSolver solver : kSolvers) {
      ComparisonSpec spec;
      spec.example = example;
      spec.solver = solver;
      spec.not_applicable = not_applicable(scene, solver);
      std::vector<std::pair<Grid, int>> runs;
      if (spec.not_applicable.empty()) {
        const int n = solver == OcpSolver::Collocation ? 1 : starts;
        for (int k = 0; k < n; ++k) runs.emplace_back(Grid::Nominal, k);
        if (!params.quick && solver != OcpSolver::ContinuousIndirect) {
          runs.emplace_back(Grid::Coarse, 0);
          runs.emplace_back(Grid::Fine, 0);
        }
      } else {
        runs.emplace_back(Grid::Nominal, 0);
      }
      for (const auto& [variant, k] : runs) {
        spec.variant = variant;
        spec.start = k;
        SuiteCase c;
        c.id = spec.id();
        c.group = example;
        c.labels = {{"system", std::string(example)},
                    {"method", std::string(solver_id(solver))},
                    {"variant", std::string(variant_name(variant))},
                    {"start", static_cast<std::int64_t>(k)}};
        // A measurement, not a test: a random start may fail (its status is a result) and so may
        // a documented guess on a coarse grid; the gate is validate's ocp-comparison group.
        c.expect = Expectation::Either;
        c.job = std::make_shared<ComparisonJob>(spec);
        s.cases.push_back(std::move(c));
      }
    }
  }

  s.render = [](const RenderContext& ctx, const std::vector<SummaryRow>& rows) {
    std::vector<fs::path> files;
    for (const auto& [example, members] : by_group(rows)) {
      for (const std::string what : {"violation", "cost"}) {
        std::vector<XyCurve> curves;
        for (const OcpSolver solver : kSolvers) {
          XyCurve c;
          c.label = solver_label(solver);
          c.style = plot_style(solver_id(solver));
          c.scatter = true;
          for (const SummaryRow* r : members) {
            if (r->text("method") != solver_id(solver) || r->text("variant") != variant_name(Grid::Nominal)) continue;
            const auto x = r->number("cpu_seconds");
            const auto y = yardstick(*r, what);
            if (x && y) c.points.emplace_back(*x, *y);
          }
          if (!c.points.empty()) curves.push_back(std::move(c));
        }
        const fs::path figure =
            plot_xy(ctx, example + "-" + what + "-cpu",
                    example + ": replayed " + what + " (gsl-rk8pd at 1e-13 on the quaternion model) against CPU time, "
                              "one point per start",
                    "CPU time per start [s]", what == "violation" ? "replayed terminal violation" : "replayed cost",
                    curves);
        if (!figure.empty()) files.push_back(figure);
      }
    }
    const std::vector<Aggregate> aggregates = aggregate(rows);
    std::string md =
        "# ocp-comparison: every optimal control method on the paper's examples\n\n"
        "Per example, discretization (h: the scene's step, collocation K = 100; 2h and h/2: K = 50 and 200) and "
        "method: starts run, starts converged by the method's own test, failed starts by status; the best converged "
        "start (least own cost): own cost and violation, replayed cost and violation (the node controls integrated on "
        "the quaternion model by gsl-rk8pd at rtol 1e-13; the continuous shooting: its own, CVODES at rtol 1e-10); "
        "median iterations and CPU time per start, CPU time per iteration (median over starts), total CPU time.\n\n"
        "| example | h | method | starts | converged | failed | own cost | own violation | replayed cost | replayed "
        "violation | iterations | CPU/start [s] | CPU/iteration [s] | CPU total [s] |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    std::string csv =
        "example,variant,method,label,starts,converged,failed,cost,violation,replayed_cost,replayed_violation,"
        "median_iterations,median_cpu_seconds,cpu_seconds_per_iteration,total_cpu_seconds,not_applicable\n";
    for (const Aggregate& a : aggregates) {
      if (!a.not_applicable.empty()) {
        md += "| " + a.example + " | | " + a.label + " | n/a: " + a.not_applicable + " | | | | | | | | | | |\n";
        csv += a.example + "," + a.variant + "," + a.method + "," + a.label + ",0,0,,,,,,,,,," + a.not_applicable + "\n";
        continue;
      }
      const SummaryRow* b = a.best;
      const bool continuous = a.method == solver_id(OcpSolver::ContinuousIndirect);
      const std::string rc = continuous ? number_text(b, "cost", "%.9g") : number_text(b, "replayed_cost", "%.9g");
      const std::string rv = continuous ? number_text(b, "violation") : number_text(b, "replayed_violation");
      const std::string cells[] = {number_text(b, "cost", "%.9g"), number_text(b, "violation"), rc, rv,
                                   number_text(a.median_iterations, "%.0f"), number_text(a.median_cpu),
                                   number_text(a.cpu_per_iteration), number_text(a.total_cpu)};
      md += "| " + a.example + " | " + a.variant + " | " + a.label + " | " + std::to_string(a.starts) + " | " +
            std::to_string(a.converged) + " | " + failed_text(a);
      csv += a.example + "," + a.variant + "," + a.method + "," + a.label + "," + std::to_string(a.starts) + "," +
             std::to_string(a.converged) + "," + failed_text(a);
      for (const std::string& cell : cells) {
        md += " | " + cell;
        csv += "," + cell;
      }
      md += " |\n";
      csv += ",\n";
    }
    files.push_back(write_text_file(ctx, "ocp-comparison-table.md", md));
    files.push_back(write_text_file(ctx, "ocp-comparison-table.csv", csv));
    return files;
  };
  return s;
}

}  // namespace lgvi::experiments::suites
