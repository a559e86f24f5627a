// Every shared robot as a bare URDF with the defaults a new user gets (issue 35:
// "loads as published, stands or hangs sensibly under gravity and runs to exit 0
// with its default settings"): rigid links, no package path given (the meshes are
// found beside the file), run by the CLI's runner.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "robophi/scene/scene.h"
#include "run/runner.h"
#include "test_files.h"

namespace robophi {
namespace {

const std::string kRobots = ROBOPHI_ROBOTS_DIR;

TEST(UrdfDefaults, EverySharedRobotRunsAsPublishedWithTheDefaults) {
  if (!std::filesystem::exists(kRobots + "/kuka_iiwa/model.urdf"))
    GTEST_SKIP() << "no robots at " << kRobots << " (ROBOPHI_ROBOTS_DIR)";
  for (const std::string& file : testing::sharedRobotUrdfs(kRobots)) {
    if (!std::filesystem::exists(file)) {
      ADD_FAILURE() << "missing " << file;
      continue;
    }
    SceneLoadResult loaded = loadUrdfFile(file);  // the defaults: rigid, no package path
    for (const Diagnostic& d : loaded.errors) ADD_FAILURE() << d.format();
    if (!loaded.ok()) continue;
    const Scene& scene = *loaded.scene;
    ASSERT_EQ(scene.model.rigidTrees.size(), 1u) << file;
    RunOptions options;
    options.settings = scene.run;
    options.settings.duration = 1.0;
    options.writeReplay = false;
    options.threads = 1;
    const RunReport report = runScene(scene, options);
    EXPECT_EQ(report.status, "ok") << file << ": " << report.failure;
    // A fixed base hangs where it is built, its joints held by their servos with
    // gravity compensation (a wheeled base stands free on its wheels).
    const Multibody& mb = scene.model.rigidTrees[0].multibody;
    const bool fixedBase = mb.bodies.front().joint != BodyJointKind::kFree;
    std::printf("%s: %s, %lld steps, %s base\n", file.c_str(), report.status.c_str(),
                static_cast<long long>(report.steps), fixedBase ? "fixed" : "free");
  }
}

}  // namespace
}  // namespace robophi
