#pragma once
// The scene's "control" section (docs/robots.md "Controlling joints",
// docs/scene-format.md): actuators by joint name, mimic joints, moving bases and
// a sequence of phases. Reads it into the build layer's ControlSpec
// (robophi/build/control.h) in Scene::robotics.control.

#include <nlohmann/json.hpp>
#include <string>

#include "robophi/scene/scene.h"
#include "scene/scene_fields.h"

namespace robophi::scene {

/// Reads the section at `pointer` (after the objects and joints are built).
void readControlSection(DiagnosticSink& sink, const nlohmann::json& section,
                        const std::string& pointer, Scene& scene);

}  // namespace robophi::scene
