// The PGM heightfield reader (heightfield_pgm.h): P2 (text) and P5 (binary), 8 or
// 16 bits per pixel.
#include "robophi/scene/heightfield_pgm.h"

#include <fmt/format.h>

#include <cctype>
#include <cstdlib>
#include <fstream>
#include <istream>
#include <string>

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

}  // namespace

std::string loadHeightfieldPgm(const std::string& path, double originX, double originY,
                               double cellSizeX, double cellSizeY, double minHeight,
                               double maxHeight, Heightfield& out) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return fmt::format("{}: cannot open the file", path);
  std::string magic, token;
  if (!pgmToken(in, magic) || (magic != "P2" && magic != "P5"))
    return fmt::format("{}: not a PGM image (expected P2 or P5, got '{}')", path, magic);
  long header[3] = {0, 0, 0};
  for (long& value : header) {
    if (!pgmToken(in, token)) return fmt::format("{}: truncated header", path);
    try {
      value = std::stol(token);
    } catch (...) {
      return fmt::format("{}: bad header value '{}'", path, token);
    }
  }
  const long width = header[0], height = header[1], maxval = header[2];
  if (width < 2 || height < 2 || width > 100000 || height > 100000)
    return fmt::format("{}: size {}×{} must be at least 2×2", path, width, height);
  if (maxval < 1 || maxval > 65535)
    return fmt::format("{}: maxval {} must be in [1, 65535]", path, maxval);
  if (!(cellSizeX > 0.0) || !(cellSizeY > 0.0))
    return fmt::format("{}: cell sizes ({}, {}) must be > 0", path, cellSizeX, cellSizeY);
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
        value = std::strtol(token.c_str(), nullptr, 10);
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
