// Rigid trees in the world (docs/model.md §7): a rigid body lands and rests on the
// ground at the height its collision geometry gives, with its energy account kept;
// a URDF robot's contact particles lie inside its <collision> geometry and links
// without <collision> have none; a held robot holds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "core/dropped_box.h"
#include "robophi/adaptive_step.h"
#include "robophi/build/model_builder.h"
#include "robophi/build/urdf_multibody.h"
#include "robophi/multibody.h"
#include "robophi/scene/scene.h"
#include "robophi/world.h"
#include "test_files.h"

namespace robophi {
namespace {

using testing::kRobots;  // ROBOPHI_ROBOTS_DIR (test_files.h)

TEST(RigidTreeWorld, ABoxBodyLandsAndRestsOnItsFace) {
  build::BuiltModel built = test::droppedBox(0.1);
  built.model.materials[0].contactStiffness = 1e5;
  built.model.materials[0].contactDamping = 50.0;
  World world(std::move(built.model), std::move(built.initial), Integrator::kVelocityVerlet);
  AdaptiveStepper stepper(world.model(), {});
  const double e0 = world.energy().total();
  while (world.state().time < 2.0) {
    const AdaptiveStepResult r = stepper.advance(world, 2.0 - world.state().time);
    ASSERT_TRUE(r.ok) << "t = " << world.state().time << ": " << r.failure;
  }
  const std::vector<double>& q = world.state().treePositions[0];
  // Rests on its 0.1 m face: centre at 0.05 m less the penetration m g / (n κ).
  EXPECT_NEAR(q[2], 0.05, 2e-3);
  EXPECT_LT(q[2], 0.05);
  // Level: the orientation is the start's (it fell straight).
  EXPECT_NEAR(std::abs(q[3]), 1.0, 1e-6);
  double speed = 0.0;
  for (double x : world.state().treeVelocities[0]) speed = std::max(speed, std::abs(x));
  EXPECT_LT(speed, 1e-3);
  // The account: E + dissipated − external stays the start's within the trees'
  // first-order step in the contact loads (semi-implicit Euler, as MuJoCo's): 1.1 %
  // of the 0.98 J impact here, well inside the run's 5 % bound.
  EXPECT_NEAR(world.energy().total(), e0, 2e-2 * std::abs(e0));
}

TEST(RigidTreeWorld, ATumblingBoxSettlesFlat) {
  build::BuiltModel built = test::droppedBox(0.3, {3.0, 5.0, 1.0});
  World world(std::move(built.model), std::move(built.initial), Integrator::kVelocityVerlet);
  AdaptiveStepper stepper(world.model(), {});
  while (world.state().time < 4.0) ASSERT_TRUE(stepper.advance(world, 4.0 - world.state().time).ok);
  const std::vector<double>& q = world.state().treePositions[0];
  // On one of its faces: the centre at half a side (0.05 or 0.1 m) within the penetration.
  const double z = q[2];
  EXPECT_TRUE(std::abs(z - 0.05) < 3e-3 || std::abs(z - 0.1) < 3e-3) << "z = " << z;
}

bool iiwaUrdfPresent() { return std::filesystem::exists(kRobots + "/kuka_iiwa/model.urdf"); }

TEST(RigidTreeWorld, ARobotTouchesOnlyByItsCollisionGeometry) {
  if (!iiwaUrdfPresent()) GTEST_SKIP() << "no robots at " << kRobots << " (ROBOPHI_ROBOTS_DIR)";
  for (const char* file : {"r2d2/r2d2.urdf", "husky/husky.urdf", "franka_panda/panda.urdf",
                           "kuka_iiwa/model.urdf", "pr2_gripper/pr2_gripper.urdf"}) {
    const std::string path = kRobots + "/" + file;
    build::UrdfMultibodySpec spec;
    spec.path = path;
    spec.packagePaths = {std::filesystem::path(path).parent_path().string(), kRobots};
    const build::UrdfMultibody robot = build::makeUrdfMultibody(spec);
    build::ModelBuilder builder;
    const build::PlacedUrdfMultibody placed = build::placeUrdfMultibody(builder, robot, {});
    const Model& model = builder.model();
    const RigidTree& tree = model.rigidTrees[static_cast<std::size_t>(placed.tree)];
    // Each body's shapes' boxes in its frame, grown by a particle's radius.
    for (const BodyParticle& bp : tree.particles) {
      bool inside = false;
      for (const build::UrdfCollisionShape& shape : robot.collisions) {
        if (shape.body != bp.body) continue;
        const Vec3 p = transposeTimes(shape.X_BS.rotation, bp.p_BP - shape.X_BS.translation);
        const double r = model.radius[static_cast<std::size_t>(bp.particle)] + 1e-9;
        Vec3 half = shape.size * 0.5;
        if (shape.kind == build::UrdfCollisionShape::Kind::kCylinder) half = {shape.size.x, shape.size.y, shape.size.z * 0.5};
        if (shape.kind == build::UrdfCollisionShape::Kind::kSphere) half = shape.size;
        if (shape.kind == build::UrdfCollisionShape::Kind::kMesh) {
          inside = true;  // meshes: fillShape keeps the cells inside or on the surface
          break;
        }
        if (std::abs(p.x) <= half.x + r && std::abs(p.y) <= half.y + r && std::abs(p.z) <= half.z + r) inside = true;
      }
      EXPECT_TRUE(inside) << file << ": particle " << bp.particle << " of body " << bp.body;
    }
    // A body without <collision> has no particles and no object.
    for (std::size_t b = 0; b < robot.multibody.bodies.size(); ++b) {
      const bool hasShape = std::any_of(robot.collisions.begin(), robot.collisions.end(),
                                        [&](const auto& s) { return s.body == static_cast<std::int32_t>(b); });
      EXPECT_EQ(hasShape, placed.objectOfBody[b] >= 0) << file << ": body " << robot.multibody.bodies[b].name;
    }
  }
}

TEST(RigidTreeWorld, TheIiwaAsABareRigidUrdfHoldsItsPose) {
  if (!iiwaUrdfPresent()) GTEST_SKIP() << "no robots at " << kRobots << " (ROBOPHI_ROBOTS_DIR)";
  UrdfSceneOptions options;
  options.rigid = true;
  SceneLoadResult loaded = loadUrdfFile(kRobots + "/kuka_iiwa/model.urdf", options);
  ASSERT_TRUE(loaded.ok());
  Scene& scene = *loaded.scene;
  const std::vector<double> q0 = scene.initial.treePositions[0];
  World world(std::move(scene.model), std::move(scene.initial), Integrator::kVelocityVerlet);
  // A push: every joint given a rate, the servos bring it back.
  world.snapshot();
  for (int s = 0; s < 10000; ++s) ASSERT_EQ(world.step(1e-3), StepStatus::kOk);
  double worst = 0.0;
  for (std::size_t i = 0; i < q0.size(); ++i)
    worst = std::max(worst, std::abs(world.state().treePositions[0][i] - q0[i]));
  EXPECT_LT(worst, 1e-4);
}

}  // namespace
}  // namespace robophi
