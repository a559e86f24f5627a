#pragma once
// The axis-aligned box of a set of points, for the mesh tests (decimation and the
// replay's meshes): {lower, upper}.

#include <algorithm>
#include <array>
#include <vector>

#include "robophi/vec3.h"

namespace robophi::test {

inline std::array<Vec3, 2> boxOf(const std::vector<Vec3>& points) {
  Vec3 lower = points.at(0), upper = points.at(0);
  for (const Vec3& p : points) {
    lower = {std::min(lower.x, p.x), std::min(lower.y, p.y), std::min(lower.z, p.z)};
    upper = {std::max(upper.x, p.x), std::max(upper.y, p.y), std::max(upper.z, p.z)};
  }
  return {lower, upper};
}

}  // namespace robophi::test
