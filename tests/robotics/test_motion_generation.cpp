// MODEL §5.1 motion generation: a passive arm following its tool to a goal, and a
// wheeled mobile robot kept on a straight line and on an arc of circle (an arc by
// the paper's mechanism: a TS between two fixed points at the inscribed angle).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "robophi/joints.h"
#include "robophi/scene/scene.h"
#include "robotics/joint_control.h"
#include "robotics/scene_files.h"
#include "robotics/tasks.h"
#include "run/runner.h"

namespace robophi {
namespace {

bool reached(const RunReport& report) {
  for (const auto& e : report.events)
    if (e.find("reached at") != std::string::npos) return true;
  return false;
}

TEST(MotionGeneration, PassiveArmToolReachesVirtualToolAndJointsGiveTheTrajectory) {
  const Scene scene = testing::loadSceneFromScenes("arm_reach.json");
  ASSERT_EQ(scene.model.joints.size(), 2u);
  EXPECT_EQ(scene.model.joints[0].name, "arm.j1");
  EXPECT_EQ(scene.model.joints[1].name, "arm.j2");
  const auto tool = static_cast<ParticleIndex>(scene.model.objects[0].particleCount - 1);
  // The joints are passive: stiffness 0 (MODEL §1).
  for (const auto& s : scene.model.jointSprings) EXPECT_EQ(s.stiffness, 0.0);
  RunOptions options;
  options.settings = scene.run;
  options.tasks = {robotics::makeSceneTasks(scene)};
  State last;
  const RunReport report = runScene(scene, options, &last);
  ASSERT_TRUE(report.ok()) << report.failure;
  EXPECT_TRUE(reached(report));
  EXPECT_LT(report.simulatedTime, scene.run.duration);  // stopped when reached
  // The joint values are the trajectory: forward kinematics of (j1, j2) puts the
  // tool at the goal (links 0.5 m and 0.4 m, angles π = straight).
  const double q1 = jointValue(scene.model, last, 0) - M_PI;
  const double q2 = jointValue(scene.model, last, 1) - M_PI;
  const double x = 0.5 * std::cos(q1) + 0.4 * std::cos(q1 + q2);
  const double y = 0.5 * std::sin(q1) + 0.4 * std::sin(q1 + q2);
  EXPECT_NEAR(x, 0.2, 0.015);
  EXPECT_NEAR(y, 0.6, 0.015);
  EXPECT_NEAR(last.position[tool].x, 0.2, 0.011);
  EXPECT_NEAR(last.position[tool].y, 0.6, 0.011);
  // Analytic inverse kinematics: |q2| = acos((d² - L1² - L2²) / (2 L1 L2)).
  const double d2 = 0.2 * 0.2 + 0.6 * 0.6;
  EXPECT_NEAR(std::abs(q2), std::acos((d2 - 0.25 - 0.16) / 0.4), 0.04);
}

// A wheeled robot on the ground (scenes/mobile_line.json, mobile_arc.json): the
// path particle's error, whether it reached its goal, and that it drove on its
// wheels (no chassis contact with the ground, the axles turned).
struct Drive {
  RunReport report;
  State last;
  double largestPathError = 0.0;  // m
  bool chassisTouched = false;
  double axleTurn = 0.0;  // largest |change| of an axle angle, rad (unwrapped)
};

Drive drive(const char* name, const std::function<double(const Vec3&)>& pathError) {
  const Scene scene = testing::loadSceneFromScenes(name);
  Drive d;
  RunOptions options;
  options.settings = scene.run;
  options.tasks = {robotics::makeSceneTasks(scene)};
  std::vector<double> previous(4, 0.0), turned(4, 0.0);
  bool first = true;
  options.tasks.push_back([&](World& world, std::vector<std::string>&) {
    const State& s = world.state();
    d.largestPathError = std::max(d.largestPathError, pathError(s.position[4]));
    for (const Contact& c : world.contacts())
      if (c.withEnvironment() && c.a < 12) d.chassisTouched = true;  // the 3×2×2 chassis
    for (std::size_t j = 0; j < 4; ++j) {
      const double value = jointValue(world.model(), s, j);
      if (!first) turned[j] += std::remainder(value - previous[j], 2.0 * M_PI);
      previous[j] = value;
      d.axleTurn = std::max(d.axleTurn, std::abs(turned[j]));
    }
    first = false;
    return true;
  });
  d.report = runScene(scene, options, &d.last);
  return d;
}

TEST(MotionGeneration, WheeledRobotStaysOnItsStraightLine) {
  // The line: y = -0.075 m (the path particle's side of the chassis).
  const Drive d = drive("mobile_line.json", [](const Vec3& p) { return std::abs(p.y + 0.075); });
  ASSERT_TRUE(d.report.ok()) << d.report.failure;
  EXPECT_TRUE(reached(d.report));
  EXPECT_NEAR(d.last.position[4].x, 2.0, 0.05);
  // Shoved sideways at 0.3 m/s as it sets off: the TS at 180° holds it within 1.5 cm.
  EXPECT_LT(d.largestPathError, 0.015);
  // On its wheels: they turned (2 m on 0.12 m wheels is 16.7 rad), the chassis never scraped.
  EXPECT_FALSE(d.chassisTouched);
  EXPECT_GT(d.axleTurn, 0.5 * 2.0 / 0.12);
  std::printf("mobile line: largest path error %.4f m, axles turned %.2f rad\n", d.largestPathError,
              d.axleTurn);
}

TEST(MotionGeneration, WheeledRobotFollowsAnArcHeldByAnInscribedAngle) {
  // The circle: radius 1.075 m about the origin.
  const Drive d = drive("mobile_arc.json",
                        [](const Vec3& p) { return std::abs(std::hypot(p.x, p.y) - 1.075); });
  ASSERT_TRUE(d.report.ok()) << d.report.failure;
  EXPECT_TRUE(reached(d.report));
  EXPECT_NEAR(d.last.position[4].x, 1.075, 0.05);
  EXPECT_NEAR(d.last.position[4].y, 0.0, 0.05);
  // The virtual robot moves along the chord, 0.31 m inside the arc at its
  // middle; the TS between two fixed points of the circle holds the robot on it.
  EXPECT_LT(d.largestPathError, 0.035);
  EXPECT_FALSE(d.chassisTouched);
  EXPECT_GT(d.axleTurn, 0.5 * (0.5 * M_PI * 1.0) / 0.12);
  std::printf("mobile arc: largest radius error %.4f m, axles turned %.2f rad\n",
              d.largestPathError, d.axleTurn);
}

// Joint control API: servo target, limits, passive switch (MODEL §1).
TEST(JointControl, ServoLimitAndSwitchOff) {
  Scene scene = testing::loadSceneFromScenes("revolute_arm.json");
  World world(scene.model, scene.initial, scene.run.integrator);
  const auto elbow = robotics::findJoint(world.model(), "elbow");
  ASSERT_TRUE(elbow.has_value());
  ASSERT_TRUE(robotics::setJointTarget(world, *elbow, 2.6));
  EXPECT_DOUBLE_EQ(jointServo(world.model(), *elbow).target, 2.6);
  // A limit at [2.8, 3.5] holds the elbow at 2.8 while its own servo wants 2.6.
  robotics::JointLimiter limiter({{*elbow, 2.8, 3.5, 400.0, 5.0}});
  for (int i = 0; i < 20000; ++i) {
    world.step(1e-4);
    limiter.update(world);
  }
  EXPECT_GT(limiter.engagements(), 0);
  EXPECT_NEAR(jointValue(world.model(), world.state(), *elbow), 2.8, 0.03);
  ASSERT_TRUE(robotics::switchOffJoint(world, *elbow, 0.01));
  EXPECT_EQ(jointServo(world.model(), *elbow).stiffness, 0.0);
}

// Every step, a joint's value and rate are readable: the rate is the time
// derivative of the value (central difference over two steps), for a revolute
// joint driven by its servo and for the passive prismatic slider.
TEST(JointControl, RateIsTheDerivativeOfTheValue) {
  for (const char* name : {"revolute_arm.json", "prismatic_slider.json"}) {
    Scene scene = testing::loadSceneFromScenes(name);
    ASSERT_FALSE(scene.model.joints.empty()) << name;
    World world(scene.model, scene.initial, Integrator::kVelocityVerlet);
    const double dt = 1e-5;
    double largestRate = 0.0, largestError = 0.0;
    for (int i = 0; i < 2000; ++i) {
      const double before = jointValue(world.model(), world.state(), 0);
      world.step(dt);
      const double rate = jointRate(world.model(), world.state(), 0);
      world.step(dt);
      const double after = jointValue(world.model(), world.state(), 0);
      largestRate = std::max(largestRate, std::abs(rate));
      largestError = std::max(largestError, std::abs((after - before) / (2.0 * dt) - rate));
    }
    EXPECT_GT(largestRate, 1e-3) << name << ": the joint should move";
    EXPECT_LT(largestError, 1e-3 * largestRate + 1e-9) << name;
  }
}

}  // namespace
}  // namespace robophi
