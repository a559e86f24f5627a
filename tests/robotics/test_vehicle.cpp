// Paper experiment 3 (scenes/vehicle_hills.json): a vehicle pulled by a moving
// virtual copy of its chassis crosses hilly terrain and reaches its goal beyond
// it; it adapts to the ground (wheels on the ground, suspension working) and
// does not tip over.
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

TEST(Vehicle, CrossesTheHillsAndReachesItsGoalUpright) {
  const Scene scene = testing::loadSceneFromScenes("vehicle_hills.json");
  ASSERT_EQ(scene.model.joints.size(), 4u);  // four passive axles
  const ObjectInfo& vehicle = scene.model.objects[0];
  constexpr ParticleIndex kChassis = 12;  // the 3×2×2 chassis lattice comes first
  const Heightfield& ground = scene.model.environment.heightfields.at(0);

  double largestTilt = 0.0, highestChassis = -1e9, smallestClearance = 1e9;
  std::int64_t steps = 0, chassisContacts = 0, stepsWithFourWheelsDown = 0;
  RunOptions options;
  options.settings = scene.run;
  options.tasks = {robotics::makeSceneTasks(scene)};
  options.tasks.push_back([&](World& world, std::vector<std::string>&) {
    const State& s = world.state();
    ++steps;
    // Tilt: the chassis lattice's own vertical (particle 0 → 1) against z.
    const Vec3 up = s.position[1] - s.position[0];
    largestTilt = std::max(largestTilt, std::acos(std::clamp(up.z / norm(up), -1.0, 1.0)));
    Vec3 centroid;
    for (ParticleIndex i = 0; i < kChassis; ++i) {
      centroid += s.position[i] / static_cast<double>(kChassis);
      smallestClearance =
          std::min(smallestClearance, s.position[i].z - scene.model.radius[i] -
                                          ground.heightAt(s.position[i].x, s.position[i].y));
    }
    highestChassis = std::max(highestChassis, centroid.z);
    // Ground contacts by part: chassis particles, and each wheel's rim.
    bool wheelDown[4] = {false, false, false, false};
    for (const Contact& c : world.contacts()) {
      if (c.other >= 0) continue;
      if (c.a < kChassis) ++chassisContacts;
      // Each wheel: 2×12 rim particles, 2 hubs, then 5 mounts (31 particles); the
      // knuckles after the four wheels.
      const int wheel = (c.a - kChassis) / 31;
      if (c.a >= kChassis && wheel < 4) wheelDown[wheel] = true;
    }
    if (wheelDown[0] && wheelDown[1] && wheelDown[2] && wheelDown[3]) ++stepsWithFourWheelsDown;
    return true;
  });
  State last;
  const RunReport report = runScene(scene, options, &last);
  ASSERT_TRUE(report.ok()) << report.failure;
  ASSERT_EQ(vehicle.particleCount, 148);  // 12 + 4 × (26 + 5 mounts) + 4 × 3 knuckle

  bool reached = false;
  for (const std::string& e : report.events)
    if (e.find("goal 'goal' reached at") != std::string::npos) reached = true;
  EXPECT_TRUE(reached);
  // The chassis ends 4.2 m ahead, on the flat beyond the hills (x from 2.5 m).
  Vec3 centroid;
  for (ParticleIndex i = 0; i < kChassis; ++i)
    centroid += last.position[i] / static_cast<double>(kChassis);
  EXPECT_NEAR(centroid.x, 3.2, 0.05);
  EXPECT_NEAR(centroid.y, 0.0, 0.05);
  // It went over the hills: its chassis rose well above its height on the flat
  // (the hills are 6 to 8 cm high; the chassis spans both axles) ...
  EXPECT_GT(highestChassis - centroid.z, 0.03);
  // ... on its wheels: all four on the ground nearly all the time, the chassis
  // never touching it, and never tilted more than 20°.
  EXPECT_EQ(chassisContacts, 0);
  EXPECT_GT(smallestClearance, 0.0);
  EXPECT_GT(static_cast<double>(stepsWithFourWheelsDown) / static_cast<double>(steps), 0.9);
  EXPECT_LT(largestTilt, 20.0 * M_PI / 180.0);
  // The energy account holds with the moving virtual robot's work booked.
  EXPECT_GT(report.externalWork, 0.0);
  EXPECT_LT(std::abs(report.energyDrift), 0.1);
}

// Issue 37: the vehicle stands at rest on flat ground whatever its wheels' width
// (the shipped scenes use 0.06 m). It used to sway sideways on its wheels and sit
// down on its chassis at 0.05 m and below (lowest particle 0.085 → 0.036 m): the
// wheels' camber stiffness grew with the square of the hub span, which was half
// the tyre's width, and the chassis leaned on nothing stiffer (docs/robotics.md).
// Nudged sideways at 0.1 m/s at the start so that an unstable sway shows within
// the run (the old builder sat down within 2 s so, at every width up to 0.06 m);
// the chassis settles on its suspension in two seconds, then holds its height.
class VehicleAtRest : public ::testing::TestWithParam<double> {};

TEST_P(VehicleAtRest, HoldsItsChassisHeightWhateverTheWheelWidth) {
  const std::string text = R"({
    "run": {"duration": 4.0, "dt": 1e-4},
    "gravity": [0, 0, -9.81],
    "environment": {"ground": {}},
    "objects": [{"name": "vehicle", "type": "vehicle", "center": [0, 0, 0.12],
                 "size": [0.6, 0.3, 0.1], "mass": 8, "wheelRadius": 0.12, "wheelWidth": )" +
                           std::to_string(GetParam()) + R"(, "wheelMass": 0.5,
                 "rimParticles": 12, "suspensionStiffness": 3000, "axleDamping": 0.001,
                 "stiffness": 20000, "velocity": [0, 0.1, 0]}]})";
  SceneLoadResult loaded = loadSceneText(text, "vehicle_at_rest.json");
  for (const auto& e : loaded.errors) ADD_FAILURE() << e.format();
  ASSERT_TRUE(loaded.ok());
  const Scene& scene = *loaded.scene;
  constexpr ParticleIndex kChassis = 12;
  constexpr double kSettled = 2.0;  // s
  double settledHeight = -1.0, lowest = 1e9, highest = -1e9, lowestParticle = 1e9;
  RunOptions options;
  options.settings = scene.run;
  options.tasks.push_back([&](World& world, std::vector<std::string>&) {
    const State& s = world.state();
    double height = 0.0;
    for (ParticleIndex i = 0; i < kChassis; ++i) {
      height += s.position[i].z / static_cast<double>(kChassis);
      lowestParticle = std::min(lowestParticle, s.position[i].z);
    }
    if (s.time < kSettled) return true;
    if (settledHeight < 0.0) settledHeight = height;
    lowest = std::min(lowest, height);
    highest = std::max(highest, height);
    return true;
  });
  const RunReport report = runScene(scene, options);
  ASSERT_TRUE(report.ok()) << report.failure;
  ASSERT_GT(settledHeight, 0.0);
  std::printf("wheel width %.3f m: chassis at %.5f m after %.1f s, then within [%.5f, %.5f] m\n",
              GetParam(), settledHeight, kSettled, lowest, highest);
  // On its suspension (8 × 3000 N/m under about 13 kg: 5 mm) and its tyres, not
  // on its chassis: the chassis' bottom particles (built at 0.095 m, at 0.085 m
  // at rest) never come near the ground (collapsed: 0.01 to 0.04 m).
  EXPECT_GT(settledHeight, 0.10);
  EXPECT_GT(lowestParticle, 0.06);
  EXPECT_LT(highest - lowest, 0.002);
}

INSTANTIATE_TEST_SUITE_P(WheelWidths, VehicleAtRest,
                         ::testing::Values(0.03, 0.045, 0.06, 0.09, 0.12));

}  // namespace
}  // namespace robophi
