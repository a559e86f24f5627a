// A bare URDF whose values the builder refuses (issue 40: <mass value="1e300"/> made
// a damping of inf and exit 1) is a load error naming the file: bad input, exit 2.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "robophi/scene/scene.h"

namespace robophi {
namespace {

TEST(UrdfBadValues, AHugeMassIsALoadErrorNotACrash) {
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "robophi_huge_mass.urdf";
  std::ofstream(file) << R"(<robot name="huge">
  <link name="base"><inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
  <link name="arm"><inertial><mass value="1e300"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><box size="0.1 0.1 0.3"/></geometry></collision></link>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm"/><origin xyz="0 0 0.2"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
</robot>)";
  const SceneLoadResult loaded = loadUrdfFile(file.string());
  std::filesystem::remove(file);
  ASSERT_FALSE(loaded.ok());
  ASSERT_FALSE(loaded.errors.empty());
  EXPECT_NE(loaded.errors[0].format().find("robophi_huge_mass.urdf"), std::string::npos)
      << loaded.errors[0].format();
}

}  // namespace
}  // namespace robophi
