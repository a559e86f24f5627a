#pragma once
// A robot described in memory as a URDF would describe it (urdf::Description:
// links with collision shapes and mass properties, joints with axes and limits)
// → rigid bodies, by the same road as a URDF file (build::makeUrdfMultibody).
// The built-in robots take it with "rigid": true (build/rigid_robots.cpp).

#include "build/urdf_parse.h"
#include "robophi/build/urdf_multibody.h"

namespace robophi::build {

/// makeUrdfMultibody of a description already read or built; `spec.path` and
/// `spec.packagePaths` are not used (the description's `file` names it in messages).
UrdfMultibody makeUrdfMultibody(const urdf::Description& description,
                                const UrdfMultibodySpec& spec);

}  // namespace robophi::build
