// Typed reading of scene-file values with diagnostics (scene_fields.h).
#include "scene/scene_fields.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>

namespace robophi {

std::string Diagnostic::format(const char* severity) const {
  std::string where = file;
  if (line > 0) where += fmt::format(":{}:{}", line, column);
  std::string text = fmt::format("{}: {}: {}", where, severity, message);
  if (!pointer.empty()) text += fmt::format(" (at {})", pointer);
  return text;
}

}  // namespace robophi

namespace robophi::scene {

// ---------------------------------------------------------------------------
// DiagnosticSink

Diagnostic DiagnosticSink::make(SourcePosition where, const std::string& pointer,
                                std::string message) const {
  return Diagnostic{file_, where.line, where.column, pointer, std::move(message)};
}

void DiagnosticSink::error(const std::string& pointer, std::string message) {
  const SourcePosition where = json_ ? json_->positionOf(pointer) : SourcePosition{};
  errors_.push_back(make(where, pointer, std::move(message)));
}

void DiagnosticSink::errorAtKey(const std::string& pointer, std::string message) {
  const SourcePosition where = json_ ? json_->keyPositionOf(pointer) : SourcePosition{};
  errors_.push_back(make(where, pointer, std::move(message)));
}

void DiagnosticSink::warning(const std::string& pointer, std::string message) {
  const SourcePosition where = json_ ? json_->positionOf(pointer) : SourcePosition{};
  warnings_.push_back(make(where, pointer, std::move(message)));
}

void DiagnosticSink::errorAt(SourcePosition where, const std::string& pointer,
                             std::string message) {
  errors_.push_back(make(where, pointer, std::move(message)));
}

namespace {

void sortByPosition(std::vector<Diagnostic>& list) {
  std::stable_sort(list.begin(), list.end(), [](const Diagnostic& a, const Diagnostic& b) {
    return std::tie(a.line, a.column) < std::tie(b.line, b.column);
  });
}

}  // namespace

std::vector<Diagnostic> DiagnosticSink::takeErrors() {
  sortByPosition(errors_);
  return std::move(errors_);
}

std::vector<Diagnostic> DiagnosticSink::takeWarnings() {
  sortByPosition(warnings_);
  return std::move(warnings_);
}

// ---------------------------------------------------------------------------
// Messages

std::string describeJson(const nlohmann::json& value) {
  switch (value.type()) {
    case nlohmann::json::value_t::string: {
      std::string text = value.get<std::string>();
      if (text.size() > 40) {
        // Cut at a character boundary: half a UTF-8 sequence is not text.
        std::size_t cut = 37;
        while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) --cut;
        text = text.substr(0, cut) + "...";
      }
      return fmt::format("string \"{}\"", text);
    }
    case nlohmann::json::value_t::boolean:
      return fmt::format("boolean {}", value.get<bool>() ? "true" : "false");
    case nlohmann::json::value_t::null:
      return "null";
    case nlohmann::json::value_t::array:
      return value.size() == 1 ? "an array of 1 value"
                               : fmt::format("an array of {} values", value.size());
    case nlohmann::json::value_t::object:
      return "an object";
    default:
      return fmt::format("number {}", value.dump());
  }
}

int editDistance(std::string_view a, std::string_view b) {
  const auto lower = [](char c) {
    return static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  };
  const std::size_t n = a.size(), m = b.size();
  // d[i][j]: distance between the first i characters of a and the first j of b.
  std::vector<std::vector<int>> d(n + 1, std::vector<int>(m + 1, 0));
  for (std::size_t i = 0; i <= n; ++i) d[i][0] = static_cast<int>(i);
  for (std::size_t j = 0; j <= m; ++j) d[0][j] = static_cast<int>(j);
  for (std::size_t i = 1; i <= n; ++i) {
    for (std::size_t j = 1; j <= m; ++j) {
      const int cost = lower(a[i - 1]) == lower(b[j - 1]) ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      // A transposition of two neighbours counts as one edit.
      if (i > 1 && j > 1 && lower(a[i - 1]) == lower(b[j - 2]) &&
          lower(a[i - 2]) == lower(b[j - 1]))
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[n][m];
}

std::string didYouMean(std::string_view word, const std::vector<std::string>& candidates) {
  const std::string* best = nullptr;
  int bestDistance = 0;
  for (const auto& candidate : candidates) {
    const int distance = editDistance(word, candidate);
    if (best == nullptr || distance < bestDistance) {
      best = &candidate;
      bestDistance = distance;
    }
  }
  // Close enough: a third of the word's length, at least 1, at most 3 edits.
  const int limit = std::clamp(static_cast<int>(word.size()) / 3, 1, 3);
  if (best == nullptr || bestDistance > limit) return {};
  return fmt::format("; did you mean '{}'?", *best);
}

Interval Interval::of(Bound bound) {
  switch (bound) {
    case Bound::kPositive:
      return above(0.0);
    case Bound::kNonNegative:
      return atLeast(0.0);
    case Bound::kAny:
      break;
  }
  return {};
}

bool Interval::contains(double x) const {
  const bool aboveLow = lowOpen ? x > low : x >= low;
  const bool belowHigh = highOpen ? x < high : x <= high;
  return aboveLow && belowHigh;
}

std::string Interval::text() const {
  const bool lowFinite = std::isfinite(low), highFinite = std::isfinite(high);
  if (lowFinite && highFinite)
    return fmt::format("in {}{}, {}{}", lowOpen ? '(' : '[', low, high, highOpen ? ')' : ']');
  if (lowFinite) return fmt::format("{} {}", lowOpen ? ">" : ">=", low);
  if (highFinite) return fmt::format("{} {}", highOpen ? "<" : "<=", high);
  return {};
}

std::optional<double> checkNumber(DiagnosticSink& sink, const nlohmann::json& value,
                                  const std::string& pointer, std::string_view name,
                                  const Interval& range, std::string_view unit) {
  if (!value.is_number()) {
    sink.error(pointer,
               fmt::format("'{}': expected a number{}, got {}", name,
                           unit.empty() ? "" : fmt::format(" ({})", unit), describeJson(value)));
    return std::nullopt;
  }
  const double x = value.get<double>();
  if (!std::isfinite(x)) {
    sink.error(pointer, fmt::format("'{}' must be finite, got {}", name, value.dump()));
    return std::nullopt;
  }
  if (!range.contains(x)) {
    sink.error(pointer, fmt::format("'{}' must be {}{}, got {}", name, range.text(),
                                    unit.empty() ? "" : fmt::format(" {}", unit), value.dump()));
    return std::nullopt;
  }
  return x;
}

std::optional<double> checkNumber(DiagnosticSink& sink, const nlohmann::json& value,
                                  const std::string& pointer, std::string_view name, Bound bound,
                                  std::string_view unit) {
  return checkNumber(sink, value, pointer, name, Interval::of(bound), unit);
}

// ---------------------------------------------------------------------------
// ObjectReader

ObjectReader::ObjectReader(DiagnosticSink& sink, const nlohmann::json& object, std::string pointer,
                           std::string what)
    : sink_(sink), object_(object), pointer_(std::move(pointer)), what_(std::move(what)) {
  valid_ = object_.is_object();
  if (!valid_)
    sink_.error(pointer_, fmt::format("{}: expected an object {{...}}, got {}", what_,
                                      describeJson(object_)));
}

std::string ObjectReader::memberPointer(std::string_view key) const {
  return pointer_ + "/" + pointerToken(key);
}

const nlohmann::json* ObjectReader::member(std::string_view key) {
  known_.emplace(key);
  if (!valid_) return nullptr;
  const auto it = object_.find(std::string(key));
  return it == object_.end() ? nullptr : &*it;
}

void ObjectReader::allow(std::initializer_list<std::string_view> keys) {
  for (const auto key : keys) known_.emplace(key);
}

void ObjectReader::missing(std::string_view key, std::string_view expected) {
  sink_.error(pointer_, fmt::format("{}: missing required key '{}' ({})", what_, key, expected));
}

std::optional<double> ObjectReader::number(std::string_view key, Bound bound, std::string_view unit,
                                           bool required) {
  const nlohmann::json* value = member(key);
  if (value == nullptr) {
    if (required && valid_)
      missing(key, unit.empty() ? "a number" : fmt::format("a number, {}", unit));
    return std::nullopt;
  }
  return checkNumber(sink_, *value, memberPointer(key), key, bound, unit);
}

std::optional<double> ObjectReader::number(std::string_view key, const Interval& range,
                                           std::string_view unit) {
  const nlohmann::json* value = member(key);
  if (value == nullptr) return std::nullopt;
  return checkNumber(sink_, *value, memberPointer(key), key, range, unit);
}

double ObjectReader::numberOr(std::string_view key, double fallback, Bound bound,
                              std::string_view unit) {
  return number(key, bound, unit).value_or(fallback);
}

std::optional<int> ObjectReader::integer(std::string_view key, int minimum, bool required) {
  const nlohmann::json* value = member(key);
  if (value == nullptr) {
    if (required && valid_) missing(key, "an integer");
    return std::nullopt;
  }
  const std::string at = memberPointer(key);
  if (!value->is_number_integer()) {
    sink_.error(at, fmt::format("'{}': expected an integer, got {}", key, describeJson(*value)));
    return std::nullopt;
  }
  const auto x = value->get<std::int64_t>();
  if (x < minimum || x > 10'000'000) {
    sink_.error(at,
                fmt::format("'{}' must be an integer in [{}, 10000000], got {}", key, minimum, x));
    return std::nullopt;
  }
  return static_cast<int>(x);
}

std::optional<std::string> ObjectReader::string(std::string_view key, bool required) {
  const nlohmann::json* value = member(key);
  if (value == nullptr) {
    if (required && valid_) missing(key, "a string");
    return std::nullopt;
  }
  if (!value->is_string()) {
    sink_.error(memberPointer(key),
                fmt::format("'{}': expected a string, got {}", key, describeJson(*value)));
    return std::nullopt;
  }
  return value->get<std::string>();
}

std::optional<bool> ObjectReader::boolean(std::string_view key) {
  const nlohmann::json* value = member(key);
  if (value == nullptr) return std::nullopt;
  if (!value->is_boolean()) {
    sink_.error(memberPointer(key),
                fmt::format("'{}': expected true or false, got {}", key, describeJson(*value)));
    return std::nullopt;
  }
  return value->get<bool>();
}

std::optional<std::vector<double>> ObjectReader::numbers(std::string_view key, std::size_t count,
                                                         std::string_view layout, bool required) {
  const nlohmann::json* value = member(key);
  if (value == nullptr) {
    if (required && valid_) missing(key, fmt::format("an array {}", layout));
    return std::nullopt;
  }
  const std::string at = memberPointer(key);
  if (!value->is_array() || value->size() != count) {
    sink_.error(at, fmt::format("'{}': expected an array of {} numbers {}, got {}", key, count,
                                layout, describeJson(*value)));
    return std::nullopt;
  }
  std::vector<double> result;
  bool ok = true;
  for (std::size_t i = 0; i < count; ++i) {
    const auto x = checkNumber(sink_, (*value)[i], fmt::format("{}/{}", at, i),
                               fmt::format("{}[{}]", key, i), Bound::kAny, "");
    ok = ok && x.has_value();
    result.push_back(x.value_or(0.0));
  }
  if (!ok) return std::nullopt;
  return result;
}

std::optional<Vec3> ObjectReader::vec3(std::string_view key, std::string_view unit, bool required) {
  const auto xyz = numbers(key, 3, fmt::format("[x, y, z] ({})", unit), required);
  if (!xyz) return std::nullopt;
  return Vec3{(*xyz)[0], (*xyz)[1], (*xyz)[2]};
}

void ObjectReader::finish() {
  if (!valid_) return;
  const std::vector<std::string> candidates(known_.begin(), known_.end());
  for (const auto& [key, value] : object_.items()) {
    if (known_.contains(key)) continue;
    sink_.errorAtKey(memberPointer(key), fmt::format("unknown key '{}' in {}{}", key, what_,
                                                     didYouMean(key, candidates)));
  }
}

}  // namespace robophi::scene
