// Paths and text handed to gnuplot are inert: a leading '<' or '|' (gnuplot's "run this shell
// command" for data files, `load` and `set output`), quotes, backslashes, backquotes (command
// substitution), newlines, spaces and non-ASCII never run anything, and a figure is published
// only as a complete PNG.
#include <unistd.h>

#include <gtest/gtest.h>

#include "experiments/cli/cli_support.hpp"
#include "experiments/output/atomic_file.hpp"
#include "experiments/output/plot.hpp"
#include "experiments/suites/common.hpp"

namespace lgvi::experiments {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

/// Runs `body` with the working directory set to `dir` (relative hostile names need it).
template <class F>
void in_directory(const fs::path& dir, F&& body) {
  const fs::path before = fs::current_path();
  fs::current_path(dir);
  try {
    body();
  } catch (...) {
    fs::current_path(before);
    throw;
  }
  fs::current_path(before);
}

TEST(GnuplotSafety, PathsAreNeverCommandsOrPseudoFiles) {
  EXPECT_EQ(gnuplot_path("<touch x;y/a.csv"), "./<touch x;y/a.csv");
  EXPECT_EQ(gnuplot_path("|cat"), "./|cat");
  EXPECT_EQ(gnuplot_path("-"), "./-");
  EXPECT_EQ(gnuplot_path("$data"), "./$data");
  EXPECT_EQ(gnuplot_path("/abs/<x"), "/abs/<x");
  EXPECT_EQ(gnuplot_literal("it's `touch x`\n\"q\" \\"), "'it''s `touch x` \"q\" \\'");
  EXPECT_THROW(gnuplot_path_literal("a\nb.csv"), OutputError);
}

TEST(GnuplotSafety, IncompletePngIsDetected) {
  TempDir dir;
  const fs::path good = dir.work() / "good.png";
  const std::string head = "\x89PNG\r\n\x1a\n";
  const std::string iend("\0\0\0\0IEND\xae\x42\x60\x82", 12);
  test::write_text(good, head + "xxxx" + iend);
  EXPECT_TRUE(is_complete_png(good));
  test::write_text(dir.work() / "cut.png", head + "xxxx" + iend.substr(0, 6));  // truncated (disk full)
  EXPECT_FALSE(is_complete_png(dir.work() / "cut.png"));
  test::write_text(dir.work() / "empty.png", "");
  EXPECT_FALSE(is_complete_png(dir.work() / "empty.png"));
}

// Hostile names for the output directory, the CSV and the legend: gnuplot draws the figure and
// runs nothing (no MARKER file appears).
TEST(GnuplotSafety, HostileNamesRunNothing) {
  TempDir dir;
  in_directory(dir.work(), [&] {
    for (const std::string out_dir : {"<touch MARKER;y", "|touch MARKER;y", "dir with 'quotes\" and \\ `touch MARKER` é"}) {
      fs::create_directories(out_dir);
      const fs::path csv = fs::path(out_dir) / "<touch MARKER;'x`touch MARKER`.csv";
      test::write_text(csv, "t,energy_error\n0,1e-10\n1,2e-10\n2,3e-10\n");
      render_plot(default_gnuplot(), default_plots_dir() / "energy_error.gp", fs::path(out_dir) / "fig.png",
                  "title \"`touch MARKER`\"\n'x", "t", "e", {{csv, "`touch MARKER`'\n<touch MARKER"}});
      EXPECT_TRUE(is_complete_png(fs::path(out_dir) / "fig.png")) << out_dir;
      // The curve-list route (the scripts that `load` a generated file).
      RenderContext ctx;
      ctx.gnuplot = default_gnuplot();
      ctx.plots_dir = default_plots_dir();
      ctx.out_dir = out_dir;
      const fs::path png = suites::plot_xy(ctx, "xy.png", "`touch MARKER`", "x", "y",
                                   {suites::XyCurve{"`touch MARKER`'\"<x", {{1.0, 2.0}, {2.0, 3.0}}}});
      EXPECT_TRUE(is_complete_png(png)) << out_dir;
    }
  });
  EXPECT_FALSE(fs::exists(dir.work() / "MARKER"));
}

// The CLI end to end: the README's suite command with --out "<touch MARKER;y".
TEST(GnuplotSafety, SuiteOutputDirectoryStartingWithLessThanRunsNothing) {
  TempDir dir;
  const test::CliResult r =
      test::run_testbed(dir, {"suite", "orthogonality", "--quick", "--out", "<touch MARKER;y"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(fs::exists(dir.work() / "MARKER"));
  bool wrote_png = false;
  for (const auto& e : fs::directory_iterator(dir.work() / "<touch MARKER;y")) {
    if (e.path().extension() == ".png") wrote_png = wrote_png || is_complete_png(e.path());
  }
  EXPECT_TRUE(wrote_png);
}

}  // namespace
}  // namespace lgvi::experiments

namespace lgvi::experiments {

// A figure whose every curve is exactly 0 at every sample (a quantity conserved to the last bit,
// a body at rest; found by the Python argument fuzz: a 10-step pendulum's vertical momentum
// error) is still drawn: gnuplot cannot autoscale a log axis without a point ("all points y
// value undefined", and the suite failed), so each script counts the points first and gives such
// a figure a fixed range and a label.
TEST(GnuplotFigures, AQuantityExactlyZeroAtEverySampleIsStillDrawn) {
  test::TempDir dir;
  const fs::path csv = dir.work() / "zero.csv";
  test::write_text(csv, "t,iteration,energy_error,momentum_error,orthogonality_error\n0,0,0,0,0\n1,1,-0,0,0\n2,2,0,0,0\n");
  for (const char* script : {"energy_error.gp", "momentum.gp", "orthogonality.gp"}) {
    const fs::path png = dir.work() / (std::string(script) + ".png");
    render_plot(default_gnuplot(), default_plots_dir() / script, png, "zero", "t", "error", {{csv, "zero"}});
    EXPECT_TRUE(is_complete_png(png)) << script;
  }
  // The curve-list scripts (suites/common.cpp: plot_time_series, plot_iterations).
  const fs::path list = dir.work() / "curves.gp";
  test::write_text(list, "n = 1\narray file[n]\narray label[n]\nfile[1] = " + gnuplot_path_literal(csv) +
                             "\nlabel[1] = \"zero\"\n");
  for (const auto& [script, column] :
       {std::pair{"time_series.gp", "momentum_error"}, std::pair{"iteration_history.gp", "energy_error"}}) {
    const fs::path png = dir.work() / (std::string(script) + ".png");
    run_gnuplot_script(default_gnuplot(), default_plots_dir() / script, png,
                       {"zero", "t", "error", gnuplot_path(list), column});
    EXPECT_TRUE(is_complete_png(png)) << script;
  }
}

}  // namespace lgvi::experiments
