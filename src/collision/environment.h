#pragma once
// Signed distances from a point to the environment's items (MODEL §3: a particle
// of radius r touches an item when d = signed distance - r < 0).

#include <cstdint>

#include "robophi/contact.h"
#include "robophi/vec3.h"

namespace robophi {

/// The signed distance (m, negative inside) from p to environment item `item` and
/// the unit outward normal there. False when the item does not reach p (a point
/// beside a heightfield's rectangle and above the height of its edge).
bool environmentDistance(const Environment& environment, std::int32_t item, const Vec3& p,
                         double& signedDistance, Vec3& normal);

/// Particle i of radius r at p against environment item `item`: true, with the
/// contact's depth and normal in `contact`, when it touches (depth < 0).
inline bool touchesEnvironment(const Environment& environment, std::int32_t i, const Vec3& p,
                               double r, std::int32_t item, Contact& contact) {
  double signedDistance = 0.0;
  Vec3 normal;
  if (!environmentDistance(environment, item, p, signedDistance, normal)) return false;
  const double depth = signedDistance - r;
  if (depth >= 0.0) return false;
  contact = Contact{};
  contact.a = i;
  contact.other = -1 - item;
  contact.depth = depth;
  contact.normal = normal;
  return true;
}

/// What a cull needs of a heightfield item: its highest sample (m) and its
/// steepness, the largest 1/n_z of its (smoothed) normal. Its distance is the
/// vertical gap times n_z (environmentDistance), so a sphere of radius r may touch
/// it down to r · steepness above its top. (Other items: top 0, steepness 1.)
struct EnvironmentReach {
  double top = 0.0;
  double steepness = 1.0;
};
EnvironmentReach environmentReach(const Environment& environment, std::int32_t item);

/// True when a sphere (center, radius) cannot touch item `item`: a cheap test for
/// culling a sphere-tree node, a ring or a ball. `reach` is environmentReach(environment, item).
bool environmentFarFrom(const Environment& environment, std::int32_t item, const Vec3& center,
                        double radius, const EnvironmentReach& reach);

/// A box containing item `item` (m); false when it has none (a plane). A
/// heightfield's reaches down to -infinity: the terrain is solid below its surface.
bool environmentBounds(const Environment& environment, std::int32_t item, Vec3& low, Vec3& high);

/// The material of environment item `item`.
std::int32_t environmentMaterial(const Environment& environment, std::int32_t item);

}  // namespace robophi
