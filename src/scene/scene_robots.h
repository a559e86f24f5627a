#pragma once
// Reading the robot objects of a scene ("arm", "vehicle", "hand";
// docs/robotics.md) into their build specs (robophi/build/robots.h).

#include <string>

#include "scene/scene_fields.h"
#include "scene/scene_objects.h"

namespace robophi::scene {

bool isRobotKind(const std::string& kind);
/// The robots that may be "rigid": true (build/rigid_robots.h): the arm and the hand.
bool hasRigidRobot(const std::string& kind);

/// Reads an arm, vehicle or hand entry into `object.geometry` (its fixed base
/// included), or with "rigid": true (an arm or a hand) into `object.rigidUrdf`. Returns false when
/// a parameter is missing or bad (reported). Throws build::SpecError when the builder refuses the
/// spec.
bool readRobot(ObjectReader& r, SceneObject& object);

}  // namespace robophi::scene
