#pragma once
// Loading a scene for a subcommand: prints every diagnostic to stderr.

#include <optional>
#include <string>

#include "robophi/scene/scene.h"

namespace robophi::cli {

/// The scene, or nothing after its errors were printed.
std::optional<Scene> loadSceneOrReport(const std::string& path);

/// One line: particles, connectors, joints, and the stability estimate.
std::string describeScene(const Scene& scene, const StabilityEstimate& stability);

}  // namespace robophi::cli
