// The adaptive step's error measure sees neither the observer nor the units
// (MODEL §4.1, issue 12): a ball drop's restitution is the same for observers
// moving at 0, 10 and 30 m/s and for the scene scaled by 1e-3, 1 and 1e3.
#include <gtest/gtest.h>

#include <cmath>

#include "robophi/adaptive_step.h"
#include "robophi/contact.h"

namespace robophi {
namespace {

constexpr double kAtsGravity = 9.81;

// A ball (1 kg) dropped from rest, its bottom `height` above the ground,
// moving sideways at `sideways` (m/s) over a frictionless ground: seen by an
// observer moving at −sideways along the ground, the whole scene moves (the
// ground plane is the same plane). Lengths scale by s, κ_c by 1/s and μ_c by
// 1/√s, which keeps the drop similar (times × √s under the same gravity).
World makeDrop(double scale, double sideways) {
  const double radius = 0.05 * scale, height = 1.0 * scale;
  Model model;
  model.gravity = {0.0, 0.0, -kAtsGravity};
  model.addParticle(1.0, radius, false, model.addObject("ball", "particles"));
  model.environment.planes.push_back(GroundPlane{});
  model.contact.pairOverrides.push_back(
      ContactPairOverride{0, -1, 1.0e7 / scale, 200.0 / std::sqrt(scale), 0.0, 0.0});
  State state = State::sizedFor(model);
  state.position[0] = {0.0, 0.0, height + radius};
  state.velocity[0] = {sideways, 0.0, 0.0};
  return World(std::move(model), std::move(state), Integrator::kVelocityVerlet);
}

// The same drop onto a fixed sphere (a kinematic particle of radius 0.5 s)
// instead of the ground, and the whole scene boosted by `boost` (m/s) in any
// direction, the fixed sphere included: a Galilean change of observer.
World makeDropOnSphere(double scale, const Vec3& boost) {
  const double radius = 0.05 * scale, sphere = 0.5 * scale, height = 1.0 * scale;
  Model model;
  model.gravity = {0.0, 0.0, -kAtsGravity};
  const int ground = model.addObject("ground", "particles");
  model.addParticle(1.0, sphere, true, ground);
  model.addParticle(1.0, radius, false, model.addObject("ball", "particles"));
  model.contact.pairOverrides.push_back(
      ContactPairOverride{0, 1, 1.0e7 / scale, 200.0 / std::sqrt(scale), 0.0, 0.0});
  State state = State::sizedFor(model);
  state.position[0] = {0.0, 0.0, 0.0};
  state.position[1] = {0.0, 0.0, sphere + height + radius};
  state.velocity[0] = boost;
  state.velocity[1] = boost;
  return World(std::move(model), std::move(state), Integrator::kVelocityVerlet);
}

// Restitution: the normal speed of separation, taken back to the contact
// surface by the energy (v² + 2 g gap), over the speed of approach √(2 g h),
// relative to particle `other` (kNoParticle: the ground), through the first
// impact; run under ATS (initial step scaled with √s).
double restitution(World world, double scale, ParticleIndex ball, ParticleIndex other) {
  AdaptiveStepSettings settings;
  settings.initialStep = 1.0e-4 * std::sqrt(scale);
  AdaptiveStepper stepper(world.model(), settings);
  const Model& model = world.model();
  const auto normalSpeedAndGap = [&](double& gap) {
    const State& s = world.state();
    if (other == kNoParticle) {
      gap = s.position[ball].z - model.radius[ball];
      return s.velocity[ball].z;
    }
    const Vec3 dp = s.position[ball] - s.position[other];
    gap = norm(dp) - model.radius[ball] - model.radius[other];
    return dot(s.velocity[ball] - s.velocity[other], dp / norm(dp));
  };
  double gap0 = 0.0;
  normalSpeedAndGap(gap0);
  const double approach = std::sqrt(2.0 * kAtsGravity * gap0);
  bool touched = false;
  const double duration = 1.0 * std::sqrt(scale);
  while (world.state().time < duration) {
    const AdaptiveStepResult r = stepper.advance(world, duration - world.state().time);
    EXPECT_TRUE(r.ok) << r.failure;
    if (!r.ok) return 0.0;
    const bool touching = !world.contacts().empty();
    if (!touched && touching) touched = true;
    if (touched && !touching) {
      double gap = 0.0;
      const double v = normalSpeedAndGap(gap);
      EXPECT_GT(v, 0.0);
      return std::sqrt(v * v + 2.0 * kAtsGravity * gap) / approach;
    }
  }
  ADD_FAILURE() << "no rebound";
  return 0.0;
}

TEST(AtsInvariance, RestitutionIsTheSameForObserversAt0_10_30MetresPerSecond) {
  const double e0 = restitution(makeDrop(1.0, 0.0), 1.0, 0, kNoParticle);
  EXPECT_GT(e0, 0.5);
  EXPECT_LT(e0, 1.0);
  for (double u : {10.0, 30.0}) {
    const double e = restitution(makeDrop(1.0, u), 1.0, 0, kNoParticle);
    EXPECT_NEAR(e, e0, 1e-3) << "observer at " << u << " m/s along the ground";
  }
  // The whole scene, a kinematic fixed sphere included, boosted in 3-D.
  const double s0 = restitution(makeDropOnSphere(1.0, {}), 1.0, 1, 0);
  EXPECT_GT(s0, 0.5);
  for (const Vec3& boost : {Vec3{10.0, 0.0, 0.0}, Vec3{0.0, 21.2, 21.2}, Vec3{-17.3, 17.3, 17.3}}) {
    const double e = restitution(makeDropOnSphere(1.0, boost), 1.0, 1, 0);
    EXPECT_NEAR(e, s0, 1e-3) << "observer at " << norm(boost) << " m/s";
  }
}

TEST(AtsInvariance, RestitutionIsTheSameAtLengthScales1e_3_1_1e3) {
  const double e1 = restitution(makeDrop(1.0, 0.0), 1.0, 0, kNoParticle);
  for (double s : {1.0e-3, 1.0e3}) {
    const double e = restitution(makeDrop(s, 0.0), s, 0, kNoParticle);
    EXPECT_NEAR(e, e1, 1e-3) << "length scale " << s;
  }
}

TEST(AtsInvariance, StepCountDoesNotGrowWithTheLengthScale) {
  // No absolute ceiling: the scaled drop takes as many steps (11× more at 1e3
  // under the old maxStep of 1e-2 s).
  std::int64_t counts[3];
  int k = 0;
  for (double s : {1.0e-3, 1.0, 1.0e3}) {
    World world = makeDrop(s, 0.0);
    AdaptiveStepSettings settings;
    settings.initialStep = 1.0e-4 * std::sqrt(s);
    AdaptiveStepper stepper(world.model(), settings);
    const double duration = 0.6 * std::sqrt(s);
    while (world.state().time < duration) {
      ASSERT_TRUE(stepper.advance(world, duration - world.state().time).ok);
    }
    counts[k++] = stepper.stats().accepted;
  }
  EXPECT_NEAR(static_cast<double>(counts[0]), static_cast<double>(counts[1]),
              0.02 * static_cast<double>(counts[1]));
  EXPECT_NEAR(static_cast<double>(counts[2]), static_cast<double>(counts[1]),
              0.02 * static_cast<double>(counts[1]));
}

TEST(AtsInvariance, EnergyScalesSeeNeitherTheDatumNorTheObserver) {
  World a = makeDrop(1.0, 0.0);
  World b = makeDrop(1.0, 30.0);
  Model shifted = a.model();
  shifted.environment.planes[0].point.z = -7.0;
  State state = a.state();
  state.position[0].z -= 7.0;
  World c(std::move(shifted), std::move(state), Integrator::kVelocityVerlet);
  const auto scale = [](const World& w) {
    return energyAccountScale(w.model(), w.state(), w.energy());
  };
  EXPECT_NEAR(scale(a), 1.0 * kAtsGravity * 1.05, 1e-9);
  EXPECT_NEAR(scale(b), scale(a), 1e-9);
  EXPECT_NEAR(scale(c), scale(a), 1e-9);
  EXPECT_NEAR(activeEnergy(b.model(), b.state(), b.energy()), 0.0, 1e-12);
}

}  // namespace
}  // namespace robophi
