// Files the harness creates are never opened through a name someone else controls (issue 34, N1):
// anyone who can write in the output directory could plant a symlink at a temporary's name, the
// suite journal's name or a results name and make a run (often as root) overwrite or truncate the
// file it points to. Each test plants links to a victim file outside the output directory and
// checks that the victim is untouched and the outputs are right.
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <regex>

#include <gtest/gtest.h>

#include "experiments/cli/cli_support.hpp"
#include "experiments/output/atomic_file.hpp"
#include "experiments/output/csv_writer.hpp"
#include "experiments/output/plot.hpp"
#include "experiments/suites/common.hpp"
#include "experiments/suites/journal.hpp"

namespace lgvi::experiments {
namespace {

namespace fs = std::filesystem;
using test::read_text;
using test::TempDir;
using test::write_text;

/// A file outside the output directory that planted links point to.
struct Victim {
  fs::path path;
  std::string text = "victim: must stay as it is\n";
  explicit Victim(const fs::path& dir) : path(dir / "victim.txt") { write_text(path, text); }
  bool untouched() const { return fs::is_regular_file(path) && read_text(path) == text; }
};

/// Links to `victim` at every name the temporaries of this process had while they were
/// predictable, ".lgvi-tmp-<pid>-<n><ext>" (a per-process counter n), for n < 40 (the test below
/// makes 8 temporaries; the names are random now, the links sit where the old counter put them) and each extension of the
/// files it writes (a symlink costs ~3 ms on the CI disk: 240 of them, not thousands).
void plant_predictable_links(const fs::path& dir, const fs::path& victim) {
  for (const char* ext : {".csv", ".json", ".png", ".log", ".curves", ".dat"}) {
    for (int n = 0; n < 40; ++n) {
      fs::create_symlink(victim, dir / (".lgvi-tmp-" + std::to_string(::getpid()) + "-" + std::to_string(n) + ext));
    }
  }
}

/// The names in `dir` starting with ".lgvi-tmp-" that are not symlinks (temporaries left).
std::vector<std::string> temporaries_left(const fs::path& dir) {
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(".lgvi-tmp-", 0) == 0 && !e.is_symlink()) left.push_back(name);
  }
  return left;
}

TEST(FileSafety, NoTemporaryStartsAfterTheEndingProcessRemovedItsOwn) {
  // An interrupted suite removes its live temporaries and exits; a worker still in a case must not
  // create one in between (it did: SuiteResume found a .lgvi-tmp- file after a clean SIGTERM).
  // The removal closes the registry for good, so it runs in a child process.
  TempDir dir;
  const fs::path target = dir.work() / "a.csv";
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    int code = 0;
    {
      TempPath live(target);
      if (remove_live_temporaries() != 1 || fs::exists(live.path())) code = 1;
    }
    try {
      const TempPath late(target);
      code = 2;  // created after the cleanup
    } catch (const OutputError& e) {
      if (std::string(e.what()).find("the process is ending") == std::string::npos) code = 3;
    }
    std::_Exit(code);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "1: the live temporary was not removed; 2: a temporary was created after "
                                       "the cleanup; 3: another error";
  EXPECT_TRUE(temporaries_left(dir.work()).empty());
}

TEST(FileSafety, TemporaryNamesAreUnpredictableAndCreatedExclusively) {
  TempDir dir;
  const fs::path target = dir.work() / "a.csv";
  const TempPath first(target);
  const TempPath second(target);
  const std::regex pattern("\\.lgvi-tmp-" + std::to_string(::getpid()) + "-[0-9a-f]{16}\\.csv");
  EXPECT_TRUE(std::regex_match(first.path().filename().string(), pattern)) << first.path();
  EXPECT_TRUE(std::regex_match(second.path().filename().string(), pattern)) << second.path();
  // 64 random bits each, not a counter: the random parts differ.
  EXPECT_NE(first.path().filename().string().substr(0, 30), second.path().filename().string().substr(0, 30));
  // Each is the regular file its descriptor holds, created by the constructor.
  struct stat by_name {};
  struct stat by_fd {};
  ASSERT_EQ(::lstat(first.path().c_str(), &by_name), 0);
  ASSERT_EQ(::fstat(first.fd(), &by_fd), 0);
  EXPECT_TRUE(S_ISREG(by_name.st_mode));
  EXPECT_EQ(by_name.st_ino, by_fd.st_ino);
}

TEST(FileSafety, LinksPlantedAtTemporaryNamesAreNeverFollowed) {
  TempDir dir;
  const Victim victim(dir.capture());
  const fs::path out = dir.work();
  plant_predictable_links(out, victim.path);
  {  // AtomicFile (summaries, manifests, JSON), the CSV writer
    AtomicFile json(out / "run.json");
    json.write("{}\n");
    json.commit();
    CsvWriter csv(out / "run.csv", {"t", "x"});
    const double row[] = {0.0, 1.0};
    csv.write_row(row);
    csv.commit({});
  }
  EXPECT_EQ(read_text(out / "run.json"), "{}\n");
  EXPECT_NE(read_text(out / "run.csv").find("0,1\n"), std::string::npos);
  // A figure: the PNG temporary and gnuplot's log; an x-y figure: its data and curve list too.
  const fs::path csv = out / "e.csv";
  write_text(csv, "t,energy_error\n0,1e-10\n1,2e-10\n2,3e-10\n");
  render_plot(default_gnuplot(), default_plots_dir() / "energy_error.gp", out / "fig.png", "t", "t", "e", {{csv, "e"}});
  EXPECT_TRUE(is_complete_png(out / "fig.png"));
  RenderContext ctx;
  ctx.gnuplot = default_gnuplot();
  ctx.plots_dir = default_plots_dir();
  ctx.out_dir = out;
  const fs::path xy = suites::plot_xy(ctx, "xy.png", "xy", "x", "y", {suites::XyCurve{"c", {{1.0, 2.0}, {2.0, 3.0}}}});
  EXPECT_TRUE(is_complete_png(xy));
  EXPECT_TRUE(victim.untouched()) << read_text(victim.path).substr(0, 80);
  EXPECT_TRUE(temporaries_left(out).empty()) << temporaries_left(out).front();
}

TEST(FileSafety, TheSuiteJournalIsNeverOpenedThroughALink) {
  TempDir dir;
  const Victim victim(dir.capture());
  const fs::path out = dir.work();
  // A new run: the planted link is replaced by the new (empty) journal, the victim untouched.
  fs::create_symlink(victim.path, journal_path(out));
  {
    JournalWriter journal(out, /*truncate=*/true);
    journal.append(JournalEntry{0, "case", "f", "0,case", "{}", {}});
  }
  EXPECT_TRUE(victim.untouched());
  EXPECT_FALSE(fs::is_symlink(journal_path(out)));
  EXPECT_EQ(read_journal(out).size(), 1u);
  // Appending (--resume): a link, or a hard link to another file, is refused.
  fs::remove(journal_path(out));
  fs::create_symlink(victim.path, journal_path(out));
  EXPECT_THROW(JournalWriter(out, /*truncate=*/false), OutputError);
  fs::remove(journal_path(out));
  fs::create_hard_link(victim.path, journal_path(out));
  EXPECT_THROW(JournalWriter(out, /*truncate=*/false), OutputError);
  EXPECT_TRUE(victim.untouched());
}

// gnuplot is handed the descriptors of the files created for it: a name in the output directory
// swapped for a link while it runs (the race a fixed name cannot avoid) leads nowhere, and the
// swapped name is not published as the figure.
TEST(FileSafety, GnuplotWritesOnlyTheFilesCreatedForIt) {
  TempDir dir;
  const Victim victim(dir.capture());
  const fs::path out = dir.work();
  const fs::path fake = dir.scenes() / "gnuplot";
  // A gnuplot that swaps every temporary in the output directory for a link to the victim, then
  // writes a complete PNG to its output argument ($5, as `gnuplot -e FORMAT -c SCRIPT OUT ...` gives it).
  write_text(fake, "#!/bin/sh\nfor f in " + test::shell_quote(out.string()) +
                       "/.lgvi-tmp-*; do rm -f \"$f\"; ln -s " + test::shell_quote(victim.path.string()) +
                       " \"$f\"; done\nprintf '\\211PNG\\r\\n\\032\\nxxxx\\0\\0\\0\\0IEND\\256\\102\\140\\202' > \"$5\"\n"
                       "echo swapped >&2\n");
  fs::permissions(fake, fs::perms::owner_all);
  const fs::path csv = dir.capture() / "e.csv";
  write_text(csv, "t,energy_error\n0,1e-10\n1,2e-10\n");
  try {
    render_plot(fake.string(), default_plots_dir() / "energy_error.gp", out / "fig.png", "t", "t", "e", {{csv, "e"}});
    ADD_FAILURE() << "a swapped temporary was published";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("replaced"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(victim.untouched()) << read_text(victim.path).substr(0, 80);
  EXPECT_FALSE(fs::exists(out / "fig.png"));
  EXPECT_FALSE(fs::is_symlink(out / "fig.png"));
}

// /dev/stdout is a link to /proc/self/fd/1: with standard output redirected to a file it leads to
// a regular file, and a temporary in /dev renamed onto it replaced the system's /dev/stdout link.
// A name under /proc (or /dev/fd, or in /dev) is written in place (appended to), never replaced.
TEST(FileSafety, ADescriptorNameLeadingToARegularFileIsWrittenInPlace) {
  TempDir dir;
  const fs::path file = dir.work() / "redirected.txt";
  write_text(file, "before\n");
  const int fd = ::open(file.c_str(), O_WRONLY | O_APPEND);
  ASSERT_GE(fd, 0);
  const fs::path name = "/proc/self/fd/" + std::to_string(fd);
  {
    AtomicFile f(name);
    EXPECT_TRUE(f.is_stream());
    f.write("after\n");
    f.commit();
  }
  ::close(fd);
  EXPECT_EQ(read_text(file), "before\nafter\n");
  EXPECT_EQ(dir.work_entries().size(), 1u);
  EXPECT_THROW(AtomicFile("/proc/self/fd/999999"), OutputError);  // never created
}

TEST(FileSafety, AResultsNameLinkedToABlockDeviceIsRefused) {
  fs::path device;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator("/dev", ec)) {
    if (e.is_block_file(ec)) {
      device = e.path();
      break;
    }
  }
  if (device.empty()) GTEST_SKIP() << "no block device in /dev";
  TempDir dir;
  fs::create_symlink(device, dir.work() / "summary.csv");
  try {
    AtomicFile f(dir.work() / "summary.csv");
    ADD_FAILURE() << "opened " << device;
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("block device"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace lgvi::experiments
