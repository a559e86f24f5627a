#pragma once
// Work on untrusted input in a child process (fork), for a library that can
// crash or hang on a malformed file (assimp's mesh readers: docs/robots.md
// "Mesh paths"). The child runs the work and sends its answer back through a pipe;
// a crash, an abort or a hang ends only the child, and the caller learns which.

#include <functional>
#include <string>

namespace robophi::build {

/// How the child ended.
struct ChildOutcome {
  enum Kind {
    kAnswered,     ///< it ran the work to its end: `answer` is what the work returned
    kCrashed,      ///< it died of a signal (`signal`) or exited otherwise (`status`)
    kTimedOut,     ///< it ran past the deadline and was killed
    kNotStarted,   ///< no child could be started (fork or pipe failed): nothing ran
  };
  Kind kind = kNotStarted;
  std::string answer;  ///< kAnswered: the bytes the work returned
  int signal = 0;      ///< kCrashed by a signal: its number, else 0
  int status = 0;      ///< kCrashed by an exit: its status
  /// "Segmentation fault", "exit status 3": for a message.
  std::string how() const;
};

/// Runs `work` in a child process and returns how it ended, within `seconds`
/// (the child is then killed). The child dies with its parent; it leaves by
/// _exit (no exit handlers, no sanitizer leak report); a fatal signal kills it
/// without the parent's handlers (a sanitizer's or a fuzzer's report). `work`
/// must not throw (catch inside it and answer with the error).
ChildOutcome runInChild(const std::function<std::string()>& work, int seconds);

}  // namespace robophi::build
