// The URDF reader on the broken-URDF corpus (tests/urdf/broken/, each message
// asserted: file:line and the element or value) and on the real robots of
// ../shared/robots (tree, limits, mimic, warnings).

#include <gtest/gtest.h>

#include <string>

#include "build/urdf_parse.h"
#include "robophi/build/urdf_error.h"
#include "test_files.h"

namespace robophi::build {
namespace {

const std::string kBroken = std::string(ROBOPHI_SOURCE_DIR) + "/tests/urdf/broken/";
using testing::kRobots;  // ROBOPHI_ROBOTS_DIR (test_files.h)

struct BrokenCase {
  const char* file;
  int line;
  const char* message;  // a part of the message
};

class BrokenUrdf : public ::testing::TestWithParam<BrokenCase> {};

TEST_P(BrokenUrdf, NamesFileLineAndElement) {
  const BrokenCase& c = GetParam();
  const std::string path = kBroken + c.file;
  try {
    urdf::readUrdf(path, {});
    FAIL() << path << " was read";
  } catch (const UrdfError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.line(), c.line) << e.what();
    EXPECT_NE(e.message().find(c.message), std::string::npos) << e.what();
    const std::string where = c.line > 0 ? path + ":" + std::to_string(c.line) + ": " : path + ": ";
    EXPECT_EQ(std::string(e.what()).rfind(where, 0), 0u) << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(
    Corpus, BrokenUrdf,
    ::testing::Values(
        BrokenCase{
            "missing_link.urdf", 9,
            "joint 'elbow': child link 'forearm' is not defined (no <link name=\"forearm\">)"},
        BrokenCase{"cycle.urdf", 14,
                   "link 'c' has two parents: joint 'a_to_c' and joint 'b_to_c' (line 13)"},
        BrokenCase{"bad_axis.urdf", 12,
                   "joint 'shoulder': <axis xyz=\"0 0 0\"> is zero (a continuous joint needs a "
                   "direction)"},
        BrokenCase{"missing_mesh.urdf", 6, "mesh 'meshes/no_such_part.stl' not found: tried "},
        BrokenCase{"missing_package_mesh.urdf", 6,
                   "mesh 'package://no_such_package/meshes/base.stl' not found"},
        BrokenCase{"robot.urdf.xacro", 0, "a xacro file: run xacro first: xacro "},
        BrokenCase{"xacro_inside.urdf", 3,
                   "<xacro:include>: a xacro file: run xacro first: xacro "},
        BrokenCase{"floating.urdf", 7,
                   "joint 'free': type \"floating\" is not supported (robophi imports revolute, "
                   "continuous, prismatic and fixed joints"},
        BrokenCase{"unknown_type.urdf", 9,
                   "joint 'socket': unknown type \"spherical\" (expected revolute, continuous, "
                   "prismatic or fixed)"},
        BrokenCase{"malformed.urdf", 5, "malformed XML: XML_ERROR_PARSING_ELEMENT"},
        BrokenCase{"not_utf8.urdf", 5, "not UTF-8 text: byte 0xC3 at offset "}),
    [](const auto& param) {
      std::string name = param.param.file;
      for (char& ch : name)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
      return name;
    });

TEST(UrdfRead, MissingMeshListsEveryPlaceTried) {
  const std::string path = kBroken + "missing_package_mesh.urdf";
  try {
    urdf::readUrdf(path, {"/nowhere/a", "/nowhere/no_such_package"});
    FAIL();
  } catch (const UrdfError& e) {
    // NAME under each package path, and a package path that is NAME itself.
    EXPECT_NE(e.message().find("/nowhere/a/no_such_package/meshes/base.stl"), std::string::npos)
        << e.what();
    EXPECT_NE(e.message().find("/nowhere/no_such_package/meshes/base.stl"), std::string::npos)
        << e.what();
  }
  // No package path, and no folder beside the URDF or above it holds the package.
  try {
    urdf::readUrdf(path, {});
    FAIL();
  } catch (const UrdfError& e) {
    EXPECT_NE(e.message().find("not beside the URDF (in its folder or one above it) and no "
                               "package path to look in"),
              std::string::npos)
        << e.what();
  }
  const std::string relative = kBroken + "missing_mesh.urdf";
  try {
    urdf::readUrdf(relative, {});
    FAIL();
  } catch (const UrdfError& e) {
    EXPECT_NE(e.message().find(kBroken + "meshes/no_such_part.stl"), std::string::npos) << e.what();
  }
}

TEST(UrdfRead, KukaIiwaTreeLimitsAndWarnings) {
  const urdf::Description d = urdf::readUrdf(kRobots + "/kuka_iiwa/model.urdf", {});
  EXPECT_EQ(d.robotName, "lbr_iiwa");
  ASSERT_EQ(d.links.size(), 8u);
  ASSERT_EQ(d.joints.size(), 7u);
  EXPECT_EQ(d.links[static_cast<std::size_t>(d.root)].name, "lbr_iiwa_link_0");
  for (std::size_t k = 0; k < d.joints.size(); ++k) {
    EXPECT_EQ(d.joints[k].type, urdf::Joint::Type::kRevolute);
    EXPECT_EQ(d.joints[k].name, "lbr_iiwa_joint_" + std::to_string(k + 1));
    EXPECT_TRUE(d.joints[k].hasLimit);
  }
  EXPECT_DOUBLE_EQ(d.joints[0].lower, -2.96705972839);
  EXPECT_DOUBLE_EQ(d.links[1].inertial.mass, 4.0);
  EXPECT_DOUBLE_EQ(d.links[1].inertial.inertia[0], 0.1);
  // The link meshes resolve relative to the URDF's folder.
  ASSERT_FALSE(d.links[1].collisions.empty());
  EXPECT_EQ(d.links[1].collisions[0].geometry.mesh, kRobots + "/kuka_iiwa/meshes/link_1.stl");
  // One warning a kind: <visual> (and the materials).
  bool visual = false;
  for (const UrdfWarning& w : d.warnings)
    visual = visual || w.message.rfind("<visual> ignored", 0) == 0;
  EXPECT_TRUE(visual);
  for (std::size_t a = 0; a < d.warnings.size(); ++a)
    for (std::size_t b = a + 1; b < d.warnings.size(); ++b)
      EXPECT_NE(d.warnings[a].message, d.warnings[b].message);
}

TEST(UrdfRead, PandaPackagePathsAndGripper) {
  // package://meshes/...: NAME "meshes" is a folder directly under the package path.
  const std::string dir = kRobots + "/franka_panda";
  // Without a package path, the URDF's folder holds "meshes": found beside it.
  const urdf::Description beside = urdf::readUrdf(dir + "/panda.urdf", {});
  bool named = false;
  for (const UrdfWarning& w : beside.warnings)
    named = named || w.message.find("package 'meshes' taken from " + dir + "/meshes/") != std::string::npos;
  EXPECT_TRUE(named);
  const urdf::Description d = urdf::readUrdf(dir + "/panda.urdf", {dir});
  ASSERT_EQ(beside.links.size(), d.links.size());
  for (std::size_t k = 0; k < d.links.size(); ++k)
    for (std::size_t c = 0; c < d.links[k].collisions.size(); ++c)
      EXPECT_EQ(beside.links[k].collisions[c].geometry.mesh, d.links[k].collisions[c].geometry.mesh);
  ASSERT_EQ(d.links.size(), 13u);
  int revolute = 0, prismatic = 0, fixed = 0;
  for (const auto& j : d.joints) {
    revolute += j.type == urdf::Joint::Type::kRevolute;
    prismatic += j.type == urdf::Joint::Type::kPrismatic;
    fixed += j.type == urdf::Joint::Type::kFixed;
  }
  EXPECT_EQ(revolute, 7);
  EXPECT_EQ(prismatic, 2);
  EXPECT_EQ(fixed, 3);
  const auto finger2 = std::find_if(d.joints.begin(), d.joints.end(),
                                    [](const auto& j) { return j.name == "panda_finger_joint2"; });
  ASSERT_NE(finger2, d.joints.end());
  EXPECT_TRUE(finger2->hasMimic);
  EXPECT_EQ(finger2->mimicJoint, "panda_finger_joint1");
  EXPECT_DOUBLE_EQ(finger2->upper, 0.04);
  EXPECT_EQ(d.links[1].collisions[0].geometry.mesh, dir + "/meshes/collision/link1.obj");
  // ROS_PACKAGE_PATH is searched after the given paths.
  setenv("ROS_PACKAGE_PATH", ("/nowhere:" + dir).c_str(), 1);
  EXPECT_NO_THROW(urdf::readUrdf(dir + "/panda.urdf", {}));
  unsetenv("ROS_PACKAGE_PATH");
}

TEST(UrdfRead, EveryShippedRobotReads) {
  for (const char* file :
       {"kuka_iiwa/model.urdf", "kuka_iiwa/model_for_sdf.urdf", "kuka_iiwa/model_free_base.urdf",
        "kuka_iiwa/model_vr_limits.urdf", "husky/husky.urdf", "r2d2/r2d2.urdf",
        "pr2_gripper/pr2_gripper.urdf", "cartpole/cartpole.urdf"}) {
    SCOPED_TRACE(file);
    const urdf::Description d = urdf::readUrdf(kRobots + "/" + file, {});
    EXPECT_EQ(d.joints.size() + 1, d.links.size());
  }
  // roslaunch's $(optenv NAME default) in husky.urdf's imu origin.
  const urdf::Description husky = urdf::readUrdf(kRobots + "/husky/husky.urdf", {});
  const auto imu = std::find_if(husky.joints.begin(), husky.joints.end(),
                                [](const auto& j) { return j.name == "imu_joint"; });
  ASSERT_NE(imu, husky.joints.end());
  EXPECT_DOUBLE_EQ(imu->origin.xyz.x, 0.19);
  EXPECT_DOUBLE_EQ(imu->origin.rpy.y, -1.5708);
}

TEST(UrdfRead, MissingCollisionMeshFallsBackToTheVisualMesh) {
  // model_for_sdf.urdf's collision meshes (meshes/coarse/) are not in the data set.
  const urdf::Description d = urdf::readUrdf(kRobots + "/kuka_iiwa/model_for_sdf.urdf", {});
  EXPECT_EQ(d.links[1].collisions[0].geometry.mesh, kRobots + "/kuka_iiwa/meshes/link_1.stl");
  int fallbacks = 0;
  for (const UrdfWarning& w : d.warnings)
    if (w.message.find("its <visual> mesh") != std::string::npos) {
      ++fallbacks;
      if (fallbacks == 1) {
        EXPECT_EQ(w.line, 73);  // its <collision>
        EXPECT_NE(w.message.find("mesh 'meshes/coarse/link_0.stl' not found: tried "),
                  std::string::npos)
            << w.message;
      }
    }
  EXPECT_EQ(fallbacks, 8);
}

}  // namespace
}  // namespace robophi::build
