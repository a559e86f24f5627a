// A rigid tree's joints are the model's joints (Joint::inTree, docs/model.md §7):
// read, driven and controlled by name as any other — servos, drives, gravity
// compensation, the energy account of their work — and generated objects can be
// declared rigid (build::placeRigidObject).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "robophi/adaptive_step.h"
#include "robophi/build/model_builder.h"
#include "robophi/build/objects.h"
#include "robophi/build/rigid_object.h"
#include "robophi/joints.h"
#include "robophi/multibody.h"
#include "robophi/scene/scene.h"
#include "robophi/world.h"
#include "test_files.h"

namespace robophi {
namespace {

using testing::kRobots;  // ROBOPHI_ROBOTS_DIR (test_files.h)
bool robotsPresent() { return std::filesystem::exists(kRobots + "/kuka_iiwa/model.urdf"); }

// A two-link planar arm (revolute about y, 0.5 m links of 1 kg) on a fixed base,
// and a prismatic slider of 0.2 kg along x at its tip; no contact particles.
build::BuiltModel armAndSlider(const Vec3& gravity) {
  build::ModelBuilder builder;
  builder.setGravity(gravity);
  RigidTree tree;
  Multibody& mb = tree.multibody;
  mb.name = "arm";
  const auto link = [](double mass, double length) {
    BodyMassProperties p;
    p.mass = mass;
    p.centerOfMass = {length / 2, 0, 0};
    const double i = mass * length * length / 12;
    p.inertia = Mat3::diagonal({i / 2, i, i});
    return p;
  };
  MultibodyBody a;
  a.name = "arm.l1";
  a.joint = BodyJointKind::kRevolute;
  a.jointName = "arm.j1";
  a.axis = {0, 1, 0};
  a.mass = link(1.0, 0.5);
  MultibodyBody b = a;
  b.name = "arm.l2";
  b.jointName = "arm.j2";
  b.parent = 0;
  b.X_PJ.translation = {0.5, 0, 0};
  MultibodyBody c;
  c.name = "arm.slider";
  c.joint = BodyJointKind::kPrismatic;
  c.jointName = "arm.slide";
  c.axis = {1, 0, 0};
  c.parent = 1;
  c.X_PJ.translation = {0.5, 0, 0};
  c.mass = link(0.2, 0.05);
  c.lower = -0.1;
  c.upper = 0.1;
  mb.bodies = {a, b, c};
  builder.addRigidTree(std::move(tree));
  return std::move(builder).build();
}

TEST(RigidTreeJoints, EachRevoluteAndPrismaticJointIsAModelJoint) {
  build::BuiltModel built = armAndSlider({0, 0, -9.81});
  const Model& m = built.model;
  ASSERT_EQ(m.joints.size(), 3u);
  EXPECT_EQ(m.joints[0].name, "arm.j1");
  EXPECT_EQ(m.joints[2].name, "arm.slide");
  EXPECT_EQ(m.joints[2].kind, JointKind::kPrismatic);
  EXPECT_EQ(m.rigidTrees[0].jointOfRate, (std::vector<std::int32_t>{0, 1, 2}));
  World world(std::move(built.model), std::move(built.initial), Integrator::kSymplecticEuler);
  // The coordinate itself, not wrapped: −4 rad stays −4 rad.
  State s = world.state();
  s.treePositions[0] = {-4.0, 0.3, 0.05};
  s.treeVelocities[0] = {0.5, -0.25, 0.01};
  EXPECT_DOUBLE_EQ(jointPosition(world.model(), s, 0), -4.0);
  EXPECT_DOUBLE_EQ(jointValue(world.model(), s, 0), -4.0);
  EXPECT_DOUBLE_EQ(jointPosition(world.model(), s, 2), 0.05);
  EXPECT_DOUBLE_EQ(jointRate(world.model(), s, 1), -0.25);
  EXPECT_DOUBLE_EQ(jointRawValue(world.model().joints[0], -4.0), -4.0);
}

// Joint servos set through the World reach their targets under gravity with
// gravity compensation, and the energy account (E + dissipated − external) holds.
TEST(RigidTreeJoints, ServosReachTheirTargetsAndTheAccountHolds) {
  build::BuiltModel built = armAndSlider({0, 0, -9.81});
  World world(std::move(built.model), std::move(built.initial), Integrator::kSymplecticEuler);
  const double targets[3] = {0.7, -1.2, 0.08};
  for (std::size_t j = 0; j < 3; ++j) {
    world.setJointServo(j, 300.0, 20.0);
    world.setJointTarget(j, targets[j]);
    world.setGravityCompensation(j, true);
  }
  world.refresh();
  const auto account = [&] {
    return world.energy().total();  // E + dissipated − external
  };
  const double a0 = account();
  double scale = 0.0;
  for (int k = 0; k < 3000; ++k) {  // 6 s at 2 ms
    ASSERT_EQ(world.step(2e-3), StepStatus::kOk);
    scale = std::max(scale, std::abs(world.energy().total()));
  }
  for (std::size_t j = 0; j < 3; ++j)
    EXPECT_NEAR(jointPosition(world.model(), world.state(), j), targets[j], 1e-6) << "joint " << j;
  // The servos' dampers' losses and the springs' implicit step are booked.
  EXPECT_LT(std::abs(account() - a0), 1e-3 * scale) << "account moved " << account() - a0 << " of " << scale;
}

// A velocity-limited effort (a gripper finger closing): moves at the limit while
// free, presses with the effort when stopped — at a hard stop here.
TEST(RigidTreeJoints, AVelocityLimitedEffortMovesAtItsLimitAndPressesWithItsEffort) {
  build::BuiltModel built = armAndSlider({0, 0, 0});
  World world(std::move(built.model), std::move(built.initial), Integrator::kSymplecticEuler);
  JointDrive drive;
  drive.effort = 10.0;
  drive.velocityLimit = 0.05;
  world.setJointDrive(2, drive);
  for (std::size_t j = 0; j < 2; ++j) world.setJointServo(j, 1e3, 50.0);  // the arm held
  for (int k = 0; k < 500; ++k) ASSERT_EQ(world.step(2e-3), StepStatus::kOk);  // 1 s
  EXPECT_NEAR(jointRate(world.model(), world.state(), 2), 0.05, 1e-3);
  for (int k = 0; k < 2000; ++k) ASSERT_EQ(world.step(2e-3), StepStatus::kOk);  // at the stop
  EXPECT_NEAR(jointPosition(world.model(), world.state(), 2), 0.1, 1e-3);
  EXPECT_NEAR(jointServoEffort(world.model(), world.state(), 2), 10.0, 1e-9);
}

// A generated box declared rigid: one free body with its particles' mass
// properties, that lands flat and rests at its half height.
TEST(RigidTreeJoints, ARigidBoxIsOneBodyOfItsParticles) {
  build::ModelBuilder builder;
  builder.addPlane({{0, 0, 0}, {0, 0, 1}, 0});
  build::BoxSpec spec;
  spec.center = {0, 0, 0.1};
  spec.size = {0.1, 0.06, 0.04};
  spec.cells = {4, 3, 2};
  spec.mass = 0.5;
  build::ObjectPlacement object;
  object.name = "box";
  object.kind = "box";
  object.geometry = build::makeBox(spec);
  const double m = 0.5;
  const build::PlacedRigidObject placed = build::placeRigidObject(builder, object);
  build::BuiltModel built = std::move(builder).build();
  const Multibody& mb = built.model.rigidTrees[static_cast<std::size_t>(placed.tree)].multibody;
  EXPECT_NEAR(mb.bodies[0].mass.mass, m, 1e-12);
  EXPECT_TRUE(built.model.joints.empty());  // a free body has no named joint
  for (std::size_t i = 0; i < object.geometry.size(); ++i)
    EXPECT_TRUE(built.model.isCarried(placed.object.firstParticle + static_cast<ParticleIndex>(i)));
  World world(std::move(built.model), std::move(built.initial), Integrator::kSymplecticEuler);
  AdaptiveStepper stepper(world.model(), {});
  while (world.state().time < 1.5) ASSERT_TRUE(stepper.advance(world, 1.5 - world.state().time).ok);
  const std::vector<double>& q = world.state().treePositions[0];
  EXPECT_NEAR(q[2], 0.02, 2e-3);               // on its 4 cm side
  EXPECT_NEAR(std::abs(q[3]), 1.0, 1e-6);      // level
}

// In a scene: {"type": "urdf", "rigid": true} with joint control by name.
TEST(RigidTreeJoints, ASceneRigidUrdfIsControlledByItsJointNames) {
  if (!robotsPresent()) GTEST_SKIP() << "no robots at " << kRobots << " (ROBOPHI_ROBOTS_DIR)";
  const std::string scene = R"({"robophi": 1, "run": {"duration": 1.0, "dt": 2e-3},
    "environment": {"ground": true},
    "objects": [{"name": "iiwa", "type": "urdf", "file": ")" + kRobots + R"(/kuka_iiwa/model.urdf",
                 "rigid": true, "holdJoints": true, "initialPositions": {"lbr_iiwa_joint_2": 0.5}}],
    "control": {"joints": {"iiwa.lbr_iiwa_joint_4": {"mode": "position", "kp": 300, "kd": 20,
                                                      "target": -1.0}}}})";
  SceneLoadResult loaded = loadSceneText(scene, "rigid_iiwa.json");
  ASSERT_TRUE(loaded.ok()) << (loaded.errors.empty() ? "" : loaded.errors[0].format());
  const Model& m = loaded.scene->model;
  ASSERT_EQ(m.rigidTrees.size(), 1u);
  const auto j2 = findJoint(m, "iiwa.lbr_iiwa_joint_2");
  ASSERT_TRUE(j2.has_value());
  EXPECT_TRUE(m.joints[*j2].inTree());
  EXPECT_DOUBLE_EQ(jointPosition(m, loaded.scene->initial, *j2), 0.5);
  // A wrong joint name is refused with the URDF's names suggested.
  const std::string bad = R"({"robophi": 1, "objects": [{"name": "iiwa", "type": "urdf", "file": ")" +
                          kRobots + R"(/kuka_iiwa/model.urdf", "rigid": true,
                          "initialPositions": {"lbr_iiwa_joint_22": 0.5}}]})";
  SceneLoadResult refused = loadSceneText(bad, "bad.json");
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.errors[0].format().find("lbr_iiwa_joint_22"), std::string::npos);
}

}  // namespace
}  // namespace robophi
