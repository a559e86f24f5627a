// Paper experiment 5 (MODEL §6.5, scenes/ball_drop.json): a ball falling on the
// ground rebounds with the restitution of the clamped visco-elastic contact
// (MODEL §3.1), computed here in closed form with gravity acting during the
// contact.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "robophi/scene/scene.h"
#include "robotics/scene_files.h"
#include "robotics/tasks.h"
#include "run/runner.h"

namespace robophi {
namespace {

/// The contact as an oscillator for the depth s = −d ≥ 0 (MODEL §3.1):
/// s'' = −ω² s − 2ζω s' + g from s(0) = 0, s'(0) = v_in, so
/// s = g/ω² + e^{−ζωt} (A cos ω_d t + B sin ω_d t), A = −g/ω², B = (v_in + ζω A)/ω_d.
/// The ball leaves when the normal force κ s + μ s' reaches 0 (the clamp), at the
/// first root of ω² s + 2ζω s' after s' < 0.
struct ClampedBounce {
  double restitution = 0.0;  // v_out / v_in
  double exitDepth = 0.0;    // s at the exit (m)
};

ClampedBounce clampedBounce(double stiffness, double damping, double mass, double g, double vIn) {
  const double omega = std::sqrt(stiffness / mass);
  const double zeta = damping / (2.0 * std::sqrt(stiffness * mass));
  const double omegaD = omega * std::sqrt(1.0 - zeta * zeta);
  const double a = -g / (omega * omega), b = (vIn + zeta * omega * a) / omegaD;
  const auto depth = [&](double t) {
    return g / (omega * omega) +
           std::exp(-zeta * omega * t) * (a * std::cos(omegaD * t) + b * std::sin(omegaD * t));
  };
  const auto rate = [&](double t) {
    const double e = std::exp(-zeta * omega * t), c = std::cos(omegaD * t),
                 s = std::sin(omegaD * t);
    return e * ((b * omegaD - zeta * omega * a) * c - (a * omegaD + zeta * omega * b) * s);
  };
  const auto force = [&](double t) {
    return omega * omega * depth(t) + 2.0 * zeta * omega * rate(t);
  };
  // The force is positive from the start until the exit, within 1.5 half periods.
  double lo = 0.5 * M_PI / omegaD, hi = lo;
  while (force(hi) > 0.0) hi += 1e-3 * M_PI / omegaD;
  for (int k = 0; k < 200; ++k) {
    const double mid = 0.5 * (lo + hi);
    (force(mid) > 0.0 ? lo : hi) = mid;
  }
  return {-rate(hi) / vIn, depth(hi)};
}

TEST(BallDrop, ReboundsWithTheClosedFormRestitution) {
  const Scene scene = testing::loadSceneFromScenes("ball_drop.json");
  ASSERT_EQ(scene.model.particleCount(), 1);
  const double mass = scene.model.mass[0], radius = scene.model.radius[0];
  const double g = 9.81, dropHeight = scene.initial.position[0].z - radius;
  const ContactPairOverride& pair = scene.model.contact.pairOverrides.at(0);
  const double vIn = std::sqrt(2.0 * g * dropHeight);
  const ClampedBounce expected = clampedBounce(pair.stiffness, pair.damping, mass, g, vIn);
  // The apex after the first bounce.
  bool touched = false, left = false, done = false;
  double apex = -1.0;
  RunOptions options;
  options.settings = scene.run;
  options.tasks = {robotics::makeSceneTasks(scene), [&](World& world, std::vector<std::string>&) {
                     const bool touching = !world.contacts().empty();
                     const State& s = world.state();
                     if (touching && !left) touched = true;
                     if (touched && !touching) left = true;
                     if (left && !done) {
                       // In flight z + v_z²/(2g) is the apex, whatever the step (the
                       // adaptive step takes long ones in flight, so sampled heights
                       // would miss it); the first step in flight gives it.
                       apex = s.position[0].z + s.velocity[0].z * s.velocity[0].z / (2.0 * g);
                       done = true;
                     }
                     return true;
                   }};
  const RunReport report = runScene(scene, options);
  ASSERT_TRUE(report.ok()) << report.failure;
  ASSERT_TRUE(done);
  // Flight from the exit (depth s_e below the ground line) to the apex: v_out² = 2 g h.
  const double rise = apex - radius + expected.exitDepth;
  const double measured = std::sqrt(2.0 * g * rise) / vIn;
  std::printf("ball drop: restitution %.6f measured, %.6f closed form (ζ = %.4f); %lld steps\n",
              measured, expected.restitution,
              pair.damping / (2.0 * std::sqrt(pair.stiffness * mass)),
              static_cast<long long>(report.steps));
  EXPECT_NEAR(measured, expected.restitution, 1e-3);
  // Not the undamped bounce: the contact's damping is what sets it.
  EXPECT_LT(measured, 0.95);
}

}  // namespace
}  // namespace robophi
