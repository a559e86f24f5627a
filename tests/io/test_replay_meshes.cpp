// The robots' meshes in the replay page (output/replay_meshes.h, docs/viewer.md
// "Robots as they look"): every format under the same triangle budget (the UR5's
// COLLADA meshes written back as OBJ with their materials, their nodes' transforms
// and units kept), and every file read by the checked reader: a FIFO or a face of
// 200 000 corners given as a visual mesh is a warning at once, and the run still
// writes its page.

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "output/mesh_decimation.h"
#include "output/replay.h"
#include "output/replay_meshes.h"
#include "robophi/build/shaded_mesh.h"
#include "robophi/scene/scene.h"
#include "run/runner.h"
#include "test_files.h"
#include "io/point_box.h"

namespace robophi {
namespace {

namespace fs = std::filesystem;

const fs::path kUr5Visual = fs::path(ROBOPHI_ROBOTS_DIR) / ".." / "robots-wild" / "example-robot-data" /
                            "robots" / "ur_description" / "meshes" / "ur5" / "visual";
const std::array<const char*, 7> kUr5Meshes = {"base",    "shoulder", "upperarm", "forearm",
                                               "wrist1", "wrist2",   "wrist3"};

double seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// The five UR5 meshes of 13 000 to 29 000 triangles go in as OBJs of at most
// 10 000, with the DAE's materials in an MTL; read back, each has its triangles
// and the original's box (within 2% of its size: the nodes' transforms and
// <unit> are in its vertices).
TEST(ReplayMeshes, TheUr5sDaeMeshesGoInUnderTheTriangleBudget) {
  if (!fs::exists(kUr5Visual / "base.dae")) GTEST_SKIP() << "no UR5 meshes at " << kUr5Visual;
  const fs::path dir = testing::makeTempFolder("robophi_ur5_meshes");
  nlohmann::json meshes = nlohmann::json::array();
  std::size_t rewritten = 0;
  for (const char* name : kUr5Meshes) {
    const fs::path path = kUr5Visual / (std::string(name) + ".dae");
    meshes.push_back({{"path", path.string()}, {"format", "dae"}});
    const auto start = std::chrono::steady_clock::now();
    const output::PageMesh page = output::pageMesh(path.string(), "dae");
    const double took = seconds(start);
    ASSERT_EQ(page.problem, "") << name;
    EXPECT_LE(page.trianglesAfter, output::kMeshTriangleBudget) << name;
    std::printf("# %-8s %6zu -> %5zu triangles, %8ju -> %7zu bytes, %.2f s\n", name,
                page.trianglesBefore, page.trianglesAfter, fs::file_size(path),
                page.bytes.size() + page.materials.size(), took);
    if (page.trianglesBefore <= output::kMeshTriangleBudget) {
      EXPECT_FALSE(page.rewritten) << name;
      EXPECT_EQ(page.format, "dae");
      continue;
    }
    ++rewritten;
    EXPECT_TRUE(page.rewritten) << name;
    ASSERT_EQ(page.format, "obj") << name;
    EXPECT_GE(page.trianglesAfter, output::kMeshTriangleBudget / 2) << name;  // not needlessly coarse
    EXPECT_NE(page.materials.find("Kd "), std::string::npos) << name << ": " << page.materials;
    const fs::path obj = dir / (std::string(name) + ".obj");
    testing::writeText(obj, page.bytes);
    const build::ShadedMesh before = build::loadShadedMesh(path.string());
    const build::ShadedMesh after = build::loadShadedMesh(obj.string());
    EXPECT_EQ(after.mesh.triangles.size(), page.trianglesAfter) << name;
    const auto boxBefore = test::boxOf(before.mesh.vertices);
    const auto boxAfter = test::boxOf(after.mesh.vertices);
    const double size = norm(boxBefore[1] - boxBefore[0]);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(boxAfter[0][k], boxBefore[0][k], 0.02 * size) << name << " axis " << k;
      EXPECT_NEAR(boxAfter[1][k], boxBefore[1][k], 0.02 * size) << name << " axis " << k;
    }
  }
  EXPECT_EQ(rewritten, 5u);
  // The page's share: the seven files went in as 6.66 MB; now 3.38 MB.
  std::uintmax_t fileBytes = 0;
  for (const char* name : kUr5Meshes) fileBytes += fs::file_size(kUr5Visual / (std::string(name) + ".dae"));
  std::vector<std::string> warnings;
  const nlohmann::json world = {{"robots", {{"meshes", meshes}}}};
  const std::string json =
      "{\"x\":0" +
      output::meshFilesJson(world.dump(), 50e6, output::kMeshBudgetBytes, output::kMeshTriangleBudget, &warnings) +
      "}";
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  std::size_t pageBytes = 0;
  const nlohmann::json files = nlohmann::json::parse(json)["meshFiles"];
  ASSERT_EQ(files.size(), kUr5Meshes.size());
  for (const nlohmann::json& file : files) {
    EXPECT_FALSE(file.contains("note")) << file["note"];
    pageBytes += file["bytes"].get<std::size_t>();
    if (file.contains("triangles")) {
      EXPECT_LE(file["triangles"].get<std::size_t>(), output::kMeshTriangleBudget);
    }
  }
  std::printf("# UR5 meshes in the page: %ju bytes of files -> %zu bytes\n", fileBytes, pageBytes);
  EXPECT_LT(static_cast<double>(pageBytes), 0.6 * static_cast<double>(fileBytes));  // 51% (2026-12-06)
  fs::remove_all(dir);
}

// A COLLADA file's <unit> is in the vertices read (as three.js's ColladaLoader
// draws it), its <up_axis> not (ROS meshes are Z-up).
TEST(ReplayMeshes, ADaesUnitIsInItsVerticesAndItsUpAxisIsNot) {
  if (!fs::exists(kUr5Visual / "wrist3.dae")) GTEST_SKIP() << "no UR5 meshes at " << kUr5Visual;
  const fs::path dir = testing::makeTempFolder("robophi_dae_unit");
  std::string text = testing::readText(kUr5Visual / "wrist3.dae");
  const std::string meter = "<unit name=\"meter\" meter=\"1\"/>";
  const std::size_t at = text.find(meter);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, meter.size(), "<unit name=\"millimetre\" meter=\"0.001\"/>");
  const std::string up = "<up_axis>Z_UP</up_axis>";
  ASSERT_NE(text.find(up), std::string::npos);
  text.replace(text.find(up), up.size(), "<up_axis>Y_UP</up_axis>");
  testing::writeText(dir / "wrist3_mm.dae", text);
  const build::ShadedMesh metres = build::loadShadedMesh((kUr5Visual / "wrist3.dae").string());
  const build::ShadedMesh millimetres = build::loadShadedMesh((dir / "wrist3_mm.dae").string());
  ASSERT_EQ(metres.mesh.vertices.size(), millimetres.mesh.vertices.size());
  for (std::size_t v = 0; v < metres.mesh.vertices.size(); v += 97)
    EXPECT_LT(norm(millimetres.mesh.vertices[v] - 0.001 * metres.mesh.vertices[v]), 1e-9) << v;
  // Its materials' colours, as its <effect>s give them.
  ASSERT_FALSE(metres.materials.empty());
  EXPECT_TRUE(metres.materials[0].hasColor);
  fs::remove_all(dir);
}

// A FIFO, a face of 200 000 corners and a missing file: each is left out of the
// page with a note and a warning that says why, at once (the FIFO is never
// waited on, the face never triangulated).
TEST(ReplayMeshes, AFifoAndAHugeFaceAreWarningsAtOnce) {
  const fs::path dir = testing::makeTempFolder("robophi_bad_visuals");
  ASSERT_EQ(mkfifo((dir / "pipe.stl").c_str(), 0600), 0);
  testing::writeText(dir / "huge_face.obj", testing::polygonObj(200000));
  const nlohmann::json world = {{"robots",
                                 {{"meshes",
                                   {{{"path", (dir / "pipe.stl").string()}, {"format", "stl"}},
                                    {{"path", (dir / "huge_face.obj").string()}, {"format", "obj"}},
                                    {{"path", (dir / "missing.dae").string()}, {"format", "dae"}}}}}}};
  std::vector<std::string> warnings;
  const auto start = std::chrono::steady_clock::now();
  const std::string json =
      "{\"x\":0" +
      output::meshFilesJson(world.dump(), 50e6, output::kMeshBudgetBytes, output::kMeshTriangleBudget, &warnings) +
      "}";
  const double took = seconds(start);
  std::printf("# three bad visual meshes: %.3f s\n", took);
  EXPECT_LT(took, 2.0);
  const nlohmann::json files = nlohmann::json::parse(json)["meshFiles"];
  ASSERT_EQ(files.size(), 3u);
  for (const nlohmann::json& file : files) EXPECT_TRUE(file["data"].is_null()) << file.dump();
  EXPECT_EQ(files[0]["note"], "not drawn: '" + (dir / "pipe.stl").string() +
                                  "': is a FIFO (named pipe), not a regular file");
  EXPECT_NE(files[1]["note"].get<std::string>().find("has 200000 vertex indices, more than the budget"),
            std::string::npos)
      << files[1]["note"];
  EXPECT_EQ(files[2]["note"], "not drawn: '" + (dir / "missing.dae").string() + "': no such file");
  ASSERT_EQ(warnings.size(), 3u);
  EXPECT_EQ(warnings[0], "replay.html: visual mesh " + files[0]["note"].get<std::string>());
  fs::remove_all(dir);
}

// A URDF whose arm's visual is a face of 200 000 corners (its collision a box):
// it loads and runs, its replay is written, and the run warns of the face. Then
// the base's visual mesh is replaced by a FIFO and the page made again from the
// folder (robophi export html): a warning, at once, and the page.
TEST(ReplayMeshes, ARunWithAHugeFaceOrAFifoAsVisualsWritesItsReplayAndWarns) {
  const fs::path dir = testing::makeTempFolder("robophi_bad_visual_run");
  testing::writeText(dir / "part.stl", testing::boxStl(0.2, 0.2, 0.2));
  testing::writeText(dir / "huge_face.obj", testing::polygonObj(200000));
  testing::writeText(dir / "robot.urdf", R"(<robot name="bad_visuals">
  <link name="base">
    <inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><geometry><mesh filename="part.stl"/></geometry></visual>
    <collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision>
  </link>
  <link name="arm">
    <inertial><mass value="0.5"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><geometry><mesh filename="huge_face.obj"/></geometry></visual>
    <collision><geometry><box size="0.1 0.1 0.3"/></geometry></collision>
  </link>
  <joint name="hinge" type="revolute">
    <parent link="base"/><child link="arm"/><origin xyz="0 0 0.3"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="10" velocity="1"/>
  </joint>
</robot>
)");
  auto start = std::chrono::steady_clock::now();
  const SceneLoadResult loaded = loadUrdfFile((dir / "robot.urdf").string());
  for (const Diagnostic& e : loaded.errors) ADD_FAILURE() << e.format();
  ASSERT_TRUE(loaded.ok());
  RunOptions options;
  options.settings = loaded.scene->run;
  options.settings.duration = 0.05;
  options.threads = 1;
  options.outDir = (dir / "run").string();
  const RunReport report = runScene(*loaded.scene, options);
  double took = seconds(start);
  std::printf("# the run with a 200 000-corner face as a visual: %.2f s\n", took);
  EXPECT_LT(took, 10.0);
  EXPECT_EQ(report.status, "ok") << report.failure;
  EXPECT_TRUE(fs::exists(dir / "run" / "replay.html"));
  std::size_t face = 0;
  for (const std::string& w : report.warnings)
    face += w.find("huge_face.obj': face 0 of mesh 0 has 200000 vertex indices") != std::string::npos;
  EXPECT_EQ(face, 1u);

  fs::remove(dir / "part.stl");
  ASSERT_EQ(mkfifo((dir / "part.stl").c_str(), 0600), 0);
  fs::remove(dir / "run" / "replay.html");
  std::vector<std::string> warnings;
  ReplayOptions replay;
  replay.warnings = &warnings;
  std::string error;
  start = std::chrono::steady_clock::now();
  EXPECT_TRUE(writeReplayHtml((dir / "run").string(), replay, error)) << error;
  took = seconds(start);
  std::printf("# robophi export html with a FIFO and a 200 000-corner face as visuals: %.2f s\n", took);
  EXPECT_LT(took, 5.0);
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_NE(warnings[0].find("part.stl': is a FIFO (named pipe), not a regular file"), std::string::npos)
      << warnings[0];
  EXPECT_NE(warnings[1].find("huge_face.obj': face 0 of mesh 0"), std::string::npos) << warnings[1];
  const std::string page = testing::readText(dir / "run" / "replay.html");
  EXPECT_NE(page.find("is a FIFO (named pipe)"), std::string::npos);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace robophi
