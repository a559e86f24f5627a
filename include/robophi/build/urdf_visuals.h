#pragma once
/// \file
/// A URDF link's <visual> as imported (robophi/visuals.h): the shape in its
/// link's frame, placed with the robot (Model::visuals) for the replay page.

#include "robophi/visuals.h"

namespace robophi::build {

/// One <visual> of the URDF's link `link` (index into the URDF's links, as
/// UrdfRobot::links); `shape.X_WV` holds its pose in the link's frame X_LV until placed.
struct UrdfVisual {
  int link = -1;
  VisualShape shape{};
};

}  // namespace robophi::build
