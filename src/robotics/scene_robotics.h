#pragma once
// The scene's "robotics" section (docs/robotics.md): goals (virtual copies and
// LS attractors, MODEL §5.1), path constraints, joint limits, obstacles with a
// security distance, local-minimum escape and grasp checks. Builds the model's
// part at load time and fills Scene::robotics for the runner.

#include <nlohmann/json.hpp>
#include <string>

#include "io/scene_fields.h"
#include "io/scene_links.h"
#include "robophi/scene.h"

namespace robophi::robotics {

/// Rest length (m) of an attractor LS: the law needs l0 > 0, and this is zero in effect.
inline constexpr double kAttractorRestLength = 1.0e-9;
/// Radius (m) of a virtual particle, small so that it hardly ever touches anything.
inline constexpr double kVirtualRadius = 1.0e-4;

void readRoboticsSection(io::DiagnosticSink& sink, const nlohmann::json& section,
                         const std::string& pointer, const io::ParticleLookup& lookup,
                         Scene& scene);

}  // namespace robophi::robotics
