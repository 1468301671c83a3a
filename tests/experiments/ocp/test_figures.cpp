// `lgvi-testbed figures`: the paper's Figs. 2-5 drawn from the optimal control runs. The fast
// indirect example (the pendulum, well under a second) is solved and drawn end to end; the others
// run in the harness (README's main command), not here.
#include <gtest/gtest.h>

#include "experiments/output/plot.hpp"
#include "tests/experiments/cli/cli_support.hpp"

namespace lgvi::test {
namespace {

bool is_png(const fs::path& file) {
  const std::string text = read_text(file);
  return text.size() > 8 && text.compare(1, 3, "PNG") == 0;
}

TEST(FiguresCommand, SolvesAndDrawsThePendulumFigure) {
  TempDir dir;
  const CliResult r = run_testbed(dir, {"figures", "--only", "pendulum", "--out", "figs"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  const fs::path figs = dir.work() / "figs";
  EXPECT_TRUE(is_png(figs / "fig3-pendulum.png"));
  // The figure is drawn from the files the solve wrote, which stay beside it.
  for (const char* f : {"ocp-pendulum-trajectory.csv", "ocp-pendulum-history.csv", "ocp-pendulum-summary.json"}) {
    EXPECT_TRUE(fs::is_regular_file(figs / f)) << f;
  }
  // Only the chosen system: nothing of the others.
  for (const auto& e : fs::directory_iterator(figs)) {
    EXPECT_EQ(e.path().filename().string().find("dumbbell"), std::string::npos) << e.path();
  }

  // Redrawing from those files (--from) gives the figure again without solving.
  // With --format png,pdf both files, each complete.
  const CliResult again =
      run_testbed(dir, {"figures", "--only", "pendulum", "--from", "figs", "--out", "redrawn", "--format", "png,pdf"});
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(again.out.find("ocp pendulum:"), std::string::npos) << again.out;
  EXPECT_TRUE(is_png(dir.work() / "redrawn" / "fig3-pendulum.png"));
  EXPECT_TRUE(experiments::is_complete_pdf(dir.work() / "redrawn" / "fig3-pendulum.pdf"));
}

TEST(FiguresCommand, DrawsAUsersOwnOcpScene) {
  TempDir dir;
  // A user's problem: the shipped free-body slew under another name and description, in the
  // user's directory (no paper example: the title has its own cost and violation alone).
  std::string text = read_text(experiments::default_scenes_dir() / "ocp-free-body-slew.toml");
  const std::size_t at = text.find("description = ");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, text.find('\n', at) - at, "description = \"my slew\"");
  write_text(dir.work() / "my-slew.toml", text);
  const CliResult r = run_testbed(dir, {"figures", "my-slew.toml", "--out", "figs", "--format", "png,svg"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("ocp my-slew.toml: converged"), std::string::npos) << r.out;
  EXPECT_TRUE(is_png(dir.work() / "figs" / "fig-my-slew.png"));
  EXPECT_TRUE(experiments::is_complete_svg(dir.work() / "figs" / "fig-my-slew.svg"));
  const std::string svg = read_text(dir.work() / "figs" / "fig-my-slew.svg");
  EXPECT_NE(svg.find("my slew"), std::string::npos);
  EXPECT_EQ(svg.find("paper"), std::string::npos);

  // A scene without [ocp], and scenes with --only: one error line each, nothing written.
  TempDir bad;
  const CliResult no_ocp = run_testbed(bad, {"figures", "free-body", "--out", "figs"});
  expect_bad_input(bad, no_ocp, {"free-body.toml", "ocp", "is required"});
  const CliResult both = run_testbed(bad, {"figures", "pendulum", "--only", "pendulum", "--out", "figs"});
  expect_bad_input(bad, both, {"--only"});
}

TEST(FiguresCommand, MissingInputsAreOneLineErrors) {
  TempDir dir;
  const CliResult no_dir = run_testbed(dir, {"figures", "--from", "nowhere", "--out", "figs"});
  expect_bad_input(dir, no_dir, {"--from", "nowhere", "not a directory"});

  const CliResult bad_system = run_testbed(dir, {"figures", "--only", "spinning-top"});
  expect_bad_input(dir, bad_system, {"--only", "spinning-top"});

  // A directory without the ocp files: the error names the missing file, and no figure is left.
  fs::create_directories(dir.work() / "empty");
  const CliResult missing = run_testbed(dir, {"figures", "--only", "cart-pendulum", "--from", "empty", "--out", "figs"});
  EXPECT_NE(missing.exit_code, 0);
  ASSERT_EQ(missing.err_lines().size(), 1u) << missing.err;
  EXPECT_NE(missing.err.find("ocp-cart-pendulum-trajectory.csv"), std::string::npos) << missing.err;
  EXPECT_FALSE(fs::exists(dir.work() / "figs" / "fig4-cart-pendulum.png"));
}

// Files of two runs (a run killed between writing its history and its summary): every file
// carries its run's id and the figure is refused, naming the odd file; a directory whose summary
// is missing (the run did not finish) likewise.
TEST(FiguresCommand, FilesOfTwoRunsAreRefused) {
  TempDir dir;
  ASSERT_EQ(run_testbed(dir, {"ocp", "pendulum", "--out", "a"}).exit_code, 0);
  ASSERT_EQ(run_testbed(dir, {"ocp", "pendulum", "--out", "b"}).exit_code, 0);
  const fs::path a = dir.work() / "a", b = dir.work() / "b";
  const std::string summary = read_text(a / "ocp-pendulum-summary.json");
  const std::size_t at = summary.find("\"run_id\": \"");
  ASSERT_NE(at, std::string::npos) << summary;
  const std::string id = summary.substr(at + 11, summary.find('"', at + 11) - at - 11);
  for (const char* f : {"ocp-pendulum-history.csv", "ocp-pendulum-trajectory.csv"}) {
    EXPECT_NE(read_text(a / f).find("# run_id: " + id + "\n"), std::string::npos) << f;
  }
  EXPECT_EQ(read_text(b / "ocp-pendulum-summary.json").find(id), std::string::npos) << "run ids must differ";

  fs::copy_file(b / "ocp-pendulum-history.csv", a / "ocp-pendulum-history.csv", fs::copy_options::overwrite_existing);
  const CliResult mixed = run_testbed(dir, {"figures", "--only", "pendulum", "--from", "a", "--out", "figs"});
  EXPECT_EQ(mixed.exit_code, 3) << mixed.err;
  ASSERT_EQ(mixed.err_lines().size(), 1u) << mixed.err;
  EXPECT_NE(mixed.err.find("ocp-pendulum-history.csv: from run"), std::string::npos) << mixed.err;
  EXPECT_NE(mixed.err.find("files of two runs"), std::string::npos) << mixed.err;
  EXPECT_FALSE(fs::exists(dir.work() / "figs" / "fig3-pendulum.png"));

  fs::remove(b / "ocp-pendulum-summary.json");
  const CliResult unfinished = run_testbed(dir, {"figures", "--only", "pendulum", "--from", "b", "--out", "figs"});
  EXPECT_EQ(unfinished.exit_code, 3) << unfinished.err;
  EXPECT_NE(unfinished.err.find("ocp-pendulum-summary.json: not found"), std::string::npos) << unfinished.err;
}

}  // namespace
}  // namespace lgvi::test
