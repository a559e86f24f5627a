// Same input, same output, bit for bit: every example scene run twice (in this
// process, and as two separate `robophi run` processes) gives the same state hash.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "robophi/scene/scene.h"
#include "robotics/tasks.h"
#include "run/runner.h"

namespace robophi {
namespace {

std::vector<std::string> exampleScenes() {
  std::vector<std::string> paths;
  for (const auto& entry : std::filesystem::directory_iterator(ROBOPHI_SOURCE_DIR "/scenes")) {
    if (entry.path().extension() == ".json") paths.push_back(entry.path().string());
  }
  std::sort(paths.begin(), paths.end());
  return paths;
}

RunReport runBriefly(const Scene& scene, StepMode mode) {
  RunOptions options;
  options.settings = scene.run;
  options.tasks = {robotics::makeSceneTasks(scene)};
  options.settings.stepMode = mode;
  options.settings.duration = std::min(scene.run.duration, 0.05);
  return runScene(scene, options);
}

TEST(Determinism, EveryExampleSceneTwiceInProcess) {
  const auto scenes = exampleScenes();
  ASSERT_FALSE(scenes.empty());
  for (const std::string& path : scenes) {
    const SceneLoadResult loaded = loadSceneFile(path);
    ASSERT_TRUE(loaded.ok()) << path;
    for (StepMode mode : {StepMode::kConstant, StepMode::kAdaptive}) {
      const RunReport first = runBriefly(*loaded.scene, mode);
      const RunReport second = runBriefly(*loaded.scene, mode);
      // Briefly: a goal may not be reached yet (status goal_not_reached).
      EXPECT_TRUE(first.sound()) << path << ": " << first.failure;
      EXPECT_GT(first.steps, 0) << path;
      EXPECT_EQ(first.stateHash, second.stateHash) << path;
    }
  }
}

std::string hashOfRun(const std::string& scene, const std::string& outDir) {
  const std::string command = std::string(ROBOPHI_BINARY) + " run " + scene + " --out " + outDir +
                              " --duration 0.05 --quiet > /dev/null";
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  std::ifstream in(outDir + "/summary.json");
  return nlohmann::json::parse(in).at("state_hash").get<std::string>();
}

TEST(Determinism, TwoProcessesGiveTheSameHash) {
  const auto dir = std::filesystem::temp_directory_path() / "robophi_determinism";
  std::filesystem::remove_all(dir);
  const std::string scene = ROBOPHI_SOURCE_DIR "/scenes/default.json";
  const std::string first = hashOfRun(scene, (dir / "a").string());
  const std::string second = hashOfRun(scene, (dir / "b").string());
  EXPECT_EQ(first, second);
  EXPECT_EQ(first.size(), 16u);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace robophi
