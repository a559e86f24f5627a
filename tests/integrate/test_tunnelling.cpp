// No tunnelling (MODEL §4.4, issue 13): in one step no pair of approaching
// surfaces closes by more than a fraction of the smaller radius beyond its gap,
// so two particles at 100 m/s with κ_c = 1e12 N/m, and a ball at 10 m/s against
// a thin plate, bounce instead of passing through each other.
#include <gtest/gtest.h>

#include <atomic>
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
// Bounded work (issue 40): the split stops at its substep limit, or at a
// requested stop, at the end of a whole substep and short of t + dt.
TEST(Tunnelling, TheSplitStopsAtItsLimitAndAtARequestedStop) {
  World reference = ballOnPlate();
  std::int64_t splits = 0;
  for (int i = 0; i < 9; ++i) stepWithoutTunnelling(reference, 2.0e-3, 0.1, 0.9, &splits);
  const std::int64_t before = reference.state().stepCount;
  ASSERT_EQ(stepWithoutTunnelling(reference, 2.0e-3, 0.1, 0.9), StepStatus::kOk);
  const std::int64_t needed = reference.state().stepCount - before;
  ASSERT_GT(needed, 3) << "the ball no longer needs a split at its tenth step";

  World limited = ballOnPlate();
  for (int i = 0; i < 9; ++i) stepWithoutTunnelling(limited, 2.0e-3, 0.1, 0.9);
  const double start = limited.state().time;
  EXPECT_EQ(stepWithoutTunnelling(limited, 2.0e-3, 0.1, 0.9, nullptr, 3), StepStatus::kStopped);
  EXPECT_EQ(limited.state().stepCount, before + 3);
  EXPECT_GT(limited.state().time, start);
  EXPECT_LT(limited.state().time, start + 2.0e-3);

  // A stop already requested: not one substep more.
  std::atomic<bool> stop{true};
  const std::int64_t steps = limited.state().stepCount;
  EXPECT_EQ(stepWithoutTunnelling(limited, 2.0e-3, 0.1, 0.9, nullptr, 0, &stop),
            StepStatus::kStopped);
  EXPECT_EQ(limited.state().stepCount, steps);
  // Neither binds: the step ends on t + dt as without them.
  stop = false;
  World free = ballOnPlate();
  for (int i = 0; i < 10; ++i)
    ASSERT_EQ(stepWithoutTunnelling(free, 2.0e-3, 0.1, 0.9, nullptr, 1000000, &stop),
              StepStatus::kOk);
  EXPECT_EQ(free.state().position[0].z, reference.state().position[0].z);
  EXPECT_EQ(free.state().velocity[0].z, reference.state().velocity[0].z);
}

// The adaptive step's floor holds for the model's own limits too: a ball at
// 1e12 m/s just above a plate may step only 5e-15 s by the approach bound,
// below the default floor (1e-8 × the first step 1e-4 s): a stall that says
// so, not a crawl of 1e-15 s steps (issue 40: steps of 4.5e-151 s).
TEST(Tunnelling, AnApproachBoundBelowTheFloorIsAStall) {
  World world = ballOnPlate();
  world.setPosition(0, {0.0, 0.0, 0.013});
  world.setVelocity(0, {0.0, 0.0, -1.0e12});
  AdaptiveStepper stepper(world.model(), AdaptiveStepSettings{});
  EXPECT_DOUBLE_EQ(stepper.floor(), 1.0e-12);
  const AdaptiveStepResult r = stepper.advance(world, 1.0);
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.stopped);
  EXPECT_NE(r.failure.find("the approach bound"), std::string::npos) << r.failure;
  EXPECT_NE(r.failure.find("below the adaptive step's floor 1e-12 s"), std::string::npos)
      << r.failure;
  EXPECT_EQ(world.state().stepCount, 0);
}

}  // namespace robophi
