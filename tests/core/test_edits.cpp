// World's edit API (issue 10): an edit between steps reaches the contact stage
// (its tables are rebuilt), a no-op edit changes nothing, a bad argument is a
// clear exception naming it, never a crash.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "collision/contact_test_util.h"
#include "robophi/adaptive_step.h"
#include "robophi/joints.h"
#include "robophi/world.h"

namespace robophi {
namespace {

constexpr double kEditedMass = 2.0;  // kg: m g = 19.62 N
constexpr double kRadius = 0.3;  // m: deep enough for the softest contact below
constexpr double kEditsGravity = 9.81;

// One ball on the ground (plane z = 0), with a pair override ball–environment.
struct BallOnGround {
  Model model;
  State state;
  std::int32_t ball = 0;
  BallOnGround() {
    test::addBall(model, state, {0.0, 0.0, kRadius}, kEditedMass, kRadius);
    ball = 0;
    model.materials.push_back(Material{"soft", 2.0e3, 20.0, 0.5, 0.4});
    model.materials.push_back(Material{"hard", 4.0e4, 20.0, 0.5, 0.4});
    model.environment.planes.push_back(GroundPlane{});
    model.linearDamping[0] = 5.0;  // settles within a few seconds
    test::overrideWithEnvironment(model, ball, 1.0e4, 50.0, 0.5, 0.4);
  }
};

// Settles the ball (3 s of 1e-4 s steps) and returns its contact depth (m, > 0).
double settledDepth(World& world) {
  for (int s = 0; s < 30000; ++s) world.step(1e-4);
  EXPECT_EQ(world.contacts().size(), 1u);
  return world.contacts().empty() ? 0.0 : -world.contacts()[0].depth;
}

TEST(Edits, ContactParameterFrictionAndMaterialReachTheContactStage) {
  BallOnGround setup;
  World world(setup.model, setup.state, Integrator::kSymplecticEuler);
  const double weight = kEditedMass * kEditsGravity;
  // A pair override: κ_c = 1e4 N/m, then 1e2 N/m (the depth is m g / κ_c).
  EXPECT_NEAR(settledDepth(world), weight / 1.0e4, 1e-3 * weight / 1.0e4);
  world.setContactPair(ContactPairOverride{setup.ball, -1, 1.0e2, 5.0, 0.5, 0.4});
  EXPECT_NEAR(settledDepth(world), weight / 1.0e2, 1e-3 * weight / 1.0e2);

  // Without the override, the materials combine in series: default (1e4) and
  // the ball's own. Give the ball "soft" (2e3), then edit "soft" to 8e3.
  world.setContactSettings(ContactSettings{});
  world.setObjectMaterial(setup.ball, 1);
  const auto series = [](double a, double b) { return a * b / (a + b); };
  EXPECT_NEAR(settledDepth(world), weight / series(1.0e4, 2.0e3), 1e-3);
  world.setMaterial(1, Material{"soft", 8.0e3, 20.0, 0.5, 0.4});
  EXPECT_NEAR(settledDepth(world), weight / series(1.0e4, 8.0e3), 1e-4);
  world.setObjectMaterial(setup.ball, 2);
  EXPECT_NEAR(settledDepth(world), weight / series(1.0e4, 4.0e4), 1e-4);
}

TEST(Edits, AFrictionCoefficientEditedBetweenStepsTakesEffect) {
  // Gravity tilted to a 16.7° slope (tan α = 0.3), the ball resting at its
  // equilibrium depth. With μ_s = 0.5 it sticks; edited to μ_s = μ_k = 0.2 it
  // slides at a = g (sin α - μ_k cos α). (The paper's particle, which does not
  // turn: a spinning ball would roll.)
  BallOnGround setup;
  setup.model.contact.rolling = false;
  const double alpha = std::atan(0.3);
  setup.model.gravity = Vec3{std::sin(alpha), 0.0, -std::cos(alpha)} * kEditsGravity;
  setup.model.linearDamping[0] = 0.0;
  setup.state.position[0].z = kRadius - kEditedMass * kEditsGravity * std::cos(alpha) / 1.0e4;
  World world(setup.model, setup.state, Integrator::kSymplecticEuler);
  for (int s = 0; s < 10000; ++s) world.step(1e-4);
  const double stuckAt = world.state().position[0].x;
  EXPECT_LT(std::abs(stuckAt), 3e-3);  // the anchor spring's deflection
  for (int s = 0; s < 10000; ++s) world.step(1e-4);
  EXPECT_NEAR(world.state().position[0].x, stuckAt, 1e-7);  // holds, no creep
  world.setContactPair(ContactPairOverride{setup.ball, -1, 1.0e4, 50.0, 0.2, 0.2});
  const double start = world.state().position[0].x;
  for (int s = 0; s < 5000; ++s) world.step(1e-4);
  const double a = kEditsGravity * (std::sin(alpha) - 0.2 * std::cos(alpha));
  EXPECT_NEAR(world.state().position[0].x - start, 0.5 * a * 0.25, 0.02 * 0.5 * a * 0.25);
}

TEST(Edits, AnEditToTheSameValueChangesNothing) {
  // Two runs of the servo arm, one with every joint's target, servo, a
  // position and a velocity re-set to their own values before every step.
  const auto run = [](bool touch) {
    Model model;
    State state;
    for (int k = 0; k < 4; ++k) test::addBall(model, state, {0.1 * k, 0.0, 0.5}, 0.1, 0.02);
    model.jointSprings.push_back({0, 1, 2, 3, 2.0, 5.0, 0.1});
    model.joints.push_back({"j", JointKind::kRevolute, 0, -1});
    model.linearSprings.push_back({0, 1, 0.1, 100.0, 0.1});
    model.linearSprings.push_back({1, 2, 0.1, 100.0, 0.1});
    model.linearSprings.push_back({1, 3, 0.1, 100.0, 0.1});
    model.environment.planes.push_back(GroundPlane{});
    World world(model, state, Integrator::kVelocityVerlet);
    for (int s = 0; s < 3000; ++s) {
      if (touch) {
        const JointServo servo = jointServo(world.model(), 0);
        world.setJointTarget(0, servo.target);
        world.setJointServo(0, servo.stiffness, servo.damping);
        world.setPosition(2, world.state().position[2]);
        world.setVelocity(2, world.state().velocity[2]);
        EXPECT_EQ(world.bookExternalWork(), 0.0);
      }
      world.step(1e-4);
    }
    return stateHash(world.state());
  };
  EXPECT_EQ(run(true), run(false));
}

TEST(Edits, BadArgumentsAreClearExceptionsNotCrashes) {
  Model empty;
  EXPECT_THROW(jointServo(empty, 0), std::out_of_range);
  BallOnGround setup;
  EXPECT_THROW(jointValue(setup.model, setup.state, 0), std::out_of_range);
  State wrong = setup.state;
  wrong.position.push_back({});
  EXPECT_THROW(World(setup.model, wrong), std::invalid_argument);
  State nan = setup.state;
  nan.velocity[0].x = std::nan("");
  EXPECT_THROW(World(setup.model, nan), std::invalid_argument);
  Model broken = setup.model;
  broken.radius[0] = -1.0;
  EXPECT_THROW(CompiledModel{broken}, std::invalid_argument);

  World world(setup.model, setup.state);
  EXPECT_THROW(world.step(0.0), std::invalid_argument);
  EXPECT_THROW(world.step(std::nan("")), std::invalid_argument);
  EXPECT_THROW(world.setPosition(1, {}), std::out_of_range);
  EXPECT_THROW(world.setPosition(-1, {}), std::out_of_range);
  EXPECT_THROW(world.setVelocity(0, {std::nan(""), 0.0, 0.0}), std::invalid_argument);
  EXPECT_THROW(world.setJointTarget(0, 1.0), std::out_of_range);
  EXPECT_THROW(world.setMaterial(7, Material{}), std::out_of_range);
  EXPECT_THROW(world.setMaterial(0, Material{"x", -1.0, 0.0, 0.5, 0.4}), std::invalid_argument);
  EXPECT_THROW(world.setObjectMaterial(0, 9), std::out_of_range);
  EXPECT_THROW(world.setContactPair(ContactPairOverride{3, -1}), std::out_of_range);
  EXPECT_THROW(world.setLinearSpring(0, LinearSpring{}), std::out_of_range);
  EXPECT_THROW(world.addSphereObstacle(SphereObstacle{{0.0, 0.0, 0.0}, 0.0, 0}),
               std::invalid_argument);
  try {
    world.setPosition(5, {});
    FAIL();
  } catch (const std::out_of_range& e) {
    EXPECT_NE(std::string(e.what()).find("particle 5"), std::string::npos) << e.what();
  }
  AdaptiveStepSettings badStep;
  badStep.maxStep = 0.5 * badStep.minStep;
  EXPECT_THROW(AdaptiveStepper(setup.model, badStep), std::invalid_argument);
  badStep = AdaptiveStepSettings{};
  badStep.energyTolerance = std::nan("");
  EXPECT_THROW(AdaptiveStepper(setup.model, badStep), std::invalid_argument);
  Model other;
  State otherState;
  test::addBall(other, otherState, {}, 1.0, 0.1);
  test::addBall(other, otherState, {1.0, 0.0, 0.0}, 1.0, 0.1);
  const World::Snapshot foreign = World(other, otherState).snapshot();
  EXPECT_THROW(world.restore(foreign), std::invalid_argument);
  // Nothing was changed by the refused edits.
  EXPECT_EQ(stateHash(world.state()), stateHash(World(setup.model, setup.state).state()));
}

// A sphere obstacle moved by trial (the escape's placement, MODEL §5.2): each
// move is an edit whose work is the contact energy it adds or takes away, so a
// sphere moved into the ball and back out books no work in all; an item that is
// not a sphere is refused.
TEST(Edits, AMovedSphereObstacleBooksTheContactEnergyItChanges) {
  BallOnGround setup;
  World world(setup.model, setup.state);
  world.bookExternalWork();
  const double before = world.energy().contact;
  const std::int32_t item =
      world.addSphereObstacle(SphereObstacle{{2.0, 0.0, kRadius}, 0.1, 0});
  EXPECT_EQ(item, 1);  // after the ground plane
  EXPECT_EQ(world.bookExternalWork(), 0.0);  // out of reach
  world.moveSphereObstacle(item, {kRadius + 0.1 - 0.01, 0.0, kRadius});  // 1 cm into the ball
  const double into = world.bookExternalWork();
  EXPECT_GT(into, 0.0);
  EXPECT_NEAR(into, world.energy().contact - before, 1e-12);
  world.moveSphereObstacle(item, {2.0, 0.0, kRadius});
  EXPECT_NEAR(world.bookExternalWork(), -into, 1e-12);
  EXPECT_THROW(world.moveSphereObstacle(0, {}), std::invalid_argument);  // the plane
  EXPECT_THROW(world.moveSphereObstacle(2, {}), std::invalid_argument);  // no such item
  EXPECT_THROW(world.moveSphereObstacle(item, {std::nan(""), 0.0, 0.0}), std::invalid_argument);
}

TEST(Edits, ConnectorEndsRebuildTheExclusionLists) {
  // Two touching balls tied by an LS do not collide; re-tie the LS to another
  // pair and they do.
  Model model;
  State state;
  for (int k = 0; k < 3; ++k) test::addBall(model, state, {0.03 * k, 0.0, 0.0}, 0.1, 0.02);
  model.gravity = {};
  model.linearSprings.push_back({0, 1, 0.03, 10.0, 0.0});
  model.linearSprings.push_back({1, 2, 0.03, 10.0, 0.0});
  World world(model, state);
  EXPECT_TRUE(world.contacts().empty());
  world.setLinearSpring(1, LinearSpring{0, 2, 0.06, 10.0, 0.0});
  ASSERT_EQ(world.contacts().size(), 1u);
  EXPECT_EQ(world.contacts()[0].a, 1);
  EXPECT_EQ(world.contacts()[0].other, 2);
}

}  // namespace
}  // namespace robophi
