#include "experiments/output/interrupt.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <thread>

#include "experiments/output/atomic_file.hpp"

namespace lgvi::experiments {

namespace {

// Lock-free atomics: reading and storing them is async-signal-safe.
std::atomic<int> g_signal{0};           // the first signal of the scope, 0 if none
std::atomic<bool> g_handled{false};     // a phase noticed it (an Interrupted was made)
std::atomic<int> g_cooperative{0};      // live CooperativeInterrupts
std::atomic<int> g_wake_fd{-1};         // the write end of the watchdog's pipe
static_assert(std::atomic<int>::is_always_lock_free && std::atomic<bool>::is_always_lock_free);

extern "C" void on_interrupt(int signo) {
  const int saved = errno;
  int none = 0;
  g_signal.compare_exchange_strong(none, signo);
  const char byte = 's';
  if (const int fd = g_wake_fd.load(); fd >= 0) (void)!::write(fd, &byte, 1);
  errno = saved;
}

struct ScopeState {
  std::mutex mutex;
  int depth = 0;
  int pipe_fds[2] = {-1, -1};
  struct sigaction old_int {};
  struct sigaction old_term {};
  std::thread watchdog;
};

ScopeState& scope_state() {
  static ScopeState* s = new ScopeState;  // never destroyed: a signal may come during exit
  return *s;
}

/// Removes this process's temporaries, says why on stderr and ends with 128 + signal.
[[noreturn]] void end_process(int signo) {
  remove_live_temporaries();
  if (::ftrylockfile(stdout) == 0) {  // progress lines already written, unless stdout is busy
    std::fflush(stdout);
    ::funlockfile(stdout);
  }
  const std::string message = "error: interrupted by " + signal_name(signo) + "\n";
  (void)!::write(2, message.data(), message.size());
  std::_Exit(128 + signo);
}

/// Waits for the handler's bytes ('s') or the scope's end ('q'). After a first signal, ends the
/// process once kInterruptGraceSeconds passed without a phase handling it (unless a cooperative
/// phase is running); after a second one at once.
void watch(int read_fd) {
  sigset_t block;
  sigemptyset(&block);
  sigaddset(&block, SIGINT);
  sigaddset(&block, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &block, nullptr);  // the handler runs on the other threads
  using Clock = std::chrono::steady_clock;
  int received = 0;
  Clock::time_point deadline{};
  for (;;) {
    pollfd p{read_fd, POLLIN, 0};
    const int ready = ::poll(&p, 1, received > 0 ? 20 : -1);
    if (ready < 0 && errno != EINTR) return;
    if (ready > 0) {
      char byte = 0;
      const ssize_t n = ::read(read_fd, &byte, 1);
      if (n == 0 || byte == 'q') return;
      if (n == 1 && byte == 's' && ++received == 1) {
        deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                      std::chrono::duration<double>(kInterruptGraceSeconds));
      }
    }
    if (received >= 2) end_process(g_signal.load());
    if (received == 1 && !g_handled.load() && g_cooperative.load() == 0 && Clock::now() >= deadline) {
      end_process(g_signal.load());
    }
  }
}

}  // namespace

Interrupted::Interrupted(int signo, const std::string& detail)
    : std::runtime_error("interrupted by " + signal_name(signo) + (detail.empty() ? "" : ": " + detail)),
      signal_(signo) {
  g_handled.store(true);
}

std::string signal_name(int signo) {
  if (signo == SIGINT) return "SIGINT";
  if (signo == SIGTERM) return "SIGTERM";
  return "signal " + std::to_string(signo);
}

InterruptScope::InterruptScope() {
  ScopeState& s = scope_state();
  const std::lock_guard lock(s.mutex);
  if (s.depth++ > 0) return;
  g_signal.store(0);
  g_handled.store(false);
  if (::pipe2(s.pipe_fds, O_CLOEXEC) == 0) {
    ::fcntl(s.pipe_fds[1], F_SETFL, O_NONBLOCK);  // the handler never blocks
    g_wake_fd.store(s.pipe_fds[1]);
    s.watchdog = std::thread(watch, s.pipe_fds[0]);
  }
  struct sigaction sa {};
  sa.sa_handler = on_interrupt;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, &s.old_int);
  sigaction(SIGTERM, &sa, &s.old_term);
}

InterruptScope::~InterruptScope() {
  ScopeState& s = scope_state();
  const std::lock_guard lock(s.mutex);
  if (--s.depth > 0) return;
  sigaction(SIGINT, &s.old_int, nullptr);
  sigaction(SIGTERM, &s.old_term, nullptr);
  if (s.watchdog.joinable()) {
    const char byte = 'q';
    (void)!::write(s.pipe_fds[1], &byte, 1);
    s.watchdog.join();
  }
  g_wake_fd.store(-1);
  for (int& fd : s.pipe_fds) {
    if (fd >= 0) ::close(fd);
    fd = -1;
  }
}

CooperativeInterrupts::CooperativeInterrupts() { g_cooperative.fetch_add(1); }
CooperativeInterrupts::~CooperativeInterrupts() { g_cooperative.fetch_sub(1); }

int interrupt_signal() { return g_signal.load(); }

void throw_if_interrupted(const std::string& detail) {
  if (const int signo = g_signal.load(); signo != 0) throw Interrupted(signo, detail);
}

}  // namespace lgvi::experiments
