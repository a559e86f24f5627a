// No tunnelling (MODEL §4.4, issue 13): in one step no pair of approaching
// surfaces closes by more than a fraction of the smaller radius beyond its gap,
// so two particles at 100 m/s with κ_c = 1e12 N/m, and a ball at 10 m/s against
// a thin plate, bounce instead of passing through each other.
#include <gtest/gtest.h>

#include <cmath>

#include "robophi/adaptive_step.h"
#include "robophi/contact.h"

namespace robophi {
namespace {

// Two 1 kg particles of radius 5 cm, 1 m apart, meeting head on at 100 m/s
// each; undamped contact of κ_c = 1e12 N/m, no gravity.
World headOn() {
  Model model;
  model.gravity = {};
  const int a = model.addObject("a", "particles");
  const int b = model.addObject("b", "particles");
  model.addParticle(1.0, 0.05, false, a);
  model.addParticle(1.0, 0.05, false, b);
  model.contact.pairOverrides.push_back(ContactPairOverride{a, b, 1.0e12, 0.0, 0.0, 0.0});
  State state = State::sizedFor(model);
  state.position[0] = {-0.5, 0.0, 0.0};
  state.position[1] = {0.5, 0.0, 0.0};
  state.velocity[0] = {100.0, 0.0, 0.0};
  state.velocity[1] = {-100.0, 0.0, 0.0};
  return World(std::move(model), std::move(state), Integrator::kVelocityVerlet);
}

// A 0.1 kg ball of radius 1 cm, 0.2 m above a plate 4 mm thick (a fixed box),
// falling at 10 m/s; undamped contact of κ_c = 1e6 N/m, no gravity.
World ballOnPlate() {
  Model model;
  model.gravity = {};
  const int ball = model.addObject("ball", "particles");
  model.addParticle(0.1, 0.01, false, ball);
  BoxObstacle plate;
  plate.center = {0.0, 0.0, 0.0};
  plate.halfExtents = {0.5, 0.5, 0.002};
  model.environment.boxes.push_back(plate);
  model.contact.pairOverrides.push_back(ContactPairOverride{ball, -1, 1.0e6, 0.0, 0.0, 0.0});
  State state = State::sizedFor(model);
  state.position[0] = {0.0, 0.0, 0.2};
  state.velocity[0] = {0.0, 0.0, -10.0};
  return World(std::move(model), std::move(state), Integrator::kVelocityVerlet);
}

void runAdaptive(World& world, double duration) {
  AdaptiveStepper stepper(world.model(), AdaptiveStepSettings{});
  while (world.state().time < duration) {
    const AdaptiveStepResult r = stepper.advance(world, duration - world.state().time);
    ASSERT_TRUE(r.ok) << r.failure;
  }
}

TEST(Tunnelling, HeadOnParticlesAt100MetresPerSecondBounceUnderAts) {
  World world = headOn();
  runAdaptive(world, 0.01);  // they meet at t = 4.5 ms
  // Elastic: the velocities are exchanged (equal masses), to within 1%.
  EXPECT_NEAR(world.state().velocity[0].x, -100.0, 1.0);
  EXPECT_NEAR(world.state().velocity[1].x, 100.0, 1.0);
  EXPECT_LT(world.state().position[0].x, world.state().position[1].x);
}

TEST(Tunnelling, BallAt10MetresPerSecondBouncesOffAThinPlateUnderAts) {
  World world = ballOnPlate();
  runAdaptive(world, 0.04);  // it reaches the plate at t = 18.8 ms
  EXPECT_GT(world.state().position[0].z, 0.0);
  EXPECT_NEAR(world.state().velocity[0].z, 10.0, 0.2);
}

TEST(Tunnelling, ConstantStepIsSplitWhereItWouldPassThrough) {
  // At a constant 2 ms the ball moves 2 cm a step, two radii, five plate
  // thicknesses, and the contact (ω = 3.2e3 rad/s) is unstable: unbounded, it
  // does not bounce back at 10 m/s.
  {
    World world = ballOnPlate();
    for (int i = 0; i < 20; ++i) world.step(2.0e-3);
    EXPECT_FALSE(world.state().position[0].z > 0.0 &&
                 std::abs(world.state().velocity[0].z - 10.0) < 1.0)
        << "the unbounded constant step no longer fails here";
  }
  World world = ballOnPlate();
  std::int64_t splits = 0;
  for (int i = 0; i < 20; ++i) {
    ASSERT_EQ(stepWithoutTunnelling(world, 2.0e-3, 0.1, 0.9, &splits), StepStatus::kOk);
  }
  EXPECT_GT(splits, 0);
  EXPECT_NEAR(world.state().time, 0.04, 1e-15);
  EXPECT_GT(world.state().position[0].z, 0.0);
  EXPECT_GT(world.state().velocity[0].z, 0.0);
  EXPECT_NEAR(world.state().velocity[0].z, 10.0, 1.0);
}

TEST(Tunnelling, ApproachBoundIsGalileanAndScalesWithTheRadius) {
  World world = headOn();
  const std::vector<Vec3> none(2);
  const double bound = approachStepBound(world.model(), world.state(), none, 0.5);
  // Closing at 200 m/s, over the gap of 0.9 m and a fraction 0.5 of 5 cm.
  EXPECT_NEAR(bound, (0.9 + 0.5 * 0.05) / 200.0, 1e-12);
  State boosted = world.state();
  for (Vec3& v : boosted.velocity) v += Vec3{30.0, -40.0, 7.0};
  EXPECT_NEAR(approachStepBound(world.model(), boosted, none, 0.5), bound, 1e-12);
  // Far from a plane, the gap counts: a ball 1 m above the ground at 5 m/s may
  // take (1 m + 0.5 r) / 5 m/s.
  Model model;
  model.addParticle(1.0, 0.1, false, model.addObject("ball", "particles"));
  model.environment.planes.push_back(GroundPlane{});
  State state = State::sizedFor(model);
  state.position[0] = {0.0, 0.0, 1.1};
  state.velocity[0] = {3.0, 0.0, -5.0};
  EXPECT_NEAR(approachStepBound(model, state, std::vector<Vec3>(1), 0.5), 1.05 / 5.0, 1e-12);
  state.velocity[0].z = 5.0;  // leaving the plane: nothing to bound
  EXPECT_TRUE(std::isinf(approachStepBound(model, state, std::vector<Vec3>(1), 0.5)));
}

}  // namespace
}  // namespace robophi
