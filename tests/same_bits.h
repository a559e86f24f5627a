#pragma once
// Bitwise equality for the tests (NaN and -0 included): results that must be
// the same bits, not merely equal.

#include <cstring>

#include "robophi/contact.h"
#include "robophi/vec3.h"

namespace robophi::testing {

inline bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

inline bool sameBits(const Vec3& a, const Vec3& b) {
  return sameBits(a.x, b.x) && sameBits(a.y, b.y) && sameBits(a.z, b.z);
}

/// Every field of two contacts, as bits.
inline bool sameContact(const Contact& a, const Contact& b) {
  return a.a == b.a && a.other == b.other && sameBits(a.depth, b.depth) &&
         sameBits(a.normalForce, b.normalForce) && sameBits(a.frictionForce, b.frictionForce) &&
         sameBits(a.anchorEnergy, b.anchorEnergy) && sameBits(a.normal, b.normal) &&
         sameBits(a.slip, b.slip) && sameBits(a.anchor, b.anchor) &&
         sameBits(a.rollVelocity, b.rollVelocity) && a.rim == b.rim && sameBits(a.arm, b.arm) &&
         sameBits(a.giveWay, b.giveWay) && a.sliding == b.sliding && a.vertex == b.vertex &&
         a.facet == b.facet && sameBits(a.facetWeights, b.facetWeights);
}

}  // namespace robophi::testing
