#pragma once
// Typed reading of scene-file values with diagnostics: every accessor checks
// the type, the range and the unit of one member and reports what is wrong at
// the member's line and column, then returns nothing; the reading goes on, so
// one pass reports every error of the file.

#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "robophi/scene/scene.h"
#include "robophi/vec3.h"
#include "scene/json_locator.h"

namespace robophi::scene {

/// Collects the errors and warnings of one file, with their positions.
class DiagnosticSink {
 public:
  DiagnosticSink(std::string file, const LocatedJson* json) : file_(std::move(file)), json_(json) {}

  /// An error on the value at `pointer` (or its nearest existing parent).
  void error(const std::string& pointer, std::string message);
  /// An error on the key of the member at `pointer` (unknown keys).
  void errorAtKey(const std::string& pointer, std::string message);
  void warning(const std::string& pointer, std::string message);
  /// An error at a known position (syntax errors).
  void errorAt(SourcePosition where, const std::string& pointer, std::string message);

  std::size_t errorCount() const { return errors_.size(); }
  /// The diagnostics, each list in the order of the text.
  std::vector<Diagnostic> takeErrors();
  std::vector<Diagnostic> takeWarnings();

 private:
  Diagnostic make(SourcePosition where, const std::string& pointer, std::string message) const;

  std::string file_;
  const LocatedJson* json_;
  std::vector<Diagnostic> errors_;
  std::vector<Diagnostic> warnings_;
};

/// A short description of a JSON value for messages: `string "abc"`, `number 3`,
/// `an array of 2 values`, `an object`, `null`, `boolean true`.
std::string describeJson(const nlohmann::json& value);

/// Optimal-string-alignment edit distance, case-insensitive.
int editDistance(std::string_view a, std::string_view b);
/// "; did you mean 'x'?" for the closest candidate within a small edit
/// distance of `word`, else "".
std::string didYouMean(std::string_view word, const std::vector<std::string>& candidates);

/// The range a number must lie in (the common ones).
enum class Bound : std::uint8_t { kAny, kPositive, kNonNegative };

/// An interval a number must lie in, each end open or closed; an infinite end is open.
struct Interval {
  double low = -std::numeric_limits<double>::infinity();
  double high = std::numeric_limits<double>::infinity();
  bool lowOpen = true, highOpen = true;

  static Interval of(Bound bound);
  /// [low, high), (low, high], ... as named.
  static Interval closed(double low, double high) { return {low, high, false, false}; }
  static Interval closedOpen(double low, double high) { return {low, high, false, true}; }
  static Interval openClosed(double low, double high) { return {low, high, true, false}; }
  static Interval open(double low, double high) { return {low, high, true, true}; }
  static Interval atLeast(double low) {
    return {low, std::numeric_limits<double>::infinity(), false, true};
  }
  static Interval above(double low) {
    return {low, std::numeric_limits<double>::infinity(), true, true};
  }

  bool contains(double x) const;
  /// For messages: "> 0", ">= 1", "in [0.1, 1)"; "" when every finite number fits.
  std::string text() const;
};

/// Checks one number at `pointer`; `name` and `unit` are for the message.
std::optional<double> checkNumber(DiagnosticSink& sink, const nlohmann::json& value,
                                  const std::string& pointer, std::string_view name, Bound bound,
                                  std::string_view unit);
/// Same, for a number that must lie in `range`.
std::optional<double> checkNumber(DiagnosticSink& sink, const nlohmann::json& value,
                                  const std::string& pointer, std::string_view name,
                                  const Interval& range, std::string_view unit);

/// Reads the members of one JSON object. Every key asked for (present or not)
/// is known; finish() reports the others as unknown, with a suggestion.
class ObjectReader {
 public:
  /// `what` names the object in messages, e.g. "rope 'chain'".
  ObjectReader(DiagnosticSink& sink, const nlohmann::json& object, std::string pointer,
               std::string what);

  /// False when the value is not an object (already reported).
  bool valid() const { return valid_; }
  const std::string& pointer() const { return pointer_; }
  const std::string& what() const { return what_; }
  DiagnosticSink& sink() { return sink_; }
  std::string memberPointer(std::string_view key) const;

  /// The member, or nullptr when absent; marks the key as known.
  const nlohmann::json* member(std::string_view key);
  /// Marks keys as known without reading them.
  void allow(std::initializer_list<std::string_view> keys);
  /// Reports a missing required key.
  void missing(std::string_view key, std::string_view expected);

  /// A number; nullopt if absent (an error when `required`) or invalid.
  std::optional<double> number(std::string_view key, Bound bound, std::string_view unit,
                               bool required = false);
  /// A number that must lie in `range`; nullopt if absent or invalid.
  std::optional<double> number(std::string_view key, const Interval& range, std::string_view unit);
  /// An optional number with a default.
  double numberOr(std::string_view key, double fallback, Bound bound, std::string_view unit);
  /// An integer >= `minimum`.
  std::optional<int> integer(std::string_view key, int minimum, bool required = false);
  std::optional<std::string> string(std::string_view key, bool required = false);
  std::optional<bool> boolean(std::string_view key);
  /// An array of exactly 3 finite numbers [x, y, z].
  std::optional<Vec3> vec3(std::string_view key, std::string_view unit, bool required = false);
  /// An array of exactly `count` numbers.
  std::optional<std::vector<double>> numbers(std::string_view key, std::size_t count,
                                             std::string_view layout, bool required = false);

  /// Reports every member that was not asked for.
  void finish();

 private:
  DiagnosticSink& sink_;
  const nlohmann::json& object_;
  std::string pointer_;
  std::string what_;
  bool valid_ = false;
  std::set<std::string, std::less<>> known_;
};

}  // namespace robophi::scene
