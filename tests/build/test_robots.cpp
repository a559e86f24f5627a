// Robots and a calibrated bar built from plain C++ specs (no JSON), placed by
// ModelBuilder: their particles, joints and fixed bases, and the same spec
// through a scene file gives the identical model.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "build/model_compare.h"
#include "robophi/build/calibration.h"
#include "robophi/build/model_builder.h"
#include "robophi/build/robots.h"
#include "robophi/joints.h"
#include "robophi/scene/scene.h"

namespace robophi::build {
namespace {

// One object built from its spec and placed alone.
BuiltModel placeAlone(const std::string& name, const std::string& kind, GeneratedObject object) {
  ModelBuilder builder;
  builder.addObject({.name = name, .kind = kind, .geometry = std::move(object)});
  return std::move(builder).build();
}

// A scene holding the one object entry `entry`.
Scene loadOne(const std::string& entry) {
  SceneLoadResult result = loadSceneText("{\"objects\": [" + entry + "]}", "one.json");
  for (const auto& e : result.errors) ADD_FAILURE() << e.format();
  if (!result.ok()) return Scene{};
  return std::move(*result.scene);
}

std::size_t fixedCount(const Model& model) {
  return static_cast<std::size_t>(
      std::count(model.inverseMass.begin(), model.inverseMass.end(), 0.0));
}

// The arm of scenes/arm_reach.json, from C++.
ArmSpec reachArm() {
  ArmSpec spec;
  spec.links = {0.5, 0.4};
  spec.axes = {{0, 0, 1}};
  spec.mass = 2.0;
  spec.width = 0.08;
  spec.structure.naturalFrequency = 1250.0;
  return spec;
}

TEST(BuildArm, ParticlesJointsAndFixedBase) {
  const GeneratedObject arm = makeArm(reachArm());
  // Base (centre, axis, reference) and per link: 2 on the line, 2 braces, the
  // next centre and its axis (or the tool's third brace).
  ASSERT_EQ(arm.size(), 3u + 2u * 6u);
  ASSERT_EQ(arm.joints.size(), 2u);
  EXPECT_EQ(arm.joints[0].name, "j1");
  EXPECT_EQ(arm.joints[1].name, "j2");
  ASSERT_EQ(arm.fixed.size(), arm.size());
  EXPECT_EQ(std::count(arm.fixed.begin(), arm.fixed.end(), true), 3);
  // The tool is last, at the end of the straight arm.
  const Vec3 tool = arm.position.back();
  EXPECT_NEAR(tool.x, 0.9, 1e-12);
  EXPECT_NEAR(std::hypot(tool.y, tool.z), 0.0, 1e-12);
  EXPECT_FALSE(arm.fixed.back());
  // The structural stiffness gives the arm's fastest mode 1250 rad/s.
  EXPECT_DOUBLE_EQ(arm.linearSprings[0].stiffness, defaultStiffness(arm, 1250.0));
  EXPECT_GT(arm.jointSprings[0].damping, 0.0);

  const BuiltModel built = placeAlone("arm", "arm", arm);
  ASSERT_EQ(built.model.joints.size(), 2u);
  EXPECT_EQ(built.model.joints[0].name, "arm.j1");
  EXPECT_NEAR(jointValue(built.model, built.initial, 0), std::numbers::pi, 1e-12);  // straight
  EXPECT_EQ(fixedCount(built.model), 3u);
  // Positions count from the pose as built: the straight arm is q = 0, and a
  // quarter turn either way reads ±π/2 (wrapped into (-π, π]).
  for (std::size_t j = 0; j < 2; ++j) {
    EXPECT_NEAR(built.model.joints[j].zero, std::numbers::pi, 1e-12);
    EXPECT_NEAR(jointPosition(built.model, built.initial, j), 0.0, 1e-12);
  }
  const Joint& j1 = built.model.joints[0];
  EXPECT_NEAR(jointRawValue(j1, 0.5 * std::numbers::pi), 1.5 * std::numbers::pi, 1e-12);
  EXPECT_NEAR(jointRawValue(j1, -0.5 * std::numbers::pi), 0.5 * std::numbers::pi, 1e-12);
  EXPECT_NEAR(wrapSigned(1.5 * std::numbers::pi), -0.5 * std::numbers::pi, 1e-12);
  EXPECT_NEAR(wrapSigned(std::numbers::pi), std::numbers::pi, 1e-12);
}

TEST(BuildArm, SameSpecThroughASceneFileGivesTheIdenticalModel) {
  const BuiltModel built = placeAlone("arm", "arm", makeArm(reachArm()));
  const Scene scene = loadOne(
      R"({"name": "arm", "type": "arm", "base": [0, 0, 0], "links": [0.5, 0.4],
          "axes": [0, 0, 1], "mass": 2.0, "width": 0.08, "naturalFrequency": 1250})");
  testing::expectSameStart(built.model, built.initial, scene.model, scene.initial);
}

// The vehicle of scenes/vehicle_hills.json, from C++.
VehicleSpec hillsVehicle() {
  VehicleSpec spec;
  spec.center = {-1, 0, 0.12};
  spec.size = {0.6, 0.3, 0.1};
  spec.mass = 8.0;
  spec.wheelRadius = 0.12;
  spec.wheelWidth = 0.06;
  spec.wheelMass = 0.5;
  spec.rimParticles = 12;
  spec.suspensionStiffness = 3000.0;
  spec.axleDamping = 0.001;
  spec.structure.stiffness = 20000.0;
  return spec;
}

TEST(BuildVehicle, ParticlesAxlesAndSuspension) {
  const GeneratedObject vehicle = makeVehicle(hillsVehicle());
  // Chassis 3×2×2, four wheels of 2·12 rim and 2 hub particles, five mounts each,
  // then each wheel's knuckle and its two upper mounts.
  ASSERT_EQ(vehicle.size(), 12u + 4u * 26u + 4u * 5u + 4u * 3u);
  ASSERT_EQ(vehicle.joints.size(), 4u);
  for (std::size_t w = 0; w < 4; ++w) {
    EXPECT_EQ(vehicle.joints[w].name, "axle" + std::to_string(w + 1));
    EXPECT_EQ(vehicle.jointSprings[w].stiffness, 0.0);  // passive
    EXPECT_EQ(vehicle.jointSprings[w].damping, 0.001);
  }
  EXPECT_EQ(std::count(vehicle.fixed.begin(), vehicle.fixed.end(), true), 0);
  // Two suspension springs per wheel, the rest structural.
  const auto suspension =
      std::count_if(vehicle.linearSprings.begin(), vehicle.linearSprings.end(),
                    [](const LinearSpring& s) { return s.stiffness == 3000.0; });
  EXPECT_EQ(suspension, 8);
  EXPECT_EQ(vehicle.linearSprings[0].stiffness, 20000.0);
}

TEST(BuildVehicle, SameSpecThroughASceneFileGivesTheIdenticalModel) {
  const BuiltModel built = placeAlone("vehicle", "vehicle", makeVehicle(hillsVehicle()));
  const Scene scene = loadOne(
      R"({"name": "vehicle", "type": "vehicle", "center": [-1, 0, 0.12], "size": [0.6, 0.3, 0.1],
          "mass": 8, "wheelRadius": 0.12, "wheelWidth": 0.06, "wheelMass": 0.5,
          "rimParticles": 12, "suspensionStiffness": 3000, "axleDamping": 0.001,
          "stiffness": 20000})");
  testing::expectSameStart(built.model, built.initial, scene.model, scene.initial);
}

// The hand of scenes/hand_grasp.json, from C++.
HandSpec graspHand() {
  HandSpec spec;
  spec.palmRadius = 0.06;
  spec.links = {0.05, 0.04, 0.03};
  spec.mass = 0.3;
  spec.spread = 0.1;
  spec.structure.naturalFrequency = 1250.0;
  return spec;
}

TEST(BuildHand, PalmFingersJointsAndTips) {
  const GeneratedObject hand = makeHand(graspHand());
  // Palm: the 13 points of a 5×5 grid (pitch ρ/2) within ρ; each finger: a base
  // of 3 and 3 links of 5 particles.
  ASSERT_EQ(hand.size(), 13u + 3u * 18u);
  ASSERT_EQ(hand.joints.size(), 9u);
  EXPECT_EQ(hand.joints[0].name, "f1.j1");
  EXPECT_EQ(hand.joints[8].name, "f3.j3");
  EXPECT_EQ(std::count(hand.fixed.begin(), hand.fixed.end(), true), 13 + 3 * 3);
  // The three tips are the last particles, free, at the fingers' ends above the palm.
  for (std::size_t k = hand.size() - 3; k < hand.size(); ++k) {
    EXPECT_FALSE(hand.fixed[k]);
    EXPECT_GT(hand.position[k].z, 0.1);
  }
}

TEST(BuildHand, SameSpecThroughASceneFileGivesTheIdenticalModel) {
  const BuiltModel built = placeAlone("hand", "hand", makeHand(graspHand()));
  const Scene scene = loadOne(
      R"({"name": "hand", "type": "hand", "center": [0, 0, 0], "palmRadius": 0.06,
          "links": [0.05, 0.04, 0.03], "mass": 0.3, "spread": 0.1, "naturalFrequency": 1250})");
  testing::expectSameStart(built.model, built.initial, scene.model, scene.initial);
}

// The bar of scenes/bar_flexion.json (16×3×3 cubic cells of 1 cm, E = 2 MPa).
BoxSpec flexionBar() { return BoxSpec{{0.08, 0, 0}, {0.16, 0.03, 0.03}, {16, 3, 3}, 0.2, 0.0}; }

TEST(BuildCalibratedBar, FibreTorsionSpringsAndPositiveLinks) {
  const BoxSpec spec = flexionBar();
  GeneratedObject bar = makeBox(spec);
  resolveSprings(bar, {});
  calibrateLattice(bar, spec, 2e6);
  ASSERT_EQ(bar.size(), 16u * 9u);
  // One TS per interior particle of each of the 9 fibres, all along x.
  ASSERT_EQ(bar.torsionSprings.size(), 9u * 14u);
  for (const TorsionSpring& s : bar.torsionSprings) {
    EXPECT_GT(s.stiffness, 0.0);
    EXPECT_NEAR(std::abs(bar.position[s.b].x - bar.position[s.a].x), 0.02, 1e-12);
  }
  for (const LinearSpring& s : bar.linearSprings) EXPECT_GE(s.stiffness, 0.0);
}

TEST(BuildCalibratedBar, SameSpecThroughASceneFileGivesTheIdenticalModel) {
  const BoxSpec spec = flexionBar();
  GeneratedObject bar = makeBox(spec);
  resolveSprings(bar, {});
  calibrateLattice(bar, spec, 2e6);
  const BuiltModel built = placeAlone("bar", "bar", bar);
  const Scene scene = loadOne(
      R"({"name": "bar", "type": "bar", "center": [0.08, 0, 0], "size": [0.16, 0.03, 0.03],
          "cells": [16, 3, 3], "mass": 0.2, "youngModulus": 2e6})");
  testing::expectSameStart(built.model, built.initial, scene.model, scene.initial);
}

// A scene's materials, environment, velocities and connectors from C++: the
// placed particles start where and as fast as asked, fixed ones at rest.
TEST(ModelBuilder, PlacesObjectsMaterialsEnvironmentAndConnectors) {
  ModelBuilder builder;
  builder.setGravity({0, 0, -1});
  const std::int32_t rubber = builder.addMaterial({"rubber", 1e5, 30.0, 0.8, 0.6});
  EXPECT_EQ(rubber, 1);
  EXPECT_EQ(builder.findMaterial("rubber"), 1);
  builder.addPlane({{0, 0, 0}, {0, 0, 2}, rubber});
  builder.addSphere({{1, 0, 0}, 0.2, 0});
  builder.setViscosity(0.5);

  GeneratedObject rope = makeRope({{0, 0, 1}, {1, 0, 1}, 5, 0.5, 0.0});
  resolveSprings(rope, {});
  rope.fixed.assign(rope.size(), false);
  rope.fixed[0] = true;
  ObjectPlacement placement{.name = "rope", .kind = "rope", .geometry = rope};
  placement.velocity = rigidVelocity(rope, {0, 1, 0}, {0, 0, 0});
  placement.linearDamping = 0.1;
  placement.material = rubber;
  const PlacedObject placedRope = builder.addObject(placement);
  const PlacedObject placedBall = builder.addObject(
      {.name = "ball", .kind = "ball", .geometry = makeBall({.center = {0, 0, 2}})});
  EXPECT_EQ(placedBall.firstParticle, 5);
  EXPECT_EQ(placedRope.particle(-1), 4);
  const Vec3 end = builder.positions()[static_cast<std::size_t>(placedRope.particle(-1))];
  const double rest = norm(end - builder.positions()[5]);
  builder.addConnector(LinearSpring{placedRope.particle(-1), placedBall.particle(0), rest, 100.0});

  const auto [model, initial] = std::move(builder).build();
  EXPECT_EQ(model.particleCount(), 6);
  EXPECT_EQ(model.linearSprings.size(), 4u + 1u);
  EXPECT_EQ(model.objects[0].material, rubber);
  EXPECT_EQ(model.environment.planes[0].normal.z, 1.0);  // normalised
  EXPECT_EQ(model.environment.viscosity, 0.5);
  EXPECT_EQ(model.gravity.z, -1.0);
  EXPECT_EQ(model.linearDamping[1], 0.1);
  EXPECT_TRUE(model.isFixed(0));
  EXPECT_EQ(initial.velocity[0].y, 0.0);  // fixed: at rest
  EXPECT_EQ(initial.velocity[1].y, 1.0);
  EXPECT_EQ(initial.position[5].z, 2.0);
  EXPECT_EQ(initial.velocity.size(), 6u);
  EXPECT_TRUE(checkModel(model).empty()) << checkModel(model);
}

}  // namespace
}  // namespace robophi::build
