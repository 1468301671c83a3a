// SIGINT and SIGTERM during a run: one mechanism for every phase (docs/cli.md, Interrupts).
//
// While an InterruptScope lives (the CLI holds one around every command, run_suite one of its
// own), SIGINT and SIGTERM are caught: the handler records the signal (interrupt_signal()) and
// wakes a watchdog thread. A phase that checks interrupt_signal() reacts itself: it stops its
// work (a child gnuplot killed and reaped), throws Interrupted, destructors remove its temporaries
// and the CLI ends with 128 + signal (130 for SIGINT, 143 for SIGTERM). A phase that never
// checks (an optimal control solve, validate's metrics) is ended by the watchdog after
// kInterruptGraceSeconds: it removes this process's live temporaries (remove_live_temporaries)
// and ends the process with the same status, so no phase ignores a signal and none leaves a
// temporary behind. A second signal ends the process at once the same way. While a
// CooperativeInterrupts lives (the suite runner, which writes what finished before it exits),
// the watchdog waits for the phase, and only a second signal ends the process at once.
#pragma once

#include <csignal>
#include <stdexcept>
#include <string>

namespace lgvi::experiments {

/// Seconds the watchdog gives a phase to notice a signal before it ends the process itself.
inline constexpr double kInterruptGraceSeconds = 1.0;

/// A phase noticed SIGINT or SIGTERM and stopped. The CLI ends with exit status 128 + signal().
class Interrupted : public std::runtime_error {
 public:
  /// what(): "interrupted by SIGTERM" and `detail` after ": " when not empty. Constructing one
  /// tells the watchdog the interrupt is being handled.
  explicit Interrupted(int signo, const std::string& detail = "");
  int signal() const { return signal_; }

 private:
  int signal_;
};

/// "SIGINT", "SIGTERM", or "signal N".
std::string signal_name(int signo);

/// SIGINT and SIGTERM caught while one lives (scopes nest; the outermost installs the handlers
/// and the watchdog, and restores the previous actions). Entering the outermost scope clears
/// interrupt_signal().
class InterruptScope {
 public:
  InterruptScope();
  ~InterruptScope();
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;
};

/// While one lives, the phase promises to check interrupt_signal() and end the run itself: the
/// watchdog does not end the process after the grace period (a second signal still does).
class CooperativeInterrupts {
 public:
  CooperativeInterrupts();
  ~CooperativeInterrupts();
  CooperativeInterrupts(const CooperativeInterrupts&) = delete;
  CooperativeInterrupts& operator=(const CooperativeInterrupts&) = delete;
};

/// The first SIGINT or SIGTERM received inside a scope, 0 if none (async-signal-safe to read).
int interrupt_signal();

/// Throws Interrupted(interrupt_signal(), detail) if a signal was received.
void throw_if_interrupted(const std::string& detail = "");

}  // namespace lgvi::experiments
