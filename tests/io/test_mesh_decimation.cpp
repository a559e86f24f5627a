// The replay page's mesh decimation (output/mesh_decimation.h): a fine sphere of
// 39 600 triangles brought under the 10 000-triangle budget keeps its bounding box
// within 2% of its size; an OBJ (its two material groups) and an STL written back
// decimated (the OBJ with an MTL of its materials); a mesh under the budget is
// embedded as it is.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "output/base64.h"
#include "output/mesh_decimation.h"
#include "output/replay_meshes.h"
#include "test_files.h"
#include "io/point_box.h"

namespace robophi {
namespace {

namespace fs = std::filesystem;
using Triangle = std::array<std::int32_t, 3>;

// A UV sphere of `radius` about (0.3, -0.2, 0.5): `around` × `along` segments.
struct Sphere {
  std::vector<Vec3> vertices;
  std::vector<Triangle> triangles;
};
Sphere uvSphere(double radius, int around, int along) {
  Sphere s;
  const Vec3 centre{0.3, -0.2, 0.5};
  for (int i = 0; i <= along; ++i) {
    const double polar = std::numbers::pi * i / along;
    for (int j = 0; j < around; ++j) {
      const double azimuth = 2.0 * std::numbers::pi * j / around;
      s.vertices.push_back(centre + radius * Vec3{std::sin(polar) * std::cos(azimuth),
                                                  std::sin(polar) * std::sin(azimuth), std::cos(polar)});
    }
  }
  const auto at = [around](int i, int j) { return i * around + (j % around); };
  for (int i = 0; i < along; ++i) {
    for (int j = 0; j < around; ++j) {
      if (i > 0) s.triangles.push_back({at(i, j), at(i + 1, j), at(i, j + 1)});
      if (i + 1 < along) s.triangles.push_back({at(i, j + 1), at(i + 1, j), at(i + 1, j + 1)});
    }
  }
  return s;
}

TEST(MeshDecimation, BringsAFineSphereUnderTheBudgetKeepingItsBox) {
  const Sphere sphere = uvSphere(0.1, 200, 100);
  ASSERT_EQ(sphere.triangles.size(), 39'600u);
  const output::ClusteredMesh clustered =
      output::clusterToBudget(sphere.vertices, sphere.triangles, output::kMeshTriangleBudget);
  EXPECT_LE(clustered.keptTriangles.size(), output::kMeshTriangleBudget);
  EXPECT_GE(clustered.keptTriangles.size(), output::kMeshTriangleBudget / 2);  // not needlessly coarse
  std::vector<Vec3> used;
  for (const std::size_t t : clustered.keptTriangles)
    for (const std::int32_t v : sphere.triangles[t])
      used.push_back(clustered.positions[static_cast<std::size_t>(clustered.clusterOf[static_cast<std::size_t>(v)])]);
  const auto before = test::boxOf(sphere.vertices);
  const auto after = test::boxOf(used);
  const double size = 0.2;  // the sphere's diameter (m)
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(after[0][k], before[0][k], 0.02 * size) << "axis " << k;
    EXPECT_NEAR(after[1][k], before[1][k], 0.02 * size) << "axis " << k;
  }
  // Every vertex within one cell's diagonal of its cluster's position.
  for (std::size_t v = 0; v < sphere.vertices.size(); ++v)
    EXPECT_LE(norm(sphere.vertices[v] - clustered.positions[static_cast<std::size_t>(clustered.clusterOf[v])]),
              std::sqrt(3.0) * clustered.cell);
}

// Two groups (materials) meeting along the equator: no cluster takes vertices of both.
TEST(MeshDecimation, ClustersEachGroupApart) {
  const Sphere sphere = uvSphere(0.1, 200, 100);
  std::vector<std::uint32_t> groupOf(sphere.vertices.size());
  for (std::size_t v = 0; v < groupOf.size(); ++v) groupOf[v] = sphere.vertices[v].z > 0.5 ? 1 : 0;
  const output::ClusteredMesh clustered =
      output::clusterToBudget(sphere.vertices, sphere.triangles, output::kMeshTriangleBudget, groupOf);
  EXPECT_LE(clustered.keptTriangles.size(), output::kMeshTriangleBudget);
  std::vector<int> groupOfCluster(clustered.positions.size(), -1);
  for (std::size_t v = 0; v < groupOf.size(); ++v) {
    int& group = groupOfCluster[static_cast<std::size_t>(clustered.clusterOf[v])];
    if (group < 0) group = static_cast<int>(groupOf[v]);
    ASSERT_EQ(group, static_cast<int>(groupOf[v])) << "vertex " << v;
  }
}

TEST(MeshDecimation, LeavesAMeshUnderTheBudgetAsItIs) {
  const Sphere sphere = uvSphere(0.1, 40, 20);
  const output::ClusteredMesh clustered = output::clusterToBudget(sphere.vertices, sphere.triangles, 10'000);
  EXPECT_EQ(clustered.keptTriangles.size(), sphere.triangles.size());
  EXPECT_EQ(clustered.cell, 0.0);
}

// The sphere as an OBJ, its upper and lower halves in two material groups.
std::string objOf(const Sphere& s) {
  std::ostringstream out;
  for (const Vec3& v : s.vertices) out << "v " << v.x << ' ' << v.y << ' ' << v.z << '\n';
  const std::size_t half = s.triangles.size() / 2;
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    if (t == 0) out << "usemtl upper\n";
    if (t == half) out << "usemtl lower\n";
    out << 'f';
    for (const std::int32_t v : s.triangles[t]) out << ' ' << v + 1;
    out << '\n';
  }
  return out.str();
}

std::string binaryStlOf(const Sphere& s) {
  std::string out(80, ' ');
  const auto count = static_cast<std::uint32_t>(s.triangles.size());
  out.append(reinterpret_cast<const char*>(&count), 4);
  for (const Triangle& t : s.triangles) {
    std::array<float, 12> values{};
    for (std::size_t k = 0; k < 3; ++k) {
      const Vec3& p = s.vertices[static_cast<std::size_t>(t[k])];
      values[3 + 3 * k] = static_cast<float>(p.x);
      values[4 + 3 * k] = static_cast<float>(p.y);
      values[5 + 3 * k] = static_cast<float>(p.z);
    }
    out.append(reinterpret_cast<const char*>(values.data()), sizeof(values));
    out.append(2, '\0');
  }
  return out;
}

TEST(MeshDecimation, WritesObjAndStlFilesBackDecimatedAndThePageSaysSo) {
  const fs::path dir = fs::temp_directory_path() / "robophi_mesh_decimation";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const Sphere sphere = uvSphere(0.1, 200, 100);
  testing::writeText(dir / "sphere.obj", objOf(sphere));
  {
    std::ofstream stl(dir / "sphere.stl", std::ios::binary);
    stl << binaryStlOf(sphere);
  }
  const output::PageMesh obj = output::pageMesh((dir / "sphere.obj").string(), "obj");
  EXPECT_EQ(obj.problem, "");
  EXPECT_TRUE(obj.rewritten);
  EXPECT_EQ(obj.format, "obj");
  EXPECT_EQ(obj.trianglesBefore, 39'600u);
  EXPECT_LE(obj.trianglesAfter, output::kMeshTriangleBudget);
  std::size_t faces = 0, groups = 0;
  std::istringstream lines(obj.bytes);
  for (std::string line; std::getline(lines, line);) {
    faces += line.starts_with("f ");
    groups += line.starts_with("usemtl ");
  }
  EXPECT_EQ(faces, obj.trianglesAfter);
  EXPECT_EQ(groups, 2u);
  EXPECT_LT(obj.bytes.size(), fs::file_size(dir / "sphere.obj") / 2);
  // Its materials in an MTL, by the names its groups use (assimp's default first).
  EXPECT_NE(obj.materials.find("newmtl m1_upper\n"), std::string::npos) << obj.materials;
  EXPECT_NE(obj.bytes.find("usemtl m1_upper\n"), std::string::npos);
  EXPECT_NE(obj.bytes.find("usemtl m2_lower\n"), std::string::npos);

  const output::PageMesh stl = output::pageMesh((dir / "sphere.stl").string(), "stl");
  EXPECT_EQ(stl.format, "stl");
  EXPECT_EQ(stl.trianglesBefore, 39'600u);
  EXPECT_TRUE(stl.materials.empty());
  ASSERT_EQ(stl.bytes.size(), 84 + 50 * stl.trianglesAfter);
  std::uint32_t count = 0;
  std::memcpy(&count, stl.bytes.data() + 80, 4);
  EXPECT_EQ(count, stl.trianglesAfter);
  EXPECT_LE(count, output::kMeshTriangleBudget);

  // In the page's data: the decimated bytes, with both triangle counts.
  const nlohmann::json world = {
      {"robots", {{"meshes", {{{"path", (dir / "sphere.obj").string()}, {"format", "obj"}}}}}}};
  const std::string json = "{\"x\":0" + output::meshFilesJson(world.dump(), 50e6) + "}";
  const nlohmann::json files = nlohmann::json::parse(json)["meshFiles"];
  ASSERT_EQ(files.size(), 1u);
  EXPECT_EQ(files[0]["decimatedFrom"], 39'600);
  EXPECT_EQ(files[0]["triangles"], obj.trianglesAfter);
  EXPECT_EQ(files[0]["bytes"], obj.bytes.size());
  EXPECT_EQ(files[0]["mtl"], obj.materials);

  // Under the budget: nothing decimated, the file as it is.
  const Sphere small = uvSphere(0.1, 40, 20);
  testing::writeText(dir / "small.obj", objOf(small));
  const output::PageMesh same = output::pageMesh((dir / "small.obj").string(), "obj");
  EXPECT_FALSE(same.rewritten);
  EXPECT_EQ(same.bytes, testing::readText(dir / "small.obj"));
  // Its materials by their own names (the page's OBJLoader takes them so).
  EXPECT_NE(same.materials.find("newmtl upper\n"), std::string::npos) << same.materials;
  EXPECT_EQ(same.trianglesBefore, small.triangles.size());
  fs::remove_all(dir);
}

}  // namespace
}  // namespace robophi
