// SIGINT and SIGTERM end every phase of a run with exit status 130 / 143 and leave no temporary
// and no unfinished file (issue 34, N6 and N10): the figure phase (gnuplot running; SIGTERM was
// ignored there, SIGINT to the process group ended as "gnuplot failed", exit 3) and `simulate`
// (which left its CSV's temporary behind), including a phase that never checks for the signal
// (the watchdog of experiments/output/interrupt.hpp ends it).
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "experiments/cli/cli_support.hpp"

namespace lgvi::test {
namespace {

using Clock = std::chrono::steady_clock;

/// lgvi-testbed started in dir.work() in a process group of its own (a signal to the group is a
/// terminal's Ctrl-C), stdout discarded, stderr in dir.capture()/stderr.
pid_t spawn(const TempDir& dir, const std::vector<std::string>& args) {
  return spawn_testbed(dir, args, dir.capture() / "stderr", [] {
    setpgid(0, 0);
    signal(SIGINT, SIG_DFL);  // as a shell starts a foreground command, whatever this test inherited
    signal(SIGTERM, SIG_DFL);
  });
}

/// Waits until `ready()` or the process exits, at most `limit` seconds; true if ready.
template <class F>
bool wait_until(pid_t pid, F ready, double limit, int* status, bool* exited) {
  const auto start = Clock::now();
  while (std::chrono::duration<double>(Clock::now() - start).count() < limit) {
    if (waitpid(pid, status, WNOHANG) == pid) {
      *exited = true;
      return false;
    }
    if (ready()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

/// The exit status after `limit` seconds at most (-1: still running, then killed).
int exit_status_within(pid_t pid, double limit) {
  int status = 0;
  const auto start = Clock::now();
  while (waitpid(pid, &status, WNOHANG) == 0) {
    if (std::chrono::duration<double>(Clock::now() - start).count() > limit) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      return -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// Every file under `dir` that is a temporary or a figure.
std::vector<std::string> leftovers(const fs::path& dir, bool figures) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : fs::recursive_directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(".lgvi-tmp-", 0) == 0 || (figures && e.path().extension() == ".png")) names.push_back(name);
  }
  return names;
}

bool has_temporary(const fs::path& dir) { return !leftovers(dir, false).empty(); }

/// A gnuplot that records its pid and sleeps (the figure phase held open), written to `path`.
void write_sleeping_gnuplot(const fs::path& path, const fs::path& pid_file) {
  write_text(path, "#!/bin/sh\necho $$ > " + shell_quote(pid_file.string()) + "\nexec sleep 30\n");
  fs::permissions(path, fs::perms::owner_all);
}

bool process_gone(pid_t pid) {
  const fs::path stat = "/proc/" + std::to_string(pid) + "/stat";
  if (!fs::exists(stat)) return true;
  const std::string text = read_text(stat);
  const std::size_t close = text.rfind(')');
  return close != std::string::npos && close + 2 < text.size() && text[close + 2] == 'Z';
}

struct Delivery {
  int signo;
  bool to_group;  // a terminal's Ctrl-C reaches gnuplot too
};

TEST(Interrupts, TheFigurePhaseEndsWith128PlusTheSignalAndLeavesNothingUnfinished) {
  for (const Delivery d : {Delivery{SIGTERM, false}, Delivery{SIGINT, false}, Delivery{SIGINT, true}}) {
    SCOPED_TRACE(std::string(d.signo == SIGTERM ? "SIGTERM" : "SIGINT") + (d.to_group ? " to the group" : ""));
    TempDir dir;
    const fs::path pid_file = dir.capture() / "gnuplot.pid";
    const fs::path gnuplot = dir.scenes() / "gnuplot";
    write_sleeping_gnuplot(gnuplot, pid_file);
    const pid_t pid = spawn(dir, {"suite", "orthogonality", "--quick", "--gnuplot", gnuplot.string(), "--out", "res"});
    ASSERT_GT(pid, 0);
    int status = 0;
    bool exited = false;
    const bool plotting = wait_until(
        pid, [&] { return fs::exists(pid_file) && !read_text(pid_file).empty(); }, 120.0, &status, &exited);
    ASSERT_TRUE(plotting) << "gnuplot never started: " << read_text(dir.capture() / "stderr");
    const pid_t gnuplot_pid = std::stoi(read_text(pid_file));
    kill(d.to_group ? -pid : pid, d.signo);
    const int code = exit_status_within(pid, 10.0);
    EXPECT_EQ(code, 128 + d.signo) << read_text(dir.capture() / "stderr");
    const std::vector<std::string> err = lines_of(read_text(dir.capture() / "stderr"));
    ASSERT_FALSE(err.empty());
    EXPECT_NE(err.back().find(d.signo == SIGTERM ? "interrupted by SIGTERM" : "interrupted by SIGINT"),
              std::string::npos)
        << err.back();
    EXPECT_TRUE(process_gone(gnuplot_pid)) << "gnuplot " << gnuplot_pid << " left running";
    const std::vector<std::string> left = leftovers(dir.work() / "res", /*figures=*/true);
    EXPECT_TRUE(left.empty()) << left.front();
    // The cases finished before the figures: their summary is whole.
    EXPECT_NE(read_text(dir.work() / "res" / "suite-run.json").find("\"complete\": true"), std::string::npos);
    if (d.signo == SIGTERM) {
      // --render-only: the same.
      fs::remove(pid_file);
      const pid_t again = spawn(dir, {"suite", "orthogonality", "--quick", "--gnuplot", gnuplot.string(), "--out",
                                      "res", "--render-only"});
      ASSERT_TRUE(wait_until(
          again, [&] { return fs::exists(pid_file) && !read_text(pid_file).empty(); }, 60.0, &status, &exited));
      kill(again, SIGTERM);
      EXPECT_EQ(exit_status_within(again, 10.0), 143) << read_text(dir.capture() / "stderr");
      EXPECT_TRUE(leftovers(dir.work() / "res", true).empty());
    }
  }
}

TEST(Interrupts, SimulateLeavesNoTemporaryAndNoCsv) {
  // A row every 1000 steps (~1 ms): the run notices the signal at its next row. With one row per
  // 10^8 steps it never looks: the watchdog ends it after its grace period.
  for (const bool rows : {true, false}) {
    for (const int signo : {SIGTERM, SIGINT}) {
      SCOPED_TRACE(std::string(signo == SIGTERM ? "SIGTERM" : "SIGINT") + (rows ? "" : ", no rows to notice it at"));
      TempDir dir;
      const std::vector<std::string> args = {"simulate", "pendulum", "--t-final", "100000", "--out", "run.csv",
                                             "--every", rows ? "1000" : "100000000"};
      const pid_t pid = spawn(dir, args);
      ASSERT_GT(pid, 0);
      int status = 0;
      bool exited = false;
      ASSERT_TRUE(wait_until(pid, [&] { return has_temporary(dir.work()); }, 30.0, &status, &exited))
          << "no temporary appeared: " << read_text(dir.capture() / "stderr");
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      kill(pid, signo);
      // Whether the run noticed the signal itself (not the watchdog) is told by its message
      // ("stopped at t = ", below), not by a clock.
      EXPECT_EQ(exit_status_within(pid, 10.0), 128 + signo) << read_text(dir.capture() / "stderr");
      EXPECT_TRUE(dir.work_entries().empty()) << "left: " << dir.work_entries().front();
      const std::vector<std::string> err = lines_of(read_text(dir.capture() / "stderr"));
      ASSERT_EQ(err.size(), 1u) << read_text(dir.capture() / "stderr");
      EXPECT_EQ(err[0].rfind(std::string("error: interrupted by ") + (signo == SIGTERM ? "SIGTERM" : "SIGINT"), 0), 0u)
          << err[0];
      if (rows) {
        EXPECT_NE(err[0].find("stopped at t = "), std::string::npos) << err[0];
      }
    }
  }
}

}  // namespace
}  // namespace lgvi::test
