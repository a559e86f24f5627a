#include "output/base64.h"

#include <fmt/format.h>

#include <array>
#include <stdexcept>


namespace robophi::output {

namespace {

constexpr std::string_view kAlphabet =
    "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

// Each character's 6-bit value, or -1 outside the alphabet.
constexpr std::array<std::int8_t, 256> kValues = [] {
  std::array<std::int8_t, 256> values{};
  values.fill(-1);
  for (std::size_t k = 0; k < kAlphabet.size(); ++k)
    values[static_cast<unsigned char>(kAlphabet[k])] = static_cast<std::int8_t>(k);
  return values;
}();

}  // namespace

void appendBase64(std::string& out, const void* bytes, std::size_t size) {
  const auto* in = static_cast<const unsigned char*>(bytes);
  const std::size_t start = out.size();
  out.resize(start + base64Size(size));
  char* o = out.data() + start;
  std::size_t i = 0;
  for (; i + 3 <= size; i += 3) {
    const std::uint32_t triple = (std::uint32_t{in[i]} << 16) | (std::uint32_t{in[i + 1]} << 8) |
                                 std::uint32_t{in[i + 2]};
    *o++ = kAlphabet[(triple >> 18) & 63];
    *o++ = kAlphabet[(triple >> 12) & 63];
    *o++ = kAlphabet[(triple >> 6) & 63];
    *o++ = kAlphabet[triple & 63];
  }
  if (i < size) {
    const bool two = i + 1 < size;
    const std::uint32_t triple =
        (std::uint32_t{in[i]} << 16) | (two ? std::uint32_t{in[i + 1]} << 8 : 0u);
    *o++ = kAlphabet[(triple >> 18) & 63];
    *o++ = kAlphabet[(triple >> 12) & 63];
    *o++ = two ? kAlphabet[(triple >> 6) & 63] : '=';
    *o++ = '=';
  }
}

std::vector<std::uint8_t> decodeBase64(std::string_view text) {
  if (text.size() % 4 != 0)
    throw std::invalid_argument(
        fmt::format("base64 text of {} characters: not a multiple of 4", text.size()));
  std::vector<std::uint8_t> bytes;
  bytes.reserve(text.size() / 4 * 3);
  for (std::size_t i = 0; i < text.size(); i += 4) {
    std::uint32_t triple = 0;
    int padding = 0;
    for (std::size_t k = 0; k < 4; ++k) {
      const char c = text[i + k];
      const bool last = i + 4 == text.size();
      if (c == '=' && last && k >= 2 && (k == 3 || text[i + 3] == '=')) {
        ++padding;
        triple <<= 6;
        continue;
      }
      const std::int8_t value = kValues[static_cast<unsigned char>(c)];
      if (value < 0 || padding > 0)
        throw std::invalid_argument(
            fmt::format("base64 text: character '{}' at offset {} is not base64", c, i + k));
      triple = (triple << 6) | static_cast<std::uint32_t>(value);
    }
    bytes.push_back(static_cast<std::uint8_t>(triple >> 16));
    if (padding < 2) bytes.push_back(static_cast<std::uint8_t>(triple >> 8));
    if (padding < 1) bytes.push_back(static_cast<std::uint8_t>(triple));
  }
  return bytes;
}

}  // namespace robophi::output
