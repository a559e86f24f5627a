// The files a load reads, gathered per thread (include/robophi/build/input_files.h).
#include "robophi/build/input_files.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>

namespace robophi::build {

namespace {

// This thread's innermost log (none outside a load).
InputFileLog*& currentLog() {
  thread_local InputFileLog* log = nullptr;
  return log;
}

// What a file that is not a regular one is, in words.
const char* kindOf(mode_t mode) {
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  return "not a regular file";
}

// Closes a descriptor when it goes.
struct Descriptor {
  int fd;
  ~Descriptor() { ::close(fd); }
};

std::string tooLarge(std::uintmax_t bytes) {
  return "is at least " + std::to_string(bytes) + " bytes, more than the limit of " +
         std::to_string(kMaxInputFileBytes) + " bytes of an input file";
}

}  // namespace

std::string readInputFile(const std::string& path) {
  // O_NONBLOCK: opening a FIFO does not wait for a writer; the type is then
  // read from the open descriptor, so the file checked is the file read.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) {
    const int error = errno;
    if (error == ENOENT || error == ENOTDIR || (error == EINVAL && path.empty()))
      throw InputFileError(path, "no such file");
    throw InputFileError(path, std::string("cannot be opened (") + std::strerror(error) + ")");
  }
  const Descriptor closer{fd};
  struct stat status {};
  if (::fstat(fd, &status) != 0)
    throw InputFileError(path, std::string("cannot be read (") + std::strerror(errno) + ")");
  if (!S_ISREG(status.st_mode))
    throw InputFileError(path,
                         std::string("is ") + kindOf(status.st_mode) + ", not a regular file");
  const auto size = static_cast<std::uintmax_t>(status.st_size);
  if (size > kMaxInputFileBytes) throw InputFileError(path, tooLarge(size));
  std::string bytes(static_cast<std::size_t>(size), '\0');
  std::size_t filled = 0;
  for (;;) {
    // A file that grows while it is read is read to its end, within the budget.
    if (filled == bytes.size()) {
      if (filled > kMaxInputFileBytes) throw InputFileError(path, tooLarge(filled));
      bytes.resize(static_cast<std::size_t>(std::min<std::uintmax_t>(
          kMaxInputFileBytes + 1, std::max<std::uintmax_t>(4096, 2 * filled))));
    }
    const ssize_t got = ::read(fd, bytes.data() + filled, bytes.size() - filled);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0)
      throw InputFileError(path, std::string("cannot be read (") + std::strerror(errno) + ")");
    if (got == 0) break;
    filled += static_cast<std::size_t>(got);
  }
  bytes.resize(filled);
  InputFileLog::record(path);
  return bytes;
}

InputFileLog::InputFileLog() : outer_(currentLog()) { currentLog() = this; }

InputFileLog::~InputFileLog() {
  currentLog() = outer_;
  if (outer_ != nullptr)
    for (const std::string& path : files_) outer_->add(path);
}

void InputFileLog::record(const std::string& path) {
  if (InputFileLog* log = currentLog()) {
    std::error_code ec;
    const std::filesystem::path absolute = std::filesystem::absolute(path, ec);
    log->add((ec ? std::filesystem::path(path) : absolute).lexically_normal().string());
  }
}

void InputFileLog::add(const std::string& path) {
  if (std::find(files_.begin(), files_.end(), path) == files_.end()) files_.push_back(path);
}

}  // namespace robophi::build
