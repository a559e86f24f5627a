#pragma once
// The scene's "sensors" (docs/scene-format.md "Sensors", robophi/sensors.h): each
// entry checked where it stands and resolved against the built model.

#include <nlohmann/json.hpp>
#include <string>

#include "robophi/scene/scene.h"
#include "scene/scene_fields.h"

namespace robophi::scene {

/// Reads the array at `pointer` into scene.sensors (after the objects are built).
void readSensors(DiagnosticSink& sink, const nlohmann::json& list, const std::string& pointer,
                 Scene& scene);

}  // namespace robophi::scene
