// Names are unique across everything a scene puts in its model: objects, a
// robot's link objects ("<robot>.<link>", "<robot>.<link>.carriers") and joints
// ("<robot>.<joint>"). A clash is an error naming both places, never an object
// silently left out.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "robophi/scene/scene.h"
#include "scene/scene_test_util.h"
#include "test_files.h"

namespace robophi {
namespace {

namespace fs = std::filesystem;

const std::string kGripper = R"({"name": "gripper", "type": "urdf", "file": ")" ROBOPHI_ROBOTS_DIR
                             R"(/pr2_gripper/pr2_gripper.urdf", "fixedBase": true})";

// A 2-particle box named `name`.
std::string box(const std::string& name) {
  return R"({"name": ")" + name +
         R"(", "type": "box", "center": [1, 0, 0.05], "size": [0.1, 0.1, 0.1], "cells": [1, 1, 1], "mass": 0.2})";
}

SceneLoadResult load(const std::string& first, const std::string& second) {
  return loadSceneText(R"({"objects": [)" + first + ", " + second + "]}", "names.json");
}

// The one error of `result`, at `pointer`, naming both places.
void expectClash(const SceneLoadResult& result, const std::string& pointer,
                 const std::vector<std::string>& parts) {
  ASSERT_FALSE(result.ok());
  ASSERT_EQ(result.errors.size(), 1u) << test::allErrors(result);
  EXPECT_EQ(result.errors[0].pointer, pointer);
  for (const std::string& part : parts)
    EXPECT_NE(result.errors[0].message.find(part), std::string::npos) << part << "\n"
                                                                      << result.errors[0].message;
}

TEST(SceneNames, AnObjectNamedLikeARobotsLinkIsAnErrorEitherWay) {
  expectClash(load(kGripper, box("gripper.gripper_pole")), "/objects/1/name",
              {"'gripper.gripper_pole'", "link 'gripper_pole' of robot 'gripper' (/objects/0)",
               "object 'gripper.gripper_pole' (/objects/1)"});
  expectClash(load(box("gripper.gripper_pole"), kGripper), "/objects/1/name",
              {"object 'gripper.gripper_pole' (/objects/0)",
               "link 'gripper_pole' of robot 'gripper' (/objects/1)"});
}

TEST(SceneNames, AnObjectNamedLikeALinksCarriersOrARobotsJointIsAnError) {
  const SceneLoadResult alone = loadSceneText(R"({"objects": [)" + kGripper + "]}", "g.json");
  ASSERT_TRUE(alone.ok()) << test::allErrors(alone);
  std::string carriers;
  for (const ObjectInfo& object : alone.scene->model.objects)
    if (object.kind == "virtual") carriers = object.name;
  ASSERT_FALSE(carriers.empty());
  const std::string link = carriers.substr(8, carriers.size() - 8 - 9);  // gripper.<link>.carriers
  expectClash(load(kGripper, box(carriers)), "/objects/1/name",
              {"the carriers of link '" + link + "' of robot 'gripper' (/objects/0)"});
  expectClash(load(kGripper, box("gripper.left_gripper_joint")), "/objects/1/name",
              {"joint 'left_gripper_joint' of robot 'gripper' (/objects/0)",
               "object 'gripper.left_gripper_joint' (/objects/1)"});
}

TEST(SceneNames, ValidateAndRunRefuseAClashWithExit2) {
  const fs::path dir = testing::makeTempFolder("robophi_scene_names_");
  const fs::path scene = dir / "clash.json";
  testing::writeText(scene,
                     R"({"objects": [)" + kGripper + ", " + box("gripper.gripper_pole") + "]}");
  for (const std::string command : {"validate", "run"}) {
    const std::string out = command == "run" ? " --out " + (dir / "out").string() : "";
    const std::string line = std::string(ROBOPHI_BINARY) + " " + command + " " + scene.string() +
                             out + " > /dev/null 2> " + (dir / "err.txt").string();
    const int status = std::system(line.c_str());
    EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 2) << command;
    const std::string errors = testing::readText(dir / "err.txt");
    EXPECT_NE(errors.find("/objects/1/name"), std::string::npos) << command << ": " << errors;
    EXPECT_NE(errors.find("robot 'gripper'"), std::string::npos) << command << ": " << errors;
  }
  EXPECT_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace robophi
