#include "run_signals.hpp"

#include <signal.h>
#include <unistd.h>

namespace run_signals {
namespace {

volatile sig_atomic_t g_stop = 0;  // the signal number, 0 while none came
volatile sig_atomic_t g_tasks_running = 0;

// Async-signal-safe only: write() and _exit().
void on_signal(int sig) {
  if (!g_tasks_running || g_stop) {
    static const char kMessage[] = "fsw_app: stopped by a signal, at once\n";
    const ssize_t ignored = write(STDERR_FILENO, kMessage, sizeof kMessage - 1);
    (void)ignored;
    _exit(128 + sig);
  }
  g_stop = sig;
}

}  // namespace

void install() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

void mark_tasks_running() {
  g_tasks_running = 1;
}

int stop_signal() {
  return g_stop;
}

}  // namespace run_signals
