#pragma once
// Argument checks of the builders: each throws SpecError naming the spec, the
// field and the value (the messages read as the scene reader's own, e.g.
// "'mass' must be > 0 kg, got -2").

#include <optional>
#include <string>

#include "robophi/build/spec_error.h"
#include "robophi/vec3.h"

namespace robophi::build::check {

/// A number as the scene reader prints it: the shortest text that reads back
/// the same double, fixed for exponents in [-4, 16), else scientific.
std::string number(double value);
/// "[x, y, z]".
std::string vector(const Vec3& value);

/// Throws SpecError(spec, field, message).
[[noreturn]] void fail(const char* spec, const char* field, const std::string& message);

/// Finite.
void finite(const char* spec, const char* field, double value, const char* unit);
void finite(const char* spec, const char* field, const Vec3& value, const char* unit);
/// Finite and > 0.
void positive(const char* spec, const char* field, double value, const char* unit);
/// Finite and >= 0.
void nonNegative(const char* spec, const char* field, double value, const char* unit);
/// Unset, or finite and >= 0.
void nonNegative(const char* spec, const char* field, const std::optional<double>& value,
                 const char* unit);
/// Each component finite and > 0 (sizes).
void positiveEach(const char* spec, const char* field, const Vec3& value, const char* unit);
/// Finite and not the zero vector.
void nonZero(const char* spec, const char* field, const Vec3& value);
/// An integer >= minimum.
void atLeast(const char* spec, const char* field, int value, int minimum);
/// An integer <= maximum.
void atMost(const char* spec, const char* field, int value, int maximum);
/// The size budget (kMaxParticlesPerObject, kMaxConnectorsPerObject): `what`
/// (e.g. "'cells' 300×300×300") makes `particles` particles and `connectors`
/// connectors; throws SpecError on `field` when either is over the budget.
/// Call it before allocating (doubles: the counts may be far beyond int).
void fitsBudget(const char* spec, const char* field, const std::string& what, double particles,
                double connectors);

}  // namespace robophi::build::check
