#include "scene_input.h"

#include <fmt/format.h>

#include <cstdio>

namespace robophi::cli {

std::optional<Scene> loadSceneOrReport(const std::string& path) {
  SceneLoadResult result = loadSceneFile(path);
  for (const Diagnostic& d : result.warnings)
    std::fprintf(stderr, "%s\n", d.format("warning").c_str());
  for (const Diagnostic& d : result.errors) std::fprintf(stderr, "%s\n", d.format("error").c_str());
  if (!result.ok()) {
    std::fprintf(stderr, "%s: %zu error%s; nothing was run or written\n", path.c_str(),
                 result.errors.size(), result.errors.size() == 1 ? "" : "s");
    return std::nullopt;
  }
  return std::move(result.scene);
}

std::string describeScene(const Scene& scene, const StabilityEstimate& stability) {
  const Model& m = scene.model;
  return fmt::format(
      "{}: {} particles, {} LS, {} TS, {} JS, {} joints; omega_max {:.4g} rad/s, critical step "
      "2/omega_max {:.4g} s",
      scene.name.empty() ? scene.sourcePath : scene.name, m.particleCount(), m.linearSprings.size(),
      m.torsionSprings.size(), m.jointSprings.size(), m.joints.size(), stability.omegaMax,
      stability.criticalStep);
}

}  // namespace robophi::cli
