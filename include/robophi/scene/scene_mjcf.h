#pragma once
/// \file
/// A bare MJCF file as a scene (`robophi run ROBOT.xml`, docs/robots.md "MJCF"): its
/// bodies as rigid bodies (build::makeMjcfMultibody) on a ground plane.

#include <string>

#include "robophi/scene/scene.h"

namespace robophi {

/// An MJCF robot on a ground plane (z = 0) under gravity, as a rigid tree: its lowest
/// surface particle resting on it (a fixed base at its own height), the joints of its
/// position actuators held at their build pose by servos of the actuators' gains, with
/// gravity compensation. Errors name the element (build/mjcf_multibody.h); without
/// libmujoco, an error saying that MJCF needs libmujoco-dev. `options`: the particles
/// of its collision shapes (particleSize, particlesPerLink); the rest is for URDF.
SceneLoadResult loadMjcfFile(const std::string& path, const UrdfSceneOptions& options = {});

/// Whether `path` names an MJCF file (".xml", ".mjcf") rather than a scene.
bool isMjcfPath(const std::string& path);

}  // namespace robophi
