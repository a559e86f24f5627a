// Sensors (robophi/sensors.h) against what statics and free fall say they must read:
// a joint's force/torque on a held arm is the weight below it, a contact sensor
// under a resting box reads m g at the box's centre, an IMU reads 0 in free fall and
// g at rest, a range finder over a heightfield its height. Each on a second case that
// was not tuned (another robot, mass, size, place). And sensors are observers: a run
// with them ends in the same state hash as one without, and writes sensors.csv.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "robophi/kinematics.h"
#include "robophi/scene/scene.h"
#include "robophi/sensors.h"
#include "run/runner.h"
#include "test_files.h"

namespace robophi {
namespace {

namespace fs = std::filesystem;

std::string robotsDir() {
  const char* env = std::getenv("ROBOPHI_ROBOTS_DIR");
  return env != nullptr ? env : ROBOPHI_ROBOTS_DIR;
}

Scene loadOk(const std::string& text) {
  SceneLoadResult result = loadSceneText(text, "sensors.json");
  for (const auto& e : result.errors) ADD_FAILURE() << e.format();
  if (!result.ok()) throw std::runtime_error("scene did not load");
  return std::move(*result.scene);
}

// A world of the scene and its sensors.
struct Sensed {
  explicit Sensed(const Scene& scene) : world(scene.model, scene.initial, scene.run.integrator) {
    for (const SensorSpec& spec : scene.sensors) sensors.add(scene.model, scene.initial, spec);
  }
  std::vector<double> read(const std::string& name) {
    std::vector<double> all(sensors.valueCount());
    sensors.read(world, all.data());
    const auto k = static_cast<std::size_t>(sensors.find(name));
    EXPECT_GE(sensors.find(name), 0) << name;
    const auto first = all.begin() + static_cast<std::ptrdiff_t>(sensors.offset(k));
    return {first, first + static_cast<std::ptrdiff_t>(SensorSet::valueCountOf(sensors.spec(k).kind))};
  }
  void run(double duration, double dt) {
    const auto steps = static_cast<int>(std::lround(duration / dt));
    for (int k = 0; k < steps; ++k) ASSERT_EQ(world.step(dt), StepStatus::kOk);
  }
  World world;
  SensorSet sensors;
};

// The mass of a rigid tree's joint's body and every body below it, and their centre of mass.
void subtree(const Model& model, const std::string& jointName, double& mass, Vec3& center,
             const State& state) {
  const auto joint = std::find_if(model.joints.begin(), model.joints.end(),
                                  [&](const Joint& j) { return j.name == jointName; });
  ASSERT_NE(joint, model.joints.end());
  const Multibody& mb = model.rigidTrees[static_cast<std::size_t>(joint->tree)].multibody;
  MultibodyKinematics kin;
  updateKinematics(mb, state.treePositions[static_cast<std::size_t>(joint->tree)].data(), kin);
  std::vector<char> below(mb.bodies.size(), 0);
  mass = 0.0;
  Vec3 moment;
  for (std::size_t b = 0; b < mb.bodies.size(); ++b) {
    below[b] = static_cast<char>(static_cast<std::int32_t>(b) == joint->treeBody ||
                                 (mb.bodies[b].parent >= 0 && below[static_cast<std::size_t>(mb.bodies[b].parent)]));
    if (!below[b]) continue;
    mass += kin.mass[b];
    moment += kin.firstMoment[b];
  }
  center = moment / mass;
}

std::string armScene(const std::string& file, const std::string& packages, const std::string& sensors) {
  return R"({"gravity": [0, 0, -9.81], "environment": {"ground": true}, "objects": [
    {"name": "arm", "type": "urdf", "file": ")" + file + R"(", "packagePaths": [")" + packages +
         R"("], "fixedBase": true, "rigid": true, "holdJoints": true, "position": [0, 0, 0.01],
     "initialPositions": )" + (file.find("panda") != std::string::npos
                                   ? R"({"panda_joint2": 0.5, "panda_joint4": -1.5, "panda_joint6": 1.2})"
                                   : R"({"lbr_iiwa_joint_2": 0.6, "lbr_iiwa_joint_4": -1.1})") + R"(}],
    "sensors": )" + sensors + "}";
}

// The F/T sensor at `joint` on a held arm reads the weight below it: force m g up, and
// torque (c − p) × m g about the joint's origin p, within 0.5 %.
void expectWeightBelow(const std::string& robot, const std::string& packages,
                       const std::string& joint) {
  const std::string file = robotsDir() + "/" + robot;
  if (!fs::exists(file)) GTEST_SKIP() << "no " << file << " (set ROBOPHI_ROBOTS_DIR)";
  const Scene scene = loadOk(armScene(
      file, robotsDir() + "/" + packages,
      R"([{"name": "ft", "type": "force_torque", "on": "arm.)" + joint + R"("}])"));
  Sensed s(scene);
  s.run(0.5, 1e-3);
  const std::vector<double> ft = s.read("ft");
  double mass = 0.0;
  Vec3 center;
  subtree(s.world.model(), "arm." + joint, mass, center, s.world.state());
  // The sensor's frame: the joint's child body.
  const Joint& j = *std::find_if(s.world.model().joints.begin(), s.world.model().joints.end(),
                                 [&](const Joint& x) { return x.name == "arm." + joint; });
  const Multibody& mb = s.world.model().rigidTrees[static_cast<std::size_t>(j.tree)].multibody;
  MultibodyKinematics kin;
  updateKinematics(mb, s.world.state().treePositions[static_cast<std::size_t>(j.tree)].data(), kin);
  const Pose& X_WB = kin.X_WB[static_cast<std::size_t>(j.treeBody)];
  const Vec3 weight = s.world.model().gravity * -mass;  // what holds it: m g upwards
  const Vec3 force = X_WB.rotation * Vec3{ft[0], ft[1], ft[2]};
  const Vec3 torque = X_WB.rotation * Vec3{ft[3], ft[4], ft[5]};
  const Vec3 expectedTorque = cross(center - X_WB.translation, weight);
  const double relForce = norm(force - weight) / norm(weight);
  const double relTorque = norm(torque - expectedTorque) / norm(expectedTorque);
  std::printf("  %s %s: m below %.4f kg, |f| %.6f N (m g %.6f N), force error %.2e, torque error %.2e\n",
              robot.c_str(), joint.c_str(), mass, norm(force), norm(weight), relForce, relTorque);
  EXPECT_LT(relForce, 0.005);
  EXPECT_LT(relTorque, 0.005);
}

TEST(Sensors, JointForceTorqueOnAHeldIiwaReadsTheWeightBelow) {
  expectWeightBelow("kuka_iiwa/model.urdf", "kuka_iiwa", "lbr_iiwa_joint_2");
  expectWeightBelow("kuka_iiwa/model.urdf", "kuka_iiwa", "lbr_iiwa_joint_4");
}

TEST(Sensors, JointForceTorqueOnAHeldPandaReadsTheWeightBelow) {  // not tuned on
  expectWeightBelow("franka_panda/panda.urdf", "franka_panda", "panda_joint3");
}

// A box of `mass` kg and side `side` m resting at (x, y) on a plate (a fixed-base rigid
// URDF's one link) on the ground: the plate's contact sensor reads −m g at the box's
// centre; the box's own reads +m g there.
void expectRestingBox(double mass, double side, double x, double y) {
  const fs::path dir = testing::makeTempFolder("robophi_sensors_");
  testing::writeText(dir / "plate.urdf", R"(<robot name="plate">
  <link name="top"><inertial><mass value="5"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><origin xyz="0 0 0.05"/><geometry><box size="0.6 0.6 0.1"/></geometry></collision></link>
</robot>)");
  const double z = 0.1 + 0.5 * side + 0.002;
  const std::string text = R"({"gravity": [0, 0, -9.81], "objects": [
    {"name": "plate", "type": "urdf", "file": ")" + (dir / "plate.urdf").string() +
                           R"(", "fixedBase": true, "rigid": true},
    {"name": "box", "type": "box", "center": [)" + std::to_string(x) + ", " + std::to_string(y) +
                           ", " + std::to_string(z) + R"(], "size": [)" + std::to_string(side) + ", " +
                           std::to_string(side) + ", " + std::to_string(side) +
                           R"(], "cells": [3, 3, 3], "mass": )" + std::to_string(mass) +
                           R"(, "rigid": true}],
    "sensors": [{"name": "under", "type": "contact", "on": "plate.top"},
                {"name": "box", "type": "contact", "on": "box"}]})";
  const Scene scene = loadOk(text);
  Sensed s(scene);
  s.run(1.5, 2e-4);
  const std::vector<double> under = s.read("under"), box = s.read("box");
  const double mg = 9.81 * mass;
  // The plate's frame is the world's (a fixed base at the origin): the box's centre projection.
  const double comX = s.world.state().treePositions[1][0], comY = s.world.state().treePositions[1][1];
  std::printf("  box %.3f kg, side %.3f m at (%.3f, %.3f): plate reads fz %.6f N (m g %.6f), "
              "centre of pressure off by (%.2e, %.2e) m, Σ|F_n| %.4f N; the box reads fz %.6f, CoP (%.2e, %.2e) m\n",
              mass, side, x, y, under[2], mg, under[3] - comX, under[4] - comY, under[6], box[2], box[3], box[4]);
  EXPECT_NEAR(under[2], -mg, 0.005 * mg);
  EXPECT_GE(under[6], mg * (1 - 1e-3));  // Σ|F_n| >= m g: normals between lattices lean
  EXPECT_NEAR(under[3], comX, 1e-3);
  EXPECT_NEAR(under[4], comY, 1e-3);
  EXPECT_NEAR(under[5], 0.1, 5e-3);  // near the plate's top face (the lattices' contact points)
  // The box's own frame: its body's, at its centre (the centre projection is x = y = 0).
  EXPECT_NEAR(box[2], mg, 0.005 * mg);
  EXPECT_NEAR(box[3], 0.0, 1e-3);
  EXPECT_NEAR(box[4], 0.0, 1e-3);
  EXPECT_NEAR(box[5], -0.5 * side, 5e-3);
  fs::remove_all(dir);
}

TEST(Sensors, ContactSensorUnderARestingBoxReadsItsWeightAtItsCentre) {
  expectRestingBox(0.5, 0.1, 0.0, 0.0);
}

TEST(Sensors, ContactSensorUnderAnotherBoxOffCentre) {  // not tuned on
  expectRestingBox(1.7, 0.16, 0.12, -0.07);
}

TEST(Sensors, ImuReadsZeroInFreeFallAndGAtRest) {
  const Scene scene = loadOk(R"({"gravity": [0, 0, -9.81], "environment": {"ground": true},
    "objects": [
      {"name": "falling", "type": "box", "center": [0, 0, 50], "size": [0.1, 0.2, 0.1],
       "cells": [2, 3, 2], "mass": 0.5, "rigid": true, "velocity": [0.3, 0, 1]},
      {"name": "lattice", "type": "box", "center": [2, 0, 50], "size": [0.1, 0.1, 0.1],
       "cells": [2, 2, 2], "mass": 0.3},
      {"name": "resting", "type": "box", "center": [-1, 0, 0.052], "size": [0.1, 0.1, 0.1],
       "cells": [3, 3, 3], "mass": 0.8, "rigid": true}],
    "sensors": [{"name": "fall", "type": "imu", "on": "falling", "position": [0.02, 0.05, 0]},
                {"name": "fall2", "type": "imu", "on": "lattice"},
                {"name": "rest", "type": "imu", "on": "resting", "rpy": [0.3, 0, 0]}]})");
  Sensed s(scene);
  s.run(1.0, 2e-4);
  const std::vector<double> fall = s.read("fall"), fall2 = s.read("fall2"), rest = s.read("rest");
  const double g = 9.81;
  std::printf("  free fall: rigid |a| %.3e m/s², lattice |a| %.3e m/s²; at rest |a| %.9f m/s² (g %.2f)\n",
              std::hypot(fall[0], fall[1], fall[2]), std::hypot(fall2[0], fall2[1], fall2[2]),
              std::hypot(rest[0], rest[1], rest[2]), g);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(fall[k], 0.0, 1e-6);
    EXPECT_NEAR(fall2[k], 0.0, 1e-6);
  }
  // At rest the accelerometer reads g upwards, in a frame turned 0.3 rad about x.
  EXPECT_NEAR(std::hypot(rest[0], rest[1], rest[2]), g, 1e-3 * g);
  EXPECT_NEAR(rest[0], 0.0, 1e-3 * g);
  EXPECT_NEAR(rest[1], g * std::sin(0.3), 1e-3 * g);
  EXPECT_NEAR(rest[2], g * std::cos(0.3), 1e-3 * g);
  // Its orientation: the 0.3 rad turn about x (the body has not turned).
  EXPECT_NEAR(rest[6], std::cos(0.15), 1e-4);
  EXPECT_NEAR(rest[7], std::sin(0.15), 1e-4);
}

TEST(Sensors, ImuOnAHeldIiwaLinkReadsG) {
  const std::string file = robotsDir() + "/kuka_iiwa/model.urdf";
  if (!fs::exists(file)) GTEST_SKIP() << "no " << file << " (set ROBOPHI_ROBOTS_DIR)";
  const Scene scene = loadOk(armScene(file, robotsDir() + "/kuka_iiwa",
                                      R"([{"name": "imu", "type": "imu", "on": "lbr_iiwa_link_7"}])"));
  Sensed s(scene);
  s.run(0.5, 1e-3);
  const std::vector<double> imu = s.read("imu");
  std::printf("  iiwa link 7 held: |a| %.9f m/s², |ω| %.2e rad/s\n", std::hypot(imu[0], imu[1], imu[2]),
              std::hypot(imu[3], imu[4], imu[5]));
  EXPECT_NEAR(std::hypot(imu[0], imu[1], imu[2]), 9.81, 1e-3 * 9.81);
  EXPECT_LT(std::hypot(imu[3], imu[4], imu[5]), 1e-3);
}

// A range finder pointing down from (x, y, 2) over a heightfield reads 2 − h(x, y); one
// tilted reads the distance to where its ray meets the surface.
TEST(Sensors, RangeFinderOverAHeightfieldReadsItsHeight) {
  const Scene scene = loadOk(R"({"gravity": [0, 0, -9.81], "objects": [
      {"name": "probe", "type": "particles", "particles": [
        {"position": [0.7, 0.9, 2.0], "mass": 0.1, "radius": 0.02, "fixed": true}]},
      {"name": "probe2", "type": "particles", "particles": [
        {"position": [1.3, 1.2, 1.5], "mass": 0.1, "radius": 0.02, "fixed": true}]}],
    "environment": {"heightfield": {"origin": [0, 0], "cellSize": 0.5, "heights": [
      [0.0, 0.1, 0.3, 0.2, 0.0], [0.2, 0.5, 0.4, 0.1, 0.0], [0.1, 0.6, 0.9, 0.3, 0.2],
      [0.0, 0.2, 0.4, 0.7, 0.1], [0.0, 0.0, 0.1, 0.2, 0.3]]}},
    "sensors": [{"name": "down", "type": "range", "on": "probe", "rpy": [3.141592653589793, 0, 0]},
                {"name": "tilted", "type": "range", "on": "probe2", "rpy": [2.8, -0.3, 0]},
                {"name": "short", "type": "range", "on": "probe", "rpy": [3.141592653589793, 0, 0],
                 "maxRange": 0.5}]})");
  Sensed s(scene);
  const Heightfield& field = s.world.model().environment.heightfields[0];
  const double down = s.read("down")[0];
  // h(0.7, 0.9) by hand: cell (1, 1), fractions 0.4 and 0.8 of the samples 0.5, 0.4 / 0.6, 0.9.
  const double h = (1 - 0.8) * ((1 - 0.4) * 0.5 + 0.4 * 0.4) + 0.8 * ((1 - 0.4) * 0.6 + 0.4 * 0.9);
  EXPECT_NEAR(field.heightAt(0.7, 0.9), h, 1e-12);
  const double tilted = s.read("tilted")[0];
  const Mat3 R = rotationFromRollPitchYaw({2.8, -0.3, 0});
  const Vec3 hit = Vec3{1.3, 1.2, 1.5} + R.column(2) * tilted;
  std::printf("  down: %.9f m (2 − h = %.9f m); tilted: %.6f m, its hit %.2e m off the surface\n",
              down, 2.0 - h, tilted, hit.z - field.heightAt(hit.x, hit.y));
  EXPECT_NEAR(down, 2.0 - h, 1e-3);
  EXPECT_GT(tilted, 0.0);
  EXPECT_NEAR(hit.z, field.heightAt(hit.x, hit.y), 1e-3);
  EXPECT_EQ(s.read("short")[0], -1.0);  // nothing within 0.5 m
}

TEST(Sensors, BadSensorsAreRefusedWithTheirPlace) {
  SceneLoadResult result = loadSceneText(R"({"objects": [
      {"name": "b", "type": "box", "center": [0, 0, 1], "size": [0.1, 0.1, 0.1], "cells": [2, 2, 2], "mass": 1}],
    "sensors": [{"name": "a", "type": "imu", "on": "nothing"},
                {"name": "c", "type": "accelerometer", "on": "b"},
                {"name": "d", "type": "force_torque", "on": "b"},
                {"name": "e", "type": "range", "on": "b", "maxRange": -1}]})",
                                         "bad.json");
  ASSERT_FALSE(result.ok());
  std::string all;
  for (const auto& e : result.errors) all += e.format() + "\n";
  EXPECT_NE(all.find("/sensors/0"), std::string::npos) << all;
  EXPECT_NE(all.find("no link or object named 'nothing'"), std::string::npos) << all;
  EXPECT_NE(all.find("unknown sensor type \"accelerometer\""), std::string::npos) << all;
  EXPECT_NE(all.find("no joint of a rigid tree named 'b'"), std::string::npos) << all;
  EXPECT_NE(all.find("/sensors/3/maxRange"), std::string::npos) << all;
}

// Sensors observe: the same steps with and without them (read at every step) end in
// the same state, bit for bit; and a run writes sensors.csv with one row a frame and
// the same state hash as the run without sensors.
TEST(Sensors, AreObserversAndARunWritesThem) {
  const std::string file = robotsDir() + "/kuka_iiwa/model.urdf";
  if (!fs::exists(file)) GTEST_SKIP() << "no " << file << " (set ROBOPHI_ROBOTS_DIR)";
  const std::string sensors = R"([{"name": "ft", "type": "force_torque", "on": "arm.lbr_iiwa_joint_3"},
      {"name": "imu", "type": "imu", "on": "lbr_iiwa_link_7"},
      {"name": "touch", "type": "contact", "on": "arm.lbr_iiwa_link_0"},
      {"name": "range", "type": "range", "on": "lbr_iiwa_link_7"}])";
  const Scene with = loadOk(armScene(file, robotsDir() + "/kuka_iiwa", sensors));
  const Scene without = loadOk(armScene(file, robotsDir() + "/kuka_iiwa", "[]"));
  Sensed a(with), b(without);
  std::vector<double> values(a.sensors.valueCount());
  for (int k = 0; k < 200; ++k) {
    ASSERT_EQ(a.world.step(1e-3), StepStatus::kOk);
    ASSERT_EQ(b.world.step(1e-3), StepStatus::kOk);
    a.sensors.read(a.world, values.data());
  }
  EXPECT_EQ(stateHash(a.world.state()), stateHash(b.world.state()));

  const fs::path dir = testing::makeTempFolder("robophi_sensors_run_");
  RunOptions options;
  options.settings = with.run;
  options.settings.duration = 0.1;
  options.settings.fps = 100;
  options.outDir = (dir / "with").string();
  options.writeReplay = false;
  const RunReport sensed = runScene(with, options);
  options.settings = without.run;
  options.settings.duration = 0.1;
  options.settings.fps = 100;
  options.outDir = (dir / "without").string();
  const RunReport plain = runScene(without, options);
  EXPECT_EQ(sensed.status, "ok");
  EXPECT_EQ(sensed.stateHash, plain.stateHash);
  EXPECT_FALSE(fs::exists(dir / "without" / "sensors.csv"));
  const std::string csv = testing::readText(dir / "with" / "sensors.csv");
  const std::string header = csv.substr(0, csv.find('\n'));
  EXPECT_EQ(header.rfind("t,ft:fx,ft:fy,ft:fz,ft:tx,ft:ty,ft:tz,imu:ax,", 0), 0u) << header;
  EXPECT_NE(header.find(",touch:fn,range:d"), std::string::npos) << header;
  const auto rows = std::count(csv.begin(), csv.end(), '\n') - 1;
  const std::string particles = testing::readText(dir / "with" / "particles.csv");
  EXPECT_EQ(rows, std::count(particles.begin(), particles.end(), '\n') - 1);  // one a frame
  EXPECT_GE(rows, 3);
  fs::remove_all(dir);
}

// A run stopped at a checkpoint and resumed writes the same sensors.csv, byte for byte,
// as the run in one go (the CLI: robophi run --stop-after, robophi resume).
TEST(Sensors, AResumedRunWritesTheSameSensorsCsv) {
  const std::string file = robotsDir() + "/kuka_iiwa/model.urdf";
  if (!fs::exists(file)) GTEST_SKIP() << "no " << file << " (set ROBOPHI_ROBOTS_DIR)";
  const fs::path dir = testing::makeTempFolder("robophi_sensors_resume_");
  testing::writeText(dir / "scene.json",
                     armScene(file, robotsDir() + "/kuka_iiwa",
                              R"([{"name": "ft", "type": "force_torque", "on": "arm.lbr_iiwa_joint_6"},
                                  {"name": "imu", "type": "imu", "on": "lbr_iiwa_link_5"}])"));
  const std::string run = std::string(ROBOPHI_BINARY) + " run " + (dir / "scene.json").string() +
                          " --duration 0.3 --step constant --dt 1e-3 --fps 50 --quiet --out ";
  ASSERT_EQ(std::system((run + (dir / "whole").string() + " 2>/dev/null").c_str()), 0);
  ASSERT_EQ(std::system((run + (dir / "parts").string() + " --stop-after 0.1 2>/dev/null").c_str()), 0);
  ASSERT_EQ(std::system((std::string(ROBOPHI_BINARY) + " resume " + (dir / "parts").string() +
                         " --quiet 2>/dev/null")
                            .c_str()),
            0);
  const std::string whole = testing::readText(dir / "whole" / "sensors.csv");
  EXPECT_GT(std::count(whole.begin(), whole.end(), '\n'), 10);
  EXPECT_EQ(whole, testing::readText(dir / "parts" / "sensors.csv"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace robophi
