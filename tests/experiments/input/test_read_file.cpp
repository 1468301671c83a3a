// Input files are read whole but bounded, and only regular files are read (issue 34, N4): a
// control CSV, scene, study or accepted-values file given as /dev/zero was read until memory ran
// out, one given as a FIFO blocked for ever. Both are refused at once with one error line.
#include "experiments/input/read_file.hpp"

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "experiments/cli/cli_support.hpp"

namespace lgvi::test {
namespace {

using experiments::read_regular_file;
using experiments::UnreadableFile;
using Clock = std::chrono::steady_clock;

/// The reason read_regular_file gives for `path` ("" if it reads), and how long it took.
std::string refusal(const fs::path& path, std::size_t max_bytes, double* seconds = nullptr) {
  const auto start = Clock::now();
  std::string reason;
  try {
    (void)read_regular_file(path, max_bytes, "the test file");
  } catch (const UnreadableFile& e) {
    reason = e.reason();
    EXPECT_NE(std::string(e.what()).find(path.string() + ": cannot read the test file: "), std::string::npos) << e.what();
  }
  if (seconds != nullptr) *seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return reason;
}

fs::path make_fifo(const fs::path& path) {
  EXPECT_EQ(::mkfifo(path.c_str(), 0600), 0) << path;
  return path;
}

TEST(ReadRegularFile, RefusesFifosDevicesAndDirectoriesWithoutReading) {
  TempDir dir;
  double seconds = 0.0;
  EXPECT_EQ(refusal(make_fifo(dir.work() / "fifo"), 1024, &seconds), "is a FIFO, not a regular file");
  EXPECT_LT(seconds, 1.0);  // not blocked in open() waiting for a writer
  EXPECT_EQ(refusal("/dev/zero", 1024, &seconds), "is a character device, not a regular file");
  EXPECT_LT(seconds, 1.0);
  EXPECT_EQ(refusal(dir.work(), 1024), "is a directory");
  EXPECT_NE(refusal(dir.work() / "missing", 1024).find("No such file"), std::string::npos);
  // Through a symlink: what it leads to counts.
  fs::create_symlink("/dev/zero", dir.work() / "zero.toml");
  EXPECT_EQ(refusal(dir.work() / "zero.toml", 1024), "is a character device, not a regular file");
}

TEST(ReadRegularFile, ReadsUpToTheLimitAndRefusesMore) {
  TempDir dir;
  const fs::path file = dir.work() / "f";
  write_text(file, std::string(1024, 'x'));
  EXPECT_EQ(read_regular_file(file, 1024, "the test file"), std::string(1024, 'x'));
  EXPECT_EQ(refusal(file, 1023), "is larger than 1023 bytes (1024 bytes), the limit for the test file");
  write_text(file, "");
  EXPECT_EQ(read_regular_file(file, 1024, "the test file"), "");
  EXPECT_EQ(experiments::byte_limit_text(experiments::kMaxDataFileBytes), "64 MiB");
  EXPECT_EQ(experiments::byte_limit_text(experiments::kMaxTomlFileBytes), "1 MiB");
}

struct Bounded {
  int exit_code = -1;
  bool timed_out = false;
  double seconds = 0.0;
  std::string err;
};

/// Runs lgvi-testbed with `args` in dir.work() (stderr captured), killed after `limit` seconds:
/// a read that blocks fails the test instead of hanging it.
Bounded run_within(const TempDir& dir, const std::vector<std::string>& args, double limit = 20.0) {
  const auto start = Clock::now();
  const pid_t pid = spawn_testbed(dir, args, dir.capture() / "stderr");
  Bounded r;
  int status = 0;
  while (waitpid(pid, &status, WNOHANG) == 0) {
    if (std::chrono::duration<double>(Clock::now() - start).count() > limit) {
      r.timed_out = true;
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.err = read_text(dir.capture() / "stderr");
  return r;
}

void expect_refused(const Bounded& r, const std::vector<std::string>& needles) {
  EXPECT_FALSE(r.timed_out) << "still reading after " << r.seconds << " s";
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(lines_of(r.err).size(), 1u) << r.err;
  for (const std::string& n : needles) EXPECT_NE(r.err.find(n), std::string::npos) << "'" << n << "' not in: " << r.err;
}

TEST(ReadRegularFile, ASceneFileThatIsAFifoOrDevZeroIsRefusedPromptly) {
  TempDir dir;
  const fs::path fifo = make_fifo(dir.scenes() / "fifo.toml");
  expect_refused(run_within(dir, {"simulate", fifo.string()}), {"fifo.toml", "cannot read the scene file: is a FIFO"});
  expect_refused(run_within(dir, {"simulate", "/dev/zero"}),
                 {"/dev/zero", "cannot read the scene file: is a character device"});
  // A study file likewise.
  expect_refused(run_within(dir, {"study", fifo.string()}), {"cannot read the study file: is a FIFO"});
  EXPECT_TRUE(dir.work_entries().empty());
}

TEST(ReadRegularFile, AControlCsvThatIsAFifoOrDevZeroIsRefusedPromptly) {
  TempDir dir;
  const fs::path fifo = make_fifo(dir.scenes() / "u.csv");
  for (const std::string& samples : {fifo.string(), std::string("/dev/zero")}) {
    SCOPED_TRACE(samples);
    const fs::path scene = dir.scenes() / "controlled.toml";
    write_text(scene, read_text(default_scene_file("pendulum")) + "\n[control]\ntype = \"piecewise-linear\"\nfile = \"" +
                          samples + "\"\n");
    expect_refused(run_within(dir, {"simulate", scene.string()}),
                   {"control.file", "cannot read the control samples '" + samples + "': is a",
                    samples == "/dev/zero" ? "character device" : "FIFO"});
  }
  EXPECT_TRUE(dir.work_entries().empty());
}

TEST(ReadRegularFile, AcceptedValuesThatAreAFifoAreRefusedPromptly) {
  TempDir dir;
  const fs::path fifo = make_fifo(dir.scenes() / "accepted.txt");
  expect_refused(run_within(dir, {"validate", "--quick", "--accepted", fifo.string()}),
                 {"accepted.txt", "cannot read the accepted values: is a FIFO"});
}

}  // namespace
}  // namespace lgvi::test
