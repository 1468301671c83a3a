// The one palette (experiments/output/palette.hpp): a method keeps its colour, marker and line
// style in every figure, whatever the other curves and their order; the figure formats and
// their completeness checks (plot.hpp); the --format option.
#include <gtest/gtest.h>

#include <algorithm>
#include <regex>
#include <set>

#include "experiments/cli/cli_support.hpp"
#include "experiments/methods/method.hpp"
#include "experiments/output/palette.hpp"
#include "experiments/output/plot.hpp"
#include "experiments/suites/common.hpp"

namespace lgvi::experiments {
namespace {

namespace fs = std::filesystem;
using suites::curve_list_text;

/// The style line of `label` in a curve list: "colour[k] = '#..'; point[k] = P; dash[k] = D"
/// with k the label's index removed, so two lists can be compared.
std::string style_of(const std::string& list, const std::string& label) {
  const std::string label_line = "] = '" + label + "'\n";
  const std::size_t at = list.find(label_line);
  if (at == std::string::npos) return "no curve " + label;
  const std::size_t open = list.rfind('[', at);
  const std::string k = list.substr(open + 1, at - open - 1);
  std::smatch m;
  const std::regex style_line("colour\\[" + k + "\\] = ('[^']*'); point\\[" + k + "\\] = (\\d+); dash\\[" + k +
                              "\\] = (\\d+)");
  if (!std::regex_search(list, m, style_line)) return "no style for " + label;
  return std::string(m[1]) + " " + std::string(m[2]) + " " + std::string(m[3]);
}

TEST(Palette, AMethodHasOneStyleInTwoFigures) {
  test::TempDir dir;
  const fs::path a = dir.work() / "a.csv";
  const fs::path b = dir.work() / "b.csv";
  // A work-precision figure and a time-series figure: other curves, another order.
  const std::string xy = curve_list_text({{a, "LGVI order 2", plot_style("lgvi")},
                                          {a, "odeint-rk4 (quaternion)", plot_style("odeint-rk4", "quaternion")},
                                          {a, "cvode-bdf (quaternion)", plot_style("cvode-bdf", "quaternion")}});
  const std::string series = curve_list_text({{b, "cvode-bdf (quaternion)", plot_style("cvode-bdf", "quaternion")},
                                              {b, "RATTLE", plot_style("rattle")},
                                              {b, "LGVI order 2", plot_style("lgvi")}});
  for (const char* label : {"LGVI order 2", "cvode-bdf (quaternion)"}) {
    EXPECT_EQ(style_of(xy, label), style_of(series, label)) << label;
    EXPECT_EQ(style_of(xy, label).rfind("'#", 0), 0u) << style_of(xy, label);
  }
  EXPECT_NE(style_of(xy, "LGVI order 2"), style_of(xy, "cvode-bdf (quaternion)"));
}

TEST(Palette, RowsOfOneMethodInTwoSuitesGetItsStyle) {
  // Summary rows as two suites write them: the style follows method and model, not the label
  // or the row's place.
  const SummaryRow energy({{"method", "cvode-bdf"}, {"model", "quaternion"}, {"label", "cvode-bdf (quaternion)"}});
  const SummaryRow other({{"method", "cvode-bdf"}, {"model", "quaternion"}, {"label", "anything"}});
  EXPECT_EQ(suites::row_style(energy), suites::row_style(other));
  EXPECT_EQ(suites::row_style(energy), plot_style("cvode-bdf", "quaternion"));
  const SummaryRow printed({{"method", "lgvi"}, {"form", "printed"}, {"label", "LGVI (printed)"}});
  EXPECT_EQ(suites::row_style(printed), plot_style("lgvi-printed"));
  EXPECT_NE(suites::row_style(printed), plot_style("lgvi"));
}

TEST(Palette, EveryRegisteredMethodIsInTheTableAndNoTwoLookAlike) {
  std::set<std::pair<std::string, int>> seen;
  for (const MethodInfo& m : method_registry()) {
    EXPECT_TRUE(in_palette(m.name)) << m.name << " has no palette entry (experiments/output/palette.cpp)";
    const PlotStyle s = plot_style(m.name);
    EXPECT_TRUE(seen.insert({s.colour, s.point}).second) << m.name << " shares colour and marker";
  }
}

TEST(Palette, TheModelSetsTheDashOnly) {
  const PlotStyle q = plot_style("odeint-rk4", "quaternion");
  const PlotStyle m = plot_style("odeint-rk4", "matrix");
  EXPECT_EQ(q.colour, m.colour);
  EXPECT_EQ(q.point, m.point);
  EXPECT_NE(q.dash, m.dash);
}

TEST(Palette, ANameNotInTheTableIsHashedTheSameEverywhere) {
  EXPECT_FALSE(in_palette("my-own-method"));
  const PlotStyle s = plot_style("my-own-method");
  EXPECT_EQ(s, plot_style("my-own-method"));
  // FNV-1a, not std::hash: pinned, so another platform or build gives the same style.
  EXPECT_EQ(s, (PlotStyle{"#000000", 15, 3}));
  EXPECT_NE(plot_style("my-own-method"), plot_style("my-own-method-2"));
}

TEST(Palette, CurvesOfOneMethodAtTwoStepsStayApart) {
  const std::string list = curve_list_text({{"a.csv", "LGVI h = 0.01", plot_style("lgvi")},
                                            {"b.csv", "LGVI h = 0.005", plot_style("lgvi")}});
  EXPECT_NE(style_of(list, "LGVI h = 0.01"), style_of(list, "LGVI h = 0.005"));
}

TEST(FigureFormat, NamesExtensionsAndCompleteness) {
  EXPECT_EQ(figure_format_named("pdf"), FigureFormat::Pdf);
  EXPECT_EQ(figure_format_named("svg"), FigureFormat::Svg);
  EXPECT_EQ(figure_format_named("png"), FigureFormat::Png);
  EXPECT_FALSE(figure_format_named("PDF").has_value());
  EXPECT_FALSE(figure_format_named("jpeg").has_value());
  EXPECT_EQ(figure_extension(FigureFormat::Svg), ".svg");
  EXPECT_EQ(figure_format_of("out/fig.pdf"), FigureFormat::Pdf);
  EXPECT_EQ(figure_format_of("out/fig.png"), FigureFormat::Png);
}

TEST(FigureFormat, IncompletePdfAndSvgAreDetected) {
  test::TempDir dir;
  const fs::path pdf = dir.work() / "f.pdf";
  const std::string body = "%PDF-1.5\n%\xb5\xed\xae\xfb\n1 0 obj << >> endobj\nxref\n0 1\ntrailer << >>\nstartxref\n42\n";
  test::write_text(pdf, body + "%%EOF\n");
  EXPECT_TRUE(is_complete_pdf(pdf));
  EXPECT_TRUE(is_complete_figure(pdf, FigureFormat::Pdf));
  EXPECT_FALSE(is_complete_figure(pdf, FigureFormat::Png));  // a PDF is no PNG
  test::write_text(pdf, body + "%%EO");                      // truncated (disk full)
  EXPECT_FALSE(is_complete_pdf(pdf));
  test::write_text(pdf, body);
  EXPECT_FALSE(is_complete_pdf(pdf));
  test::write_text(pdf, "");
  EXPECT_FALSE(is_complete_pdf(pdf));

  const fs::path svg = dir.work() / "f.svg";
  const std::string head = "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<svg viewBox=\"0 0 10 10\">\n<g></g>\n";
  test::write_text(svg, head + "</svg>\n\n");
  EXPECT_TRUE(is_complete_svg(svg));
  EXPECT_TRUE(is_complete_figure(svg, FigureFormat::Svg));
  test::write_text(svg, head + "</sv");
  EXPECT_FALSE(is_complete_svg(svg));
  test::write_text(svg, "<html></svg>");
  EXPECT_FALSE(is_complete_svg(svg));
  test::write_text(svg, "");
  EXPECT_FALSE(is_complete_svg(svg));
}

// gnuplot draws each format through the scripts' shared terminal, and the figure is published
// (not refused as an incomplete PNG).
TEST(FigureFormat, EveryFormatIsDrawnAndPublished) {
  test::TempDir dir;
  const fs::path csv = dir.work() / "run.csv";
  test::write_text(csv, "t,energy_error\n0,0\n1,1e-10\n2,3e-10\n");
  for (const FigureFormat format : {FigureFormat::Png, FigureFormat::Pdf, FigureFormat::Svg}) {
    RenderContext ctx;
    ctx.gnuplot = default_gnuplot();
    ctx.plots_dir = default_plots_dir();
    ctx.out_dir = dir.work();
    ctx.data_dir = dir.work();
    ctx.format = format;
    const fs::path xy = suites::plot_xy(ctx, "xy", "h = 0.005", "x", "y",
                                        {suites::XyCurve{"LGVI order 2", {{1.0, 2.0}, {2.0, 3.0}, {3.0, 1e140}}}});
    EXPECT_EQ(xy, dir.work() / ("xy" + figure_extension(format)));
    EXPECT_TRUE(is_complete_figure(xy, format)) << figure_format_name(format);
    const SummaryRow row({{"csv_path", "run.csv"}, {"label", "LGVI order 2"}, {"method", "lgvi"},
                                  {"status", "completed"}, {"system", "free-body"}});
    const fs::path series = suites::plot_time_series(ctx, "series", "energy", "|E - E_0|", "energy_error", false, {&row});
    EXPECT_TRUE(is_complete_figure(series, format)) << figure_format_name(format);
  }
}

TEST(FigureFormat, AListNamesEachFormatOnceInItsOrder) {
  EXPECT_EQ(figure_formats_named("--format", "png"), std::vector<FigureFormat>{FigureFormat::Png});
  EXPECT_EQ(figure_formats_named("--format", "pdf,png,svg"),
            (std::vector<FigureFormat>{FigureFormat::Pdf, FigureFormat::Png, FigureFormat::Svg}));
  for (const char* bad : {"", "png,", ",pdf", "png,,pdf", "PNG", "png pdf"}) {
    EXPECT_THROW(figure_formats_named("--format", bad), InvalidInput) << bad;
  }
  try {
    figure_formats_named("--format", "png,pdf,png");
    ADD_FAILURE() << "a repeated format was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_STREQ(e.what(), "--format: names png twice (got 'png,pdf,png')");
  }
}

TEST(FigureFormat, ABadFormatIsOneErrorLine) {
  test::TempDir dir;
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"suite", "orthogonality", "--quick", "--format", "jpeg"},
        std::vector<std::string>{"study", "my-study.toml", "--format", "jpeg"},
        std::vector<std::string>{"figures", "--from", ".", "--format", "jpeg"}}) {
    const test::CliResult r = test::run_testbed(dir, args);
    EXPECT_EQ(r.exit_code, 1) << args.front() << ": " << r.err;
    ASSERT_EQ(r.err_lines().size(), 1u) << r.err;
    EXPECT_EQ(r.err_lines()[0], "error: --format: must be png, pdf or svg, or a comma-separated list of them (got 'jpeg')")
        << args.front();
  }
}

}  // namespace
}  // namespace lgvi::experiments
