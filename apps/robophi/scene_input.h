#pragma once
// Loading a scene for a subcommand: prints every diagnostic to stderr.

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "robophi/scene/scene.h"

namespace robophi::cli {

/// The scene (a scene file, or a bare URDF: loadUrdfFile with `urdf`), or nothing after its
/// errors were printed.
std::optional<Scene> loadSceneOrReport(const std::string& path, const UrdfSceneOptions& urdf = {});

/// Adds the bare-URDF options to a subcommand: --package-path DIR (repeatable), --base
/// fixed|free. `base` is checked by urdfOptionsOk.
void addUrdfOptions(CLI::App& command, UrdfSceneOptions& urdf, std::string& base);
/// Applies `base` ("", "fixed", "free") to `urdf`; false (and a message) for another value.
bool urdfOptionsOk(const char* command, const std::string& base, UrdfSceneOptions& urdf);
/// urdfOptionsOk, then loadSceneOrReport: the scene, or nothing after a message.
std::optional<Scene> loadInputOrReport(const char* command, const std::string& path,
                                       UrdfSceneOptions urdf, const std::string& base);

/// One line: particles, connectors, joints, and the stability estimate.
std::string describeScene(const Scene& scene, const StabilityEstimate& stability);

}  // namespace robophi::cli
