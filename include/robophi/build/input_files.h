#pragma once
/// \file
/// The files a load reads, for a digest of a run's inputs (a checkpoint records
/// one per file; robophi resume refuses a changed one). Mesh files are recorded
/// where they are read (loadMesh); the scene layer adds scene files, URDF files
/// and heightfields.

#include <string>
#include <vector>

namespace robophi::build {

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
