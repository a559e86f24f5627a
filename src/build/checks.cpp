#include "build/checks.h"

#include <charconv>
#include <cmath>

#include "robophi/build/objects.h"

namespace robophi::build {

SpecError::SpecError(std::string spec, std::string field, std::string message)
    : std::invalid_argument(spec + ": " + message),
      spec_(std::move(spec)),
      field_(std::move(field)),
      message_(std::move(message)) {}

namespace check {

std::string number(double value) {
  if (!std::isfinite(value)) return std::isnan(value) ? "nan" : (value > 0 ? "inf" : "-inf");
  char text[64];
  // The shortest round-trip digits; their exponent picks the notation.
  const auto scientific =
      std::to_chars(text, text + sizeof text, value, std::chars_format::scientific);
  const char* e = scientific.ptr;
  while (e > text && *(e - 1) != 'e') --e;
  int exponent = 0;
  std::from_chars(*e == '+' ? e + 1 : e, scientific.ptr, exponent);
  if (exponent < -4 || exponent >= 16) return std::string(text, scientific.ptr);
  const auto fixed = std::to_chars(text, text + sizeof text, value, std::chars_format::fixed);
  return std::string(text, fixed.ptr);
}

std::string vector(const Vec3& value) {
  return "[" + number(value.x) + ", " + number(value.y) + ", " + number(value.z) + "]";
}

void fail(const char* spec, const char* field, const std::string& message) {
  throw SpecError(spec, field, message);
}

namespace {

std::string unitText(const char* unit) { return *unit == '\0' ? "" : std::string(" ") + unit; }

}  // namespace

void finite(const char* spec, const char* field, double value, const char* unit) {
  if (!std::isfinite(value))
    fail(spec, field,
         "'" + std::string(field) + "' must be finite (" + unit + "), got " + number(value));
}

void finite(const char* spec, const char* field, const Vec3& value, const char* unit) {
  if (!(std::isfinite(value.x) && std::isfinite(value.y) && std::isfinite(value.z)))
    fail(spec, field,
         "'" + std::string(field) + "' must be finite (" + unit + "), got " + vector(value));
}

void positive(const char* spec, const char* field, double value, const char* unit) {
  if (!(std::isfinite(value) && value > 0.0))
    fail(spec, field,
         "'" + std::string(field) + "' must be > 0" + unitText(unit) + ", got " + number(value));
}

void nonNegative(const char* spec, const char* field, double value, const char* unit) {
  if (!(std::isfinite(value) && value >= 0.0))
    fail(spec, field,
         "'" + std::string(field) + "' must be >= 0" + unitText(unit) + ", got " + number(value));
}

void nonNegative(const char* spec, const char* field, const std::optional<double>& value,
                 const char* unit) {
  if (value) nonNegative(spec, field, *value, unit);
}

void positiveEach(const char* spec, const char* field, const Vec3& value, const char* unit) {
  if (!(value.x > 0.0 && value.y > 0.0 && value.z > 0.0) ||
      !std::isfinite(value.x + value.y + value.z))
    fail(spec, field,
         "'" + std::string(field) + "' must be > 0" + unitText(unit) + " in each direction, got " +
             vector(value));
}

void nonZero(const char* spec, const char* field, const Vec3& value) {
  finite(spec, field, value, "-");
  if (!(norm(value) > 0.0))
    fail(spec, field,
         "'" + std::string(field) + "' must be a non-zero vector, got " + vector(value));
}

void atLeast(const char* spec, const char* field, int value, int minimum) {
  if (value < minimum)
    fail(spec, field,
         "'" + std::string(field) + "' must be >= " + std::to_string(minimum) + ", got " +
             std::to_string(value));
}

void atMost(const char* spec, const char* field, int value, int maximum) {
  if (value > maximum)
    fail(spec, field,
         "'" + std::string(field) + "' must be <= " + std::to_string(maximum) + ", got " +
             std::to_string(value));
}

void fitsBudget(const char* spec, const char* field, const std::string& what, double particles,
                double connectors) {
  const auto count = [](double x) {
    return x < 1e15 ? std::to_string(static_cast<long long>(x)) : number(x);
  };
  const bool particlesFit = particles <= kMaxParticlesPerObject;
  const bool connectorsFit = connectors <= static_cast<double>(kMaxConnectorsPerObject);
  if (particlesFit && connectorsFit) return;
  fail(spec, field,
       what + " makes " + count(particles) + " particles and " + count(connectors) +
           " connectors, more than the budget of " + std::to_string(kMaxParticlesPerObject) +
           " particles and " + std::to_string(kMaxConnectorsPerObject) +
           " connectors (docs/scene-format.md#limits)");
}

}  // namespace check
}  // namespace robophi::build
