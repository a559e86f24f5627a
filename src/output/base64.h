#pragma once
/// \file
/// Base64 (RFC 4648, with padding): the replay page carries its series as
/// little-endian binary numbers in this text (docs/viewer.md, "The page's data").

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace robophi::output {

/// The length of the text appendBase64 writes for `size` bytes.
constexpr std::size_t base64Size(std::size_t size) { return 4 * ((size + 2) / 3); }

/// Appends the base64 text of the `size` bytes at `bytes`.
void appendBase64(std::string& out, const void* bytes, std::size_t size);

/// The bytes of base64 text. Throws std::invalid_argument naming the offset of
/// the first character outside the alphabet, or a length that is not a multiple of 4.
std::vector<std::uint8_t> decodeBase64(std::string_view text);

}  // namespace robophi::output
