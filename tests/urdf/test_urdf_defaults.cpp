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

namespace robophi {
namespace {

const std::string kRobots = ROBOPHI_ROBOTS_DIR;

std::vector<std::string> sharedRobotFiles() {
  std::vector<std::string> files;
  for (const char* f : {"cartpole/cartpole.urdf", "husky/husky.urdf", "pr2_gripper/pr2_gripper.urdf",
                        "r2d2/r2d2.urdf", "franka_panda/panda.urdf", "kuka_iiwa/model.urdf",
                        "kuka_iiwa/model_vr_limits.urdf", "kuka_iiwa/model_free_base.urdf",
                        "kuka_iiwa/model_for_sdf.urdf"})
    files.push_back(kRobots + "/" + f);
  const std::string wild = kRobots + "/../robots-wild/example-robot-data/robots/";
  for (const char* f : {"laikago_description/urdf/laikago.urdf",
                        "allegro_hand_description/urdf/allegro_right_hand.urdf",
                        "allegro_hand_description/urdf/allegro_left_hand.urdf",
                        "ur_description/urdf/ur5_joint_limited_robot.urdf",
                        "ur_description/urdf/ur5_robot.urdf", "ur_description/urdf/ur5_gripper.urdf",
                        "solo_description/robots/solo.urdf", "solo_description/robots/solo12.urdf"})
    files.push_back(wild + f);
  return files;
}

TEST(UrdfDefaults, EverySharedRobotRunsAsPublishedWithTheDefaults) {
  if (!std::filesystem::exists(kRobots + "/kuka_iiwa/model.urdf"))
    GTEST_SKIP() << "no robots at " << kRobots << " (ROBOPHI_ROBOTS_DIR)";
  for (const std::string& file : sharedRobotFiles()) {
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
