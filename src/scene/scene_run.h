#pragma once
// The scene's "run" section (docs/scene-format.md#run): how long, the step, the
// integrator, the frame rate, and the adaptive step's settings ("run.adaptive").

#include <nlohmann/json.hpp>

#include "robophi/scene/scene.h"
#include "scene/scene_fields.h"

namespace robophi::scene {

/// Reads "run" (nullptr: absent, every default).
RunSettings readRunSettings(DiagnosticSink& sink, const nlohmann::json* value);

/// Reads "run.adaptive" at `pointer` into `settings` (given keys only).
void readAdaptiveSettings(DiagnosticSink& sink, const nlohmann::json& value,
                          const std::string& pointer, AdaptiveStepSettings& settings);

}  // namespace robophi::scene
