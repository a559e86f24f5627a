// MODEL §3.1: a ball dropped on the ground bounces with the restitution of a
// damped linear oscillator, e = exp(-ζπ/√(1-ζ²)), ζ = μ_c / (2√(κ_c m)).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "collision/contact_test_util.h"

namespace robophi {
namespace {

// The restitution with the normal force clamped at >= 0 (MODEL §3.1): the ball
// leaves when the force vanishes, i.e. at the largest outward speed of
// x(t) = (v0/ω_d) e^{-ζωt} sin(ω_d t) over the first half period.
double clampedRestitution(double zeta) {
  const double omegaD = std::sqrt(1.0 - zeta * zeta);  // ω = 1
  double fastest = 0.0;
  const int samples = 2'000'000;
  for (int k = 0; k <= samples; ++k) {
    const double t = M_PI / omegaD * k / samples;
    const double speed =
        std::exp(-zeta * t) * (std::cos(omegaD * t) - zeta / omegaD * std::sin(omegaD * t));
    fastest = std::min(fastest, speed);
  }
  return -fastest;
}

double formulaRestitution(double zeta) {
  return std::exp(-zeta * M_PI / std::sqrt(1.0 - zeta * zeta));
}

// Drops a ball of 0.1 kg from 0.2 m onto the ground; returns v_out / v_in.
double measuredRestitution(double zeta) {
  Model model;
  State state;
  constexpr double kMass = 0.1, kRadius = 0.05, kStiffness = 1.0e7;
  const ParticleIndex ball = test::addBall(model, state, {0.0, 0.0, kRadius + 0.2}, kMass, kRadius);
  model.environment.planes.push_back(GroundPlane{});
  test::overrideWithEnvironment(model, 0, kStiffness, 2.0 * zeta * std::sqrt(kStiffness * kMass),
                                0.0, 0.0);
  World world(model, state, Integrator::kSymplecticEuler);
  constexpr double kStep = 1.0e-6;  // ω δ = 0.01
  double incoming = 0.0;
  bool touched = false;
  for (int step = 0; step < 400'000; ++step) {
    const double before = world.state().velocity[ball].z;
    world.step(kStep);
    const bool touching = !world.contacts().empty();
    if (touching && !touched) {
      incoming = before;
      touched = true;
    }
    if (touched && !touching) return world.state().velocity[ball].z / -incoming;
  }
  return -1.0;
}

TEST(ContactRestitution, SmallDampingMatchesTheDampedOscillator) {
  const double zeta = 0.01;
  const double e = measuredRestitution(zeta);
  const double expected = formulaRestitution(zeta);
  std::printf("ζ = %.2f: e measured %.6f, exp(-ζπ/√(1-ζ²)) %.6f\n", zeta, e, expected);
  EXPECT_NEAR(e, expected, 1e-3) << "ζ = " << zeta;
}

TEST(ContactRestitution, ClampedForceMatchesItsExactSolution) {
  // With more damping the clamp of F_n >= 0 matters: the ball leaves before
  // d = 0, faster than the unclamped oscillator. Compare with both.
  for (const double zeta : {0.05, 0.1, 0.3}) {
    const double e = measuredRestitution(zeta);
    const double clamped = clampedRestitution(zeta);
    EXPECT_NEAR(e, clamped, 1e-3) << "ζ = " << zeta << ", formula (unclamped) "
                                  << formulaRestitution(zeta);
    std::printf("ζ = %.2f: e measured %.6f, clamped exact %.6f, exp(-ζπ/√(1-ζ²)) %.6f\n", zeta, e,
                clamped, formulaRestitution(zeta));
  }
}

}  // namespace
}  // namespace robophi
