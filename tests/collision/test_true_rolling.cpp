// Rolling (MODEL §3.3, issue 11): friction acts at the contact point, single
// particles spin, and a wheel's rings meet the ground through their round
// surface. A body of mass m, inertia I about its axis and outer radius R rolls
// down a slope α at a = g sin α / (1 + I / (m R²)) and covers 2πR per turn.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "collision/scene_world.h"

namespace robophi {
namespace {

constexpr double kG = 9.81;
constexpr double kSlope = 10.0 * M_PI / 180.0;
constexpr double kStep = 5e-5;

// Gravity tilted about y by `slope`: downhill is +x on the ground z = 0.
std::string rollingScene(const std::string& object, double slope, double damping = 30.0) {
  char text[2048];
  std::snprintf(text, sizeof text, R"({
    "robophi": 1, "name": "rolling",
    "gravity": [%.17g, 0, %.17g],
    "materials": [{"name": "rubber", "contactStiffness": 2e5, "contactDamping": %.17g,
                   "staticFriction": 0.8, "kineticFriction": 0.6}],
    "environment": {"ground": {"material": "rubber"}},
    "objects": [%s]
  })",
                kG * std::sin(slope), -kG * std::cos(slope), damping, object.c_str());
  return text;
}

// I about the axis y through the centre of mass, from the particles.
double inertiaAboutY(const World& world) {
  const Vec3 c = test::centerOfMass(world);
  double inertia = 0.0;
  for (ParticleIndex i = 0; i < world.model().particleCount(); ++i) {
    const Vec3 r = world.state().position[i] - c;
    inertia += world.model().mass[i] * (r.x * r.x + r.z * r.z);
  }
  return inertia;
}

double totalMass(const World& world) {
  double m = 0.0;
  for (double mi : world.model().mass) m += mi;
  return m;
}

// Measured along the slope from 0.2 s to 1.2 s.
double measuredAcceleration(World& world) {
  test::advance(world, 0.2, kStep);
  const double v1 = test::comVelocity(world).x;
  test::advance(world, 1.0, kStep);
  return test::comVelocity(world).x - v1;
}

std::string wheel(int rim, const char* extra = "") {
  char text[512];
  std::snprintf(text, sizeof text,
                R"({"name": "wheel", "type": "wheel", "center": [0, 0, 0.0999], "radius": 0.1,
                    "width": 0.04, "mass": 1, "rimParticles": %d, "stiffness": 5e4,
                    "material": "rubber"%s})",
                rim, extra);
  return text;
}

TEST(TrueRolling, WheelRollsDownTheSlopeAtTheClosedForm) {
  for (const int rim : {12, 32}) {
    World world = test::sceneWorld(rollingScene(wheel(rim), kSlope));
    const double m = totalMass(world), inertia = inertiaAboutY(world), R = 0.1;
    const double expected = kG * std::sin(kSlope) / (1.0 + inertia / (m * R * R));
    const double a = measuredAcceleration(world);
    std::printf(
        "wheel of %d rim particles: a = %.5f m/s^2, g sin a / (1 + I/mR^2) = %.5f (%+.2f%%)\n", rim,
        a, expected, 100.0 * (a / expected - 1.0));
    EXPECT_NEAR(a / expected, 1.0, 0.02) << rim;
  }
}

// The hub's travel against the angle a rim particle has turned about it.
TEST(TrueRolling, WheelCoversItsCircumferencePerTurn) {
  for (const int rim : {12, 32}) {
    World world = test::sceneWorld(rollingScene(wheel(rim), kSlope));
    const ParticleIndex hub = 2 * rim, spoke = 0;
    const auto angle = [&] {
      const Vec3 r = world.state().position[spoke] - world.state().position[hub];
      return std::atan2(r.x, r.z);  // about +y, turning forward as it rolls towards +x
    };
    double turned = 0.0, previous = angle();
    const double start = world.state().position[hub].x;
    while (turned < 4.0 * M_PI) {
      test::advance(world, 1e-3, kStep);
      double now = angle(), change = now - previous;
      if (change > M_PI) change -= 2.0 * M_PI;
      if (change < -M_PI) change += 2.0 * M_PI;
      turned += change;
      previous = now;
      ASSERT_LT(world.state().time, 10.0);
    }
    const double perTurn = (world.state().position[hub].x - start) / (turned / (2.0 * M_PI));
    std::printf("wheel of %d: %.5f m per turn, 2 pi R = %.5f (%+.3f%%)\n", rim, perTurn,
                2.0 * M_PI * 0.1, 100.0 * (perTurn / (2.0 * M_PI * 0.1) - 1.0));
    EXPECT_NEAR(perTurn / (2.0 * M_PI * 0.1), 1.0, 0.01) << rim;
  }
}

TEST(TrueRolling, WheelOnFlatGroundKeepsItsKineticEnergy) {
  for (const int rim : {12, 32}) {
    // Launched rolling at 1 m/s (ω = v / R about +y), no contact damping.
    World world = test::sceneWorld(rollingScene(
        wheel(rim, R"(, "velocity": [1, 0, 0], "angularVelocity": [0, 10, 0])"), 0.0, 0.0));
    const double start = world.energy().kinetic;
    const double x0 = test::centerOfMass(world).x;
    while (test::centerOfMass(world).x - x0 < 2.0) {
      test::advance(world, 1e-2, kStep);
      ASSERT_LT(world.state().time, 5.0);
    }
    const double kept = world.energy().kinetic / start;
    std::printf("wheel of %d after 2 m on flat ground: kinetic energy kept %.4f\n", rim, kept);
    EXPECT_GE(kept, 0.99) << rim;
  }
}

TEST(TrueRolling, OneParticleBallRollsAtFiveSevenths) {
  World world = test::sceneWorld(rollingScene(
      R"({"name": "ball", "type": "ball", "center": [0, 0, 0.0499], "radius": 0.05,
          "mass": 1, "material": "rubber"})",
      kSlope));
  const double expected = 5.0 / 7.0 * kG * std::sin(kSlope);
  const double a = measuredAcceleration(world);
  std::printf("one-particle ball: a = %.5f m/s^2, 5/7 g sin a = %.5f (%+.2f%%)\n", a, expected,
              100.0 * (a / expected - 1.0));
  EXPECT_NEAR(a / expected, 1.0, 0.02);
}

}  // namespace
}  // namespace robophi
