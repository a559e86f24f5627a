// ChildServer: fork once, a socket for requests and answers (each a length and
// its bytes), poll with a deadline, waitpid when the child ends.
#include "build/child_process.h"

#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <system_error>

namespace robophi::build {

std::string ChildOutcome::how() const {
  if (kind == kTimedOut) return "a hang";
  if (signal != 0) return strsignal(signal);
  return "exit status " + std::to_string(status);
}

namespace {

// A frame: its length (8 bytes) and its bytes.
std::string frame(const std::string& bytes) {
  const std::uint64_t n = bytes.size();
  std::string out(reinterpret_cast<const char*>(&n), sizeof n);
  return out + bytes;
}

bool sendAll(int fd, const std::string& bytes) {
  for (std::size_t at = 0; at < bytes.size();) {
    const ssize_t n = send(fd, bytes.data() + at, bytes.size() - at, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    at += static_cast<std::size_t>(n);
  }
  return true;
}

// The child's side: reads `size` bytes, blocking; false at the end of the stream.
bool receiveAll(int fd, char* to, std::size_t size) {
  for (std::size_t at = 0; at < size;) {
    const ssize_t n = read(fd, to + at, size - at);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    at += static_cast<std::size_t>(n);
  }
  return true;
}

bool receiveFrame(int fd, std::string& bytes) {
  std::uint64_t n = 0;
  if (!receiveAll(fd, reinterpret_cast<char*>(&n), sizeof n)) return false;
  bytes.resize(n);
  return receiveAll(fd, bytes.data(), n);
}

// The file descriptor the child talks through, once it has closed the rest.
constexpr int kChildSocket = 3;

// The child's side: closes what it inherited, then answers requests (the
// asker's folder, then the request) until the asker closes its end.
[[noreturn]] void serve(ChildServer::Handler handler, pid_t parent, int socket) {
  prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (getppid() != parent) _exit(4);  // the parent died before the prctl
  // A crash is this process's end, reported to the asker (not the asker's
  // handlers': a sanitizer's or a fuzzer's report); an interrupt too.
  for (const int number : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGINT, SIGTERM, SIGHUP})
    ::signal(number, SIG_DFL);
  if (socket != kChildSocket && dup2(socket, kChildSocket) < 0) _exit(6);
  if (close_range(kChildSocket + 1, ~0U, 0) != 0) {
    for (int fd = kChildSocket + 1; fd < 4096; ++fd) close(fd);
  }
  std::string folder;
  std::string here;
  std::string request;
  for (;;) {
    if (!receiveFrame(kChildSocket, folder) || !receiveFrame(kChildSocket, request)) _exit(0);
    if (folder != here) {
      if (chdir(folder.c_str()) != 0) _exit(7);
      here = folder;
    }
    if (!sendAll(kChildSocket, frame(handler(request)))) _exit(5);
  }
}

}  // namespace

ChildServer::~ChildServer() {
  const std::lock_guard<std::mutex> lock(mutex_);
  stop(false);
}

pid_t ChildServer::pid() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return child_;
}

bool ChildServer::start() {
  int fds[2];
  if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0) return false;
  const pid_t parent = getpid();
  const pid_t child = fork();
  if (child < 0) {
    close(fds[0]);
    close(fds[1]);
    return false;
  }
  if (child == 0) serve(handler_, parent, fds[1]);
  close(fds[1]);
  child_ = child;
  socket_ = fds[0];
  return true;
}

void ChildServer::stop(bool kill) {
  if (child_ < 0) return;
  if (kill) ::kill(child_, SIGKILL);
  close(socket_);  // a child waiting for a request reads the end and leaves
  while (waitpid(child_, nullptr, 0) < 0 && errno == EINTR) {
  }
  child_ = -1;
  socket_ = -1;
}

ChildOutcome ChildServer::ask(const std::string& request, int seconds) {
  const std::lock_guard<std::mutex> lock(mutex_);
  std::error_code error;
  const std::string folder = std::filesystem::current_path(error).string();
  const std::string message = frame(folder) + frame(request);
  // A child that died while it waited (the thread that forked it ended) is
  // forked again; so is one that could not take the request.
  if (child_ >= 0) {
    int status = 0;
    if (waitpid(child_, &status, WNOHANG) == child_) {
      close(socket_);
      child_ = -1;
      socket_ = -1;
    }
  }
  for (int attempt = 0; attempt < 2; ++attempt) {
    if (child_ < 0 && !start()) return {};
    if (sendAll(socket_, message)) return exchange(seconds);
    stop(true);
  }
  return {};
}

// Waits for the answer to the request just sent.
ChildOutcome ChildServer::exchange(int seconds) {
  ChildOutcome outcome;
  std::string received;
  std::uint64_t expected = 0;
  bool haveLength = false;
  bool timedOut = false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
  for (;;) {
    if (haveLength && received.size() == expected) {
      outcome.kind = ChildOutcome::kAnswered;
      outcome.answer = std::move(received);
      return outcome;
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      timedOut = true;
      break;
    }
    pollfd watch{socket_, POLLIN, 0};
    const int ready = poll(&watch, 1, static_cast<int>(std::min<long long>(left.count(), 1000)));
    if (ready < 0 && errno != EINTR) break;
    if (ready <= 0) continue;
    char buffer[1 << 16];
    const std::size_t want =
        haveLength ? std::min<std::size_t>(sizeof buffer, expected - received.size())
                   : sizeof expected - received.size();
    const ssize_t n = read(socket_, buffer, want);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // the child closed its end: it is leaving
    received.append(buffer, static_cast<std::size_t>(n));
    if (!haveLength && received.size() == sizeof expected) {
      std::memcpy(&expected, received.data(), sizeof expected);
      received.clear();
      haveLength = true;
    }
  }
  // It ended (its end of the socket closed once its exit status was set), or it
  // is past its deadline: killed, waited for, and said which.
  const pid_t child = child_;
  ::kill(child, SIGKILL);
  close(socket_);
  int status = 0;
  while (waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  child_ = -1;
  socket_ = -1;
  if (timedOut) {
    outcome.kind = ChildOutcome::kTimedOut;
  } else {
    outcome.kind = ChildOutcome::kCrashed;
    outcome.signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
    outcome.status = WIFEXITED(status) ? WEXITSTATUS(status) : 0;
  }
  return outcome;
}

}  // namespace robophi::build
