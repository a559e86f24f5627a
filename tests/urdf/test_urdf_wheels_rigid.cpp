// Round wheels on rigid robots (docs/contact.md "Round wheels"): a bare URDF is
// rigid bodies (docs/model.md §7), and a body turned by a revolute or continuous
// joint whose one <collision> is a cylinder coaxial with it meets the ground as
// that cylinder, not as the polygon of its surface particles. So a wheeled robot
// stands on its wheels' true radius and rolls R per radian of its wheels: the
// Husky as published, and a cart written here with other sizes and axes.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "robophi/joints.h"
#include "robophi/scene/scene.h"
#include "robophi/world.h"
#include "test_files.h"

namespace robophi {
namespace {

using testing::kRobots;  // ROBOPHI_ROBOTS_DIR (test_files.h)

// What a drive measured: the base's speed over the last part of the run, the
// wheels' mean rate over it, and the base's height range and heading change.
struct WheelDrive {
  int rims = 0;
  double speed = 0.0, wheelRate = 0.0;
  double lowest = 1e9, highest = -1e9;
  double lateral = 0.0;
};

// Loads `urdf` rigid on a free base, drives every continuous joint whose name holds
// "wheel" at `rate` (rad/s) by a velocity servo (`gain` N·m·s/rad, ±`limit` N·m), at
// a constant step of 2 ms for `seconds`, and measures from `settle` s on.
WheelDrive drive(const std::string& urdf, double rate, double gain, double limit, double seconds,
                 double settle) {
  UrdfSceneOptions options;
  options.fixedBase = false;
  SceneLoadResult loaded = loadUrdfFile(urdf, options);
  WheelDrive d;
  for (const Diagnostic& e : loaded.errors) ADD_FAILURE() << e.format();
  if (!loaded.ok()) return d;
  Scene& scene = *loaded.scene;
  d.rims = static_cast<int>(scene.model.rims.size());
  Multibody& mb = scene.model.rigidTrees.at(0).multibody;
  std::vector<std::size_t> wheels;
  for (std::size_t j = 0; j < scene.model.joints.size(); ++j) {
    Joint& joint = scene.model.joints[j];
    joint.servoStiffness = joint.servoDamping = 0.0;
    joint.compensateGravity = false;
    if (!joint.inTree() || joint.name.find("wheel") == std::string::npos) continue;
    joint.drive.rateGain = gain;
    joint.drive.targetRate = rate;
    mb.bodies[static_cast<std::size_t>(joint.treeBody)].effortLimit = limit;
    wheels.push_back(j);
  }
  EXPECT_GE(wheels.size(), 2u);
  World world(std::move(scene.model), std::move(scene.initial), Integrator::kSymplecticEuler);
  const auto base = [&] {
    const std::vector<double>& q = world.state().treePositions[0];
    return Vec3{q[0], q[1], q[2]};
  };
  const double dt = 2e-3;
  const Vec3 start = base();
  Vec3 from;
  double turned = 0.0, t0 = -1.0;
  for (int s = 0; s < static_cast<int>(std::lround(seconds / dt)); ++s) {
    if (world.step(dt) != StepStatus::kOk) {
      ADD_FAILURE() << "not finite at t = " << world.state().time;
      return d;
    }
    if (world.state().time < settle - 1e-9) continue;
    if (t0 < 0.0) {
      t0 = world.state().time;
      from = base();
      continue;
    }
    double mean = 0.0;
    for (std::size_t j : wheels) mean += jointRate(world.model(), world.state(), j);
    turned += mean / static_cast<double>(wheels.size()) * dt;
    d.lowest = std::min(d.lowest, base().z);
    d.highest = std::max(d.highest, base().z);
  }
  const double span = world.state().time - t0;
  const Vec3 to = base();
  d.speed = norm(Vec3{to.x - from.x, to.y - from.y, 0.0}) / span;
  d.wheelRate = turned / span;
  d.lateral = std::abs(to.y - start.y);
  return d;
}

TEST(RigidWheels, TheHuskyRollsOnItsWheelsTrueRadius) {
  const std::string husky = kRobots + "/husky/husky.urdf";
  if (!std::filesystem::exists(husky)) GTEST_SKIP() << "no " << husky << " (ROBOPHI_ROBOTS_DIR)";
  constexpr double kRadius = 0.17775;  // husky.urdf's wheel <cylinder radius>
  const WheelDrive d = drive(husky, 4.0, 100.0, 15.0, 3.5, 1.5);  // bench/multibody_husky.cpp's
  EXPECT_EQ(d.rims, 4);
  // R per radian of the wheels' own mean rate: within 0.1 % (0.6 % short on its
  // particles' polygon).
  EXPECT_NEAR(d.speed / (d.wheelRate * kRadius), 1.0, 1e-3)
      << "speed " << d.speed << " m/s, wheels " << d.wheelRate << " rad/s";
  EXPECT_NEAR(d.wheelRate / 4.0, 1.0, 5e-3);
  EXPECT_LT(d.highest - d.lowest, 2e-4);  // rolls smoothly: no polygon bumps
  EXPECT_LT(d.lateral, 0.01);
}

// A cart the importer was not tuned to: 6 cm wheels 3 cm wide whose cylinders are
// turned onto the joint's y axis by their <origin rpy>, a 4 kg chassis.
TEST(RigidWheels, ACartWithOtherWheelsRollsOnTheirRadiusToo) {
  const std::string path = ::testing::TempDir() + "/robophi_rigid_cart.urdf";
  {
    std::ofstream out(path);
    out << R"(<robot name="cart">
  <link name="chassis">
    <inertial><mass value="4"/><inertia ixx="0.02" iyy="0.04" izz="0.05" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><box size="0.4 0.24 0.06"/></geometry></collision>
  </link>)";
    const char* names[] = {"front_left", "front_right", "rear_left", "rear_right"};
    const double xs[] = {0.15, 0.15, -0.15, -0.15}, ys[] = {0.15, -0.15, 0.15, -0.15};
    for (int k = 0; k < 4; ++k) {
      out << "\n  <link name=\"" << names[k] << "_wheel_link\">"
          << "<inertial><mass value=\"0.3\"/><inertia ixx=\"3e-4\" iyy=\"5.4e-4\" izz=\"3e-4\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial>"
          << "<collision><origin rpy=\"1.5707963267948966 0 0\"/><geometry><cylinder radius=\"0.06\" length=\"0.03\"/></geometry></collision></link>"
          << "\n  <joint name=\"" << names[k] << "_wheel\" type=\"continuous\"><parent link=\"chassis\"/><child link=\""
          << names[k] << "_wheel_link\"/><origin xyz=\"" << xs[k] << " " << ys[k] << " -0.02\"/><axis xyz=\"0 1 0\"/></joint>";
    }
    out << "\n</robot>\n";
  }
  const WheelDrive d = drive(path, 6.0, 0.5, 0.5, 2.5, 1.0);  // (±0.5 N·m: no wheelie)
  EXPECT_EQ(d.rims, 4);
  EXPECT_NEAR(d.speed / (d.wheelRate * 0.06), 1.0, 1e-3)
      << "speed " << d.speed << " m/s, wheels " << d.wheelRate << " rad/s";
  EXPECT_LT(d.highest - d.lowest, 2e-4);
  EXPECT_LT(d.lateral, 0.01);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace robophi
