// The built-in hand as rigid bodies ("rigid": true; docs/robotics.md "The hand as
// rigid bodies", issue 35): the particle hand's geometry and joints, each link one
// rigid body of a tree, built by the URDF's road (build::makeRigidHand →
// makeUrdfMultibody → placeUrdfMultibody). Closed on a free ball by joint effort
// with a velocity limit, it holds the ball against 1 g in each of six directions.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "robophi/build/model_builder.h"
#include "robophi/build/rigid_robots.h"
#include "robophi/build/robots.h"
#include "robophi/joints.h"
#include "robophi/scene/scene.h"
#include "robotics/tasks.h"
#include "run/runner.h"

namespace robophi {
namespace {

std::int32_t handObjectNamed(const Model& model, const std::string& name) {
  for (std::size_t o = 0; o < model.objects.size(); ++o)
    if (model.objects[o].name == name) return static_cast<std::int32_t>(o);
  return -1;
}

Vec3 handCenterOf(const Model& model, const State& state, std::int32_t object) {
  const ObjectInfo& o = model.objects[static_cast<std::size_t>(object)];
  Vec3 sum{};
  double mass = 0.0;
  for (ParticleIndex i = o.firstParticle; i < o.firstParticle + o.particleCount; ++i) {
    sum += state.position[static_cast<std::size_t>(i)] * model.mass[i];
    mass += model.mass[i];
  }
  return sum / mass;
}

// The rigid hand is the particle hand's: the same joints, names and masses, its
// finger tips where the particle hand's are (q = 0 is the straight finger).
TEST(HandRigid, HasTheParticleHandsJointsMassAndTips) {
  build::HandSpec spec;
  spec.spread = 0.2;
  const build::GeneratedObject particles = build::makeHand(spec);
  const build::UrdfMultibody rigid = build::makeRigidHand(spec, "hand");
  ASSERT_EQ(rigid.joints.size(), 9u);
  ASSERT_EQ(particles.joints.size(), 9u);
  for (std::size_t k = 0; k < 9; ++k)
    EXPECT_EQ(rigid.joints[k].name, "hand." + particles.joints[k].name);
  double mass = 0.0;
  for (const MultibodyBody& body : rigid.multibody.bodies) mass += body.mass.mass;
  EXPECT_NEAR(mass, spec.mass, 1e-12);
  EXPECT_TRUE(rigid.adjustments.empty());
  MultibodyKinematics kin;
  const std::vector<double> q = neutralConfiguration(rigid.multibody);
  updateKinematics(rigid.multibody, q.data(), kin);
  for (int f = 0; f < 3; ++f) {
    const std::string link = "hand.f" + std::to_string(f + 1) + ".l3";
    const auto it = std::find_if(rigid.multibody.bodies.begin(), rigid.multibody.bodies.end(),
                                 [&](const MultibodyBody& b) { return b.name == link; });
    ASSERT_NE(it, rigid.multibody.bodies.end()) << link;
    const auto b = static_cast<std::size_t>(it - rigid.multibody.bodies.begin());
    const Vec3 tip = kin.X_WB[b] * Vec3{0.0, 0.0, spec.links[2]};
    const Vec3 expected = particles.position[particles.size() - 3 + static_cast<std::size_t>(f)];
    EXPECT_LT(norm(tip - expected), 1e-12) << link;
  }
}

// One run: the ball's largest displacement relative to the palm (m) from the
// moment gravity comes on to the end, and the sum of the hand's normal contact
// forces on the ball (N) when the fingers have closed and at the end.
// The arm as rigid bodies: the particle arm's joints, its tool where the particle
// arm's is, and a scene entry with "rigid": true places it as a rigid tree.
TEST(ArmRigid, HasTheParticleArmsJointsAndToolAndLoadsInAScene) {
  build::ArmSpec spec;
  spec.links = {0.5, 0.4, 0.3};
  spec.axes = {{0, 0, 1}, {0, 1, 0}, {0, 1, 0}};
  spec.direction = {1, 0, 0.2};
  const build::GeneratedObject particles = build::makeArm(spec);
  const build::UrdfMultibody rigid = build::makeRigidArm(spec, "arm");
  ASSERT_EQ(rigid.joints.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k)
    EXPECT_EQ(rigid.joints[k].name, "arm." + particles.joints[k].name);
  MultibodyKinematics kin;
  const std::vector<double> q = neutralConfiguration(rigid.multibody);
  updateKinematics(rigid.multibody, q.data(), kin);
  const Vec3 tool = kin.X_WB.back() * Vec3{0.0, 0.0, 0.3};
  EXPECT_LT(norm(tool - particles.position.back()), 1e-12);
  SceneLoadResult loaded = loadSceneText(R"({"robophi": 1, "run": {"duration": 0.1},
    "objects": [{"name": "arm", "type": "arm", "rigid": true, "base": [0, 0, 1],
                 "links": [0.5, 0.4], "mass": 2, "jointStiffness": 50}]})",
                                         "rigid_arm.json");
  for (const auto& e : loaded.errors) ADD_FAILURE() << e.format();
  ASSERT_TRUE(loaded.ok());
  ASSERT_EQ(loaded.scene->model.rigidTrees.size(), 1u);
  const auto j2 = findJoint(loaded.scene->model, "arm.j2");
  ASSERT_TRUE(j2.has_value());
  EXPECT_EQ(loaded.scene->model.joints[*j2].servoStiffness, 50.0);
}

struct GripRun {
  double drift = 0.0, closedGrip = 0.0, grip = 0.0, wall = 0.0;
};

// The hand (defaults: palm radius 6 cm, links 5, 4, 3 cm, 0.3 kg), its flexion
// joints (j2, j3) closed by `effort` (N·m) at most 2 rad/s, the sideways joints (j1)
// held at 0 by position servos; a free rigid ball of `radius`, `mass` on it, 5 mm
// above the palm. No gravity for the first second (the fingers close), then 1 g
// along `down` for 2.5 s.
GripRun runGrip(double radius, double mass, double effort, const Vec3& down) {
  const double hold = 2.5, closing = 1.0;
  std::string joints;
  for (int f = 1; f <= 3; ++f) {
    const std::string h = "\"hand.f" + std::to_string(f);
    joints += h + ".j1\": {\"mode\": \"position\", \"kp\": 2, \"kd\": 0.02, \"target\": 0},";
    for (int j = 2; j <= 3; ++j)
      joints += h + ".j" + std::to_string(j) +
                "\": {\"mode\": \"effort\", \"target\": " + std::to_string(effort) +
                ", \"velocityLimit\": 2},";
  }
  joints.pop_back();
  const std::string text = R"({
    "robophi": 1, "name": "rigid hand grip",
    "run": {"duration": )" +
                           std::to_string(closing + hold) + R"(, "dt": 2e-3,
            "integrator": "symplectic", "adaptive": {"maxStep": 2e-3}},
    "gravity": [0, 0, 0],
    "materials": [{"name": "pad", "contactStiffness": 2e4, "contactDamping": 20,
                   "staticFriction": 1.0, "kineticFriction": 0.8}],
    "objects": [
      {"name": "hand", "type": "hand", "rigid": true, "center": [0, 0, 0], "palmRadius": 0.06,
       "links": [0.05, 0.04, 0.03], "mass": 0.3, "material": "pad"},
      {"name": "ball", "type": "ball", "center": [0, 0, )" +
                           std::to_string(0.015 + radius + 0.005) + R"(], "radius": )" +
                           std::to_string(radius) + R"(, "mass": )" + std::to_string(mass) + R"(,
       "cells": 3, "material": "pad", "rigid": true}],
    "control": {"joints": {)" +
                           joints + R"(}}
  })";
  GripRun out;
  SceneLoadResult loaded = loadSceneText(text, "rigid_hand_grip.json");
  for (const auto& e : loaded.errors) ADD_FAILURE() << e.format();
  if (!loaded.ok()) return out;
  const Scene& scene = *loaded.scene;
  const Model& model = scene.model;
  const std::int32_t ball = handObjectNamed(model, "ball");
  const std::int32_t palm = handObjectNamed(model, "hand.palm");
  EXPECT_TRUE(ball >= 0 && palm >= 0);
  if (ball < 0 || palm < 0) return out;
  const auto objectOf = [&](std::int32_t particle) {
    return particle < 0 ? -1 : model.objectOf[static_cast<std::size_t>(particle)];
  };
  const auto isLink = [&](std::int32_t object) {
    return object >= 0 && model.objects[static_cast<std::size_t>(object)].kind == "link";
  };
  const auto gripForce = [&](World& world) {
    double sum = 0.0;
    for (const Contact& c : world.contacts()) {
      const std::int32_t a = objectOf(c.a), b = objectOf(c.other);
      if ((a == ball && isLink(b)) || (b == ball && isLink(a))) sum += c.normalForce;
    }
    return sum;
  };
  bool gravityOn = false;
  Vec3 start{};
  RunOptions options;
  options.settings = scene.run;
  options.writeReplay = false;
  options.threads = 1;
  // The energy account is not what this test checks. While the fingers close
  // (0.3-0.7 s) their contacts with the explicit rigid ball lose energy at first
  // order in the step (the 4 cm ball at constant steps of 20, 10, 5, 2.5 µs:
  // -2.3e-4, -8.9e-5, -4.7e-5, -2.7e-5 J of a 2 mJ scale), and at the default
  // tolerance the run ends 5-6 % of that scale short, past the default 5 % bound.
  // (The step no longer collapses: the flexion joints' bounded servos are solved
  // at v+ - docs/model.md §7 - 26 286 steps for 3.5 s where 53 697 were, 1 445
  // rejected where 28 883 were.)
  options.energyAccountBound = 0.1;
  const robotics::SceneTaskHook hook = robotics::makeSceneTaskHook(scene);
  options.tasks = {hook.task, [&](World& world, std::vector<std::string>&) {
                     const State& s = world.state();
                     if (s.time < closing) return true;
                     const Vec3 relative =
                         handCenterOf(model, s, ball) - handCenterOf(model, s, palm);
                     if (!gravityOn) {
                       out.closedGrip = gripForce(world);
                       world.setGravity(down * 9.81);
                       start = relative;
                       gravityOn = true;
                     }
                     out.drift = std::max(out.drift, norm(relative - start));
                     if (s.time > closing + hold - 0.01) out.grip = gripForce(world);
                     return true;
                   }};
  const auto began = std::chrono::steady_clock::now();
  const RunReport report = runScene(scene, options);
  out.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
  EXPECT_EQ(report.status, "ok") << report.failure;
  return out;
}

// The flexion joints' effort (N·m).
constexpr double kEffort = 0.05;

// One run a direction of gravity and a ball: (ball radius, m; mass, kg; direction).
struct GripCase {
  double radius, mass;
  Vec3 down;
  const char* name;
};

class HandRigidGrip : public ::testing::TestWithParam<GripCase> {};

// The must-show (issue 35): the 4 cm, 100 g ball (μ 1) held against 1 g in each of
// six directions, drifting less than 5 mm relative to the palm in each; and a ball
// it was not tuned to, 3 cm and 200 g.
TEST_P(HandRigidGrip, HoldsItsBallAgainstOneG) {
  const GripCase c = GetParam();
  const GripRun run = runGrip(c.radius, c.mass, kEffort, c.down);
  std::printf(
      "rigid hand, %.0f cm %.0f g ball, gravity %s: grip %.3f N after closing, %.3f N at "
      "the end; drift %.3f mm; %.1f s wall\n",
      100 * c.radius, 1000 * c.mass, c.name, run.closedGrip, run.grip, 1e3 * run.drift, run.wall);
  EXPECT_GT(run.closedGrip, 0.5);
  EXPECT_GT(run.grip, 0.5);
  EXPECT_LT(run.drift, 5e-3);
}

INSTANTIATE_TEST_SUITE_P(
    Ball4cm100g, HandRigidGrip,
    ::testing::Values(GripCase{0.04, 0.1, {1, 0, 0}, "+x"}, GripCase{0.04, 0.1, {-1, 0, 0}, "-x"},
                      GripCase{0.04, 0.1, {0, 1, 0}, "+y"}, GripCase{0.04, 0.1, {0, -1, 0}, "-y"},
                      GripCase{0.04, 0.1, {0, 0, 1}, "+z"}, GripCase{0.04, 0.1, {0, 0, -1}, "-z"}));
INSTANTIATE_TEST_SUITE_P(
    Ball3cm200g, HandRigidGrip,
    ::testing::Values(GripCase{0.03, 0.2, {1, 0, 0}, "+x"}, GripCase{0.03, 0.2, {-1, 0, 0}, "-x"},
                      GripCase{0.03, 0.2, {0, 1, 0}, "+y"}, GripCase{0.03, 0.2, {0, -1, 0}, "-y"},
                      GripCase{0.03, 0.2, {0, 0, 1}, "+z"}, GripCase{0.03, 0.2, {0, 0, -1}, "-z"}));

}  // namespace
}  // namespace robophi

namespace robophi {
namespace {

// Fingers pressing at their bound (docs/model.md §7 "Joints and their inputs"): the
// rigid hand's flexion joints, each a velocity-limited effort (a rate servo bounded
// by its 0.05 N·m), close on a fixed sphere of the environment and press on it for
// 3 s. A bounded servo is solved at v+: while a finger presses, its joint neither
// flips between saturated and held at every step (which set steps of a few µs, two
// in three rejected: 363 501 steps for this run, 239 596 rejected) nor breaks the
// energy account.
TEST(HandRigid, FingersPressingAFixedSphereKeepTheirStepAndTheAccount) {
  std::string joints;
  for (int f = 1; f <= 3; ++f) {
    const std::string h = "\"hand.f" + std::to_string(f);
    joints += h + ".j1\": {\"mode\": \"position\", \"kp\": 2, \"kd\": 0.02, \"target\": 0},";
    for (int j = 2; j <= 3; ++j)
      joints += h + ".j" + std::to_string(j) + "\": {\"mode\": \"effort\", \"target\": 0.05, \"velocityLimit\": 2},";
  }
  joints.pop_back();
  SceneLoadResult loaded = loadSceneText(R"({"robophi": 1, "name": "hand on a sphere",
    "run": {"duration": 3.5, "dt": 2e-3, "integrator": "symplectic", "adaptive": {"maxStep": 2e-3}},
    "gravity": [0, 0, 0],
    "materials": [{"name": "pad", "contactStiffness": 2e4, "contactDamping": 20,
                   "staticFriction": 1.0, "kineticFriction": 0.8}],
    "objects": [{"name": "hand", "type": "hand", "rigid": true, "center": [0, 0, 0],
                 "palmRadius": 0.06, "links": [0.05, 0.04, 0.03], "mass": 0.3, "material": "pad"}],
    "environment": {"spheres": [{"center": [0, 0, 0.06], "radius": 0.04, "material": "pad"}]},
    "control": {"joints": {)" + joints + R"(}}})",
                                         "hand_on_sphere.json");
  for (const auto& e : loaded.errors) ADD_FAILURE() << e.format();
  ASSERT_TRUE(loaded.ok());
  const Scene& scene = *loaded.scene;
  RunOptions options;
  options.settings = scene.run;
  options.writeReplay = false;
  options.threads = 1;
  const robotics::SceneTaskHook hook = robotics::makeSceneTaskHook(scene);
  double pressing = 1e300;  // the least sum of the normal forces over the last second (N)
  options.tasks = {hook.task, [&](World& world, std::vector<std::string>&) {
                     if (world.state().time < 2.5) return true;
                     double sum = 0.0;
                     for (const Contact& c : world.contacts()) sum += c.normalForce;
                     pressing = std::min(pressing, sum);
                     return true;
                   }};
  const RunReport report = runScene(scene, options);
  std::printf("hand on a sphere: %lld steps (%lld rejected, smallest %.3g s), account error %.4f, "
              "normal forces on it over the last second at least %.3f N\n",
              static_cast<long long>(report.adaptive.accepted),
              static_cast<long long>(report.adaptive.rejected), report.adaptive.smallestStep,
              report.largestAccountError, pressing);
  EXPECT_EQ(report.status, "ok") << report.failure;
  EXPECT_GT(pressing, 1.0);
  EXPECT_LT(report.adaptive.accepted, 60000);
  EXPECT_LT(report.adaptive.rejected, report.adaptive.accepted / 20);
  EXPECT_LT(report.largestAccountError, 0.05);
}

}  // namespace
}  // namespace robophi
