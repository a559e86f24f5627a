#pragma once
// Message formatting for the core, which depends on the standard library only:
// text("particle {}: mass {} must be > 0", i, m). A "{}" prints a number in its
// shortest round-trip form (as fmt and std::format do), "{:.Ng}" with N
// significant digits; strings print as they are.

#include <charconv>
#include <cstddef>
#include <string>
#include <string_view>
#include <type_traits>

namespace robophi::detail {

inline void appendValue(std::string& out, std::string_view value, int) { out.append(value); }
inline void appendValue(std::string& out, const std::string& value, int) { out.append(value); }
inline void appendValue(std::string& out, const char* value, int) { out.append(value); }

template <class T>
requires std::is_arithmetic_v<T>
void appendValue(std::string& out, T value, int precision) {
  char buffer[64];
  std::to_chars_result r{};
  if constexpr (std::is_floating_point_v<T>) {
    r = precision > 0 ? std::to_chars(buffer, buffer + sizeof buffer, value,
                                      std::chars_format::general, precision)
                      : std::to_chars(buffer, buffer + sizeof buffer, value);
  } else {
    r = std::to_chars(buffer, buffer + sizeof buffer, value);
  }
  out.append(buffer, r.ptr);
}

// Appends the pattern up to its next placeholder and returns the placeholder's
// precision (0 for "{}"), or -1 when there is none left.
inline int appendUntilPlaceholder(std::string& out, std::string_view& pattern) {
  const std::size_t open = pattern.find('{');
  if (open == std::string_view::npos) {
    out.append(pattern);
    pattern = {};
    return -1;
  }
  out.append(pattern.substr(0, open));
  const std::size_t close = pattern.find('}', open);
  const std::string_view spec = pattern.substr(open + 1, close - open - 1);
  pattern.remove_prefix(close + 1);
  int precision = 0;
  if (spec.size() > 3 && spec.substr(0, 2) == ":.") {
    std::from_chars(spec.data() + 2, spec.data() + spec.size() - 1, precision);
  }
  return precision;
}

template <class... Args>
std::string text(std::string_view pattern, const Args&... args) {
  std::string out;
  out.reserve(pattern.size() + 16 * sizeof...(Args));
  (
      [&] {
        const int precision = appendUntilPlaceholder(out, pattern);
        if (precision >= 0) appendValue(out, args, precision);
      }(),
      ...);
  out.append(pattern);
  return out;
}

}  // namespace robophi::detail
