// ATS against CTS on a rigid collision (issue 4, case 1): a ball dropped 1 m on
// the ground with stiff undamped contact must rebound to 1 m. ATS resolves the
// impact with small steps and flies with large ones; a constant step must be
// small all the time.
#include <gtest/gtest.h>

#include <cmath>

#include "robophi/adaptive_step.h"
#include "robophi/contact.h"

namespace robophi {
namespace {

constexpr double kRadius = 0.05, kHeight = 1.0, kGravity = 9.81, kDuration = 0.5;

World makeDrop(double contactStiffness) {
  Model model;
  model.gravity = {0.0, 0.0, -kGravity};
  model.addParticle(1.0, kRadius, false, model.addObject("ball", "particles"));
  model.environment.planes.push_back(GroundPlane{});
  model.contact.pairOverrides.push_back(ContactPairOverride{0, -1, contactStiffness, 0, 0, 0});
  State state = State::sizedFor(model);
  state.position[0] = {0.0, 0.0, kHeight + kRadius};
  return World(std::move(model), std::move(state), Integrator::kVelocityVerlet);
}

// The rebound height implied by the state just after the ball leaves the ground.
struct Rebound {
  bool touched = false, measured = false;
  double height = 0.0;
  double maxPenetration = 0.0;
  void observe(const World& world) {
    const double bottom = world.state().position[0].z - kRadius;
    const double vz = world.state().velocity[0].z;
    maxPenetration = std::max(maxPenetration, -bottom);
    if (bottom < 0.0) touched = true;
    if (touched && !measured && bottom >= 0.0 && vz > 0.0) {
      measured = true;
      height = bottom + vz * vz / (2.0 * kGravity);
    }
  }
  double error() const { return measured ? std::abs(height - kHeight) : kHeight; }
};

struct RunResult {
  std::int64_t steps = 0;
  double error = 0.0;
  double maxPenetration = 0.0;
};

RunResult runAdaptive(double stiffness) {
  World world = makeDrop(stiffness);
  AdaptiveStepper stepper(world.model(), AdaptiveStepSettings{});
  Rebound rebound;
  while (world.state().time < kDuration) {
    const AdaptiveStepResult r = stepper.advance(world, kDuration - world.state().time);
    EXPECT_TRUE(r.ok) << r.failure;
    if (!r.ok) break;
    rebound.observe(world);
  }
  return {stepper.stats().accepted, rebound.error(), rebound.maxPenetration};
}

RunResult runConstant(double stiffness, std::int64_t steps) {
  World world = makeDrop(stiffness);
  const double dt = kDuration / static_cast<double>(steps);
  Rebound rebound;
  for (std::int64_t i = 0; i < steps; ++i) {
    world.step(dt);
    rebound.observe(world);
  }
  return {steps, rebound.error(), rebound.maxPenetration};
}

// κ_c = 1e10 N/m (a steel-like contact): CTS with 1000× ATS's steps is still
// less accurate, so equal accuracy costs CTS more than 1000× the steps.
TEST(AdaptiveVersusConstant, RigidCollisionNeedsOver1000TimesFewerSteps) {
  const double stiffness = 1.0e10;
  const RunResult ats = runAdaptive(stiffness);
  EXPECT_LT(ats.error, 1e-4);  // rebound height within 0.1 mm of 1 m
  EXPECT_LT(ats.steps, 250);
  const RunResult cts = runConstant(stiffness, 1000 * ats.steps);
  EXPECT_GT(cts.error, ats.error) << "ATS " << ats.steps << " steps";
}

// κ_c = 1e7 N/m: the gain is smaller (the contact lasts longer) but ATS still
// wins by over 100× at equal error, and penetration stays within 10% of r.
TEST(AdaptiveVersusConstant, SofterCollisionStillGainsOver100Times) {
  const double stiffness = 1.0e7;
  const RunResult ats = runAdaptive(stiffness);
  EXPECT_LT(ats.error, 1e-4);
  EXPECT_LT(ats.maxPenetration, 0.1 * kRadius);
  const RunResult cts = runConstant(stiffness, 100 * ats.steps);
  EXPECT_GT(cts.error, ats.error) << "ATS " << ats.steps << " steps";
}

// A stiff contact with a constant step far too large blows up (or loses the
// ball through the ground); ATS runs it to the end with the right rebound.
TEST(AdaptiveVersusConstant, ConstantStepFailsWhereAdaptiveDoesNot) {
  const double stiffness = 1.0e9;
  const RunResult cts = runConstant(stiffness, 500);  // δ = 1 ms >> 2/ω = 63 µs
  EXPECT_GT(cts.error, 0.01);
  const RunResult ats = runAdaptive(stiffness);
  EXPECT_LT(ats.error, 1e-4);
}

}  // namespace
}  // namespace robophi
