// The PGM heightfield reader (heightfield_pgm.h): P2 (text) and P5 (binary), 8 or
// 16 bits per pixel.
#include "robophi/scene/heightfield_pgm.h"

#include <fmt/format.h>

#include <cctype>
#include <charconv>
#include <cstdlib>
#include <istream>
#include <sstream>
#include <string>

#include "robophi/build/input_files.h"

namespace robophi {

namespace {

// Next PGM header token, skipping whitespace and # comments.
bool pgmToken(std::istream& in, std::string& token) {
  token.clear();
  int c = in.get();
  while (c != EOF) {
    if (c == '#') {
      while (c != EOF && c != '\n') c = in.get();
    } else if (!std::isspace(c)) {
      break;
    }
    c = in.get();
  }
  while (c != EOF && !std::isspace(c)) {
    token.push_back(static_cast<char>(c));
    c = in.get();
  }
  return !token.empty();
}

// A token of the file for a message: itself when it is short printable ASCII,
// else its first bytes in hexadecimal (a binary file's bytes are not UTF-8 text).
std::string shown(const std::string& token) {
  bool printable = token.size() <= 24;
  for (const char c : token) printable = printable && c >= 0x20 && c < 0x7F;
  if (printable) return "'" + token + "'";
  std::string hex = "bytes";
  for (std::size_t k = 0; k < token.size() && k < 8; ++k)
    hex += fmt::format(" 0x{:02X}", static_cast<unsigned char>(token[k]));
  return hex + (token.size() > 8 ? " ..." : "");
}

// `token` as a whole decimal integer.
bool parseWhole(const std::string& token, long& value) {
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, value);
  return ec == std::errc() && ptr == end;
}

}  // namespace

std::string loadHeightfieldPgm(const std::string& path, double originX, double originY,
                               double cellSizeX, double cellSizeY, double minHeight,
                               double maxHeight, Heightfield& out) {
  std::istringstream in;
  try {
    in.str(build::readInputFile(path));  // a regular file (never a FIFO), recorded
  } catch (const build::InputFileError& e) {
    return fmt::format("{}: cannot open the file: {}", path, e.problem());
  }
  std::string magic, token;
  if (!pgmToken(in, magic) || (magic != "P2" && magic != "P5"))
    return fmt::format("{}: not a PGM image (expected P2 or P5, got {})", path, shown(magic));
  long header[3] = {0, 0, 0};
  const char* names[3] = {"width", "height", "maxval"};
  for (int k = 0; k < 3; ++k) {
    if (!pgmToken(in, token)) return fmt::format("{}: truncated header", path);
    if (!parseWhole(token, header[k]))
      return fmt::format("{}: bad header value {} for the {} (expected an integer)", path,
                         shown(token), names[k]);
  }
  const long width = header[0], height = header[1], maxval = header[2];
  if (width < 2 || height < 2)
    return fmt::format("{}: size {}×{} must be at least 2×2", path, width, height);
  // The size budget, checked before anything is allocated (docs/scene-format.md#limits).
  if (static_cast<double>(width) * static_cast<double>(height) > kMaxHeightfieldSamples)
    return fmt::format(
        "{}: size {}×{} is {} pixels, more than the budget of {} pixels of a heightfield "
        "(docs/scene-format.md#limits)",
        path, width, height, static_cast<double>(width) * static_cast<double>(height),
        kMaxHeightfieldSamples);
  if (maxval < 1 || maxval > 65535)
    return fmt::format("{}: maxval {} must be in [1, 65535]", path, maxval);
  if (!(cellSizeX > 0.0) || !(cellSizeY > 0.0))
    return fmt::format("{}: cell sizes ({}, {}) must be > 0", path, cellSizeX, cellSizeY);
  if (magic == "P5") {
    // One whitespace byte ends the header; then exactly the pixels.
    const std::streamoff start = in.tellg();
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    in.seekg(start);
    const auto needed = static_cast<std::streamoff>(width * height * (maxval < 256 ? 1 : 2));
    if (start < 0 || size - start < needed)
      return fmt::format("{}: truncated pixel data: {}×{} pixels need {} bytes, the file has {}",
                         path, width, height, needed, start < 0 ? 0 : size - start);
  }
  Heightfield field;
  field.originX = originX;
  field.originY = originY;
  field.cellSizeX = cellSizeX;
  field.cellSizeY = cellSizeY;
  field.columns = static_cast<std::int32_t>(width);
  field.rows = static_cast<std::int32_t>(height);
  field.heights.assign(static_cast<std::size_t>(width * height), 0.0);
  const double scale = (maxHeight - minHeight) / static_cast<double>(maxval);
  for (long r = 0; r < height; ++r) {
    for (long i = 0; i < width; ++i) {
      long value = 0;
      if (magic == "P2") {
        if (!pgmToken(in, token)) return fmt::format("{}: truncated pixel data", path);
        if (!parseWhole(token, value))
          return fmt::format("{}: pixel ({}, {}) is {}, not an integer", path, i, r, shown(token));
      } else if (maxval < 256) {
        const int c = in.get();
        if (c == EOF) return fmt::format("{}: truncated pixel data", path);
        value = c;
      } else {
        const int hi = in.get(), lo = in.get();
        if (lo == EOF) return fmt::format("{}: truncated pixel data", path);
        value = hi * 256 + lo;
      }
      if (value < 0 || value > maxval)
        return fmt::format("{}: pixel ({}, {}) = {} exceeds maxval {}", path, i, r, value, maxval);
      const std::size_t j = static_cast<std::size_t>(height - 1 - r);
      field.heights[j * static_cast<std::size_t>(width) + static_cast<std::size_t>(i)] =
          minHeight + scale * static_cast<double>(value);
    }
  }
  field.material = out.material;
  out = std::move(field);
  return {};
}

}  // namespace robophi
