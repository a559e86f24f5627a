// Scene objects of type "mesh" (docs/scene-format.md#mesh): a mesh file next to
// the scene, filled with particles at uniform density, placed by its centre of
// mass, turned by rpy, with the common keys (velocity, fixed, material).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <numeric>

#include "robophi/build/rigid_body.h"
#include "robophi/scene/scene.h"
#include "robophi/world.h"
#include "scene/scene_test_util.h"
#include "test_files.h"

namespace robophi {
namespace {

namespace fs = std::filesystem;

TEST(SceneMesh, FilledAtUniformDensityPlacedByItsCentreOfMass) {
  const fs::path dir = testing::makeTempFolder("robophi_scene_mesh_");
  fs::create_directories(dir / "parts");
  testing::writeText(dir / "parts" / "box.stl", testing::boxStl(0.1, 0.2, 0.3));
  const fs::path scene = dir / "scene.json";
  testing::writeText(scene, R"({
  "objects": [
    {"name": "part", "type": "mesh", "file": "parts/box.stl", "scale": [2, 1, 1],
     "center": [1, 2, 3], "rpy": [0, 0, 1.5707963267948966], "mass": 6, "particles": 60,
     "velocity": [0.5, 0, 0]}
  ]
})");
  const SceneLoadResult result = loadSceneFile(scene.string());
  ASSERT_TRUE(result.ok()) << test::allErrors(result);
  const Model& model = result.scene->model;
  ASSERT_EQ(model.objects.size(), 1u);
  const auto n = static_cast<std::size_t>(model.particleCount());
  EXPECT_GE(n, 30u);
  EXPECT_LE(n, 120u);
  std::vector<Vec3> position(result.scene->initial.position.begin(),
                             result.scene->initial.position.end());
  std::vector<double> mass(model.mass.begin(), model.mass.end());
  const build::MassProperties got = build::massProperties(position, mass);
  EXPECT_NEAR(got.mass, 6.0, 1e-9);
  EXPECT_NEAR(got.centerOfMass.x, 1.0, 1e-6);
  EXPECT_NEAR(got.centerOfMass.y, 2.0, 1e-6);
  EXPECT_NEAR(got.centerOfMass.z, 3.0, 1e-6);
  // The 0.2 × 0.2 × 0.3 box (x scaled by 2), turned 90° about z: uniform inertia.
  const double ixx = 6.0 * (0.04 + 0.09) / 12.0, izz = 6.0 * (0.04 + 0.04) / 12.0;
  EXPECT_NEAR(got.inertia.xx, ixx, 1e-6 * ixx);
  EXPECT_NEAR(got.inertia.yy, ixx, 1e-6 * ixx);
  EXPECT_NEAR(got.inertia.zz, izz, 1e-6 * izz);
  // A uniform box gets equal masses.
  for (const double m : mass) EXPECT_NEAR(m, 6.0 / static_cast<double>(n), 1e-9);
  for (std::size_t i = 0; i < n; ++i) EXPECT_DOUBLE_EQ(result.scene->initial.velocity[i].x, 0.5);
  fs::remove_all(dir);
}

TEST(SceneMesh, ARobotLinkMeshDroppedOnTheGroundComesToRest) {
  // The iiwa's link_1 STL (ROBOPHI_ROBOTS_DIR), 100 particles, laid on its
  // side with its lowest particles at the ground: it settles, rocks (measured:
  // still by 1.5 s) and 2 s later lies still on the ground, no particle through it.
  const fs::path stl = fs::path(ROBOPHI_ROBOTS_DIR) / "kuka_iiwa" / "meshes" / "link_1.stl";
  if (!fs::exists(stl)) GTEST_SKIP() << "no robot data at " << stl;
  const std::string text = R"({
  "objects": [{"name": "link", "type": "mesh", "file": ")" +
                           stl.string() + R"(", "center": [0, 0, 0.075],
               "rpy": [1.5707963267948966, 0, 0], "mass": 4, "particles": 100}],
  "environment": {"ground": true}
})";
  const SceneLoadResult result = loadSceneText(text, "drop.json");
  ASSERT_TRUE(result.ok()) << test::allErrors(result);
  World world(result.scene->model, result.scene->initial);
  for (int step = 0; step < 20000; ++step) ASSERT_EQ(world.step(1e-4), StepStatus::kOk);
  double fastest = 0.0, lowest = 1e300;
  const auto& model = world.model();
  for (std::size_t i = 0; i < world.state().position.size(); ++i) {
    fastest = std::max(fastest, norm(world.state().velocity[i]));
    lowest = std::min(lowest, world.state().position[i].z - model.radius[i]);
  }
  EXPECT_LT(fastest, 0.02);  // m/s: at rest (measured 0.009)
  // On the ground, not through it: the 39 N weight on the default material's
  // contact springs sinks the particles it rests on (measured 6.2 mm).
  EXPECT_GT(lowest, -0.01);
  EXPECT_LT(lowest, 0.0);
}

TEST(SceneMesh, MissingFileNamesTheKeyAndThePath) {
  const SceneLoadResult result = loadSceneText(R"({
  "objects": [
    {"name": "part", "type": "mesh", "center": [0, 0, 0], "mass": 1,
     "file": "/nonexistent/part.stl"}
  ]
})",
                                               "inline.json");
  ASSERT_FALSE(result.ok());
  const Diagnostic* error = test::findError(result, "part.stl");
  ASSERT_NE(error, nullptr) << test::allErrors(result);
  EXPECT_EQ(error->format(),
            "inline.json:4:14: error: 'file': mesh '/nonexistent/part.stl': no such file (at "
            "/objects/0/file)");
}

}  // namespace
}  // namespace robophi
