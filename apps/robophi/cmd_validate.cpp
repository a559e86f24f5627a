// robophi validate SCENE: exit 0 if the scene is valid, 2 otherwise.
#include <cstdio>

#include "commands.h"
#include "run/runner.h"
#include "run/start_checks.h"
#include "scene_input.h"

namespace robophi::cli {

void addValidateCommand(CLI::App& app, int& exitCode) {
  auto* cmd = app.add_subcommand("validate",
                                 "Check a scene file or a URDF robot; exit 0 if valid, 2 if not");
  auto path = std::make_shared<std::string>();
  auto urdf = std::make_shared<UrdfSceneOptions>();
  auto base = std::make_shared<std::string>();
  cmd->add_option("scene", *path, "Scene file (JSON) or a URDF robot (.urdf)")->required();
  addUrdfOptions(*cmd, *urdf, *base);
  cmd->callback([path, urdf, base, &exitCode] {
    const auto scene = loadInputOrReport("validate", *path, *urdf, *base);
    if (!scene) {
      exitCode = kExitBadInput;
      return;
    }
    const StabilityEstimate stability = estimateStability(scene->model, &scene->initial.position);
    // What robophi run refuses before it starts, with the scene's own settings
    // (and the default energy rate): validate accepts exactly what run accepts.
    std::string problem = adaptiveStepLimitProblem(scene->run, stability);
    if (const auto settings = checkRunSettings(scene->run, RunOptions().energyRate))
      problem = settings->message;
    if (!problem.empty()) {
      std::fprintf(stderr, "robophi validate: %s: %s\n", path->c_str(), problem.c_str());
      exitCode = kExitBadInput;
      return;
    }
    std::printf("%s\n", describeScene(*scene, stability).c_str());
    for (const auto& w : preflightWarnings(scene->run, stability)) {
      std::fprintf(stderr, "%s: warning: %s\n", path->c_str(), w.c_str());
    }
    for (const auto& w : startingOverlapWarnings(scene->model, scene->initial)) {
      std::fprintf(stderr, "%s: warning: %s\n", path->c_str(), w.c_str());
    }
    std::printf("%s: valid\n", path->c_str());
    exitCode = kExitOk;
  });
}

}  // namespace robophi::cli
