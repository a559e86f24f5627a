// Wheel motors (MODEL §1.6) on the built-in vehicle: it drives by traction alone
// (no tow spring, no virtual copy). On flat ground at wheel rate ω it covers
// ω R t within 2 % and keeps its heading; it climbs a 10° slope, its motors
// carrying the weight's pull m g sin α.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "robophi/joints.h"
#include "robophi/scene/scene.h"
#include "robophi/world.h"
#include "robotics/tasks.h"

namespace robophi {
namespace {

constexpr double kWheelRadius = 0.12;  // m

std::string vehicleScene(double slopeDegrees, double wheelSpeed) {
  const double a = slopeDegrees * M_PI / 180.0;
  // A slope as tilted gravity: "uphill" is +x.
  const std::string gravity = "[" + std::to_string(-9.81 * std::sin(a)) + ", 0, " +
                              std::to_string(-9.81 * std::cos(a)) + "]";
  // Wheels and ground of a hard material (κ_c = 1e5 N/m each, 5e4 N/m in series):
  // a wheel sinks 0.5 mm under its 25 N, so that it rolls on nearly its radius R.
  return R"({"robophi": 1, "gravity": )" + gravity + R"(,
    "materials": [{"name": "hard", "contactStiffness": 1e5, "contactDamping": 50}],
    "environment": {"ground": {"material": "hard"}},
    "objects": [{"name": "vehicle", "type": "vehicle", "center": [0, 0, 0.12], "material": "hard",
                 "size": [0.6, 0.3, 0.1], "mass": 8, "wheelRadius": 0.12, "wheelWidth": 0.06,
                 "wheelMass": 0.5, "rimParticles": 12, "suspensionStiffness": 3000,
                 "stiffness": 20000, "wheelSpeed": )" +
         std::to_string(wheelSpeed) + R"(, "wheelGain": 5, "wheelTorqueLimit": 1.5}]})";
}

struct TractionDrive {
  Scene scene;
  std::optional<World> world;
  explicit TractionDrive(const std::string& text) {
    SceneLoadResult r = loadSceneText(text, "vehicle.json");
    for (const auto& e : r.errors) ADD_FAILURE() << e.format();
    if (!r.ok()) return;
    scene = std::move(*r.scene);
    world.emplace(scene.model, scene.initial, Integrator::kVelocityVerlet);
  }
  // The chassis' centre (its first 12 particles).
  Vec3 chassis() const {
    Vec3 c{};
    for (int i = 0; i < 12; ++i) c += world->state().position[i];
    return c * (1.0 / 12.0);
  }
  // Heading: the chassis' long axis (particle 0 → particle 8 runs along x) in the ground plane.
  double heading() const {
    const Vec3 d = world->state().position[8] - world->state().position[0];
    return std::atan2(d.y, d.x);
  }
  void run(double seconds) {
    const int steps = static_cast<int>(std::lround(seconds / 1e-4));
    for (int s = 0; s < steps; ++s) world->step(1e-4);
  }
  // A leg: 1 s to settle on the suspension and spin up, then `seconds` measured:
  // the chassis' displacement (m), the time (s) and the heading's change (rad).
  struct Leg {
    Vec3 moved;
    double time = 0.0, turned = 0.0;
  };
  Leg leg(double seconds) {
    run(1.0);
    const Vec3 from = chassis();
    const double heading0 = heading(), t0 = world->state().time;
    run(seconds);
    return {chassis() - from, world->state().time - t0, heading() - heading0};
  }
};

TEST(VehicleTraction, DrivesOmegaRTimesTOnFlatGroundByTractionAlone) {
  const double omega = 2.0;  // rad/s: 0.24 m/s
  TractionDrive drive(vehicleScene(0.0, omega));
  ASSERT_TRUE(drive.world);
  for (const Joint& j : drive.world->model().joints) EXPECT_GT(j.drive.rateGain, 0.0);
  const TractionDrive::Leg leg = drive.leg(4.0);
  const double expected = omega * kWheelRadius * leg.time;
  EXPECT_NEAR(leg.moved.x, expected, 0.02 * expected)
      << "moved " << leg.moved.x << " m in " << leg.time << " s; ω R t = " << expected << " m";
  EXPECT_LT(std::abs(leg.moved.y), 0.01);
  EXPECT_LT(std::abs(leg.turned) * 180.0 / M_PI, 2.0) << leg.turned * 180.0 / M_PI << "°";
  // Every wheel turns at the commanded rate (left +ω, right −ω: axes point outward).
  for (std::size_t j = 0; j < 4; ++j) {
    const double sign = (j % 2 == 0) ? 1.0 : -1.0;
    EXPECT_NEAR(sign * jointRate(drive.world->model(), drive.world->state(), j), omega, 0.02)
        << drive.world->model().joints[j].name;
  }
}

TEST(VehicleTraction, ClimbsATenDegreeSlopeOnItsMotors) {
  const double omega = 2.0;
  TractionDrive drive(vehicleScene(10.0, omega));
  ASSERT_TRUE(drive.world);
  const TractionDrive::Leg leg = drive.leg(3.0);
  const double expected = omega * kWheelRadius * leg.time;
  // Uphill (+x) near ω R: the rate drive's error τ / k_v = 0.68 / 5 rad/s is 7 %.
  EXPECT_GT(leg.moved.x, 0.88 * expected) << "moved " << leg.moved.x << " m; ω R t = " << expected;
  EXPECT_LT(leg.moved.x, 1.02 * expected);
  // The motors carry the weight's pull down the slope: Σ τ ≈ m g sin α R.
  double mass = 0.0;
  for (double m : drive.world->model().mass) mass += m;
  double torque = 0.0;
  const auto& effort = drive.world->evaluation().jointMotorEffort;
  for (std::size_t j = 0; j < 4; ++j) torque += (j % 2 == 0 ? 1.0 : -1.0) * effort[j];
  const double pull = mass * 9.81 * std::sin(10.0 * M_PI / 180.0) * kWheelRadius;
  EXPECT_NEAR(torque, pull, 0.15 * pull) << "Σ τ = " << torque << " N·m, m g sin α R = " << pull;
}

TEST(VehicleTraction, AnArmMountedOnTheVehicleRidesWithIt) {
  // A one-link arm whose base stands 10 cm above the chassis, mounted on it
  // (control.mounts), held straight by its servo while the vehicle drives 2 s.
  const std::string text = R"({"robophi": 1, "environment": {"ground": true},
    "objects": [{"name": "vehicle", "type": "vehicle", "center": [0, 0, 0.12],
                 "size": [0.6, 0.3, 0.1], "mass": 8, "wheelRadius": 0.12, "wheelWidth": 0.06,
                 "wheelMass": 0.5, "suspensionStiffness": 3000, "stiffness": 20000,
                 "wheelSpeed": 2, "wheelGain": 5, "wheelTorqueLimit": 1.5},
                {"name": "arm", "type": "arm", "base": [0, 0, 0.27], "direction": [0, 0, 1],
                 "links": [0.3], "axes": [[0, 1, 0]], "mass": 0.3, "stiffness": 20000}],
    "control": {"mounts": [{"object": "arm", "on": "vehicle", "stiffness": 20000}],
                "joints": {"arm.j1": {"mode": "position", "kp": 20, "kd": 0.5, "target": 0}}}})";
  TractionDrive drive(text);
  ASSERT_TRUE(drive.world);
  const Model& model = drive.world->model();
  const ObjectInfo& arm = model.objects[1];
  for (ParticleIndex i = arm.firstParticle; i < arm.firstParticle + arm.particleCount; ++i)
    EXPECT_FALSE(model.isFixed(i)) << "the mount frees the arm's base";
  robotics::SceneTaskHook hook = robotics::makeSceneTaskHook(drive.scene);
  std::vector<std::string> events;
  hook.task->start(*drive.world, events);
  // The arm's particle nearest its first joint's centre: a base particle.
  ParticleIndex base = arm.firstParticle;
  for (ParticleIndex i = arm.firstParticle; i < arm.firstParticle + arm.particleCount; ++i)
    if (norm(drive.world->state().position[i] - Vec3{0, 0, 0.27}) <
        norm(drive.world->state().position[base] - Vec3{0, 0, 0.27}))
      base = i;
  const Vec3 base0 = drive.world->state().position[base];
  const Vec3 chassis0 = drive.chassis();
  for (int s = 0; s < 20000; ++s) {
    drive.world->step(1e-4);
    hook.task(*drive.world, events);
  }
  const Vec3 moved = drive.world->state().position[base] - base0;
  const Vec3 carried = drive.chassis() - chassis0;
  EXPECT_GT(carried.x, 0.3);  // it drove (ω R t ≈ 0.48 m less the spin-up)
  // The base rides with the chassis (measured: 0.430 m against its centre's 0.455 m;
  // the base stands 15 cm above that centre, on a chassis that pitches as it drives).
  EXPECT_LT(norm(moved - carried), 0.04)
      << "the base moved " << moved.x << " m, the chassis " << carried.x << " m";
  // The arm still stands: its tool above its base (0.3 m upright; measured 0.244 m).
  const Vec3 tool = drive.world->state().position[arm.firstParticle + arm.particleCount - 1];
  EXPECT_GT(tool.z - drive.world->state().position[base].z, 0.2);
}

}  // namespace
}  // namespace robophi
