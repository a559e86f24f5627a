// The energy-based adaptive step (MODEL §4): rejection restores the state
// exactly, the step adapts to stiffness, divergence is avoided, a stall is
// reported with where it happened.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "robophi/adaptive_step.h"
#include "run/checkpoint.h"

namespace robophi {
namespace {

// Two free particles on a stiff LS, stretched: an oscillator of ω = sqrt(2κ/m).
World makeStretchedPair(double stiffness, Integrator integrator) {
  Model model;
  model.gravity = {};
  const int object = model.addObject("pair", "particles");
  model.addParticle(1.0, 0.05, false, object);
  model.addParticle(1.0, 0.05, false, object);
  model.linearSprings.push_back({0, 1, 1.0, stiffness, 0.0});
  State state = State::sizedFor(model);
  state.position[1] = {1.1, 0.0, 0.0};
  return World(std::move(model), std::move(state), integrator);
}

// A rejected trial leaves no trace: replaying the accepted steps with a plain
// constant-step World gives a bit-identical state.
TEST(AdaptiveStep, RejectionRestoresExactly) {
  World adaptive = makeStretchedPair(1.0e4, Integrator::kVelocityVerlet);
  World replay = makeStretchedPair(1.0e4, Integrator::kVelocityVerlet);
  AdaptiveStepSettings settings;
  settings.initialStep = 0.05;     // far too large: the first trials are rejected
  settings.stabilitySafety = 1e9;  // let the energy test do the work
  AdaptiveStepper stepper(adaptive.model(), settings);
  for (int i = 0; i < 500; ++i) {
    const AdaptiveStepResult r = stepper.advance(adaptive, 1.0);
    ASSERT_TRUE(r.ok) << r.failure;
    replay.step(r.dt);
    ASSERT_EQ(stateHash(adaptive.state()), stateHash(replay.state())) << "step " << i;
  }
  EXPECT_GT(stepper.stats().rejected, 0);
  EXPECT_EQ(stepper.stats().accepted, 500);
  EXPECT_EQ(adaptive.state().stepCount, 500);
}

// The energy error per accepted step stays within the tolerance, so the
// oscillator keeps its energy; and the step settles where ωδ is small.
TEST(AdaptiveStep, KeepsEnergyWithinTolerance) {
  for (Integrator integrator :
       {Integrator::kSymplecticEuler, Integrator::kVelocityVerlet, Integrator::kTaylor}) {
    World world = makeStretchedPair(1.0e4, integrator);
    AdaptiveStepSettings settings;
    AdaptiveStepper stepper(world.model(), settings);
    world.refresh();
    const double e0 = world.energy().total();
    double t = 0.0;
    while (t < 1.0) {
      const AdaptiveStepResult r = stepper.advance(world, 1.0 - t);
      ASSERT_TRUE(r.ok) << r.failure;
      EXPECT_LE(r.energyError, settings.energyTolerance);
      t = world.state().time;
    }
    const double drift = std::abs(world.energy().total() - e0) / e0;
    // ATS bounds each step's energy error, so the drift stays below (accepted
    // steps) × tolerance; with velocity Verlet, the default, it is far smaller.
    EXPECT_LT(drift, static_cast<double>(stepper.stats().accepted) * settings.energyTolerance)
        << integratorName(integrator);
    if (integrator == Integrator::kVelocityVerlet) {
      EXPECT_LT(drift, 1e-3);
    }
    EXPECT_GT(stepper.stats().accepted, 100);
  }
}

// A stiff spring with a step 10× above the stability limit: the constant step
// blows up, the adaptive one runs to the end without NaN or runaway energy.
TEST(AdaptiveStep, SurvivesWhereConstantStepDiverges) {
  const double stiffness = 1.0e6;
  const double omega = std::sqrt(2.0 * stiffness);
  const double dt = 20.0 / omega;
  World constant = makeStretchedPair(stiffness, Integrator::kSymplecticEuler);
  StepStatus status = StepStatus::kOk;
  for (int i = 0; i < 2000 && status == StepStatus::kOk; ++i) status = constant.step(dt);
  EXPECT_EQ(status, StepStatus::kNonFinite);

  World adaptive = makeStretchedPair(stiffness, Integrator::kSymplecticEuler);
  AdaptiveStepSettings settings;
  settings.initialStep = dt;
  settings.stabilitySafety = 1e9;  // no help from the stability estimate
  AdaptiveStepper stepper(adaptive.model(), settings);
  adaptive.refresh();
  const double e0 = adaptive.energy().total();
  while (adaptive.state().time < 0.2) {
    const AdaptiveStepResult r = stepper.advance(adaptive, 0.2 - adaptive.state().time);
    ASSERT_TRUE(r.ok) << r.failure;
  }
  EXPECT_TRUE(std::isfinite(adaptive.energy().total()));
  EXPECT_LT(adaptive.energy().total(), 1.05 * e0);
}

// Growth: a free particle in gravity with Verlet (exact) reaches the largest
// step, when one is set (there is none by default).
TEST(AdaptiveStep, GrowsToTheLargestStepWhenCalm) {
  Model model;
  model.addParticle(1.0, 0.1, false, model.addObject("ball", "particles"));
  State state = State::sizedFor(model);
  World world(std::move(model), std::move(state), Integrator::kVelocityVerlet);
  AdaptiveStepSettings settings;
  settings.maxStep = 1e-2;
  AdaptiveStepper stepper(world.model(), settings);
  while (world.state().time < 1.0) stepper.advance(world, 1.0 - world.state().time);
  EXPECT_EQ(stepper.stats().largestStep, settings.maxStep);
  EXPECT_EQ(stepper.stats().rejected, 0);
  EXPECT_LT(stepper.stats().accepted, 200);  // a constant 1e-4 step would take 10 000
  // Most steps set by the ceiling (AdaptiveStepStats::setBy*), the last by the time left.
  EXPECT_GT(stepper.stats().setByMaxStep, stepper.stats().accepted / 2);
  EXPECT_EQ(stepper.stats().setByTimeLeft, 1);
}

// Each accepted step is counted once under what set its size (a calm ball with a
// ceiling: GrowsToTheLargestStepWhenCalm): a ball resting on the ground by the
// contacts' stability limit; a stiff oscillating pair by the connectors' cap or
// its energy error. The counts go through a checkpoint unchanged.
TEST(AdaptiveStep, CountsWhatSetEachStep) {
  const auto counted = [](const AdaptiveStepStats& a) {
    return a.setByError + a.setByConnectors + a.setByContacts + a.setByApproach + a.setByMaxStep +
           a.setByTimeLeft;
  };
  {
    Model model;
    model.gravity = {0.0, 0.0, -9.81};
    model.environment.planes.push_back(GroundPlane{});
    model.addParticle(0.01, 0.01, false, model.addObject("ball", "particles"));
    State state = State::sizedFor(model);
    state.position[0] = {0.0, 0.0, 0.0099};  // resting, pressed in by about m g / κ_c
    World world(std::move(model), std::move(state), Integrator::kVelocityVerlet);
    AdaptiveStepper stepper(world.model(), AdaptiveStepSettings{});
    while (world.state().time < 0.5) ASSERT_TRUE(stepper.advance(world, 0.5 - world.state().time).ok);
    const AdaptiveStepStats& a = stepper.stats();
    EXPECT_EQ(counted(a), a.accepted);
    EXPECT_GT(a.setByContacts, 9 * a.accepted / 10) << a.setByError << " by the error";
    const AdaptiveStepper::Progress saved =
        adaptiveProgressFromJson(adaptiveProgressToJson(stepper.progress()));
    EXPECT_EQ(saved.stats.setByContacts, a.setByContacts);
    EXPECT_EQ(saved.stats.setByError, a.setByError);
    EXPECT_EQ(saved.stats.setByTimeLeft, a.setByTimeLeft);
  }
  {
    World world = makeStretchedPair(1e6, Integrator::kVelocityVerlet);
    AdaptiveStepper stepper(world.model(), AdaptiveStepSettings{});
    while (world.state().time < 0.05) stepper.advance(world, 0.05 - world.state().time);
    const AdaptiveStepStats& a = stepper.stats();
    EXPECT_EQ(counted(a), a.accepted);
    EXPECT_GT(a.setByError + a.setByConnectors, a.accepted - 2);
  }
}

// Without a ceiling the calm step keeps growing (here up to the time left).
TEST(AdaptiveStep, HasNoAbsoluteCeilingByDefault) {
  Model model;
  model.addParticle(1.0, 0.1, false, model.addObject("ball", "particles"));
  State state = State::sizedFor(model);
  World world(std::move(model), std::move(state), Integrator::kVelocityVerlet);
  AdaptiveStepper stepper(world.model(), AdaptiveStepSettings{});
  while (world.state().time < 1.0) stepper.advance(world, 1.0 - world.state().time);
  EXPECT_GT(stepper.stats().largestStep, 0.1);
  EXPECT_LT(stepper.stats().accepted, 20);
}

// Below the floor the run stops and names where: no endless loop, no garbage.
TEST(AdaptiveStep, StallIsReportedWithTheParticle) {
  World world = makeStretchedPair(1.0e4, Integrator::kTaylor);
  AdaptiveStepSettings settings;
  settings.energyTolerance = 1e-300;  // unreachable above round-off
  settings.lossToleranceFactor = 0.0;
  // (At 1e-6 s the step's error, 2e-14 J, is within the energy sums' round-off,
  // which is no error: the floor must stop the run before that.)
  settings.minStep = 1e-5;
  AdaptiveStepper stepper(world.model(), settings);
  const std::uint64_t before = stateHash(world.state());
  const AdaptiveStepResult r = stepper.advance(world, 1.0);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.failure.find("particle"), std::string::npos) << r.failure;
  EXPECT_NE(r.failure.find("LS 0"), std::string::npos) << r.failure;
  EXPECT_EQ(stateHash(world.state()), before);  // the state is the last good one
}

}  // namespace
}  // namespace robophi
