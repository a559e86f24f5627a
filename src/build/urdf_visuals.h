#pragma once
// The URDF's <visual> elements as the model's display shapes (robophi/visuals.h):
// read with the URDF (urdf_parse.h), placed with either form of the robot.

#include <string>
#include <vector>

#include "build/urdf_parse.h"
#include "robophi/build/model_builder.h"
#include "robophi/build/urdf.h"
#include "robophi/build/urdf_multibody.h"
#include "robophi/build/urdf_visuals.h"

namespace robophi::build {

/// The visuals of every link of `d`, named "<prefix>.<link>", in their links' frames,
/// each named colour looked up in the robot's <material> list.
std::vector<UrdfVisual> urdfVisuals(const urdf::Description& d, const std::string& prefix);

/// Adds the robot's visuals (particle form): each carried by its link's body
/// (a frame link's: the body it is attached to), at its world pose as built.
void placeUrdfVisuals(ModelBuilder& builder, const UrdfRobot& robot, const PlacedUrdfRobot& placed);

/// Adds the robot's visuals (rigid form): each carried by its link's tree body, at
/// its world pose in the kinematics `kin` the tree starts at.
void placeUrdfMultibodyVisuals(ModelBuilder& builder, const UrdfMultibody& robot,
                               std::int32_t tree, const MultibodyKinematics& kin);

}  // namespace robophi::build
