#pragma once
// A small JSON reader that keeps positions: it parses scene text (JSON plus
// `//` and `/* */` comments) into an nlohmann::json value and records, for
// every value and every object key, its 1-based line and column, indexed by
// JSON pointer. nlohmann's own parser neither accepts every comment form we
// want nor reports positions per value, and the scene loader must name the
// line and column of each bad value.

#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace robophi::scene {

/// 1-based line and column (column counts characters, not bytes); 0 when unknown.
struct SourcePosition {
  int line = 0;
  int column = 0;
};

/// A problem found while reading the text itself.
struct JsonProblem {
  SourcePosition where;
  /// JSON pointer of the value being read when the problem was found.
  std::string pointer;
  std::string message;
};

/// A parsed document and where each of its parts is in the text.
struct LocatedJson {
  nlohmann::json value;
  /// Start of each value, by JSON pointer ("" is the root).
  std::map<std::string, SourcePosition> valuePositions;
  /// Start of the key of each object member, by the member's JSON pointer.
  std::map<std::string, SourcePosition> keyPositions;

  /// Where the value at `pointer` starts; its key's position for a member; or,
  /// when the pointer names nothing (a missing key), the nearest existing parent.
  SourcePosition positionOf(const std::string& pointer) const;
  /// Where the key of the member at `pointer` starts, else positionOf(pointer).
  SourcePosition keyPositionOf(const std::string& pointer) const;
};

/// The outcome of reading: a document if the syntax is valid. A syntax error
/// stops the reading (only the first is reported); a duplicate key is reported
/// and the reading goes on.
struct JsonReadResult {
  std::optional<LocatedJson> json;
  std::vector<JsonProblem> errors;
};

/// Reads JSON with comments. NaN and Infinity are rejected (JSON has no such
/// numbers), as is a number too large for a double; large finite numbers are fine.
JsonReadResult readLocatedJson(std::string_view text);

/// The first place where `text` is not well-formed UTF-8 (RFC 3629), with the
/// bytes found there; nullopt when all of it is. readLocatedJson checks this first.
std::optional<JsonProblem> findInvalidUtf8(std::string_view text);

/// Escapes a key for use as a JSON pointer token (RFC 6901: ~ → ~0, / → ~1).
std::string pointerToken(std::string_view key);

}  // namespace robophi::scene
