// What the importer keeps of meshes between loads (issue 40: the URDF fuzz
// target ran at 58 inputs a second, classifying the shared robots' meshes anew
// in every input): a kept mesh, volume or lattice is the one the work gives,
// a mesh file changed on disk (or a file of its own that appears) is read
// again, and a load served from what was kept records the files it reads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "build/mesh_memo.h"
#include "build/shape_fill.h"
#include "robophi/build/input_files.h"
#include "robophi/build/rigid_body.h"
#include "test_files.h"

namespace robophi::build {
namespace {

namespace fs = std::filesystem;

// An OBJ tetrahedron whose apex is at height `apex`, naming `mtl` if not empty.
std::string tetrahedron(double apex, const std::string& mtl = "") {
  std::string text = mtl.empty() ? "" : "mtllib " + mtl + "\n";
  return text + "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0.2 0.2 " + std::to_string(apex) +
         "\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";
}

bool sameBits(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0);
}

class MeshMemo : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = testing::makeTempFolder("robophi_mesh_memo_"); }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(MeshMemo, AMeshFileChangedOnDiskIsReadAgain) {
  const fs::path obj = dir_ / "t.obj";
  testing::writeText(obj, tetrahedron(1.0));
  const TriangleMesh first = loadMesh(obj.string());
  EXPECT_TRUE(detail::sameMesh(loadMesh(obj.string()), first));
  testing::writeText(obj, tetrahedron(2.0));
  const TriangleMesh second = loadMesh(obj.string());
  EXPECT_FALSE(detail::sameMesh(second, first));
  double top = 0.0;
  for (const Vec3& v : second.vertices) top = std::max(top, v.z);
  EXPECT_EQ(top, 2.0);
  // Another scale of the same file is its own mesh.
  const TriangleMesh scaled = loadMesh(obj.string(), {1.0, 1.0, 0.5});
  top = 0.0;
  for (const Vec3& v : scaled.vertices) top = std::max(top, v.z);
  EXPECT_EQ(top, 1.0);
}

TEST_F(MeshMemo, ALoadFromWhatWasKeptRecordsTheFilesAndSeesAFileThatAppears) {
  const fs::path obj = dir_ / "t.obj", mtl = dir_ / "t.mtl";
  testing::writeText(obj, tetrahedron(1.0, "t.mtl"));
  const std::string objPath = fs::absolute(obj).lexically_normal().string();
  const std::string mtlPath = fs::absolute(mtl).lexically_normal().string();
  const auto logged = [&](const InputFileLog& log, const std::string& path) {
    return std::find(log.files().begin(), log.files().end(), path) != log.files().end();
  };
  (void)loadMesh(obj.string());
  {
    const InputFileLog log;  // served from what was kept: the OBJ recorded all the same
    (void)loadMesh(obj.string());
    EXPECT_TRUE(logged(log, objPath));
  }
  // Its material file appears: the load reads it (and records it).
  testing::writeText(mtl, "newmtl m\nKd 1 0 0\n");
  {
    const InputFileLog log;
    (void)loadMesh(obj.string());
    EXPECT_TRUE(logged(log, objPath));
    EXPECT_TRUE(logged(log, mtlPath));
  }
  {
    const InputFileLog log;  // and again, kept with it
    (void)loadMesh(obj.string());
    EXPECT_TRUE(logged(log, mtlPath));
  }
}

TEST_F(MeshMemo, AKeptVolumeAndLatticeAreTheWorksOwn) {
  const fs::path obj = dir_ / "open.obj";
  // A tetrahedron without its base: open, so its volume is the voxel count.
  testing::writeText(obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0.2 0.2 1\nf 1 2 4\nf 2 3 4\nf 3 1 4\n");
  ShapeSpec shape;
  shape.kind = ShapeSpec::Kind::kMesh;
  shape.mesh = loadMesh(obj.string());
  const double volume = detail::shapeVolume(shape);
  const double again = detail::shapeVolume(shape);  // kept
  EXPECT_EQ(std::memcmp(&volume, &again, sizeof(double)), 0);
  const double worked = detail::meshVolume(shape.mesh);
  EXPECT_EQ(std::memcmp(&volume, &worked, sizeof(double)), 0);
  EXPECT_GT(volume, 0.0);
  const detail::ShapeLattice lattice = detail::fillShape(shape, 0.1);
  const detail::ShapeLattice kept = detail::fillShape(shape, 0.1);
  EXPECT_FALSE(lattice.position.empty());
  EXPECT_TRUE(sameBits(lattice.position, kept.position));
  EXPECT_EQ(lattice.report.openEdges, kept.report.openEdges);
  EXPECT_GT(kept.report.openEdges, 0);
  // Another frame moves the kept lattice as it moves the work's.
  ShapeSpec moved = shape;
  moved.frame = Frame::fromXyzRpy({0.5, -0.25, 1.0}, {0.1, 0.2, 0.3});
  const detail::ShapeLattice there = detail::fillShape(moved, 0.1);
  ASSERT_EQ(there.position.size(), lattice.position.size());
  for (std::size_t k = 0; k < there.position.size(); ++k)
    EXPECT_LT(norm(there.position[k] - moved.frame.apply(lattice.position[k])), 1e-12);
  // A memo of its own, one mesh past its budget: nothing kept, nothing wrong.
  detail::MeshWorkMemo small(64);
  const std::uint64_t digest = detail::meshDigest(shape.mesh);
  small.keepVolume(shape.mesh, digest, volume);
  EXPECT_FALSE(small.volume(shape.mesh, digest).has_value());
}

}  // namespace
}  // namespace robophi::build
