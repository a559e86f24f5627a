#pragma once
// The scene's "robotics" section (docs/robotics.md): goals (virtual copies and
// LS attractors, MODEL §5.1) with their local-minimum escape, path constraints,
// joint limits, obstacles with a security distance and grasp checks. Reads the
// JSON into the build layer's specs (robophi/build/goals.h), builds the model's
// part with them and fills Scene::robotics for the application's tasks.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "robophi/scene/scene.h"
#include "scene/scene_fields.h"
#include "scene/scene_links.h"

namespace robophi::scene {

/// An object's index by name, or an error at `at` with a suggestion.
std::optional<std::int32_t> findObject(DiagnosticSink& sink, const Scene& scene,
                                       const std::string& name, const std::string& at);
/// A joint's index by name, or an error at `at` with a suggestion.
std::optional<std::size_t> findNamedJoint(DiagnosticSink& sink, const Model& model,
                                          const std::string& name, const std::string& at);

/// A point of a rigid robot's link where a particle reference stands (docs/robotics.md
/// "Links in goals"): "robot.link" (its origin), a name from the section's "points",
/// or {"link": "robot.link", "point": [x, y, z]} (m, in the link's frame). Adds the
/// particle the link carries there (build::addLinkPoint) and returns it; reports
/// an unknown link at `at`.
std::optional<ParticleIndex> resolveLinkPoint(DiagnosticSink& sink, const nlohmann::json& ref,
                                              const std::string& at, Scene& scene);

/// Reads the section at `pointer`; particle references resolve through `lookup`.
void readRoboticsSection(DiagnosticSink& sink, const nlohmann::json& section,
                         const std::string& pointer, const ParticleLookup& lookup, Scene& scene);

}  // namespace robophi::scene
