#pragma once
// Bit-for-bit comparison of two models and their initial states, for the tests
// that build one object from C++ specs and from a scene file.

#include <gtest/gtest.h>

#include "robophi/model.h"
#include "robophi/state.h"

namespace robophi::testing {

/// Every particle array, connector, object and joint of `a` equals `b`'s
/// exactly (doubles compared with ==).
inline void expectSameModel(const Model& a, const Model& b) {
  EXPECT_EQ(a.mass, b.mass);
  EXPECT_EQ(a.inverseMass, b.inverseMass);
  EXPECT_EQ(a.radius, b.radius);
  EXPECT_EQ(a.linearDamping, b.linearDamping);
  EXPECT_EQ(a.objectOf, b.objectOf);
  ASSERT_EQ(a.linearSprings.size(), b.linearSprings.size());
  for (std::size_t i = 0; i < a.linearSprings.size(); ++i) {
    const LinearSpring &s = a.linearSprings[i], &t = b.linearSprings[i];
    EXPECT_TRUE(s.a == t.a && s.b == t.b && s.restLength == t.restLength &&
                s.stiffness == t.stiffness && s.damping == t.damping)
        << "LS " << i;
  }
  ASSERT_EQ(a.torsionSprings.size(), b.torsionSprings.size());
  for (std::size_t i = 0; i < a.torsionSprings.size(); ++i) {
    const TorsionSpring &s = a.torsionSprings[i], &t = b.torsionSprings[i];
    EXPECT_TRUE(s.a == t.a && s.b == t.b && s.c == t.c && s.restAngle == t.restAngle &&
                s.stiffness == t.stiffness && s.damping == t.damping)
        << "TS " << i;
  }
  ASSERT_EQ(a.jointSprings.size(), b.jointSprings.size());
  for (std::size_t i = 0; i < a.jointSprings.size(); ++i) {
    const JointSpring &s = a.jointSprings[i], &t = b.jointSprings[i];
    EXPECT_TRUE(s.a == t.a && s.b == t.b && s.c == t.c && s.d == t.d &&
                s.restAngle == t.restAngle && s.stiffness == t.stiffness && s.damping == t.damping)
        << "JS " << i;
  }
  ASSERT_EQ(a.objects.size(), b.objects.size());
  for (std::size_t i = 0; i < a.objects.size(); ++i) {
    const ObjectInfo &o = a.objects[i], &p = b.objects[i];
    EXPECT_TRUE(o.name == p.name && o.kind == p.kind && o.firstParticle == p.firstParticle &&
                o.particleCount == p.particleCount && o.material == p.material)
        << "object " << i;
  }
  ASSERT_EQ(a.joints.size(), b.joints.size());
  for (std::size_t i = 0; i < a.joints.size(); ++i) {
    const Joint &j = a.joints[i], &k = b.joints[i];
    EXPECT_TRUE(j.name == k.name && j.kind == k.kind && j.connector == k.connector &&
                j.driveSpring == k.driveSpring && j.zero == k.zero)
        << "joint " << i;
  }
  EXPECT_TRUE(a.gravity.x == b.gravity.x && a.gravity.y == b.gravity.y &&
              a.gravity.z == b.gravity.z);
}

/// The same model and the same initial positions and velocities, bit for bit.
inline void expectSameStart(const Model& a, const State& sa, const Model& b, const State& sb) {
  expectSameModel(a, b);
  EXPECT_EQ(stateHash(sa), stateHash(sb));
  EXPECT_EQ(sa.position.size(), sb.position.size());
}

}  // namespace robophi::testing
