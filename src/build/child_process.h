#pragma once
// Work on untrusted input in a child process, for a library that can crash or
// hang on a malformed file (assimp's mesh readers: docs/robots.md "Mesh
// paths"). A long-lived child (ChildServer) answers requests through a socket; a
// crash, an abort or a hang ends only the child, and the caller learns which.

#include <sys/types.h>

#include <mutex>
#include <string>

namespace robophi::build {

/// How the child ended, or that it answered.
struct ChildOutcome {
  enum Kind {
    kAnswered,     ///< it ran the work to its end: `answer` is what the work returned
    kCrashed,      ///< it died of a signal (`signal`) or exited otherwise (`status`)
    kTimedOut,     ///< it ran past the deadline and was killed
    kNotStarted,   ///< no child could be started (fork or socket failed): nothing ran
  };
  Kind kind = kNotStarted;
  std::string answer;  ///< kAnswered: the bytes the work returned
  int signal = 0;      ///< kCrashed by a signal: its number, else 0
  int status = 0;      ///< kCrashed by an exit: its status
  /// "Segmentation fault", "exit status 3": for a message.
  std::string how() const;
};

/// A child process, forked on the first request and kept, that answers each
/// request with `handler` (which must not throw: it catches and answers with
/// the error). One fork serves many requests: forking a large process for each
/// one cost more than the work (a fuzz run's mesh files: 194 reads a CPU-second
/// with a fork each, 460 in process). A crash, an abort or a request past its
/// deadline ends the child (killed), that request is answered as such, and the
/// next request forks a new one. The child dies with the thread that forked it
/// (PR_SET_PDEATHSIG); one found gone before a request is forked again. It works
/// in the asker's folder at each request, and it closes every file it inherited
/// but the standard streams when it starts (a lock or a pipe the asker closes is
/// closed). Requests are served one at a time (a mutex).
class ChildServer {
 public:
  using Handler = std::string (*)(const std::string& request);
  explicit ChildServer(Handler handler) : handler_(handler) {}
  ~ChildServer();
  ChildServer(const ChildServer&) = delete;
  ChildServer& operator=(const ChildServer&) = delete;

  /// Sends `request` and waits up to `seconds` for the answer.
  ChildOutcome ask(const std::string& request, int seconds);
  /// The child's process id, or -1 when none runs (for tests).
  pid_t pid() const;

 private:
  bool start();
  void stop(bool kill);  // closes the socket, waits for the child (killed first when `kill`)
  ChildOutcome exchange(int seconds);

  Handler handler_;
  mutable std::mutex mutex_;
  pid_t child_ = -1;
  int socket_ = -1;
};

}  // namespace robophi::build
