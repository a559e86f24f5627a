#pragma once
/// \file
/// The one error of the build layer: a spec or an argument that cannot be built.
/// Builders check every field before they build anything, so a caught SpecError
/// leaves no half-built object behind.

#include <stdexcept>
#include <string>

namespace robophi::build {

/// A bad spec field or argument: a non-positive mass, too few particles, a
/// non-finite number, a zero axis, an index out of range.
/// what() is "<spec>: <message>", e.g. "ArmSpec: 'mass' must be > 0 kg, got -2".
class SpecError : public std::invalid_argument {
 public:
  SpecError(std::string spec, std::string field, std::string message);

  /// The spec or function that refused it, e.g. "ArmSpec", "calibrateLattice".
  const std::string& spec() const { return spec_; }
  /// The field or argument, e.g. "mass". Fields are named as the scene keys
  /// that fill them (docs/scene-format.md), so a scene reader can point at the key.
  const std::string& field() const { return field_; }
  /// The problem, naming the field and its value, without the spec's name.
  const std::string& message() const { return message_; }

 private:
  std::string spec_, field_, message_;
};

}  // namespace robophi::build
