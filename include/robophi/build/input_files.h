#pragma once
/// \file
/// The files a load reads, for a digest of a run's inputs (a checkpoint records
/// one per file; robophi resume refuses a changed one). Mesh files are recorded
/// where they are read (loadMesh); the scene layer adds scene files, URDF files
/// and heightfields.

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace robophi::build {

/// The most bytes an input file (a scene, a URDF, a mesh and the files it
/// names, a heightfield, a checkpoint) may have: 1 GiB.
inline constexpr std::uintmax_t kMaxInputFileBytes = std::uintmax_t{1} << 30;

/// An input file that cannot be read: what() is "<path>: <problem>".
class InputFileError : public std::runtime_error {
 public:
  InputFileError(const std::string& path, const std::string& problem)
      : std::runtime_error(path + ": " + problem), path_(path), problem_(problem) {}
  const std::string& path() const { return path_; }
  /// Why, without the path: "no such file", "is a FIFO (named pipe), not a
  /// regular file", "is 2147483648 bytes, more than ...".
  const std::string& problem() const { return problem_; }

 private:
  std::string path_, problem_;
};

/// The bytes of the input file `path`, the one way a load opens a file. Opened
/// without blocking and read only when it is a regular file of at most
/// kMaxInputFileBytes: a folder, a FIFO, a socket or a device is refused, never
/// waited on. Recorded in this thread's InputFileLog. Throws InputFileError.
std::string readInputFile(const std::string& path);

/// Gathers the files read on this thread while it lives. Logs nest: an inner
/// log's files are also the outer one's.
class InputFileLog {
 public:
  InputFileLog();
  ~InputFileLog();
  InputFileLog(const InputFileLog&) = delete;
  InputFileLog& operator=(const InputFileLog&) = delete;

  /// The files read (absolute, lexically normal), each once, in the order first read.
  const std::vector<std::string>& files() const { return files_; }

  /// Adds `path` to this thread's current log, when there is one.
  static void record(const std::string& path);

 private:
  void add(const std::string& path);

  std::vector<std::string> files_;
  InputFileLog* outer_ = nullptr;
};

}  // namespace robophi::build
