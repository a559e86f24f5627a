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

#include "robophi/joints.h"
#include "robophi/scene/scene.h"
#include "robophi/world.h"
#include "robotics/tasks.h"
#include "run/object_report.h"
#include "run/runner.h"
#include "test_files.h"

namespace robophi {
namespace {

using testing::kRobots;  // ROBOPHI_ROBOTS_DIR (test_files.h)

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

// Every shared robot on a free base (`--base free`): it falls to the ground and
// lies or stands there, 2 s to exit 0. (The PR2 gripper stalled at 0.94 s: its
// pole's particles lie on a line, and its contact tree turned with a frame made
// of rounding; test_rigid_tree.cpp.)
TEST(UrdfDefaults, EverySharedRobotRunsOnAFreeBase) {
  if (!std::filesystem::exists(kRobots + "/kuka_iiwa/model.urdf"))
    GTEST_SKIP() << "no robots at " << kRobots << " (ROBOPHI_ROBOTS_DIR)";
  for (const std::string& file : testing::sharedRobotUrdfs(kRobots)) {
    if (!std::filesystem::exists(file)) continue;
    UrdfSceneOptions free;
    free.fixedBase = false;
    SceneLoadResult loaded = loadUrdfFile(file, free);
    for (const Diagnostic& d : loaded.errors) ADD_FAILURE() << d.format();
    if (!loaded.ok()) continue;
    RunOptions options;
    options.settings = loaded.scene->run;
    options.settings.duration = 2.0;
    options.writeReplay = false;
    options.threads = 1;
    const RunReport report = runScene(*loaded.scene, options);
    EXPECT_EQ(report.status, "ok") << file << ": " << report.failure;
    std::printf("%s on a free base: %s, %lld steps\n", file.c_str(), report.status.c_str(),
                static_cast<long long>(report.steps));
  }
}

// The Panda's <mimic> finger follows the first as a bare URDF: finger 1's servo
// target moved from 0 to 0.03 m, finger 2 follows within 0.1 mm.
TEST(UrdfDefaults, AMimicJointFollowsItsLeader) {
  const std::string file = kRobots + "/franka_panda/panda.urdf";
  if (!std::filesystem::exists(file)) GTEST_SKIP() << "no robots at " << kRobots;
  SceneLoadResult loaded = loadUrdfFile(file);
  ASSERT_TRUE(loaded.ok());
  const Scene& scene = *loaded.scene;
  ASSERT_EQ(scene.robotics.control.mimics.size(), 1u);
  std::size_t leader = 0, follower = 0;
  for (std::size_t k = 0; k < scene.model.joints.size(); ++k) {
    if (scene.model.joints[k].name == "panda.panda_finger_joint1") leader = k;
    if (scene.model.joints[k].name == "panda.panda_finger_joint2") follower = k;
  }
  EXPECT_EQ(scene.robotics.control.mimics[0].leader, leader);
  EXPECT_EQ(scene.robotics.control.mimics[0].joint, follower);
  double q1 = 0.0, q2 = 0.0;
  RunOptions options;
  options.settings = scene.run;
  options.settings.duration = 1.0;
  options.writeReplay = false;
  options.threads = 1;
  const robotics::SceneTaskHook hook = robotics::makeSceneTaskHook(scene);
  bool moved = false;
  options.tasks = {[&](World& world, std::vector<std::string>& events) {
                     if (!moved) world.setJointTarget(leader, 0.03);
                     moved = true;
                     return hook.task(world, events);
                   },
                   [&](World& world, std::vector<std::string>&) {
                     q1 = jointPosition(world.model(), world.state(), leader);
                     q2 = jointPosition(world.model(), world.state(), follower);
                     return true;
                   }};
  const RunReport report = runScene(scene, options);
  ASSERT_EQ(report.status, "ok") << report.failure;
  EXPECT_NEAR(q1, 0.03, 1e-3);
  EXPECT_NEAR(q2, q1, 1e-4);
}

}  // namespace
}  // namespace robophi

namespace robophi {
namespace {

// `robophi info` on a rigid robot shows each body's own mass properties, the URDF's
// (docs/robots.md "robophi info"), not moments of its surface particles: the iiwa's
// link 1 (4 kg, centre (0, −0.03, 0.12) from its joint at z = 0.1575, moments 0.02,
// 0.09, 0.1 kg·m²).
TEST(UrdfDefaults, InfoShowsARigidLinksOwnMassProperties) {
  const std::string file = ROBOPHI_ROBOTS_DIR "/kuka_iiwa/model.urdf";
  if (!std::filesystem::exists(file)) GTEST_SKIP() << "no " << file << " (ROBOPHI_ROBOTS_DIR)";
  SceneLoadResult loaded = loadUrdfFile(file);
  ASSERT_TRUE(loaded.ok());
  const SceneReport report = reportScene(*loaded.scene);
  const auto link = std::find_if(report.objects.begin(), report.objects.end(),
                                 [](const ObjectReport& r) { return r.name == "lbr_iiwa.lbr_iiwa_link_1"; });
  ASSERT_NE(link, report.objects.end());
  EXPECT_EQ(link->kind, "rigid body");
  EXPECT_GT(link->particles, 0);
  EXPECT_DOUBLE_EQ(link->built.mass, 4.0);
  EXPECT_NEAR(link->built.centerOfMass.x, 0.0, 1e-12);  // (the base at the origin, q = 0)
  EXPECT_NEAR(link->built.centerOfMass.y, -0.03, 1e-12);
  EXPECT_NEAR(link->principalMoments[0], 0.02, 1e-12);
  EXPECT_NEAR(link->principalMoments[1], 0.09, 1e-12);
  EXPECT_NEAR(link->principalMoments[2], 0.1, 1e-12);
}

}  // namespace
}  // namespace robophi
