#pragma once
// Scene objects of type "mesh" (docs/scene-format.md#mesh): a mesh file filled
// with mass-fitted particles at uniform density (build/rigid_body.h).

#include <string>

#include "robophi/build/objects.h"
#include "scene/scene_fields.h"

namespace robophi::scene {

/// Reads a "mesh" entry: its file (relative to `sceneDirectory`), scale,
/// placement, mass and resolution; false (errors reported) when it cannot.
bool readMesh(ObjectReader& r, build::GeneratedObject& out, const std::string& sceneDirectory);

}  // namespace robophi::scene
