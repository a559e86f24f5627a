#pragma once
// Runs a shipped scene for a fixed number of steps, as `robophi run` does (its
// own step mode, integrator and robotics tasks), for the hash tests.

#include <algorithm>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "robophi/scene/scene.h"
#include "robotics/tasks.h"
#include "run/runner.h"

namespace robophi::testing {

/// The scene files in scenes/, sorted.
inline std::vector<std::string> shippedScenes() {
  std::vector<std::string> paths;
  for (const auto& entry : std::filesystem::directory_iterator(ROBOPHI_SOURCE_DIR "/scenes")) {
    if (entry.path().extension() == ".json") paths.push_back(entry.path().string());
  }
  std::sort(paths.begin(), paths.end());
  return paths;
}

/// Runs `scene` for `steps` steps (or its whole duration, if shorter), calling
/// `hook` after each step, on up to `threads` threads (0: the cores available);
/// returns the report (its stateHash is the final state's).
inline RunReport runSteps(const Scene& scene, std::int64_t steps,
                          const std::function<void(World&)>& hook = {}, int threads = 0) {
  RunOptions options;
  options.settings = scene.run;
  options.threads = threads;
  options.writeReplay = false;
  options.tasks.push_back(robotics::makeSceneTasks(scene));
  options.tasks.push_back([&](World& world, std::vector<std::string>&) {
    if (hook) hook(world);
    return world.state().stepCount < steps;
  });
  return runScene(scene, options);
}

}  // namespace robophi::testing
