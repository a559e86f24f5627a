// Paper experiment 2 (MODEL §6.2, scenes/wheel_cube_ramp.json), as in the
// paper's figure: from rest, a wheel rolls down a ramp, hits a cube standing on
// it, and the cube leaves the ramp or topples. The test asserts that outcome
// (where things end up, the cube's turn), not a tuned distance.
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

Vec3 centroid(const std::vector<Vec3>& x, const ObjectInfo& o) {
  Vec3 sum;
  for (ParticleIndex i = o.firstParticle; i < o.firstParticle + o.particleCount; ++i) sum += x[i];
  return sum / static_cast<double>(o.particleCount);
}

TEST(WheelCube, FromRestTheWheelRollsDownTheRampAndKnocksTheCubeOff) {
  const Scene scene = testing::loadSceneFromScenes("wheel_cube_ramp.json");
  const ObjectInfo& wheel = scene.model.objects.at(0);
  const ObjectInfo& cube = scene.model.objects.at(1);
  // Nothing moves at the start: only gravity sets them going.
  for (const Vec3& v : scene.initial.velocity) ASSERT_EQ(norm(v), 0.0);
  const BoxObstacle& ramp = scene.model.environment.boxes.at(0);
  // The ramp's top face and its lower edge (the top face's +x end).
  const Vec3 rampUp = ramp.axisZ, rampDown = ramp.axisX;
  const Vec3 lowerEdge = ramp.center + rampUp * ramp.halfExtents.z + rampDown * ramp.halfExtents.x;
  const ParticleIndex hub = wheel.firstParticle + wheel.particleCount - 2;
  const ParticleIndex rim = wheel.firstParticle;
  const Vec3 cube0 = centroid(scene.initial.position, cube);
  // The cube's own axis (its first edge, particle 0 → 1) at the start.
  const auto edge = [&](const std::vector<Vec3>& x) {
    const Vec3 e = x[cube.firstParticle + 1] - x[cube.firstParticle];
    return e / norm(e);
  };
  const Vec3 edge0 = edge(scene.initial.position);
  bool hit = false;
  double cubeMovedBeforeHit = 0.0, turned = 0.0;
  double previousAngle = 0.0;
  bool first = true;
  RunOptions options;
  options.settings = scene.run;
  options.tasks = {robotics::makeSceneTasks(scene), [&](World& world, std::vector<std::string>&) {
                     const State& s = world.state();
                     for (const Contact& c : world.contacts()) {
                       if (c.withEnvironment()) continue;
                       const bool aWheel = scene.model.objectOf[c.a] == 0;
                       const bool otherCube = scene.model.objectOf[c.other] == 1;
                       if (aWheel && otherCube) hit = true;
                     }
                     if (!hit)
                       cubeMovedBeforeHit =
                           std::max(cubeMovedBeforeHit, norm(centroid(s.position, cube) - cube0));
                     // The wheel's turn: a rim particle about the hub, in the x-z plane, unwrapped.
                     const Vec3 r = s.position[rim] - s.position[hub];
                     const double angle = std::atan2(r.z, r.x);
                     if (!first) turned += std::remainder(angle - previousAngle, 2.0 * M_PI);
                     previousAngle = angle;
                     first = false;
                     return true;
                   }};
  State last;
  const RunReport report = runScene(scene, options, &last);
  ASSERT_TRUE(report.ok()) << report.failure;
  const Vec3 wheelMove = centroid(last.position, wheel) - centroid(scene.initial.position, wheel);
  const Vec3 cube1 = centroid(last.position, cube);
  const double cubeTurn = std::acos(std::clamp(dot(edge(last.position), edge0), -1.0, 1.0));
  const double pastEdge = dot(cube1 - lowerEdge, rampDown);
  std::printf(
      "wheel and cube: wheel down %.3f m along x, turned %.2f rad; cube %.3f m past the ramp's "
      "edge at height %.3f m, turned %.1f°; cube moved %.2g m before the hit\n",
      wheelMove.x, turned, pastEdge, cube1.z, cubeTurn * 180.0 / M_PI, cubeMovedBeforeHit);
  // The wheel rolled down the ramp from rest (turning, not sliding: a rolled
  // distance is at least half the turn times the radius) ...
  EXPECT_GT(wheelMove.x, 0.3);
  EXPECT_LT(wheelMove.z, -0.1);
  EXPECT_GT(std::abs(turned) * 0.11, 0.5 * wheelMove.x / std::cos(0.2618));
  // ... and hit the cube, which had stood still on the ramp until then ...
  EXPECT_TRUE(hit);
  EXPECT_LT(cubeMovedBeforeHit, 5e-3);  // it may settle on the slope by a fraction of a mm
  // ... which then left the ramp (beyond its lower edge, on the ground) or toppled.
  const bool leftTheRamp = pastEdge > 0.0 && cube1.z < 0.07 + 0.02;
  const bool toppled = cubeTurn > M_PI / 4.0;
  EXPECT_TRUE(leftTheRamp || toppled)
      << "cube " << pastEdge << " m past the edge, at z = " << cube1.z << ", turned " << cubeTurn;
  EXPECT_LT(std::abs(report.energyDrift), 0.02);
}

}  // namespace
}  // namespace robophi
