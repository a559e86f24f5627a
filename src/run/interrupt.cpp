// SIGINT and SIGTERM as a flag (async-signal-safe: the handler stores to
// lock-free atomics and does nothing else).
#include "run/interrupt.h"

#include <signal.h>

#include <cassert>

namespace robophi {

namespace {

static_assert(std::atomic<bool>::is_always_lock_free && std::atomic<int>::is_always_lock_free,
              "the signal handler needs lock-free atomics");

std::atomic<bool> gRequested{false};
std::atomic<int> gSignal{0};
bool gInstalled = false;
struct sigaction gPreviousInt, gPreviousTerm;

void onSignal(int signalNumber) {
  int none = 0;
  gSignal.compare_exchange_strong(none, signalNumber);
  gRequested.store(true);
}

}  // namespace

InterruptGuard::InterruptGuard() {
  assert(!gInstalled && "one InterruptGuard at a time");
  gRequested.store(false);
  gSignal.store(0);
  struct sigaction action {};
  action.sa_handler = onSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;  // file writes in progress carry on
  sigaction(SIGINT, &action, &gPreviousInt);
  sigaction(SIGTERM, &action, &gPreviousTerm);
  gInstalled = true;
}

InterruptGuard::~InterruptGuard() {
  // After a caught signal the process is ending because of it: a further
  // signal must not kill it while it finishes (and its exit code says which).
  if (!gRequested.load()) {
    sigaction(SIGINT, &gPreviousInt, nullptr);
    sigaction(SIGTERM, &gPreviousTerm, nullptr);
  }
  gInstalled = false;
}

const std::atomic<bool>& InterruptGuard::flag() { return gRequested; }

int InterruptGuard::caughtSignal() { return gSignal.load(); }

}  // namespace robophi
