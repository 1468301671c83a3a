#include "experiments/cli/cli.hpp"

#include <CLI/CLI.hpp>

#include <cstdint>
#include <filesystem>
#include <iomanip>
#include <thread>

#include "experiments/output/atomic_file.hpp"
#include "experiments/output/interrupt.hpp"
#include "validation/check_against.hpp"
#include "experiments/ocp/figures_command.hpp"
#include "experiments/suites/merge.hpp"
#include "experiments/methods/method.hpp"
#include "experiments/ocp/ocp_command.hpp"
#include "experiments/output/plot.hpp"
#include "experiments/scene/scene.hpp"
#include "experiments/methods/simulate.hpp"
#include "experiments/suites/study.hpp"
#include "experiments/suites/suite.hpp"
#include "validation/validate.hpp"

namespace lgvi::experiments {

namespace fs = std::filesystem;

namespace {

std::string one_line(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.pop_back();
  for (char& c : s) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  return s;
}

int report(std::ostream& err, const std::string& message, int code) {
  err << "error: " << one_line(message) << "\n" << std::flush;
  return code;
}

/// The help of suite's and study's --timing-jobs.
constexpr const char* kTimingJobsHelp =
    "Timed cases measured at once, at most one per core (default: --jobs); 1 keeps a core for the rest of the "
    "machine: the most reproducible timings on a shared machine (docs/suites.md, Timing)";

/// Parses --form, naming the option in the error.
LgviForm parse_form_option(const std::string& text) {
  try {
    return parse_lgvi_form(text);
  } catch (const InvalidInput&) {
    throw InvalidInput("--form", "must be 'symmetric' or 'printed' (got '" + text + "')");
  }
}

int list_scenes(const fs::path& scenes_dir, std::ostream& out) {
  const std::vector<std::string> names = scene_names(scenes_dir);
  if (names.empty()) throw SceneError(scenes_dir.string(), "", "no scene files (*.toml) in this directory");
  std::size_t width = 0;
  for (const std::string& n : names) width = std::max(width, n.size());
  for (const std::string& n : names) {
    const Scene scene = load_scene(scenes_dir / (n + ".toml"));
    out << std::left << std::setw(static_cast<int>(width) + 2) << n << scene.description << "\n";
  }
  return kExitOk;
}

}  // namespace

std::string quote_command_line(int argc, const char* const* argv) {
  std::string s;
  for (int i = 0; i < argc; ++i) {
    std::string a = argv[i];
    const bool plain = !a.empty() && a.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                                         "0123456789-_./=:,+@%") == std::string::npos;
    if (!plain) {
      std::string q = "'";
      for (const char c : a) q += (c == '\'') ? std::string("'\\''") : std::string(1, c);
      a = q + "'";
    }
    s += (i > 0 ? " " : "") + a;
  }
  return s;
}

namespace {

/// The command line: every option of every subcommand, bound to CLI11 and checked by parse(),
/// then run by run() (run_cli; parse_cli is parse() alone).
class CommandLine {
 public:
  /// Parses the arguments into the options and checks them, reading and writing no file.
  /// Returns the exit status when the command line ends here (--help, --version: 0, their text
  /// on `out`; an option CLI11 refuses: 1, one "error:" line on `err`), else nullopt. Throws
  /// InvalidInput for an option refused after parsing.
  std::optional<int> parse(int argc, const char* const* argv, std::ostream& out, std::ostream& err);
  /// Runs the parsed subcommand; throws as the subcommands do.
  int run(std::ostream& out, std::ostream& err);

 private:
  CLI::App app{"lgvi-testbed: Lie group variational integrators (LGVI) for rigid bodies.\n"
               "Runs scenes (TOML files) with the LGVI, writes CSV results, JSON summaries and plots.",
               "lgvi-testbed"};
  // The options, as CLI11 fills them (run_cli's defaults), by subcommand.
  std::string scenes_dir = default_scenes_dir().string();
  CLI::App* scenes_cmd = nullptr;

  CLI::App* sim = nullptr;
  std::string scene_arg;
  std::string csv_out;
  double h = 0.0;
  double t_final = 0.0;
  std::string form;
  std::int64_t every = 1;
  CLI::Option* h_opt = nullptr;
  CLI::Option* t_opt = nullptr;
  CLI::Option* form_opt = nullptr;
  CLI::Option* every_opt = nullptr;
  std::string method_name = "lgvi";
  std::string model_name;
  double rtol = 0.0;
  double atol = 0.0;
  CLI::Option* model_opt = nullptr;
  CLI::Option* rtol_opt = nullptr;
  CLI::Option* atol_opt = nullptr;

  // suite; study shares its run options
  CLI::App* suite_cmd = nullptr;
  std::string suite_name;
  std::string suite_out;
  std::string plots_dir = default_plots_dir().string();
  std::string gnuplot = default_gnuplot();
  std::string figure_format = "png";
  bool no_plots = false;
  bool quick = false;
  bool list_cases = false;
  bool render_only = false;
  bool resume = false;
  std::string shard_text = "0/1";
  unsigned jobs = std::max(1u, std::thread::hardware_concurrency());
  unsigned timing_jobs = 0;  // 0: as --jobs
  std::string check_against;

  CLI::App* study_cmd = nullptr;
  std::string study_file;
  std::optional<std::size_t> study_sample;

  CLI::App* validate_cmd = nullptr;
  bool validate_quick = false;
  std::string accepted_file;
  std::string validate_json;
  std::string validate_markdown;
  bool accept = false;
  std::vector<std::string> only_groups;
  bool degraded = false;
  std::vector<std::string> degrade_names;
  std::string literature_out;

  CLI::App* merge_cmd = nullptr;
  std::string merge_out;
  std::vector<std::string> merge_shards_dirs;

  OcpCommand ocp_options;
  CLI::App* ocp_cmd = nullptr;
  FiguresCommand figures_options;
  CLI::App* figures_cmd = nullptr;

  // Set by parse(): the command line as recorded in the outputs, and the checked options.
  std::string command_line;
  SceneOverrides overrides;        ///< simulate
  std::unique_ptr<Method> method;  ///< simulate
  std::vector<Degradation> degradations_planted;  ///< validate
  Shard shard;                     ///< suite, study
  std::vector<FigureFormat> formats = {FigureFormat::Png};  ///< suite, study
};

std::optional<int> CommandLine::parse(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
  app.require_subcommand(1);
  app.fallthrough();
  app.set_version_flag("--version", std::string("lgvi-testbed ") + git_describe());
  app.footer(
      "Exit status: 0 success; 1 bad input (scene file or option; one 'error:' line on stderr);\n"
      "2 a run stopped early (rotation update failed, a non-finite state, a baseline solver failed or hit\n"
      "  gimbal lock; the CSV of the completed steps is written), or a suite case did not end as expected;\n"
      "3 results could not be written (file system, gnuplot);\n"
      "4 validate or suite --check-against: a metric regressed against its accepted value;\n"
      "130, 143 interrupted by SIGINT, SIGTERM (no temporary left; a suite writes the finished cases'\n"
      "  summaries: --resume).");
  app.add_option("--scenes-dir", scenes_dir, "Directory of the named scenes (NAME.toml)")->capture_default_str();

  scenes_cmd = app.add_subcommand("scenes", "List the named scenes (name and description)");

  sim = app.add_subcommand(
      "simulate", "Run one scene with the LGVI or a baseline solver; write a CSV, print a summary line");
  sim->add_option("SCENE", scene_arg,
                  "Scene name (see 'lgvi-testbed scenes') or path to a scene file (contains '/' or ends in .toml)")
      ->required();
  sim->add_option("--out", csv_out,
                  "CSV file to write (default: SCENE_NAME.csv in the current directory; - for standard output)");
  h_opt = sim->add_option("--h", h, "Time step (replaces integration.h)");
  t_opt = sim->add_option("--t-final", t_final, "Horizon (replaces integration.t_final)");
  form_opt = sim->add_option("--form", form, "LGVI form: symmetric | printed (replaces integration.form)");
  every_opt =
      sim->add_option("--every", every, "Write every K-th step to the CSV (replaces integration.output_every)");
  std::string method_help = "Method:";
  for (const std::string& n : method_names()) method_help += " " + n;
  method_help += " (lgvi: order 2; lgvi-yoshida4, lgvi-suzuki4: composed, order 4; lgvi-yoshida6, "
                 "lgvi-kahan-li6: composed, order 6)";
  sim->add_option("--method", method_name, method_help)->capture_default_str();
  model_opt = sim->add_option(
      "--model", model_name, "Baseline's coordinate model: quaternion | quaternion-renormalized | euler | matrix");
  // The range is every adaptive method's (baselines/tolerance.hpp: above 0.1 a run is no
  // solution, below 1e-14 no step size meets the tolerance), checked where the method's options
  // are validated (make_method), for the CLI, the studies and Python alike.
  const std::string tolerance_range = baselines::kToleranceRange.text();
  rtol_opt = sim->add_option("--rtol", rtol, "Adaptive method's relative tolerance, in " + tolerance_range +
                                                 " (default 1e-6)");
  atol_opt =
      sim->add_option("--atol", atol, "Adaptive method's absolute tolerance, in " + tolerance_range + " (default: rtol)");

  suite_cmd = app.add_subcommand(
      "suite", "Run a suite of independent cases in parallel: CSV per case, summary.csv/.jsonl, figures");
  std::string suite_help = "Suite name:";
  for (const auto& [n, d] : suite_list()) suite_help += "\n  " + n + ": " + d;
  suite_cmd->add_option("SUITE", suite_name, suite_help)->required();
  suite_cmd->add_flag("--quick", quick, "The small version (minutes; CI and the README's results)");
  suite_cmd->add_option("--out", suite_out, "Output directory (default: results/SUITE)");
  suite_cmd->add_flag("--list", list_cases, "Print the case ids (of the shard) and exit");
  suite_cmd->add_option("--shard", shard_text,
                        "Run the i-th of N contiguous blocks of cases (0 <= i < N); no figures; "
                        "summaries of shards 0..N-1 concatenate")
      ->capture_default_str();
  suite_cmd->add_option("--jobs", jobs, "Cases run in parallel (default: hardware threads)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  suite_cmd->add_option("--timing-jobs", timing_jobs,
                      kTimingJobsHelp)
      ->check(CLI::PositiveNumber);
  suite_cmd->add_flag("--resume", resume,
                      "Continue the run in OUT (interrupted, killed): keep the finished cases whose files "
                      "verify, run the rest; the same suite, --quick, --shard and version only");
  suite_cmd->add_flag("--render-only", render_only,
                      "Only draw the figures and tables from OUT/summary.csv and the case CSVs (merged shards)");
  suite_cmd->add_flag("--no-plots", no_plots, "Skip the gnuplot figures and tables");
  suite_cmd->add_option("--format", figure_format, "Figure file formats: png, pdf, svg or a list (png,pdf)")->capture_default_str();
  suite_cmd->add_option("--plots-dir", plots_dir, "Directory of the gnuplot scripts")->capture_default_str();
  suite_cmd->add_option("--gnuplot", gnuplot, "gnuplot executable")->capture_default_str();
  suite_cmd->add_option("--check-against", check_against,
                        "After the run, compare OUT/summary.jsonl with DIR/summary.jsonl (an accepted run of the "
                        "same suite and form) per case and metric, timings ignored; exit 4 if a metric regressed");

  // `study FILE`: a study file's cases run by the same harness, with the suite's run options.
  study_cmd = app.add_subcommand(
      "study", "Run a study file (scenes x methods x steps or tolerances x horizons; experiments/studies/README.md) "
               "like a suite: CSV per case, summary.csv/.jsonl, figures, tables");
  study_cmd->add_option("FILE", study_file,
                        "Study file (TOML), e.g. experiments/studies/spacecraft-tumble.toml")
      ->required();
  study_cmd->add_flag("--quick", quick, "Apply the study's [quick] table (a small version)");
  study_cmd->add_option("--out", suite_out, "Output directory (default: results/NAME, NAME the study's name)");
  study_cmd->add_flag("--list", list_cases, "Print the case ids (of the shard) and exit");
  study_cmd->add_option("--sample", study_sample,
                        "A study with an [ensemble]: run only sample K (0-based), drawn exactly as in the whole run");
  study_cmd->add_option("--shard", shard_text,
                        "Run the i-th of N contiguous blocks of cases (0 <= i < N); no figures; "
                        "summaries of shards 0..N-1 concatenate ('merge' joins them)")
      ->capture_default_str();
  study_cmd->add_option("--jobs", jobs, "Cases run in parallel (default: hardware threads)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  study_cmd->add_option("--timing-jobs", timing_jobs,
                      kTimingJobsHelp)
      ->check(CLI::PositiveNumber);
  study_cmd->add_flag("--resume", resume, "Continue the run in OUT: keep the finished cases whose files verify");
  study_cmd->add_flag("--render-only", render_only, "Only draw the figures and tables from OUT/summary.csv");
  study_cmd->add_flag("--no-plots", no_plots, "Skip the gnuplot figures and tables");
  study_cmd->add_option("--format", figure_format, "Figure file formats: png, pdf, svg or a list (png,pdf)")->capture_default_str();
  study_cmd->add_option("--plots-dir", plots_dir, "Directory of the gnuplot scripts")->capture_default_str();
  study_cmd->add_option("--gnuplot", gnuplot, "gnuplot executable")->capture_default_str();

  validate_cmd = app.add_subcommand(
      "validate", "Regression gate: compute the accuracy metrics and compare them with the accepted values");
  std::string groups_help = "Run only these metric groups:";
  for (const auto& [n, d] : metric_groups()) groups_help += "\n  " + n + ": " + d;
  validate_cmd->add_flag("--quick", validate_quick, "The fast form (CI; under two minutes on 2 cores)");
  validate_cmd->add_option("--accepted", accepted_file,
                           "Accepted values (default: validation/accepted-quick.txt or accepted-full.txt; an installed "
                           "lgvi-testbed's --accept needs this file)");
  validate_cmd->add_option("--json", validate_json, "Also write the report as JSON to this file");
  validate_cmd->add_option("--markdown", validate_markdown, "Also write the report as a Markdown table");
  validate_cmd->add_flag("--accept", accept,
                         "Rewrite the accepted file (--accepted; in a source checkout, the default) with the values now "
                         "and print what changed (exit 0)");
  validate_cmd->add_option("--only", only_groups, groups_help)->delimiter(',');
  std::string degrade_help = "Plant these defects on purpose, to show that the gate catches them (exit 4):";
  for (const DegradationInfo& d : degradations()) degrade_help += "\n  " + std::string(d.name) + ": " + d.plants;
  validate_cmd->add_option("--degrade", degrade_names, degrade_help)->delimiter(',');
  validate_cmd->add_flag("--degraded-rotation-update", degraded, "The same as --degrade rotation-update");
  validate_cmd->add_option("--write-literature-references", literature_out,
                           "Compute the literature problems' references again (closed forms at each scene's "
                           "t_final, checked against gsl-rk8pd at rtol 1e-13) and write them to this file "
                           "(validation/literature_references.toml); computes no metric");
  merge_cmd = app.add_subcommand(
      "merge", "Join the output directories of the shards of one suite run (suite --shard i/N) into OUT");
  merge_cmd->add_option("OUT", merge_out, "Directory to write the merged run into")->required();
  merge_cmd->add_option("SHARD_DIR", merge_shards_dirs,
                        "The shards' output directories, all N of them (any order); each must be complete")
      ->required();

  ocp_cmd = add_ocp_command(app, ocp_options);
  figures_cmd = add_figures_command(app, figures_options);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e, out, err);  // --help, --version
    return report(err, std::string(e.what()) + " (see lgvi-testbed --help)", kExitBadInput);
  }
  command_line = quote_command_line(argc, argv);

  // The checks of the chosen subcommand's options that read no file, in run_cli's order.
  if (validate_cmd->parsed() && literature_out.empty()) {
    if (degraded) degradations_planted.push_back(Degradation::RotationUpdate);
    for (const std::string& name : degrade_names) degradations_planted.push_back(parse_degradation(name));
    if (accept && (!only_groups.empty() || !degradations_planted.empty())) {
      throw InvalidInput("--accept", "accepts the complete default set only (no --only, no --degrade)");
    }
  }
  if (sim->parsed()) {
    if (h_opt->count() > 0) overrides.h = h;
    if (t_opt->count() > 0) overrides.t_final = t_final;
    if (form_opt->count() > 0) overrides.form = parse_form_option(form);
    if (every_opt->count() > 0) overrides.output_every = every;
    MethodOptions method_options;
    if (model_opt->count() > 0) method_options.model = model_name;
    if (rtol_opt->count() > 0) method_options.rtol = rtol;
    if (atol_opt->count() > 0) method_options.atol = atol;
    const MethodInfo& method_kind = method_info(method_name);
    if (form_opt->count() > 0 && !method_kind.takes_form) {
      throw InvalidInput("--form", "applies to the LGVI only (--method lgvi; the composed lgvi-* are symmetric)");
    }
    try {
      method = method_kind.make(method_options);
    } catch (const InvalidInput& e) {
      // The options as the command line names them: "--rtol: is below round-off ...".
      const std::string& f = e.field();
      if (f != "rtol" && f != "atol" && f != "model") throw;
      const std::string what = e.what();
      throw InvalidInput("--" + f, what.substr(std::min(what.size(), f.size() + 2)));
    }
  }
  if (suite_cmd->parsed() || study_cmd->parsed()) {
    shard = parse_shard(shard_text);
    formats = figure_formats_named("--format", figure_format);
  }
  return std::nullopt;
}

int CommandLine::run(std::ostream& out, std::ostream& err) {
  if (scenes_cmd->parsed()) return list_scenes(scenes_dir, out);
  if (validate_cmd->parsed() && !literature_out.empty()) {
    const std::vector<LiteratureReference> refs = compute_literature_references(scenes_dir);
    const std::string header =
        "The literature problems' stored references, read by `lgvi-testbed validate` (group literature).\n"
        "Written by `lgvi-testbed validate --write-literature-references FILE` (" + std::string(git_describe()) +
        "): for each\nscene, its state at t_final (R body to inertial, Omega body frame) by the closed form,\n"
        "checked against an independent integration; agreement is their final-state distance\n"
        "(max of ||dR||_F and |dOmega| / |Omega|), digits = floor(-log10(agreement)).";
    AtomicFile file(literature_out);
    file.write(literature_references_toml(refs, header));
    file.commit();
    out << "wrote " << refs.size() << " literature references to " << literature_out << "\n";
    return kExitOk;
  }
  if (validate_cmd->parsed()) {
    ValidateOptions options;
    options.quick = validate_quick;
    options.only = only_groups;
    options.scenes_dir = scenes_dir;
    options.degraded = degradations_planted;
    const fs::path file = accept ? accept_destination(accepted_file, validate_quick)
                          : accepted_file.empty() ? default_accepted_file(validate_quick) : fs::path(accepted_file);
    const AcceptedFile before = read_accepted(file, /*missing_is_empty=*/accept);
    const std::string form = validate_quick ? "quick" : "full";
    if (!before.form.empty() && before.form != form) {
      throw InvalidInput(file.string(), "holds the " + before.form + " form's values; this run is the " + form +
                                            " form (" + (validate_quick ? "with" : "without") + " --quick)");
    }
    const std::vector<Metric> metrics = compute_metrics(options, out);
    ValidateReport result = compare(metrics, before, only_groups);
    result.form = form;
    result.version = git_describe();
    print_report(result, out);
    if (!validate_json.empty()) write_report_json(result, validate_json);
    if (!validate_markdown.empty()) write_report_markdown(result, validate_markdown);
    if (accept) {
      write_accepted(file, metrics, form, git_describe());
      const std::vector<std::string> diff = accepted_diff(before, metrics);
      out << "accepted " << metrics.size() << " metrics into " << file.string() << " (" << diff.size()
          << " changed):\n";
      for (const std::string& line : diff) out << "  " << line << "\n";
      return kExitOk;
    }
    return result.failed() ? kExitRegressed : kExitOk;
  }
  if (merge_cmd->parsed()) {
    std::vector<fs::path> dirs(merge_shards_dirs.begin(), merge_shards_dirs.end());
    merge_shards(merge_out, dirs, out);
    return kExitOk;
  }
  if (ocp_cmd->parsed()) return run_ocp_command(ocp_options, command_line, out, err);
  if (figures_cmd->parsed()) return run_figures_command(figures_options, command_line, out, err);

  if (sim->parsed()) {
    const Scene scene = load_scene(resolve_scene(scene_arg, scenes_dir), overrides);
    const fs::path csv = csv_out.empty() ? fs::path(scene.name + ".csv") : fs::path(csv_out);
    const RunSummary summary = simulate(scene, *method, {csv, command_line, {}, /*stop_on_interrupt=*/true});
    if (!summary.stats.ok()) {
      return report(err, scene.name + ": " + summary.stats.brief() + " (CSV of the completed steps: " +
                             csv.string() + ")",
                    kExitRunFailed);
    }
    // With --out - the CSV is standard output: the one-line summary goes to standard error.
    (csv == "-" ? err : out) << summary.stats.brief() << "\n";
    return kExitOk;
  }

  if (suite_cmd->parsed() || study_cmd->parsed()) {
    const bool is_study = study_cmd->parsed();
    const Suite suite = is_study ? load_study(study_file, SuiteParams{quick, scenes_dir, study_sample})
                                 : make_suite(suite_name, SuiteParams{quick, scenes_dir});
    if (is_study) suite_name = suite.name;
    const char* kind = is_study ? "study " : "suite ";
    if (list_cases) {
      for (const std::size_t i : shard_cases(suite.cases.size(), shard)) out << suite.cases[i].id << "\n";
      return kExitOk;
    }
    SuiteOptions options;
    options.out_dir = suite_out.empty() ? fs::path("results") / suite_name : fs::path(suite_out);
    options.scenes_dir = scenes_dir;
    options.plots_dir = plots_dir;
    options.gnuplot = gnuplot;
    options.formats = formats;
    options.plots = !no_plots;
    options.command_line = command_line;
    options.shard = shard;
    options.jobs = jobs;
    options.timing_jobs = timing_jobs;
    if (render_only && resume) throw InvalidInput("--resume", "runs cases; --render-only runs none");
    options.resume = resume;
    if (render_only) {
      const std::vector<fs::path> files = render_suite(suite, options);
      out << "wrote " << files.size() << " figures and tables in " << options.out_dir.string() << "\n";
      return kExitOk;
    }
    options.quick = quick;
    if (!check_against.empty() && !fs::exists(fs::path(check_against) / "summary.jsonl")) {
      throw InvalidInput("--check-against", (fs::path(check_against) / "summary.jsonl").string() + " does not exist");
    }
    const SuiteResult result = run_suite(suite, options, out);
    if (!check_against.empty()) {
      ValidateReport check = check_suite_against(options.out_dir, check_against, suite_name, quick);
      print_report(check, out);
      if (check.failed()) {
        return report(err, "suite " + suite_name + ": " + std::to_string(check.count(Verdict::Regressed)) +
                               " metrics regressed against " + check_against, kExitRegressed);
      }
    }
    if (!result.all_ok()) {
      std::string which;
      for (const CaseOutcome& c : result.cases) {
        if (!c.as_expected && which.size() < 200) which += (which.empty() ? "" : ", ") + c.id;
      }
      return report(err, kind + suite_name + ": " + std::to_string(result.unexpected()) + " of " +
                             std::to_string(result.cases.size()) + " cases did not end as expected (" + which +
                             "; see summary.csv)",
                    kExitRunFailed);
    }
    return kExitOk;
  }
  return report(err, "no subcommand (see lgvi-testbed --help)", kExitBadInput);
}

/// The exit status and error line of the exception being handled.
int report_exception(std::ostream& err) {
  try {
    throw;
  } catch (const Interrupted& e) {
    remove_live_temporaries();  // those of objects not destroyed by the unwinding (none expected)
    return report(err, e.what(), kExitInterrupted + e.signal());
  } catch (const SceneError& e) {
    return report(err, e.what(), kExitBadInput);
  } catch (const InvalidInput& e) {
    return report(err, e.what(), kExitBadInput);
  } catch (const OutputError& e) {
    return report(err, e.what(), kExitOutputError);
  } catch (const std::exception& e) {
    return report(err, std::string("internal error: ") + e.what(), kExitOutputError);
  } catch (...) {
    return report(err, "internal error: unknown exception", kExitOutputError);
  }
}

}  // namespace

int run_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
  try {
    CommandLine command;
    if (const std::optional<int> code = command.parse(argc, argv, out, err)) return *code;
    // SIGINT/SIGTERM during any command (interrupt.hpp): a phase that checks stops and throws
    // Interrupted (caught in report_exception); any other is ended by the watchdog. Exit status
    // 128 + signal.
    const InterruptScope interrupt_scope;
    return command.run(out, err);
  } catch (...) {
    return report_exception(err);
  }
}

std::optional<int> parse_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
  try {
    CommandLine command;
    return command.parse(argc, argv, out, err);
  } catch (...) {
    return report_exception(err);
  }
}

}  // namespace lgvi::experiments
