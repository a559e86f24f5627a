#pragma once
/// \file
/// The URDF importer's error (build/urdf.h): a file robophi cannot import.

#include <stdexcept>
#include <string>

namespace robophi::build {

/// A URDF file that cannot be imported: unreadable, malformed XML, a missing or
/// doubly parented link, a zero axis, a floating joint, a moving link without
/// mass, a missing mesh... what() is "FILE:LINE: message" (LINE 0: the file as a
/// whole), the message naming the element and the value.
class UrdfError : public std::runtime_error {
 public:
  UrdfError(std::string file, int line, const std::string& message);

  /// The URDF file as given.
  const std::string& file() const { return file_; }
  /// The line of the element (1-based), 0 for the file as a whole.
  int line() const { return line_; }
  /// The problem, without "FILE:LINE: ".
  const std::string& message() const { return message_; }

 private:
  std::string file_;
  int line_ = 0;
  std::string message_;
};

/// An element of a URDF that robophi ignores (<gazebo>, <transmission>, <visual>, ...): one
/// a kind, at its first appearance.
struct UrdfWarning {
  std::string file{};
  int line = 0;
  /// E.g. "<gazebo> ignored (robophi does not model it; one warning for all of them)".
  std::string message{};
};

}  // namespace robophi::build
