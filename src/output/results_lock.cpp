// The advisory lock of a results folder: flock on NAME.lock beside it, with
// the holder's pid inside, counted within a process.
#include "output/results_lock.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <map>
#include <mutex>
#include <thread>

#include "output/results_folder.h"

namespace robophi::output {

namespace {

namespace fs = std::filesystem;

// The locks this process holds: lock file → (descriptor, holders).
struct HeldLock {
  int fd = -1;
  int holders = 0;
};
std::mutex& heldMutex() {
  static std::mutex mutex;
  return mutex;
}
std::map<std::string, HeldLock>& held() {
  static std::map<std::string, HeldLock> locks;
  return locks;
}

// The pid the holder wrote into `lockFile`; it writes it just after taking the
// lock, so an empty file is read again a few times.
std::string holderPid(const fs::path& lockFile) {
  for (int attempt = 0; attempt < 50; ++attempt) {
    const int fd = ::open(lockFile.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd >= 0) {
      char text[32] = {};
      const ssize_t n = ::read(fd, text, sizeof(text) - 1);
      ::close(fd);
      std::string pid(text, n > 0 ? static_cast<std::size_t>(n) : 0);
      while (!pid.empty() && (pid.back() == '\n' || pid.back() == ' ')) pid.pop_back();
      if (!pid.empty()) return pid;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return "unknown";
}

// Opens and locks `lockFile`, or throws. A file its last holder removed after
// we opened it is stale (another process may lock a new one): open again.
int takeLock(const fs::path& target, const fs::path& lockFile) {
  for (;;) {
    const int fd = ::open(lockFile.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) {
      throw ResultsFolderError(fmt::format("{}: cannot make the results folder's lock file ({})",
                                           lockFile.string(), std::strerror(errno)));
    }
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int error = errno;
      ::close(fd);
      if (error != EWOULDBLOCK) {
        throw ResultsFolderError(
            fmt::format("{}: cannot lock ({})", lockFile.string(), std::strerror(error)));
      }
      throw ResultsFolderError(fmt::format(
          "{} is being written by another robophi (pid {}; its lock file {}): wait for it to "
          "end or choose another --out",
          target.string(), holderPid(lockFile), lockFile.string()));
    }
    struct stat opened {};
    struct stat named {};
    if (::fstat(fd, &opened) == 0 && ::stat(lockFile.c_str(), &named) == 0 &&
        opened.st_dev == named.st_dev && opened.st_ino == named.st_ino) {
      // (Without the pid the lock still holds; a refused run then says "unknown".)
      const std::string pid = fmt::format("{}\n", ::getpid());
      const bool written = ::ftruncate(fd, 0) == 0 &&
                           ::write(fd, pid.data(), pid.size()) == static_cast<ssize_t>(pid.size());
      static_cast<void>(written);
      return fd;
    }
    ::close(fd);
  }
}

}  // namespace

fs::path lockFileOf(const fs::path& target) {
  const fs::path path = target.filename().empty() ? target.parent_path() : target;
  return path.parent_path() / (path.filename().string() + ".lock");
}

ResultsFolderLock::ResultsFolderLock(const fs::path& target) {
  const fs::path lockFile = lockFileOf(target);
  key_ = fs::absolute(lockFile).lexically_normal().string();
  const std::lock_guard guard(heldMutex());
  HeldLock& lock = held()[key_];
  if (lock.holders == 0) {
    std::error_code ec;
    if (lockFile.has_parent_path()) fs::create_directories(lockFile.parent_path(), ec);
    try {
      lock.fd = takeLock(target, lockFile);
    } catch (...) {
      held().erase(key_);
      throw;
    }
  }
  ++lock.holders;
}

ResultsFolderLock::~ResultsFolderLock() {
  const std::lock_guard guard(heldMutex());
  HeldLock& lock = held()[key_];
  if (--lock.holders > 0) return;
  // Removed while still locked: a process that opened it meanwhile sees a
  // stale file once it gets the lock, and opens the path again.
  ::unlink(key_.c_str());
  ::close(lock.fd);
  held().erase(key_);
}

}  // namespace robophi::output
