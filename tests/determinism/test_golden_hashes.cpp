// Golden hashes: the final state hash of every shipped scene after a fixed
// number of steps (its own step mode, integrator and robotics tasks). Any
// change to the physics shows here. When a change is deliberate, update the
// table from this test's output and say why in the commit message.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <map>

#include "determinism/scene_steps.h"

namespace robophi {
namespace {

constexpr std::int64_t kSteps = 2000;

// stateHash (time, step count, positions, velocities, friction history,
// energy accumulators) after kSteps steps, or the whole run if shorter.
const std::map<std::string, std::string>& goldenHashes() {
  static const std::map<std::string, std::string> table = {
#include "determinism/golden_hashes.inc"
  };
  return table;
}

TEST(GoldenHashes, EveryShippedSceneEndsWhereItDidBefore) {
  const auto& golden = goldenHashes();
  std::string table;
  int checked = 0;
  for (const std::string& path : testing::shippedScenes()) {
    const std::string name = std::filesystem::path(path).stem().string();
    const SceneLoadResult loaded = loadSceneFile(path);
    ASSERT_TRUE(loaded.ok()) << path;
    const RunReport report = testing::runSteps(*loaded.scene, kSteps);
    char hash[17];
    std::snprintf(hash, sizeof hash, "%016llx", static_cast<unsigned long long>(report.stateHash));
    table += "    {\"" + name + "\", \"" + hash + "\"},\n";
    const auto it = golden.find(name);
    if (it == golden.end()) {
      ADD_FAILURE() << name << ": no golden hash recorded";
      continue;
    }
    EXPECT_EQ(it->second, hash) << name << " (" << report.steps << " steps)";
    ++checked;
  }
  EXPECT_EQ(checked, static_cast<int>(golden.size())) << "a recorded scene is missing";
  if (::testing::Test::HasFailure()) {
    std::printf("Hashes of this build (tests/determinism/golden_hashes.inc):\n%s", table.c_str());
  }
}

}  // namespace
}  // namespace robophi
