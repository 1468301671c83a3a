#include "experiments/output/plot.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <algorithm>
#include <fstream>

#include "experiments/output/atomic_file.hpp"
#include "experiments/output/data_dir.hpp"
#include "experiments/output/interrupt.hpp"
#include "lgvi/inertia.hpp"

extern char** environ;

namespace lgvi::experiments {

namespace fs = std::filesystem;

fs::path default_plots_dir() { return data_dir("plots", "experiments/plots"); }
std::string default_gnuplot() { return LGVI_GNUPLOT; }

namespace {

std::string first_line(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  // gnuplot echoes the offending script line before the message; keep the first non-blank one
  // that says something ("line N: ...") when there is one.
  std::string first;
  while (std::getline(in, line)) {
    if (line.find_first_not_of(" \t^") == std::string::npos) continue;
    if (first.empty()) first = line;
    if (line.find("line ") != std::string::npos) return line;
  }
  return first.empty() ? "no message" : first;
}

}  // namespace

std::string gnuplot_path(const fs::path& path) {
  const std::string p = path.string();
  if (path.is_absolute()) return p;
  return "./" + p;
}

std::string gnuplot_literal(const std::string& text) {
  std::string q = "'";
  for (const char c : text) {
    if (c == '\'') {
      q += "''";
    } else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      q += ' ';
    } else {
      q += c;
    }
  }
  return q + "'";
}

std::string gnuplot_path_literal(const fs::path& path) {
  const std::string p = gnuplot_path(path);
  for (const char c : p) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      throw OutputError(path.string() + ": a path with a control character cannot be handed to gnuplot");
    }
  }
  return gnuplot_literal(p);
}

const char* figure_format_name(FigureFormat format) {
  switch (format) {
    case FigureFormat::Pdf:
      return "pdf";
    case FigureFormat::Svg:
      return "svg";
    case FigureFormat::Png:
      break;
  }
  return "png";
}

std::optional<FigureFormat> figure_format_named(std::string_view name) {
  for (const FigureFormat f : {FigureFormat::Png, FigureFormat::Pdf, FigureFormat::Svg}) {
    if (name == figure_format_name(f)) return f;
  }
  return std::nullopt;
}

std::vector<FigureFormat> figure_formats_named(const std::string& option, std::string_view list) {
  std::vector<FigureFormat> formats;
  std::size_t begin = 0;
  while (true) {
    const std::size_t comma = list.find(',', begin);
    const std::string_view word = list.substr(begin, comma == std::string_view::npos ? std::string_view::npos : comma - begin);
    const std::optional<FigureFormat> format = figure_format_named(word);
    if (!format) {
      throw InvalidInput(option, "must be png, pdf or svg, or a comma-separated list of them (got '" + std::string(list) + "')");
    }
    if (std::find(formats.begin(), formats.end(), *format) != formats.end()) {
      throw InvalidInput(option, "names " + std::string(word) + " twice (got '" + std::string(list) + "')");
    }
    formats.push_back(*format);
    if (comma == std::string_view::npos) break;
    begin = comma + 1;
  }
  return formats;
}

std::string figure_extension(FigureFormat format) { return std::string(".") + figure_format_name(format); }

FigureFormat figure_format_of(const fs::path& file) {
  const std::string ext = file.extension().string();
  if (ext == ".pdf") return FigureFormat::Pdf;
  if (ext == ".svg") return FigureFormat::Svg;
  return FigureFormat::Png;
}

namespace {

/// The first `n` bytes of `file` and its last `n` (fewer when the file is shorter); false when
/// the file cannot be read.
bool head_and_tail(const fs::path& file, std::size_t n, std::string& head, std::string& tail) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return false;
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) return false;
  const std::size_t take = std::min<std::size_t>(n, static_cast<std::size_t>(size));
  head.assign(take, '\0');
  tail.assign(take, '\0');
  in.seekg(0);
  if (!in.read(head.data(), static_cast<std::streamsize>(take))) return false;
  in.seekg(size - static_cast<std::streamoff>(take));
  return static_cast<bool>(in.read(tail.data(), static_cast<std::streamsize>(take)));
}

bool blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

std::string_view trim_end(std::string_view s) {
  while (!s.empty() && blank(s.back())) s.remove_suffix(1);
  return s;
}

std::string_view trim_start(std::string_view s) {
  while (!s.empty() && blank(s.front())) s.remove_prefix(1);
  return s;
}

bool ends_with(std::string_view s, std::string_view end) {
  return s.size() >= end.size() && s.substr(s.size() - end.size()) == end;
}

}  // namespace

bool is_complete_pdf(const fs::path& file) {
  std::string head, tail;
  if (!head_and_tail(file, 64, head, tail)) return false;
  return head.rfind("%PDF-", 0) == 0 && ends_with(trim_end(tail), "%%EOF");
}

bool is_complete_svg(const fs::path& file) {
  std::string head, tail;
  if (!head_and_tail(file, 256, head, tail)) return false;
  const std::string_view start = trim_start(head);
  const bool opens = start.rfind("<?xml", 0) == 0 || start.rfind("<svg", 0) == 0;
  return opens && ends_with(trim_end(tail), "</svg>");
}

bool is_complete_figure(const fs::path& file, FigureFormat format) {
  switch (format) {
    case FigureFormat::Pdf:
      return is_complete_pdf(file);
    case FigureFormat::Svg:
      return is_complete_svg(file);
    case FigureFormat::Png:
      break;
  }
  return is_complete_png(file);
}

std::string wrap_text(const std::string& text, std::size_t width) {
  std::string out;
  std::size_t line = 0;
  std::size_t i = 0;
  while (i < text.size()) {
    const std::size_t space = text.find(' ', i);
    const std::string word = text.substr(i, space == std::string::npos ? std::string::npos : space - i);
    if (line > 0 && line + 1 + word.size() > width) {
      out += '\n';
      line = 0;
    } else if (line > 0) {
      out += ' ';
      ++line;
    }
    out += word;
    line += word.size();
    if (space == std::string::npos) break;
    i = space + 1;
  }
  return out;
}

bool is_complete_png(const fs::path& file) {
  static constexpr unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  // The last chunk: length 0, type IEND, CRC ae 42 60 82.
  static constexpr unsigned char kEnd[12] = {0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xae, 0x42, 0x60, 0x82};
  std::ifstream in(file, std::ios::binary);
  unsigned char head[8], tail[12];
  if (!in.read(reinterpret_cast<char*>(head), sizeof head)) return false;
  if (!in.seekg(-static_cast<std::streamoff>(sizeof tail), std::ios::end)) return false;
  if (!in.read(reinterpret_cast<char*>(tail), sizeof tail)) return false;
  return std::equal(head, head + 8, kSignature) && std::equal(tail, tail + 12, kEnd);
}

void render_plot(const std::string& gnuplot, const fs::path& script, const fs::path& png,
                 const std::string& title, const std::string& xlabel, const std::string& ylabel,
                 const std::vector<Curve>& curves) {
  std::vector<std::string> args = {title, xlabel, ylabel};
  for (const Curve& c : curves) {
    args.push_back(gnuplot_path(c.csv));
    args.push_back(c.label);
  }
  run_gnuplot_script(gnuplot, script, png, args);
}

void run_gnuplot_script(const std::string& gnuplot, const fs::path& script, const fs::path& png,
                        const std::vector<std::string>& script_args, const std::vector<const TempPath*>& inputs) {
  std::error_code ec;
  if (!fs::is_regular_file(script, ec)) throw OutputError(script.string() + ": gnuplot script not found");
  // Both created here, exclusively (TempPath); gnuplot writes the figure through the inherited
  // descriptor's /proc/self/fd name and its messages to the log as its standard error: it never
  // opens a name in the output directory that someone else could have replaced.
  TempPath out(png);
  TempPath log(png.string() + ".log");
  // The output goes through the temporary's descriptor name, which has no extension: the format
  // is handed over as a variable the scripts' terminal.gp reads (a fixed word, never a path).
  const FigureFormat format = figure_format_of(png);
  std::vector<std::string> args = {gnuplot, "-e", std::string("lgvi_format = '") + figure_format_name(format) + "'",
                                   "-c", gnuplot_path(script), gnuplot_path(out.fd_path())};
  args.insert(args.end(), script_args.begin(), script_args.end());
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::vector<int> inherited = {out.fd()};
  for (const TempPath* t : inputs) inherited.push_back(t->fd());

  // fork + exec rather than posix_spawn: the child asks the kernel for SIGTERM when this thread
  // (which waits for it below) dies, so killing the harness, even with SIGKILL, never leaves
  // gnuplot running. Between fork and exec the child calls async-signal-safe functions only.
  const pid_t parent = ::getpid();
  const int log_fd = log.fd();
  const pid_t pid = fork();
  if (pid < 0) throw OutputError(png.string() + ": cannot run " + gnuplot + ": " + std::strerror(errno));
  if (pid == 0) {
    if (prctl(PR_SET_PDEATHSIG, SIGTERM) != 0 || getppid() != parent) _exit(126);
    // The caught SIGINT/SIGTERM are reset by exec; a mask the parent's threads set is not.
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, nullptr);
    const int in = open("/dev/null", O_RDONLY | O_CLOEXEC);
    const int out_fd = open("/dev/null", O_WRONLY | O_CLOEXEC);
    if (in < 0 || out_fd < 0 || dup2(in, 0) < 0 || dup2(out_fd, 1) < 0 || dup2(log_fd, 2) < 0) _exit(126);
    for (const int fd : inherited) {
      if (fcntl(fd, F_SETFD, 0) != 0) _exit(126);  // kept across exec: /proc/self/fd/N names it
    }
    execve(gnuplot.c_str(), argv.data(), environ);
    const char msg[] = "cannot execute gnuplot\n";
    (void)!write(2, msg, sizeof msg - 1);
    _exit(127);
  }
  // Waits in steps of 5 ms, watching for SIGINT/SIGTERM (interrupt.hpp): then gnuplot is ended
  // (SIGTERM, SIGKILL after a second), reaped, and Interrupted thrown; the temporaries (the
  // unfinished figure, the log, the inputs) are removed on the way out.
  int status = 0;
  int interrupted_by = 0;
  const auto reap = [&](int options) {
    for (;;) {
      const pid_t r = waitpid(pid, &status, options);
      if (r >= 0 || errno != EINTR) return r;
    }
  };
  for (;;) {
    const pid_t r = reap(WNOHANG);
    if (r == pid) break;
    if (r < 0) throw OutputError(png.string() + ": waiting for gnuplot: " + std::strerror(errno));
    if (const int signo = interrupt_signal(); signo != 0) {
      interrupted_by = signo;
      kill(pid, SIGTERM);
      for (int i = 0; i < 200 && reap(WNOHANG) == 0; ++i) usleep(5000);
      if (reap(WNOHANG) == 0) {
        kill(pid, SIGKILL);
        (void)reap(0);
      }
      break;
    }
    usleep(5000);
  }
  // A signal to the whole process group (Ctrl-C) reaches gnuplot too: it dies of it, and this
  // process's handler has recorded it by the time the child's death is seen.
  if (interrupted_by == 0) interrupted_by = interrupt_signal();
  if (interrupted_by != 0) {
    throw Interrupted(interrupted_by, "gnuplot stopped while drawing " + png.string() + " (no figure written)");
  }
  const bool exited_ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
  if (!exited_ok) {
    throw OutputError(png.string() + ": gnuplot " + script.filename().string() + " failed: " + first_line(log.fd_path()));
  }
  if (!is_complete_figure(out.fd_path(), format)) {
    struct stat st {};
    const long long size = fstat(out.fd(), &st) == 0 ? static_cast<long long>(st.st_size) : -1;
    const char* missing = format == FigureFormat::Pdf   ? "no %%EOF at the end"
                          : format == FigureFormat::Svg ? "no closing </svg>"
                                                        : "no IEND chunk";
    std::string kind = figure_format_name(format);
    for (char& c : kind) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    throw OutputError(png.string() + ": gnuplot " + script.filename().string() + " exited 0 but wrote an incomplete " +
                      kind + " (" + std::to_string(size) + " bytes, " + missing + ": disk full?)");
  }
  throw_if_interrupted("after gnuplot drew " + png.string() + " (not published)");
  out.commit();
}

}  // namespace lgvi::experiments
