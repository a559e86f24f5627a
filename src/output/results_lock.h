#pragma once
/// \file
/// The advisory lock of a results folder (docs/output-format.md "Safe results
/// folders"): one robophi at a time writes a folder. The lock is an flock on
/// `NAME.lock` beside the folder, which holds the owner's process id.

#include <filesystem>
#include <string>

namespace robophi::output {

/// The lock file of the results folder `target`: `NAME.lock` beside it.
std::filesystem::path lockFileOf(const std::filesystem::path& target);

/// Holds the lock of a results folder while it lives. Taking it again in the
/// same process (robophi resume, then its run) only counts; the lock file is
/// removed when the last holder lets go.
class ResultsFolderLock {
 public:
  /// Takes the lock of `target` without waiting. Throws ResultsFolderError
  /// naming the lock file and the process that holds it when another one does,
  /// or naming the lock file when it cannot be made.
  explicit ResultsFolderLock(const std::filesystem::path& target);
  ~ResultsFolderLock();
  ResultsFolderLock(const ResultsFolderLock&) = delete;
  ResultsFolderLock& operator=(const ResultsFolderLock&) = delete;

 private:
  std::string key_;  // the lock file's path, as taken
};

}  // namespace robophi::output
