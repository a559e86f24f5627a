// The Panda picks a 5 cm box (scenes/panda_pick.json, docs/robots.md "Picking with a
// URDF gripper"): its arm servoed along joint keyframes, its own fingers closed by a
// 10 N effort and the URDF's mimic, the lift started by the fingers' contact force,
// then a 5 s hold.

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#ifdef ROBOPHI_HAVE_KDL
#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/tree.hpp>
#include <kdl_parser/kdl_parser.hpp>
#endif

#include "robophi/joints.h"
#include "robophi/scene/scene.h"
#include "robotics/tasks.h"
#include "run/runner.h"
#include "test_files.h"

namespace robophi {
namespace {

using testing::kRobots;  // ROBOPHI_ROBOTS_DIR (test_files.h)
const std::string kScene = std::string(ROBOPHI_SOURCE_DIR) + "/scenes/panda_pick.json";

// The scene finds the robot at $(optenv ROBOPHI_ROBOTS_DIR ../../shared/robots): the
// tests' robots folder, wherever the checkout is.
SceneLoadResult loadPick() {
  setenv("ROBOPHI_ROBOTS_DIR", kRobots.c_str(), 0);
  return loadSceneFile(kScene);
}

std::int32_t objectNamed(const Model& model, const std::string& name) {
  for (std::size_t o = 0; o < model.objects.size(); ++o)
    if (model.objects[o].name == name) return static_cast<std::int32_t>(o);
  return -1;
}

// Centre of mass of an object's particles (m).
Vec3 centerOf(const Model& model, const State& state, std::int32_t object) {
  const ObjectInfo& o = model.objects[static_cast<std::size_t>(object)];
  Vec3 sum{};
  double mass = 0.0;
  for (ParticleIndex i = o.firstParticle; i < o.firstParticle + o.particleCount; ++i) {
    sum += state.position[static_cast<std::size_t>(i)] * model.mass[i];
    mass += model.mass[i];
  }
  return sum / mass;
}

// The scene loads: the Panda with both fingers open (q = 0.04 m), the faceted box on
// the ground between them, and the control sequence of four phases.
TEST(UrdfPick, TheSceneValidates) {
  SceneLoadResult result = loadPick();
  for (const auto& e : result.errors) ADD_FAILURE() << e.format();
  ASSERT_TRUE(result.ok());
  const Scene& scene = *result.scene;
  ASSERT_EQ(scene.urdfRobots.size(), 1u);
  ASSERT_EQ(scene.robotics.control.phases.size(), 4u);
  EXPECT_EQ(scene.robotics.control.phases[2].name, "lift");
  EXPECT_EQ(scene.robotics.control.mimics.size(), 1u);
  const std::int32_t box = objectNamed(scene.model, "box");
  ASSERT_GE(box, 0);
  EXPECT_GT(scene.model.objects[static_cast<std::size_t>(box)].triangleCount, 0);
  for (const char* finger : {"panda.panda_finger_joint1", "panda.panda_finger_joint2"}) {
    const auto j = findJoint(scene.model, finger);
    ASSERT_TRUE(j.has_value()) << finger;
    EXPECT_NEAR(jointPosition(scene.model, scene.initial, *j), 0.04, 1e-9) << finger;
  }
  const Vec3 c = centerOf(scene.model, scene.initial, box);
  EXPECT_NEAR(c.x, 0.5, 1e-12);
  EXPECT_NEAR(c.z, 0.025, 1e-12);
}

// The must-show (issue 14): the Panda picks the 5 cm box from the ground with its own
// fingers, lifts it 10 cm and holds it 5 s with a slip below 2 mm, driven by the
// scene's control sequence. Measured 2026-12-02: see docs/robots.md "Status".
// Slow/* (label slow): 11 s simulated.
class UrdfPickRun : public ::testing::TestWithParam<const char*> {};

TEST_P(UrdfPickRun, ThePandaPicksTheBoxLiftsIt10cmAndHoldsIt5s) {
  setenv("ROBOPHI_ROBOTS_DIR", kRobots.c_str(), 0);
  SceneLoadResult result = loadSceneFile(std::string(ROBOPHI_SOURCE_DIR) + "/scenes/" + GetParam());
  for (const auto& e : result.errors) ADD_FAILURE() << e.format();
  ASSERT_TRUE(result.ok());
  const Scene& scene = *result.scene;
  const Model& model = scene.model;
  const std::int32_t box = objectNamed(model, "box");
  const std::int32_t left = objectNamed(model, "panda.panda_leftfinger");
  const std::int32_t right = objectNamed(model, "panda.panda_rightfinger");
  ASSERT_TRUE(box >= 0 && left >= 0 && right >= 0);
  // After every step: the box's centre, and its place relative to the fingers
  // (box centre minus the mean of the two fingers' centres).
  struct Sample {
    double t;
    Vec3 box, relative;
  };
  std::vector<Sample> samples;
  RunOptions options;
  options.settings = scene.run;
  options.writeReplay = false;
  options.threads = 1;
  const robotics::SceneTaskHook hook = robotics::makeSceneTaskHook(scene);
  options.tasks = {hook.task, [&](World& world, std::vector<std::string>&) {
                     const State& s = world.state();
                     const Vec3 fingers =
                         (centerOf(model, s, left) + centerOf(model, s, right)) * 0.5;
                     const Vec3 b = centerOf(model, s, box);
                     samples.push_back({s.time, b, b - fingers});
                     return true;
                   }};
  const auto start = std::chrono::steady_clock::now();
  const RunReport report = runScene(scene, options);
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(report.status, "ok") << report.failure;
  ASSERT_FALSE(samples.empty());
  // Every phase started, by its condition rather than its timeout.
  const nlohmann::json& phases = report.outcomes.at("control").at("phases");
  ASSERT_EQ(phases.size(), 4u);
  for (const nlohmann::json& phase : phases) {
    ASSERT_TRUE(phase.at("started").get<bool>()) << report.outcomes.dump();
    EXPECT_EQ(phase.at("by").get<std::string>().find("timeout"), std::string::npos) << phase.dump();
  }
  const double lifted = phases.at(2).at("started_s").get<double>();
  const double hold = phases.at(3).at("started_s").get<double>();
  ASSERT_LE(hold + 5.0, samples.back().t) << "the run ends before the 5 s hold does";
  // The box's centre when the lift began and over the 5 s hold that follows it.
  const auto at = [&](double t) {
    const auto it = std::lower_bound(samples.begin(), samples.end(), t,
                                     [](const Sample& s, double v) { return s.t < v; });
    return *(it == samples.end() ? samples.end() - 1 : it);
  };
  const Sample before = at(lifted), held = at(hold), end = at(hold + 5.0);
  double slip = 0.0, lowest = 1e9, highest = -1e9;
  for (const Sample& s : samples) {
    if (s.t < hold || s.t > hold + 5.0) continue;
    slip = std::max(slip, norm(s.relative - held.relative));
    lowest = std::min(lowest, s.box.z - before.box.z);
    highest = std::max(highest, s.box.z - before.box.z);
  }
  const double rise = end.box.z - before.box.z;
  std::printf(
      "panda pick: lift at %.3f s, hold %.3f-%.3f s; box rose %.5f m (during the hold %.5f to "
      "%.5f m), slip relative to the fingers over the hold %.3g m (%.3g m at its end); "
      "%.1f s simulated in %.1f s wall (%lld steps)\n",
      lifted, hold, hold + 5.0, rise, lowest, highest, slip, norm(end.relative - held.relative),
      samples.back().t, wall, static_cast<long long>(report.steps));
  // Rises 10 cm ± 5 mm (the arm's servos, kp = 300 N·m/rad, give a little under the
  // box; measured 0.0992 m, 0.0983-0.0996 m over the hold) and stays there.
  EXPECT_NEAR(rise, 0.10, 5e-3);
  EXPECT_NEAR(lowest, 0.10, 5e-3);
  EXPECT_NEAR(highest, 0.10, 5e-3);
  EXPECT_LT(slip, 2e-3);
}

INSTANTIATE_TEST_SUITE_P(Slow, UrdfPickRun, ::testing::Values("panda_pick.json"));
// The same task with the Panda and the box as rigid bodies (issue 35; 11 s simulated
// in 0.2-0.4 s at steps of at most 2 ms, its contacts implicit: not slow).
INSTANTIATE_TEST_SUITE_P(Rigid, UrdfPickRun, ::testing::Values("panda_pick_rigid.json"));

#ifdef ROBOPHI_HAVE_KDL
// The scene's joint targets (arm joints 1..7, rad) put panda_grasptarget, the point
// between the fingertips, at (0.5, 0, z) with the hand's z axis straight down
// (orocos-kdl's forward kinematics of the URDF): pre-grasp z = 0.2, grasp 0.025, lift 0.125.
TEST(UrdfPick, TheJointTargetsPutTheGraspPointOverTheBox) {
  KDL::Tree tree;
  ASSERT_TRUE(kdl_parser::treeFromFile(kRobots + "/franka_panda/panda.urdf", tree));
  KDL::Chain chain;
  ASSERT_TRUE(tree.getChain("panda_link0", "panda_grasptarget", chain));
  ASSERT_EQ(chain.getNrOfJoints(), 7u);
  KDL::ChainFkSolverPos_recursive fk(chain);
  const struct {
    double z;
    double q[7];
  } targets[] = {{0.2, {0, 0.04296, 0, -2.37494, 0, 2.41749, 0.78539}},
                 {0.025, {0, 0.46896, 0, -2.36292, 0, 2.83182, 0.78539}},
                 {0.125, {0, 0.20600, 0, -2.40130, 0, 2.60757, 0.78540}}};
  for (const auto& target : targets) {
    KDL::JntArray q(7);
    for (unsigned k = 0; k < 7; ++k) q(k) = target.q[k];
    KDL::Frame frame;
    ASSERT_GE(fk.JntToCart(q, frame), 0);
    SCOPED_TRACE(target.z);
    // Five-digit joint values: within 0.1 mm and 0.01 rad.
    EXPECT_NEAR(frame.p.x(), 0.5, 1e-4);
    EXPECT_NEAR(frame.p.y(), 0.0, 1e-4);
    EXPECT_NEAR(frame.p.z(), target.z, 1e-4);
    EXPECT_NEAR(frame.M(2, 2), -1.0, 1e-4);  // the approach axis, straight down
    // The fingers close along the world's y axis (the hand's y), the box's faces ±y.
    EXPECT_NEAR(std::abs(frame.M(1, 1)), 1.0, 1e-4);
    std::printf("z = %.3f: grasp point (%.6f, %.6f, %.6f), hand z axis (%.5f, %.5f, %.5f)\n",
                target.z, frame.p.x(), frame.p.y(), frame.p.z(), frame.M(0, 2), frame.M(1, 2),
                frame.M(2, 2));
  }
}
#endif

}  // namespace
}  // namespace robophi
