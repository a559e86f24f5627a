// The files a load reads, gathered per thread (include/robophi/build/input_files.h).
#include "robophi/build/input_files.h"

#include <algorithm>
#include <filesystem>

namespace robophi::build {

namespace {

// This thread's innermost log (none outside a load).
InputFileLog*& currentLog() {
  thread_local InputFileLog* log = nullptr;
  return log;
}

}  // namespace

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
