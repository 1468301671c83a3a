// The lgvi-testbed command line: `scenes`, `simulate`, `suite`.
#pragma once

#include <iostream>
#include <optional>
#include <string>

namespace lgvi::experiments {

/// Exit status of lgvi-testbed.
enum ExitCode : int {
  kExitOk = 0,
  kExitBadInput = 1,    ///< bad scene file or option: one "error: ..." line on stderr
  kExitRunFailed = 2,   ///< a run stopped early (rotation update failed); its CSV is written
  kExitOutputError = 3, ///< results could not be written (file system, gnuplot) or internal error
  kExitRegressed = 4,   ///< validate / suite --check-against: a metric regressed against its accepted value
  kExitInterrupted = 128,  ///< plus the signal: 130 SIGINT, 143 SIGTERM (interrupt.hpp)
};

/// Parses the arguments and runs the subcommand. Never throws: every error becomes exactly one
/// line "error: ..." on `err` and a non-zero exit code. Results go to files; progress and
/// one-line summaries to `out`.
int run_cli(int argc, const char* const* argv, std::ostream& out = std::cout, std::ostream& err = std::cerr);

/// run_cli's parse step alone: parses the arguments into the subcommand's options and checks
/// them as run_cli does before it reads or writes any file, and runs nothing. Returns the exit
/// status run_cli returns when the command line ends there (0 after --help or --version, their
/// text on `out`; 1 with one "error: ..." line on `err`), or nullopt when run_cli would go on to
/// run the subcommand. Never throws.
std::optional<int> parse_cli(int argc, const char* const* argv, std::ostream& out = std::cout,
                             std::ostream& err = std::cerr);

/// The command line as one shell-quoted string (recorded in output metadata).
std::string quote_command_line(int argc, const char* const* argv);

}  // namespace lgvi::experiments
