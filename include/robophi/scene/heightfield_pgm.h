#pragma once
/// \file
/// Heightfield images (docs/contact.md, `environment.heightfield.pgm`): a PGM
/// file read as terrain heights.

#include <string>

#include "robophi/contact.h"

namespace robophi {

/// The most samples (rows × columns) a heightfield may have: 2048 × 2048
/// (32 MB of heights). A larger image is refused before anything is allocated.
inline constexpr double kMaxHeightfieldSamples = 2048.0 * 2048.0;

/// Reads a binary (P5) or text (P2) PGM image as a heightfield: pixel value v maps
/// to minHeight + (maxHeight - minHeight) v / maxval (m); image column i is x index i,
/// image row r is y index rows-1-r (the image seen from above, +y up). The grid starts
/// at (originX, originY) (m) with cells of cellSizeX × cellSizeY (m, > 0); `out` keeps
/// its material. Returns an empty string on success, otherwise the file and what is
/// wrong with it (and leaves `out` unchanged).
std::string loadHeightfieldPgm(const std::string& path, double originX, double originY,
                               double cellSizeX, double cellSizeY, double minHeight,
                               double maxHeight, Heightfield& out);

}  // namespace robophi
