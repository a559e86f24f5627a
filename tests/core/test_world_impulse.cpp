// World::applyImpulse (the live view's drag, docs/viewer.md "Live view"): an
// impulse p at a free particle changes its velocity by p/m; at a point of a free
// rigid body it changes the body's momentum by p and its angular momentum (about
// the world origin) by p_WP × p; on a robot's tree the kinetic energy it adds is
// what World books as external work. A fixed particle nothing carries: no change.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "collision/contact_test_util.h"
#include "core/dropped_box.h"
#include "robophi/multibody.h"
#include "robophi/scene/scene.h"
#include "robophi/world.h"

namespace robophi {
namespace {

std::string sharedRobotsDir() {
  const char* env = std::getenv("ROBOPHI_ROBOTS_DIR");
  return env != nullptr && *env != '\0' ? std::string(env) : std::string(ROBOPHI_ROBOTS_DIR);
}

// The tree's kinetic energy and spatial momentum about the world origin.
struct TreeMotion {
  double kinetic = 0.0;
  SpatialVector momentum{};
};
TreeMotion treeMotion(const World& world, std::size_t t) {
  const Multibody& multibody = world.model().rigidTrees[t].multibody;
  MultibodyKinematics kinematics;
  updateKinematics(multibody, world.state().treePositions[t].data(), kinematics);
  updateVelocities(multibody, world.state().treeVelocities[t].data(), kinematics);
  return {kineticEnergy(kinematics), spatialMomentum(kinematics)};
}

TEST(WorldImpulse, AFreeParticleGetsPOverM) {
  Model model;
  State state;
  test::addBall(model, state, {0.0, 0.0, 1.0}, 2.0, 0.1);
  model.gravity = {0, 0, 0};
  state.velocity[0] = {0.5, -1.0, 0.0};
  World world(model, state, Integrator::kSymplecticEuler);
  world.bookExternalWork();
  world.applyImpulse(0, {1.0, 2.0, -3.0});
  const Vec3 v = world.state().velocity[0];
  EXPECT_DOUBLE_EQ(v.x, 0.5 + 0.5);
  EXPECT_DOUBLE_EQ(v.y, -1.0 + 1.0);
  EXPECT_DOUBLE_EQ(v.z, -1.5);
  // ΔKE = ½ m (|v₁|² − |v₀|²) = ½ 2 (1 + 0 + 2.25 − 1.25) = 2 J, booked as external work.
  EXPECT_NEAR(world.bookExternalWork(), 2.0, 1e-12);
  EXPECT_THROW(world.applyImpulse(0, {NAN, 0, 0}), std::invalid_argument);
  EXPECT_THROW(world.applyImpulse(1, {1, 0, 0}), std::out_of_range);
}

TEST(WorldImpulse, AFreeRigidBodyGetsPAndRCrossP) {
  // The box of the rigid tree tests 1 m over the ground, turning and moving, no gravity.
  build::BuiltModel built = test::droppedBox(1.0, {0.5, -1.0, 2.0});
  built.model.gravity = {0, 0, 0};
  std::vector<double>& rates = built.initial.treeVelocities[0];
  rates[3] = 0.3, rates[5] = -0.2;
  World world(std::move(built.model), std::move(built.initial), Integrator::kVelocityVerlet);
  world.step(1e-3);  // turned a little: the body's frame is not the world's
  const TreeMotion before = treeMotion(world, 0);
  world.bookExternalWork();
  const ParticleIndex corner = 5;  // on the box's surface
  ASSERT_TRUE(world.model().isCarried(corner));
  const Vec3 p_WP = world.state().position[static_cast<std::size_t>(corner)];
  const Vec3 impulse{0.7, -1.1, 0.4};
  world.applyImpulse(corner, impulse);
  const TreeMotion after = treeMotion(world, 0);
  const Vec3 dLinear = after.momentum.linear - before.momentum.linear;
  const Vec3 dAngular = after.momentum.angular - before.momentum.angular;
  const Vec3 expected = cross(p_WP, impulse);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(dLinear[k], impulse[k], 1e-12) << "axis " << k;
    EXPECT_NEAR(dAngular[k], expected[k], 1e-12) << "axis " << k;
  }
  EXPECT_NEAR(world.bookExternalWork(), after.kinetic - before.kinetic, 1e-12);
  // The carried particle moves with the body's new velocity.
  MultibodyKinematics kinematics;
  const Multibody& multibody = world.model().rigidTrees[0].multibody;
  updateKinematics(multibody, world.state().treePositions[0].data(), kinematics);
  updateVelocities(multibody, world.state().treeVelocities[0].data(), kinematics);
  const Vec3 v = pointVelocity(kinematics, 0, p_WP);
  EXPECT_NEAR(norm(world.state().velocity[static_cast<std::size_t>(corner)] - v), 0.0, 1e-12);
}

TEST(WorldImpulse, OnTheIiwaTheEnergyBookedIsTheKineticEnergyAdded) {
  const std::string robots = sharedRobotsDir();
  if (!std::filesystem::exists(robots + "/kuka_iiwa/model.urdf"))
    GTEST_SKIP() << "no robots at " << robots << " (ROBOPHI_ROBOTS_DIR)";
  UrdfSceneOptions options;
  options.rigid = true;
  SceneLoadResult loaded = loadUrdfFile(robots + "/kuka_iiwa/model.urdf", options);
  ASSERT_TRUE(loaded.ok());
  Scene& scene = *loaded.scene;
  World world(std::move(scene.model), std::move(scene.initial), Integrator::kVelocityVerlet);
  for (int s = 0; s < 100; ++s) ASSERT_EQ(world.step(1e-3), StepStatus::kOk);
  // The last carried particle: on the arm's last link.
  ParticleIndex tip = kNoParticle;
  for (ParticleIndex i = 0; i < world.model().particleCount(); ++i)
    if (world.model().isCarried(i)) tip = i;
  ASSERT_NE(tip, kNoParticle);
  const std::vector<double> q0 = world.state().treePositions[0];
  const TreeMotion before = treeMotion(world, 0);
  world.bookExternalWork();
  world.applyImpulse(tip, {0.5, 0.2, -0.3});
  const TreeMotion after = treeMotion(world, 0);
  EXPECT_GT(after.kinetic, before.kinetic + 1e-3);
  EXPECT_EQ(world.state().treePositions[0], q0);  // an impulse: the pose as it was
  EXPECT_NEAR(world.bookExternalWork(), after.kinetic - before.kinetic, 1e-9 * after.kinetic);
  // Then the arm moves: the tip's particle leaves where it was.
  const Vec3 start = world.state().position[static_cast<std::size_t>(tip)];
  for (int s = 0; s < 20; ++s) ASSERT_EQ(world.step(1e-3), StepStatus::kOk);
  EXPECT_GT(norm(world.state().position[static_cast<std::size_t>(tip)] - start), 1e-3);
}

TEST(WorldImpulse, AFixedParticleNothingCarriesStays) {
  Model model;
  State state;
  test::addBall(model, state, {0.0, 0.0, 1.0}, 2.0, 0.1);
  model.inverseMass[0] = 0.0;
  World world(model, state, Integrator::kSymplecticEuler);
  const std::uint64_t changes = world.changeCount();
  world.applyImpulse(0, {1.0, 0.0, 0.0});
  EXPECT_EQ(world.state().velocity[0], (Vec3{0, 0, 0}));
  EXPECT_EQ(world.changeCount(), changes);
}

}  // namespace
}  // namespace robophi
