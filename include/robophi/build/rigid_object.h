#pragma once
/// \file
/// A generated object declared rigid (a scene object's "rigid": true; docs/model.md
/// §7): its particles become the contact surface of one free rigid body whose mass,
/// centre of mass and inertia are the particles' own.

#include "robophi/build/model_builder.h"
#include "robophi/vec3.h"

namespace robophi::build {

/// Where a rigid object went in the model.
struct PlacedRigidObject {
  PlacedObject object;
  /// Index into Model::rigidTrees.
  std::int32_t tree = -1;
};

/// Places `object` as one free rigid body: mass Σ m_i, centre of mass Σ m_i p_i / m,
/// inertia about it Σ m_i (|r_i|² 1 − r_i r_iᵀ + ⅖ r_i,particle² 1) (each particle a
/// uniform ball), its particles fixed to it (moved by the body, their connectors
/// dropped); starting with the centre of mass at `velocity` (m/s) and turning at
/// `angularVelocity` (rad/s, in W). Throws SpecError for an object with joints or
/// fixed particles (a robot, an anchored object: not one rigid body).
PlacedRigidObject placeRigidObject(ModelBuilder& builder, ObjectPlacement object,
                                   const Vec3& velocity = {}, const Vec3& angularVelocity = {});

}  // namespace robophi::build
