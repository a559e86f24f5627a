#pragma once
/// \file
/// Ending a run cleanly on SIGINT (Ctrl-C) and SIGTERM: while an InterruptGuard
/// lives, those signals set a flag instead of killing the process; the runner
/// checks it between steps (RunOptions::stop) and writes the results so far.

#include <atomic>

namespace robophi {

/// Catches SIGINT and SIGTERM while it lives (the handlers are process-wide:
/// one guard at a time) and restores the previous handlers when it goes, unless
/// a signal came: then the process is ending because of it, and the handlers
/// stay so that a further signal does not cut its last writes short. Every
/// further signal only sets the flag again.
class InterruptGuard {
 public:
  /// Installs the handlers and clears the flag.
  InterruptGuard();
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

  /// True once a signal came (for RunOptions::stop).
  static const std::atomic<bool>& flag();
  /// The first signal that came (SIGINT or SIGTERM), or 0.
  static int caughtSignal();
};

/// The exit code of a command ended by signal `signalNumber`: 128 + its number (130 for
/// SIGINT, 143 for SIGTERM), as a shell reports a process killed by it.
inline int exitCodeForSignal(int signalNumber) { return 128 + signalNumber; }

}  // namespace robophi
