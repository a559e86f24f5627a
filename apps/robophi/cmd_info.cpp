// robophi info FILE [--json]: every object and URDF link with its particle count, mass,
// centre of mass and inertia, next to the values the file declares (docs/robots.md).
#include <cstdio>

#include "commands.h"
#include "run/object_report.h"
#include "scene_input.h"

namespace robophi::cli {

void addInfoCommand(CLI::App& app, int& exitCode) {
  auto* cmd = app.add_subcommand(
      "info", "Objects and URDF links of a scene or a URDF: particles, mass, centre, inertia");
  auto path = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  auto urdf = std::make_shared<UrdfSceneOptions>();
  auto base = std::make_shared<std::string>();
  cmd->add_option("file", *path, "Scene file (JSON) or a URDF robot (.urdf)")->required();
  cmd->add_flag("--json", *json, "Print JSON (docs/robots.md \"robophi info\")");
  addUrdfOptions(*cmd, *urdf, *base);
  cmd->callback([path, json, urdf, base, &exitCode] {
    const auto scene = loadInputOrReport("info", *path, *urdf, *base);
    if (!scene) {
      exitCode = kExitBadInput;
      return;
    }
    const SceneReport report = reportScene(*scene);
    if (*json) {
      std::printf("%s\n", reportJson(report).dump(2).c_str());
    } else {
      std::printf("%s", reportText(report).c_str());
    }
    exitCode = kExitOk;
  });
}

}  // namespace robophi::cli
