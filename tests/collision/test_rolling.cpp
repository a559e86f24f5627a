// The paper's experiment 2 (MODEL §6): a wheel rolls while a cube of the same
// mass, launched alike, tumbles or slides and comes to rest. Both move on a 3°
// slope (gravity tilted) with friction μ_s = 0.8, μ_k = 0.6.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "collision/contact_test_util.h"
#include "robophi/scene/scene.h"
#include "robotics/tasks.h"
#include "run/runner.h"

namespace robophi {
namespace {

constexpr double kMass = 0.5;             // kg, each body
constexpr double kSpringStiffness = 2e4;  // N/m
constexpr double kSpeed = 1.0;            // m/s, launch

// Wheel in the x-z plane: a hub and 32 rim particles on radius R, rim and spokes LS.
std::pair<int, int> addWheel(Model& model, State& state, const Vec3& hub, double rimRadius,
                             double particleRadius) {
  constexpr int kRim = 32;
  const std::int32_t object = model.addObject("wheel", "wheel");
  const double m = kMass / (kRim + 1);
  const int first = model.particleCount();
  const double rollingRadius = rimRadius + particleRadius;
  const Vec3 spin{0.0, kSpeed / rollingRadius, 0.0};  // rolls towards +x
  model.addParticle(m, particleRadius, false, object);
  state.position.push_back(hub);
  state.velocity.push_back({kSpeed, 0.0, 0.0});
  for (int k = 0; k < kRim; ++k) {
    const double a = 2.0 * M_PI * k / kRim;
    const Vec3 offset{rimRadius * std::cos(a), 0.0, rimRadius * std::sin(a)};
    model.addParticle(m, particleRadius, false, object);
    state.position.push_back(hub + offset);
    state.velocity.push_back(Vec3{kSpeed, 0.0, 0.0} + cross(spin, offset));
  }
  const double damping = 0.05 * std::sqrt(kSpringStiffness * m);
  for (int k = 0; k < kRim; ++k) {
    const int rim = first + 1 + k, next = first + 1 + (k + 1) % kRim;
    model.linearSprings.push_back(
        {rim, next, norm(state.position[rim] - state.position[next]), kSpringStiffness, damping});
    model.linearSprings.push_back({first, rim, rimRadius, kSpringStiffness, damping});
  }
  return {first, model.particleCount()};
}

// Cube: 2 × 2 × 2 particles, every pair tied by an LS; launched like the wheel
// (moving at kSpeed and spinning as if it rolled), so that it tumbles over.
std::pair<int, int> addCube(Model& model, State& state, const Vec3& center, double side) {
  const std::int32_t object = model.addObject("cube", "box");
  const double m = kMass / 8.0;
  const int first = model.particleCount();
  for (int k = 0; k < 8; ++k) {
    model.addParticle(m, side / 4.0, false, object);
    state.position.push_back(center + Vec3{(k & 1) - 0.5, ((k >> 1) & 1) - 0.5, (k >> 2) - 0.5} *
                                          (side / 2.0));
    const Vec3 spin{0.0, kSpeed / side, 0.0};
    state.velocity.push_back(Vec3{kSpeed, 0.0, 0.0} + cross(spin, state.position.back() - center));
  }
  const double damping = 0.05 * std::sqrt(kSpringStiffness * m);
  for (int a = first; a < first + 8; ++a) {
    for (int b = a + 1; b < first + 8; ++b) {
      model.linearSprings.push_back(
          {a, b, norm(state.position[a] - state.position[b]), kSpringStiffness, damping});
    }
  }
  return {first, model.particleCount()};
}

Vec3 centroid(const State& state, std::pair<int, int> range) {
  Vec3 c;
  for (int i = range.first; i < range.second; ++i) c += state.position[i];
  return c / (range.second - range.first);
}

double speed(const State& state, std::pair<int, int> range) {
  Vec3 v;
  for (int i = range.first; i < range.second; ++i) v += state.velocity[i];
  return norm(v / (range.second - range.first));
}

TEST(Rolling, WheelRollsFarWhileTheCubeComesToRest) {
  Model model;
  State state;
  constexpr double kSlope = 3.0 * M_PI / 180.0;
  model.gravity = Vec3{std::sin(kSlope), 0.0, -std::cos(kSlope)} * 9.81;
  model.materials[0].contactStiffness = 1e5;  // pair with the ground: 5e4 N/m
  model.materials[0].contactDamping = 30.0;
  model.materials[0].staticFriction = 0.8;
  model.materials[0].kineticFriction = 0.6;
  model.environment.planes.push_back(GroundPlane{});
  const double rimRadius = 0.1, particleRadius = 0.01;
  const auto wheel =
      addWheel(model, state, {0.0, 0.0, rimRadius + particleRadius}, rimRadius, particleRadius);
  const auto cube = addCube(model, state, {0.0, 0.5, 0.05}, 0.1);
  ASSERT_EQ(checkModel(model), "");
  World world(model, state);
  const Vec3 wheel0 = centroid(world.state(), wheel), cube0 = centroid(world.state(), cube);
  // 3 s: the cube's last tumble ends at about 2.2 s (it holds from then on,
  // speed < 1e-12 m/s by 4.6 s, without creep).
  for (int step = 0; step < 60'000; ++step) {
    ASSERT_EQ(world.step(5e-5), StepStatus::kOk);
  }
  const double wheelDistance = centroid(world.state(), wheel).x - wheel0.x;
  const double cubeDistance = centroid(world.state(), cube).x - cube0.x;
  // The direction of the cube's edge from particle 0 to 1 (along +x at the start).
  const double cubeTurn =
      std::atan2(world.state().position[cube.first + 1].z - world.state().position[cube.first].z,
                 world.state().position[cube.first + 1].x - world.state().position[cube.first].x);
  std::printf("cube edge angle %.1f°\n", cubeTurn * 180.0 / M_PI);
  std::printf("after 3 s: wheel %.3f m (speed %.3f m/s), cube %.3f m (speed %.2e m/s)\n",
              wheelDistance, speed(world.state(), wheel), cubeDistance, speed(world.state(), cube));
  EXPECT_GT(std::abs(cubeTurn), M_PI / 4.0);  // it toppled over (an edge along x is now vertical)
  EXPECT_GT(wheelDistance, 1.5);
  EXPECT_GT(cubeDistance, 0.0);
  EXPECT_LT(cubeDistance, 0.3);
  EXPECT_LT(speed(world.state(), cube), 1e-2);
  EXPECT_GT(wheelDistance, 5.0 * cubeDistance);
}

// The same experiment from its scene file (scenes/wheel_cube.json, generated
// wheel and cube, adaptive step) as `robophi run` plays it.
TEST(Rolling, WheelCubeSceneFile) {
  SceneLoadResult loaded =
      loadSceneFile(std::string(ROBOPHI_SOURCE_DIR) + "/scenes/wheel_cube.json");
  for (const auto& e : loaded.errors) ADD_FAILURE() << e.format();
  ASSERT_TRUE(loaded.ok());
  const Scene& scene = *loaded.scene;
  const ObjectInfo& w = scene.model.objects[0];
  const ObjectInfo& c = scene.model.objects[1];
  const std::pair<int, int> wheel{w.firstParticle, w.firstParticle + w.particleCount};
  const std::pair<int, int> cube{c.firstParticle, c.firstParticle + c.particleCount};
  RunOptions options;
  options.settings = scene.run;
  options.tasks = {robotics::makeSceneTasks(scene)};
  State last;
  const RunReport report = runScene(scene, options, &last);
  ASSERT_TRUE(report.ok()) << report.failure;
  const double wheelDistance = centroid(last, wheel).x - centroid(scene.initial, wheel).x;
  const double cubeDistance = centroid(last, cube).x - centroid(scene.initial, cube).x;
  std::printf("scene, after 2 s: wheel %.3f m (speed %.3f m/s), cube %.3f m (speed %.2e m/s)\n",
              wheelDistance, speed(last, wheel), cubeDistance, speed(last, cube));
  // The wheel rolls on and speeds up down the slope (1 m/s at the start); the
  // cube stops within a few of its sizes.
  EXPECT_GT(wheelDistance, 1.5);
  EXPECT_GT(speed(last, wheel), 1.0);
  EXPECT_GT(cubeDistance, 0.0);
  EXPECT_LT(cubeDistance, 0.3);
  EXPECT_LT(speed(last, cube), 1e-2);
  EXPECT_LT(std::abs(report.energyDrift), 0.02);
}

}  // namespace
}  // namespace robophi
