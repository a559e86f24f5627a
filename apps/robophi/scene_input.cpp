#include "scene_input.h"

#include <fmt/format.h>

#include <cstdio>

#include "robophi/scene/scene_mjcf.h"

namespace robophi::cli {

std::optional<Scene> loadSceneOrReport(const std::string& path, const UrdfSceneOptions& urdf) {
  SceneLoadResult result = isMjcfPath(path)   ? loadMjcfFile(path, urdf)
                           : isUrdfPath(path) ? loadUrdfFile(path, urdf)
                                              : loadSceneFile(path);
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

void addUrdfOptions(CLI::App& command, UrdfSceneOptions& urdf, std::string& base) {
  command.add_option(
      "--package-path", urdf.packagePaths,
      "A bare URDF: folder for package:// meshes (repeatable; then ROS_PACKAGE_PATH)");
  command.add_option("--base", base,
                     "A bare URDF: fixed | free (default: free for a wheeled base, two or more "
                     "continuous joints; fixed otherwise)");
  command.add_flag("--rigid{true},--particles{false}", urdf.rigid,
                   "A bare URDF: --rigid (the default) its links as rigid bodies with the "
                   "file's exact mass properties and joints in reduced coordinates "
                   "(docs/robots.md \"Rigid bodies\"); --particles the paper's model, links "
                   "filled with particles tied by connectors (docs/robots.md \"A bare URDF\")");
}

bool urdfOptionsOk(const char* command, const std::string& base, UrdfSceneOptions& urdf) {
  if (base.empty()) return true;
  if (base == "fixed" || base == "free") {
    urdf.fixedBase = base == "fixed";
    return true;
  }
  std::fprintf(stderr, "robophi %s: --base '%s': expected fixed or free\n", command, base.c_str());
  return false;
}

std::optional<Scene> loadInputOrReport(const char* command, const std::string& path,
                                       UrdfSceneOptions urdf, const std::string& base) {
  if (!urdfOptionsOk(command, base, urdf)) return std::nullopt;
  return loadSceneOrReport(path, urdf);
}

std::string describeScene(const Scene& scene, const StabilityEstimate& stability) {
  const Model& m = scene.model;
  // The critical step is 2/omega_max reduced for damping (MODEL §2): both are given.
  const double undamped = 2.0 / stability.omegaMax;
  const std::string damped =
      stability.criticalStep < undamped * (1.0 - 1e-3)
          ? fmt::format(", reduced for damping from 2/omega_max = {:.4g} s", undamped)
          : std::string(" (2/omega_max)");
  return fmt::format(
      "{}: {} particles, {} LS, {} TS, {} JS, {} joints; omega_max {:.4g} rad/s, critical step "
      "{:.4g} s{}",
      scene.name.empty() ? scene.sourcePath : scene.name, m.particleCount(), m.linearSprings.size(),
      m.torsionSprings.size(), m.jointSprings.size(), m.joints.size(), stability.omegaMax,
      stability.criticalStep, damped);
}

}  // namespace robophi::cli
