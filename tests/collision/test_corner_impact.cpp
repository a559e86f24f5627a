// A faceted cube thrown onto a corner (issue 36: "sinks 2 cm at 20 m/s"): one
// surface vertex carries the whole impact, and MODEL §3.1's spring stores the
// kinetic energy of the corner's effective mass, so an undamped, frictionless
// rigid cube must sink d = v √(m_eff / κ), 1/m_eff = 1/m + |r × n|² / I (r from
// the centre to the corner, I the cube's moment of inertia, κ the pair's
// stiffness: two materials of κ_c in series, κ_c / 2). That is the law's
// answer, not a fault of the detection: at the stress scene's κ_c 2e5 N/m
// (pair 1e5) it is several centimetres (box_thrown_spinning.json), and a sink
// of at most 2 mm at 20 m/s needs a pair stiffness of m_eff v² / (2 mm)², up to
// 1e8 N/m.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "collision/scene_world.h"
#include "robophi/adaptive_step.h"

namespace robophi {
namespace {

// A 1 kg, 10 cm rigid cube (3 cells, flat faces) turned by roll/pitch so that
// one corner is lowest, that corner 1 mm above the ground, falling at 20 m/s.
std::string thrownCorner(double stiffness, double roll, double pitch, double centerHeight) {
  char text[1536];
  std::snprintf(text, sizeof text, R"({
    "robophi": 1, "name": "corner impact", "gravity": [0, 0, 0],
    "environment": {"ground": true},
    "materials": [{"name": "default", "contactStiffness": %.17g, "contactDamping": 0,
                   "staticFriction": 0, "kineticFriction": 0}],
    "objects": [
      {"name": "box", "type": "cube", "center": [0, 0, %.17g], "size": 0.1, "cells": 3,
       "mass": 1, "rigid": true, "velocity": [0, 0, -20],
       "rpy": [%.17g, %.17g, 0]}]
  })",
                stiffness, centerHeight, roll, pitch);
  return text;
}

// The lowest corner's height above the centre, for a cube turned by roll and
// pitch (the scene's rpy: R = Rz Ry Rx), and its offset from the centre.
Vec3 lowestCorner(double roll, double pitch) {
  const double cr = std::cos(roll), sr = std::sin(roll), cp = std::cos(pitch), sp = std::sin(pitch);
  Vec3 lowest{0, 0, 1e9};
  for (const double x : {-0.05, 0.05})
    for (const double y : {-0.05, 0.05})
      for (const double z : {-0.05, 0.05}) {
        // Rx then Ry.
        const Vec3 afterRoll{x, cr * y - sr * z, sr * y + cr * z};
        const Vec3 r{cp * afterRoll.x + sp * afterRoll.z, afterRoll.y,
                     -sp * afterRoll.x + cp * afterRoll.z};
        if (r.z < lowest.z) lowest = r;
      }
  return lowest;
}

struct CornerImpact {
  double deepest;   // m, the deepest contact during the impact
  double expected;  // v √(m_eff / κ_c)
};

CornerImpact throwOnCorner(double stiffness, double roll, double pitch, double dt) {
  const Vec3 corner = lowestCorner(roll, pitch);
  World world = test::sceneWorld(thrownCorner(stiffness, roll, pitch, 1e-3 - corner.z));
  const Model& model = world.model();
  // The cube's moment of inertia about its centre, from its particles (a
  // cube's is the same about every axis).
  const Vec3 center = test::centerOfMass(world);
  double inertia = 0.0, mass = 0.0;
  for (ParticleIndex i = 0; i < model.particleCount(); ++i) {
    const Vec3 r = world.state().position[i] - center;
    inertia += model.mass[i] * (r.x * r.x + r.y * r.y);
    mass += model.mass[i];
  }
  // The lowest surface vertex starts 1 mm above the ground (the rpy read as
  // the scene reads it).
  double lowest = 1e9;
  for (const SurfaceVertex& v : model.surfaceVertices) {
    Vec3 x;
    for (int k = 0; k < SurfaceVertex::kMaxParticles; ++k)
      if (v.particle[k] >= 0) x += world.state().position[v.particle[k]] * v.weight[k];
    lowest = std::min(lowest, x.z);
  }
  EXPECT_NEAR(lowest, 1e-3, 1e-9);
  const Vec3 arm = cross(corner, Vec3{0, 0, 1});
  const double effectiveMass = 1.0 / (1.0 / mass + squaredNorm(arm) / inertia);
  double deepest = 0.0;
  bool touched = false;
  for (int k = 0; k < 200000; ++k) {
    EXPECT_EQ(world.step(dt), StepStatus::kOk);
    for (const Contact& c : world.contacts()) deepest = std::max(deepest, -c.depth);
    if (!world.contacts().empty()) touched = true;
    if (touched && world.contacts().empty()) break;  // bounced off
  }
  return {deepest, 20.0 * std::sqrt(effectiveMass / (0.5 * stiffness))};
}

TEST(CornerImpact, ACubeThrownOnACornerSinksAsTheLawStoresItsEnergy) {
  // Turns with the corner off the vertical through the centre (the impact
  // also spins the cube) and one with it on it (m_eff = m).
  const double onDiagonal = std::atan(1.0 / std::sqrt(2.0));
  for (const auto& [roll, pitch] :
       {std::pair{0.5, 0.3}, std::pair{0.2, 0.7}, std::pair{M_PI / 4, onDiagonal}}) {
    // The materials' κ_c (the ground's too): pairs of 2.5e6 and 1e8 N/m (the
    // first soft enough for a sink of 13 mm, still on the corner alone).
    for (const double stiffness : {5e6, 2e8}) {
      const double dt = 0.02 / std::sqrt(stiffness);  // ~200 steps a contact period
      const CornerImpact impact = throwOnCorner(stiffness, roll, pitch, dt);
      std::printf(
          "corner impact at 20 m/s, rpy (%.2f, %.2f), kappa_c %.1e (pair %.1e): sinks %.3f "
          "mm, the law's v sqrt(m_eff/kappa) %.3f mm\n",
          roll, pitch, stiffness, 0.5 * stiffness, 1e3 * impact.deepest, 1e3 * impact.expected);
      // (The cube turns during the impact, which changes r and m_eff: more in
      // the longer impact of the softer pair.)
      const double tolerance = stiffness >= 2e8 ? 0.02 : 0.07;
      EXPECT_NEAR(impact.deepest, impact.expected, tolerance * impact.expected)
          << "rpy " << roll << ", " << pitch << ", kappa_c " << stiffness;
      if (stiffness >= 2e8) {
        EXPECT_LE(impact.deepest, 2e-3);
      }
    }
  }
}

// The same impact under the default adaptive step (MODEL §4), the corner on
// the vertical diagonal (m_eff = m, no spin): an undamped, frictionless contact
// gives the speed back, and the sink is the law's. A rigid body's vertex
// contact with the environment is implicit in the body's step (docs/model.md
// §7); its backward-Euler loss is integration error, which the energy test must
// see: booked as dissipation, the step crossed the impact in 3 steps of up to
// 0.1 ms, the cube bounced back at 5.3 m/s of 20 and sank 1.37 mm, with the
// account closed.
TEST(CornerImpact, UnderTheAdaptiveStepTheImpactIsElasticAndSinksAsTheLawSays) {
  const double roll = M_PI / 4, pitch = std::atan(1.0 / std::sqrt(2.0)), stiffness = 2e8;
  const Vec3 corner = lowestCorner(roll, pitch);
  World world = test::sceneWorld(thrownCorner(stiffness, roll, pitch, 1e-3 - corner.z));
  AdaptiveStepper stepper(world.model(), AdaptiveStepSettings{});
  double deepest = 0.0;
  while (world.state().time < 0.01) {
    const AdaptiveStepResult r = stepper.advance(world, 0.01 - world.state().time);
    ASSERT_TRUE(r.ok) << r.failure;
    for (const Contact& c : world.contacts()) deepest = std::max(deepest, -c.depth);
  }
  const double expected = 20.0 * std::sqrt(1.0 / (0.5 * stiffness));
  const Vec3 v = test::comVelocity(world);
  std::printf(
      "corner impact, adaptive step: %lld steps, sinks %.3f mm (law %.3f mm), leaves at "
      "%.3f m/s\n",
      static_cast<long long>(stepper.stats().accepted), 1e3 * deepest, 1e3 * expected, v.z);
  EXPECT_NEAR(deepest, expected, 0.03 * expected);
  EXPECT_NEAR(v.z, 20.0, 0.4);
}

}  // namespace
}  // namespace robophi
