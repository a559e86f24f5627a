// The URDF's <visual> elements kept for the replay (robophi/visuals.h): shapes,
// materials by name, a missing visual mesh as a warning, and each visual's pose as
// built in both forms of the robot (particle bodies and a rigid tree).

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "build/urdf_parse.h"
#include "robophi/build/model_builder.h"
#include "robophi/build/urdf.h"
#include "robophi/build/urdf_multibody.h"
#include "robophi/multibody.h"
#include "test_files.h"

namespace robophi::build {
namespace {

using testing::kRobots;  // ROBOPHI_ROBOTS_DIR (test_files.h)

// A two-link arm whose links carry a box, a cylinder, a named material and a
// visual mesh that is not there.
std::string writeArm() {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("robophi_visuals_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::filesystem::path file = dir / "arm.urdf";
  std::ofstream(file) << R"(<robot name="arm">
  <material name="blue"><color rgba="0 0 1 1"/></material>
  <link name="base">
    <inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><origin xyz="0 0 0.05"/><geometry><box size="0.1 0.2 0.1"/></geometry>
      <material name="blue"/></visual>
    <collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>
  </link>
  <link name="arm">
    <inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><origin xyz="0 0 0.2" rpy="0 0 0"/><geometry><cylinder radius="0.03" length="0.4"/></geometry>
      <material name="red"><color rgba="1 0 0 0.5"/></material></visual>
    <visual><geometry><mesh filename="meshes/not_there.stl"/></geometry></visual>
    <collision><origin xyz="0 0 0.2"/><geometry><cylinder radius="0.03" length="0.4"/></geometry></collision>
  </link>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
</robot>)";
  return file.string();
}

TEST(UrdfVisuals, ReadsShapesMaterialsAndAMissingMeshAsAWarning) {
  const urdf::Description d = urdf::readUrdf(writeArm(), {});
  ASSERT_EQ(d.links.size(), 2u);
  ASSERT_EQ(d.links[0].visuals.size(), 1u);
  ASSERT_EQ(d.links[1].visuals.size(), 2u);
  EXPECT_EQ(d.links[0].visuals[0].material, "blue");
  EXPECT_FALSE(d.links[0].visuals[0].hasColor);  // named only: the robot's material
  EXPECT_TRUE(d.links[1].visuals[0].hasColor);
  EXPECT_EQ(d.links[1].visuals[0].rgba[3], 0.5);
  EXPECT_TRUE(d.links[1].visuals[1].geometry.mesh.empty());
  EXPECT_NE(d.links[1].visuals[1].warning.find("not_there.stl"), std::string::npos);
  ASSERT_EQ(d.materials.size(), 1u);
  EXPECT_EQ(d.materials[0].first, "blue");
}

TEST(UrdfVisuals, ParticleFormCarriesEachVisualByItsLinksBody) {
  UrdfSpec spec;
  spec.path = writeArm();
  const UrdfRobot robot = makeUrdfRobot(spec);
  ModelBuilder builder;
  placeUrdfRobot(builder, robot);
  const Model& model = builder.model();
  ASSERT_EQ(model.visuals.size(), 3u);
  const VisualShape& box = model.visuals[0];
  EXPECT_EQ(box.kind, VisualShape::Kind::kBox);
  EXPECT_EQ(box.link, "arm.base");
  EXPECT_TRUE(box.hasColor);  // "blue" from the robot's materials
  EXPECT_EQ(box.rgba[2], 1.0);
  EXPECT_GE(box.body, 0);
  EXPECT_NEAR(box.X_WV.translation.z, 0.05, 1e-12);
  const VisualShape& cylinder = model.visuals[1];
  EXPECT_EQ(cylinder.kind, VisualShape::Kind::kCylinder);
  EXPECT_NE(cylinder.body, box.body);
  EXPECT_NEAR(cylinder.X_WV.translation.z, 0.3, 1e-12);  // joint at 0.1, visual 0.2 above
  EXPECT_FALSE(model.visuals[2].warning.empty());
}

TEST(UrdfVisuals, RigidFormCarriesEachVisualByItsTreeBody) {
  UrdfMultibodySpec spec;
  spec.path = writeArm();
  const UrdfMultibody robot = makeUrdfMultibody(spec);
  ModelBuilder builder;
  const PlacedUrdfMultibody placed = placeUrdfMultibody(builder, robot, {});
  const Model& model = builder.model();
  ASSERT_EQ(model.visuals.size(), 3u);
  for (const VisualShape& v : model.visuals) {
    EXPECT_EQ(v.tree, placed.tree);
    EXPECT_GE(v.treeBody, 0);
  }
  EXPECT_NEAR(model.visuals[1].X_WV.translation.z, 0.3, 1e-12);
}

TEST(UrdfVisuals, SharedRobotsKeepTheirVisualMeshes) {
  if (!std::filesystem::exists(kRobots + "/kuka_iiwa/model.urdf")) GTEST_SKIP() << "no robots";
  UrdfSpec spec;
  spec.path = kRobots + "/kuka_iiwa/model.urdf";
  const UrdfRobot robot = makeUrdfRobot(spec);
  std::size_t meshes = 0;
  for (const UrdfVisual& v : robot.visuals)
    meshes += v.shape.kind == VisualShape::Kind::kMesh && !v.shape.mesh.empty() ? 1 : 0;
  EXPECT_GE(meshes, 8u);
}

}  // namespace
}  // namespace robophi::build
