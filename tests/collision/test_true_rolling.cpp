// Rolling (MODEL §3.3, issue 11): friction acts at the contact point, single
// particles spin, and a wheel's rings and a generated ball's lattice meet the
// ground through their round surface. A body of mass m, inertia I about its axis and outer radius R
// rolls down a slope α at a = g sin α / (1 + I / (m R²)) and covers 2πR per turn.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "collision/scene_world.h"

namespace robophi {
namespace {

constexpr double kRollingG = 9.81;
constexpr double kSlope = 10.0 * M_PI / 180.0;
constexpr double kRollingStep = 5e-5;

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
                kRollingG * std::sin(slope), -kRollingG * std::cos(slope), damping, object.c_str());
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
  test::advance(world, 0.2, kRollingStep);
  const double v1 = test::comVelocity(world).x;
  test::advance(world, 1.0, kRollingStep);
  return test::comVelocity(world).x - v1;
}

// The centre's travel per turn of the body: the angle the line from its centre
// to particle `far` has turned about +y (forward as it rolls towards +x), over
// two turns.
template <typename Centre>
double travelPerTurn(World& world, ParticleIndex far, Centre centre) {
  const auto angle = [&] {
    const Vec3 r = world.state().position[far] - centre();
    return std::atan2(r.x, r.z);
  };
  double turned = 0.0, previous = angle();
  const double start = centre().x;
  while (turned < 4.0 * M_PI) {
    test::advance(world, 1e-3, kRollingStep);
    double now = angle(), change = now - previous;
    if (change > M_PI) change -= 2.0 * M_PI;
    if (change < -M_PI) change += 2.0 * M_PI;
    turned += change;
    previous = now;
    if (world.state().time > 10.0) return 0.0;  // (it stopped turning)
  }
  return (centre().x - start) / (turned / (2.0 * M_PI));
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
    const double expected = kRollingG * std::sin(kSlope) / (1.0 + inertia / (m * R * R));
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
    const double perTurn =
        travelPerTurn(world, spoke, [&] { return world.state().position[hub]; });
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
      test::advance(world, 1e-2, kRollingStep);
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
  const double expected = 5.0 / 7.0 * kRollingG * std::sin(kSlope);
  const double a = measuredAcceleration(world);
  std::printf("one-particle ball: a = %.5f m/s^2, 5/7 g sin a = %.5f (%+.2f%%)\n", a, expected,
              100.0 * (a / expected - 1.0));
  EXPECT_NEAR(a / expected, 1.0, 0.02);
}

// A generated ball (docs/contact.md "Round balls"): a lattice of `cells` across
// the diameter 0.1 m, 1 kg, meeting the ground as a sphere of its radius R.
constexpr double kBallRadius = 0.05;

std::string latticeBall(int cells, double z = kBallRadius - 5e-5, const char* extra = "") {
  char text[512];
  std::snprintf(text, sizeof text,
                R"({"name": "ball", "type": "ball", "center": [0, 0, %.17g], "radius": %.17g,
                    "cells": %d, "mass": 1, "stiffness": 5e4, "material": "rubber"%s})",
                z, kBallRadius, cells, extra);
  return text;
}

// The scene of rollingScene with the ball's material at μ_s 0.5, μ_k 0.4.
std::string ballScene(const std::string& object, double slope, double damping = 30.0) {
  std::string text = rollingScene(object, slope, damping);
  const std::string from = R"("staticFriction": 0.8, "kineticFriction": 0.6)";
  text.replace(text.find(from), from.size(), R"("staticFriction": 0.5, "kineticFriction": 0.4)");
  return text;
}

TEST(TrueRolling, GeneratedBallRollsDownTheSlopeAtTheClosedForm) {
  for (const int cells : {5, 7}) {
    World world = test::sceneWorld(ballScene(latticeBall(cells), kSlope));
    ASSERT_EQ(world.model().rims.size(), 1u);
    ASSERT_TRUE(world.model().rims[0].isSphere());
    const double m = totalMass(world), inertia = inertiaAboutY(world), R = kBallRadius;
    const double expected = kRollingG * std::sin(kSlope) / (1.0 + inertia / (m * R * R));
    const double start = world.energy().total();
    const double a = measuredAcceleration(world);
    const double scale = world.energy().kinetic;  // what it has gained rolling
    const double drift = world.energy().total() - start;
    std::printf(
        "ball of %d cells (%d particles, I/mR^2 = %.4f): a = %.5f m/s^2, g sin a / (1 + I/mR^2) = "
        "%.5f (%+.2f%%), 5/7 g sin a = %.5f; energy account drift %.3g of %.4f J\n",
        cells, world.model().particleCount(), inertia / (m * R * R), a, expected,
        100.0 * (a / expected - 1.0), 5.0 / 7.0 * kRollingG * std::sin(kSlope), drift, scale);
    EXPECT_NEAR(a / expected, 1.0, 0.02) << cells;
    EXPECT_LT(std::fabs(drift), 1e-3 * scale) << cells;
  }
}

// The centre's travel against the angle a particle far from it has turned.
TEST(TrueRolling, GeneratedBallCoversItsCircumferencePerTurn) {
  for (const int cells : {5, 7}) {
    World world = test::sceneWorld(ballScene(latticeBall(cells), kSlope));
    const ParticleIndex far = 0;  // the lattice's first point, off the centre
    const double circumference = 2.0 * M_PI * kBallRadius;
    const double perTurn = travelPerTurn(world, far, [&] { return test::centerOfMass(world); });
    std::printf("ball of %d cells: %.5f m per turn, 2 pi R = %.5f (%+.3f%%)\n", cells, perTurn,
                circumference, 100.0 * (perTurn / circumference - 1.0));
    EXPECT_NEAR(perTurn / circumference, 1.0, 0.01) << cells;
  }
}

TEST(TrueRolling, GeneratedBallOnFlatGroundKeepsItsKineticEnergy) {
  for (const int cells : {5, 7}) {
    // Launched rolling at 1 m/s (ω = v / R = 20 rad/s about +y), no contact damping.
    World world = test::sceneWorld(
        ballScene(latticeBall(cells, kBallRadius - 5e-5,
                              R"(, "velocity": [1, 0, 0], "angularVelocity": [0, 20, 0])"),
                  0.0, 0.0));
    const double start = world.energy().kinetic;
    const double total = world.energy().total();
    const double x0 = test::centerOfMass(world).x;
    while (test::centerOfMass(world).x - x0 < 2.0) {
      test::advance(world, 1e-2, kRollingStep);
      ASSERT_LT(world.state().time, 5.0);
    }
    const double kept = world.energy().kinetic / start;
    const double drift = world.energy().total() - total;
    std::printf(
        "ball of %d cells after 2 m on flat ground: kinetic energy kept %.5f, energy account "
        "drift %.3g of %.4f J\n",
        cells, kept, drift, start);
    EXPECT_GE(kept, 0.99) << cells;
    EXPECT_LT(std::fabs(drift), 1e-3 * start) << cells;
  }
}

// Dropped from 5 cm above the ground (1 m/s at impact): it bounces back at the
// restitution of the contact's damped spring for the ball's mass, e =
// exp(-ζπ/√(1-ζ²)), ζ = μ_c / (2√(κ_c m)), with rubber on rubber in series
// (κ_c = 1e5 N/m, μ_c = 15 N·s/m, docs/contact.md "Materials and pairs").
TEST(TrueRolling, GeneratedBallBounces) {
  for (const int cells : {5, 7}) {
    const double drop = 1.0 / (2.0 * kRollingG);  // falls 1/(2g) m: 1 m/s at impact
    World world = test::sceneWorld(ballScene(latticeBall(cells, kBallRadius + drop), 0.0));
    double down = 0.0, up = 0.0;
    while (world.state().time < 0.5) {
      test::advance(world, 1e-4, kRollingStep);
      const double vz = test::comVelocity(world).z;
      down = std::min(down, vz);
      up = std::max(up, vz);
    }
    const double zeta = 15.0 / (2.0 * std::sqrt(1e5 * 1.0));
    const double expected = std::exp(-zeta * M_PI / std::sqrt(1.0 - zeta * zeta));
    const double e = up / -down;
    std::printf(
        "ball of %d cells dropped at %.4f m/s: back at %.4f m/s, e = %.4f (damped spring "
        "%.4f)\n",
        cells, -down, up, e, expected);
    EXPECT_NEAR(-down, 1.0, 0.01) << cells;
    EXPECT_NEAR(e, expected, 0.01) << cells;
  }
}

TEST(TrueRolling, GeneratedBallAtRestStaysAtRest) {
  for (const int cells : {5, 7}) {
    World world = test::sceneWorld(ballScene(latticeBall(cells), 0.0));
    test::advance(world, 0.2, kRollingStep);  // settles onto the ground
    const Vec3 before = test::centerOfMass(world);
    test::advance(world, 2.0, kRollingStep);
    const Vec3 moved = test::centerOfMass(world) - before;
    const double creep = std::hypot(moved.x, moved.y);
    std::printf("ball of %d cells at rest: moved %.3g m sideways in 2 s\n", cells, creep);
    EXPECT_LT(creep, 1e-6) << cells;
  }
}

// "round": false: the lattice's particles meet the ground one by one, its flat
// bottom sticks on the slope (μ_s 0.5 holds a block up to 26.6°).
TEST(TrueRolling, GeneratedBallWithoutRoundContactIsItsLattice) {
  World world = test::sceneWorld(
      ballScene(latticeBall(5, kBallRadius - 5e-5, R"(, "round": false)"), kSlope));
  EXPECT_TRUE(world.model().rims.empty());
  const double a = measuredAcceleration(world);
  std::printf("ball of 5 cells, round false: a = %.5f m/s^2 (sticks)\n", a);
  EXPECT_LT(std::fabs(a), 0.05);
}

TEST(TrueRolling, RoundBallModelIsChecked) {
  World world = test::sceneWorld(ballScene(latticeBall(5), 0.0));
  Model model = world.model();
  EXPECT_EQ(checkModel(model), "");
  for (const double radius : {-0.05, std::nan("")}) {
    model.rims[0].sphereRadius = radius;
    EXPECT_NE(checkModel(model).find("rim 0 (a ball)"), std::string::npos) << checkModel(model);
  }
  model.rims[0].sphereRadius = kBallRadius;
  model.rims[0].count = model.particleCount() + 1;
  EXPECT_NE(checkModel(model).find("not >= 2 particles"), std::string::npos);
}

// On a curved heightfield (z = x², curvature radius 0.5 m at the bottom) the
// ball's depth is that of its sphere against the surface, at the contact point
// (the tangent plane there), not the tangent plane below its centre.
TEST(TrueRolling, GeneratedBallOnCurvedTerrainTouchesAtItsContactPoint) {
  const double x0 = 0.1, spacing = 0.001;
  const int columns = 601, rows = 5;  // x in [-0.3, 0.3], y in [-0.002, 0.002]
  std::string heights = "[";
  for (int j = 0; j < rows; ++j) {
    heights += j == 0 ? "[" : ", [";
    for (int i = 0; i < columns; ++i) {
      const double x = -0.3 + i * spacing;
      heights += (i == 0 ? "" : ",") + std::to_string(x * x);
    }
    heights += "]";
  }
  heights += "]";
  // The exact distance from a centre (x0, 0, z0) to the curve z = x².
  const auto distanceToCurve = [](double cx, double cz) {
    double best = 1e9;
    for (int k = 0; k <= 600000; ++k) {
      const double x = -0.3 + k * 1e-6;
      best = std::min(best, std::hypot(x - cx, x * x - cz));
    }
    return best;
  };
  const double z0 = x0 * x0 + (kBallRadius - 1e-4) * std::sqrt(1.0 + 4.0 * x0 * x0);
  const double exact = distanceToCurve(x0, z0) - kBallRadius;
  const double belowCentre = (z0 - x0 * x0) / std::sqrt(1.0 + 4.0 * x0 * x0) - kBallRadius;
  char text[256];
  std::snprintf(text, sizeof text,
                R"({"origin": [-0.3, -0.002], "cellSize": %.17g, "material": "rubber", )", spacing);
  std::string scene = ballScene(latticeBall(5, 0.0), 0.0);
  const std::string ground = R"("ground": {"material": "rubber"})";
  scene.replace(scene.find(ground), ground.size(),
                std::string(R"("heightfield": )") + text + R"("heights": )" + heights + "}");
  World world = test::sceneWorld(scene);
  for (ParticleIndex i = 0; i < world.model().particleCount(); ++i)
    world.setPosition(i, world.state().position[i] + Vec3{x0, 0.0, z0});
  ASSERT_EQ(world.contacts().size(), 1u);
  const Contact& c = world.contacts()[0];
  EXPECT_EQ(c.rim, 0);
  std::printf(
      "ball on z = x^2 at x = %.2f: depth %.4g m, exact %.4g m (tangent plane below the "
      "centre: %.4g m)\n",
      x0, c.depth, exact, belowCentre);
  EXPECT_NEAR(c.depth, exact, 1e-6);
}

// Down a ramp that is an environment box tilted 10° (gravity vertical): the same
// rolling, through the box's distance.
TEST(TrueRolling, GeneratedBallRollsDownABoxRamp) {
  const Vec3 down{std::cos(kSlope), 0.0, -std::sin(kSlope)},
      up{std::sin(kSlope), 0.0, std::cos(kSlope)};
  const Vec3 top = Vec3{0.0, 0.0, -0.5} + up * 0.5;
  const Vec3 start = top + up * (kBallRadius - 5e-5);
  char ramp[256];
  std::snprintf(ramp, sizeof ramp,
                R"("boxes": [{"center": [0, 0, -0.5], "size": [4, 1, 1], "rpy": [0, %.17g, 0],
                             "material": "rubber"}])",
                kSlope);
  std::string scene = ballScene(latticeBall(5, start.z), 0.0);
  const std::string ground = R"("ground": {"material": "rubber"})";
  scene.replace(scene.find(ground), ground.size(), ramp);
  World world = test::sceneWorld(scene);
  for (ParticleIndex i = 0; i < world.model().particleCount(); ++i)
    world.setPosition(i, world.state().position[i] + Vec3{start.x, 0.0, 0.0});
  const double m = totalMass(world), inertia = inertiaAboutY(world), R = kBallRadius;
  const double expected = kRollingG * std::sin(kSlope) / (1.0 + inertia / (m * R * R));
  test::advance(world, 0.2, kRollingStep);
  const double v1 = dot(test::comVelocity(world), down);
  test::advance(world, 1.0, kRollingStep);
  const double a = dot(test::comVelocity(world), down) - v1;
  std::printf("ball of 5 cells down a box ramp: a = %.5f m/s^2, expected %.5f (%+.2f%%)\n", a,
              expected, 100.0 * (a / expected - 1.0));
  EXPECT_NEAR(a / expected, 1.0, 0.02);
}

// Where a contact acts (docs/contact.md): against the ground, on the body's own
// surface, so a round body rolls at v = ωR whatever its overlap d = -m g / κ_c.
// At κ_c 2e4 N/m (rubber on rubber in series: 1e4) the 1 kg ball sinks 1 mm, 2 %
// of R: with the contact point on the ground's surface it covered 0.9804 × 2πR
// per turn (measured with the build before the change).
TEST(TrueRolling, ARoundBodyRollsOnItsOwnRadius) {
  for (const double stiffness : {2e4, 2e6}) {
    const auto scene = [&](const std::string& object) {
      std::string text = rollingScene(object, 0.0);
      const std::string from = R"("contactStiffness": 2e5)";
      text.replace(text.find(from), from.size(),
                   "\"contactStiffness\": " + std::to_string(stiffness));
      return text;
    };
    World ball = test::sceneWorld(scene(latticeBall(
        5, kBallRadius, R"(, "velocity": [1, 0, 0], "angularVelocity": [0, 20, 0])")));
    const double ballTurn =
        travelPerTurn(ball, 0, [&] { return test::centerOfMass(ball); }) / (2.0 * M_PI * kBallRadius);
    World ring = test::sceneWorld(
        scene(wheel(12, R"(, "velocity": [1, 0, 0], "angularVelocity": [0, 10, 0])")));
    const ParticleIndex hub = 24;
    const double ringTurn =
        travelPerTurn(ring, 0, [&] { return ring.state().position[hub]; }) / (2.0 * M_PI * 0.1);
    double deepest = 0.0;
    for (const Contact& c : ring.contacts()) deepest = std::min(deepest, c.depth);
    std::printf(
        "kappa_c %.0e N/m: ball of 5 cells %.6f x 2 pi R per turn, wheel of 12 %.6f (its "
        "overlap %.3g m, %.3f %% of R)\n",
        stiffness, ballTurn, ringTurn, -deepest, -100.0 * deepest / 0.1);
    EXPECT_NEAR(ballTurn, 1.0, 2e-4) << stiffness;
    EXPECT_NEAR(ringTurn, 1.0, 2e-4) << stiffness;
  }
}

}  // namespace
}  // namespace robophi
