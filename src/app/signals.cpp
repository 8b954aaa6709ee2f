// SPDX-License-Identifier: BSD-3-Clause
// SIGINT/SIGTERM handling: async-signal-safe handler that only stores the
// signal number; everything else happens in the run loop.
#include <nacre/app/signals.hpp>

#include <atomic>
#include <csignal>

namespace nacre::app {

namespace {
std::atomic<int> g_signal{0};
static_assert(std::atomic<int>::is_always_lock_free, "the signal flag must be lock-free to be set in a handler");

extern "C" void nacre_on_signal(int sig) {
  int expected = 0;
  g_signal.compare_exchange_strong(expected, sig);
}

struct sigaction g_old_int, g_old_term;
}  // namespace

SignalGuard::SignalGuard() {
  g_signal.store(0);
  struct sigaction sa{};
  sa.sa_handler = nacre_on_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESETHAND | SA_RESTART;  // a second signal takes the default action
  sigaction(SIGINT, &sa, &g_old_int);
  sigaction(SIGTERM, &sa, &g_old_term);
}

SignalGuard::~SignalGuard() {
  sigaction(SIGINT, &g_old_int, nullptr);
  sigaction(SIGTERM, &g_old_term, nullptr);
}

int pending_signal() { return g_signal.load(std::memory_order_relaxed); }

const char* signal_name(int sig) {
  switch (sig) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    default: return "a signal";
  }
}

}  // namespace nacre::app
