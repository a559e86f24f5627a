// URDF robots in scenes ({"type": "urdf"}), and the command line on bare URDF files:
// robophi validate ROBOT.urdf, robophi info FILE --json (its figures checked).

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "robophi/joints.h"
#include "robophi/scene/scene.h"
#include "test_files.h"

namespace robophi {
namespace {

namespace fs = std::filesystem;
using testing::kRobots;  // ROBOPHI_ROBOTS_DIR (test_files.h)

struct UrdfOutcome {
  int exitCode = -1;
  std::string out, errors;
};

UrdfOutcome robophi(const std::string& args) {
  const fs::path dir = testing::makeTempFolder("robophi_urdf_cli_");
  const std::string command = std::string(ROBOPHI_BINARY) + " " + args + " > " +
                              (dir / "out.txt").string() + " 2> " + (dir / "err.txt").string();
  const int status = std::system(command.c_str());
  UrdfOutcome o{WIFEXITED(status) ? WEXITSTATUS(status) : -1, testing::readText(dir / "out.txt"),
                testing::readText(dir / "err.txt")};
  fs::remove_all(dir);
  return o;
}

TEST(UrdfScene, AUrdfObjectLoadsPlacedAndNamed) {
  const std::string text = R"({"objects": [
    {"name": "gripper", "type": "urdf", "file": ")" +
                           kRobots + R"(/pr2_gripper/pr2_gripper.urdf",
     "position": [0, 0, 0.5], "orientation": [0, 0, 1.5707963267948966], "fixedBase": true,
     "particlesPerLink": 12, "initialPositions": {"left_gripper_joint": 0.3}},
    {"name": "cube", "type": "box", "center": [1, 0, 0.05], "size": [0.1, 0.1, 0.1], "cells": [2, 2, 2], "mass": 0.2}],
    "environment": {"ground": true}})";
  SceneLoadResult result = loadSceneText(text, "urdf_scene.json");
  for (const auto& e : result.errors) ADD_FAILURE() << e.format();
  ASSERT_TRUE(result.ok());
  const Scene& scene = *result.scene;
  ASSERT_GE(scene.model.objects.size(), 6u);
  EXPECT_EQ(scene.model.objects[0].name, "gripper.gripper_pole");
  EXPECT_EQ(scene.model.objects[0].kind, "link");
  EXPECT_TRUE(scene.model.objects[0].rigid);
  // The robot's links, their carriers (kind "virtual"), then the cube.
  EXPECT_EQ(scene.model.objects.back().name, "cube");
  for (std::size_t o = 5; o + 1 < scene.model.objects.size(); ++o)
    EXPECT_EQ(scene.model.objects[o].kind, "virtual");
  ASSERT_EQ(scene.urdfRobots.size(), 1u);
  // The root link's frame: at the position, turned 90° about z.
  const build::Frame& root = scene.urdfRobots[0]->links[0].frame;
  EXPECT_NEAR(root.origin.z, 0.5, 1e-12);
  EXPECT_NEAR(root.axes[0].y, 1.0, 1e-12);
  const auto left = findJoint(scene.model, "gripper.left_gripper_joint");
  ASSERT_TRUE(left.has_value());
  EXPECT_NEAR(jointPosition(scene.model, scene.initial, *left), 0.3, 1e-9);
  // The root's particles are fixed; the links touch the cube but not each other.
  const ObjectInfo& pole = scene.model.objects[0];
  for (ParticleIndex i = pole.firstParticle; i < pole.firstParticle + pole.particleCount; ++i)
    EXPECT_TRUE(scene.model.isFixed(i));
  // Its five links in one contact group (not their ten pairs); the cube in none.
  EXPECT_TRUE(scene.model.noContactPairs.empty());
  for (std::size_t o = 0; o < 5; ++o) {
    EXPECT_GE(scene.model.objects[o].contactGroup, 0);
    EXPECT_EQ(scene.model.objects[o].contactGroup, pole.contactGroup);
  }
  EXPECT_EQ(scene.model.objects.back().contactGroup, -1);
}

TEST(UrdfScene, UrdfErrorsNameTheUrdfLineAndTheScenePlace) {
  const std::string broken = std::string(ROBOPHI_SOURCE_DIR) + "/tests/urdf/broken/bad_axis.urdf";
  SceneLoadResult result = loadSceneText(
      R"({"objects": [{"name": "r", "type": "urdf", "file": ")" + broken + R"("}]})", "s.json");
  ASSERT_EQ(result.errors.size(), 1u);
  EXPECT_EQ(result.errors[0].pointer, "/objects/0/file");
  EXPECT_EQ(result.errors[0].line, 1);
  EXPECT_NE(result.errors[0].message.find(broken + ":12: joint 'shoulder': <axis xyz=\"0 0 0\">"),
            std::string::npos)
      << result.errors[0].format();
  // A key of the wrong type, and an unknown key.
  result = loadSceneText(R"({"objects": [{"name": "r", "type": "urdf", "file": "x.urdf",
      "fixedBase": 1, "wheels": 4}]})",
                         "s.json");
  ASSERT_EQ(result.errors.size(), 2u);
  EXPECT_EQ(result.errors[0].pointer, "/objects/0/fixedBase");
  EXPECT_EQ(result.errors[1].pointer, "/objects/0/wheels");
}

// "file" and "packagePaths" take roslaunch's $(optenv NAME default) and $(env NAME).
TEST(UrdfScene, PathsTakeEnvironmentArguments) {
  setenv("ROBOPHI_TEST_ROBOTS", kRobots.c_str(), 1);
  SceneLoadResult result = loadSceneText(
      R"js({"objects": [{"name": "c", "type": "urdf",
          "file": "$(env ROBOPHI_TEST_ROBOTS)/cartpole/cartpole.urdf",
          "packagePaths": ["$(optenv ROBOPHI_UNSET_VARIABLE_14 /nowhere)"]}]})js",
      "s.json");
  for (const auto& e : result.errors) ADD_FAILURE() << e.format();
  EXPECT_TRUE(result.ok());
  result = loadSceneText(R"js({"objects": [{"name": "c", "type": "urdf",
          "file": "$(env ROBOPHI_UNSET_VARIABLE_14)/a.urdf"}]})js",
                         "s.json");
  ASSERT_EQ(result.errors.size(), 1u);
  EXPECT_EQ(result.errors[0].pointer, "/objects/0/file");
  EXPECT_NE(result.errors[0].message.find("'$(env ROBOPHI_UNSET_VARIABLE_14)': only $(optenv NAME "
                                          "default) and $(env NAME) (NAME set) are understood"),
            std::string::npos)
      << result.errors[0].format();
}

TEST(UrdfCommand, ValidateABareUrdfAndABrokenOne) {
  const UrdfOutcome ok = robophi("validate " + kRobots + "/cartpole/cartpole.urdf");
  EXPECT_EQ(ok.exitCode, 0) << ok.errors;
  EXPECT_NE(ok.out.find("cartpole.urdf: valid"), std::string::npos) << ok.out;
  // One warning a kind of ignored element, with the URDF's file:line.
  EXPECT_NE(ok.errors.find(kRobots + "/cartpole/cartpole.urdf:5: warning: <visual> ignored"),
            std::string::npos)
      << ok.errors;
  const std::string broken = std::string(ROBOPHI_SOURCE_DIR) + "/tests/urdf/broken/cycle.urdf";
  const UrdfOutcome bad = robophi("validate " + broken);
  EXPECT_EQ(bad.exitCode, 2);
  EXPECT_NE(bad.errors.find(broken + ":14: error: link 'c' has two parents"), std::string::npos)
      << bad.errors;
  // The Panda's package://meshes/... is found beside it (a warning names the
  // folder taken), or in the package path given.
  const std::string panda = kRobots + "/franka_panda/panda.urdf";
  const UrdfOutcome beside = robophi("validate " + panda);
  EXPECT_EQ(beside.exitCode, 0) << beside.errors;
  EXPECT_NE(beside.errors.find("package 'meshes' taken from " + kRobots + "/franka_panda/meshes/"),
            std::string::npos)
      << beside.errors;
  const UrdfOutcome given =
      robophi("validate " + panda + " --package-path " + kRobots + "/franka_panda");
  EXPECT_EQ(given.exitCode, 0);
  EXPECT_EQ(given.errors.find("package 'meshes' taken from"), std::string::npos) << given.errors;
  EXPECT_EQ(robophi("validate " + panda + " --base sideways").exitCode, 2);
}

TEST(UrdfCommand, InfoJsonReportsEveryLinkAgainstTheUrdf) {
  // The particle robot: one object a link, each against the URDF's values.
  const UrdfOutcome o =
      robophi("info " + kRobots + "/pr2_gripper/pr2_gripper.urdf --particles --json");
  ASSERT_EQ(o.exitCode, 0) << o.errors;
  const nlohmann::json info = nlohmann::json::parse(o.out);
  EXPECT_EQ(info["file"], kRobots + "/pr2_gripper/pr2_gripper.urdf");
  const auto& objects = info["objects"];
  ASSERT_EQ(objects.size(), 5u);
  EXPECT_EQ(objects[0]["name"], "physics.gripper_pole");  // <robot name="physics">
  EXPECT_EQ(objects[0]["urdf"]["link"], "gripper_pole");
  double total = 0.0;
  for (const auto& object : objects) {
    SCOPED_TRACE(object["name"].get<std::string>());
    EXPECT_GT(object["particles"].get<int>(), 5);
    EXPECT_NEAR(object["mass"].get<double>(), object["urdf"]["mass"].get<double>(),
                0.01 * object["urdf"]["mass"].get<double>());
    EXPECT_LT(object["errors"]["mass"].get<double>(), 0.01);
    EXPECT_LT(object["errors"]["centerOfMass"].get<double>(), 2e-3);
    for (int k = 0; k < 3; ++k)
      EXPECT_LT(object["errors"]["principalMoments"][k].get<double>(), 0.1);
    EXPECT_EQ(object["inertia"].size(), 6u);
    total += object["mass"].get<double>();
  }
  EXPECT_NEAR(total, 0.5 + 4 * 0.1, 1e-6);
  // The text form names the declared values too.
  const UrdfOutcome text = robophi("info " + kRobots + "/kuka_iiwa/model.urdf --particles");
  ASSERT_EQ(text.exitCode, 0) << text.errors;
  EXPECT_NE(text.out.find("declared (URDF)"), std::string::npos);
  EXPECT_NE(text.out.find("notional base"), std::string::npos);
}

}  // namespace
}  // namespace robophi
