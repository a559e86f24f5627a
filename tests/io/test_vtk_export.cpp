// ParaView export: a hand-made run folder comes back from the .vtp/.pvd files
// with its points, velocities, radii and connector strains.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "output/vtk_export.h"
#include "test_files.h"

namespace robophi {
namespace {

namespace fs = std::filesystem;

using testing::readText;
using testing::writeText;

// The value of attribute `name` in the first tag that starts at or after `from`.
std::string attribute(const std::string& xml, std::size_t from, const std::string& name) {
  const std::size_t tagEnd = xml.find('>', from);
  const std::size_t at = xml.find(" " + name + "=\"", from);
  if (at == std::string::npos || at > tagEnd) return "";
  const std::size_t start = at + name.size() + 3;
  return xml.substr(start, xml.find('"', start) - start);
}

// The numbers of <DataArray ... Name="name" ...>...</DataArray>; empty if absent.
std::vector<double> dataArray(const std::string& xml, const std::string& name) {
  const std::size_t at = xml.find("Name=\"" + name + "\"");
  if (at == std::string::npos) return {};
  const std::size_t start = xml.find('>', at) + 1;
  const std::size_t end = xml.find("</DataArray>", start);
  std::istringstream in(xml.substr(start, end - start));
  std::vector<double> values;
  for (double v; in >> v;) values.push_back(v);
  return values;
}

// A run folder by hand: three particles in a line along x, two connectors of rest
// length 1, three frames at t = 0, 0.1, 0.3 s, particle 2 moving along x.
class VtkExportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::makeTempFolder("robophi_vtk_test_");
    writeText(dir_ / "model.json", R"({
      "name": "three in a line",
      "particles": {"count": 3, "mass": [1, 1, 1], "radius": [0.1, 0.2, 0.3],
                    "object": [0, 0, 1], "fixed": [1, 0, 0]},
      "objects": [{"name": "a", "kind": "rope", "first": 0, "count": 2, "material": 0},
                  {"name": "b", "kind": "ball", "first": 2, "count": 1, "material": 0}],
      "connectors": {"linear": [[0, 1, 1.0], [1, 2, 1.0]], "torsion": [], "joint": []},
      "joints": [],
      "gravity": [0, 0, -9.81]
    })");
    writeText(dir_ / "particles.csv",
              "t,x0,y0,z0,x1,y1,z1,x2,y2,z2\n"
              "0,0,0,0,1,0,0,2,0,0\n"
              "0.1,0,0,0,1,0,0,2.1,0,0\n"
              "0.3,0,0,0,1,0,0,2.5,0,0\n");
    writeText(dir_ / "energy.csv",
              "t,dt,kinetic,potential,dissipated,total\n0,0.001,0,1,0,1\n0.3,0.001,0.5,0.5,0,1\n");
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
};

TEST_F(VtkExportTest, WritesOneFramePerRowAndACollection) {
  std::string error;
  ASSERT_TRUE(writeVtkSeries(dir_.string(), (dir_ / "vtk").string(), error)) << error;

  const std::string pvd = readText(dir_ / "vtk" / "run.pvd");
  std::vector<double> timesteps;
  std::vector<std::string> files;
  for (std::size_t at = pvd.find("<DataSet"); at != std::string::npos;
       at = pvd.find("<DataSet", at + 1)) {
    timesteps.push_back(std::stod(attribute(pvd, at, "timestep")));
    files.push_back(attribute(pvd, at, "file"));
  }
  EXPECT_EQ(timesteps, (std::vector<double>{0.0, 0.1, 0.3}));
  ASSERT_EQ(files.size(), 3u);
  for (const std::string& file : files) EXPECT_TRUE(fs::exists(dir_ / "vtk" / file)) << file;

  const std::string frame = readText(dir_ / "vtk" / files[2]);
  const std::size_t piece = frame.find("<Piece");
  EXPECT_EQ(attribute(frame, piece, "NumberOfPoints"), "3");
  EXPECT_EQ(attribute(frame, piece, "NumberOfLines"), "2");
  EXPECT_EQ(dataArray(frame, "position"), (std::vector<double>{0, 0, 0, 1, 0, 0, 2.5, 0, 0}));
  EXPECT_EQ(dataArray(frame, "radius"), (std::vector<double>{0.1, 0.2, 0.3}));
  EXPECT_EQ(dataArray(frame, "object"), (std::vector<double>{0, 0, 1}));
  EXPECT_EQ(dataArray(frame, "fixed"), (std::vector<double>{1, 0, 0}));
  EXPECT_EQ(dataArray(frame, "connectivity"), (std::vector<double>{0, 1, 1, 2}));
  EXPECT_EQ(dataArray(frame, "offsets"), (std::vector<double>{2, 4}));
}

TEST_F(VtkExportTest, StrainIsStretchOverRestLength) {
  std::string error;
  ASSERT_TRUE(writeVtkSeries(dir_.string(), (dir_ / "vtk").string(), error)) << error;
  const std::vector<double> expected[] = {{0.0, 0.0}, {0.0, 0.1}, {0.0, 0.5}};
  for (int k = 0; k < 3; ++k) {
    const std::vector<double> strain =
        dataArray(readText(dir_ / "vtk" / ("frame_00000" + std::to_string(k) + ".vtp")), "strain");
    ASSERT_EQ(strain.size(), 2u) << "frame " << k;
    for (std::size_t s = 0; s < 2; ++s) EXPECT_NEAR(strain[s], expected[k][s], 1e-12);
  }
}

TEST_F(VtkExportTest, VelocityIsCentralDifferenceInsideOneSidedAtEnds) {
  std::string error;
  ASSERT_TRUE(writeVtkSeries(dir_.string(), (dir_ / "vtk").string(), error)) << error;
  // Particle 2: x = 2, 2.1, 2.5 at t = 0, 0.1, 0.3.
  const double expectedVx[] = {0.1 / 0.1, 0.5 / 0.3, 0.4 / 0.2};
  for (int k = 0; k < 3; ++k) {
    const std::vector<double> v = dataArray(
        readText(dir_ / "vtk" / ("frame_00000" + std::to_string(k) + ".vtp")), "velocity");
    ASSERT_EQ(v.size(), 9u);
    EXPECT_NEAR(v[6], expectedVx[k], 1e-12) << "frame " << k;
    for (int i = 0; i < 6; ++i) EXPECT_EQ(v[i], 0.0);
  }
}

TEST_F(VtkExportTest, NamesTheFileAndLineOfABadRow) {
  writeText(dir_ / "particles.csv", "t,x0,y0,z0,x1,y1,z1,x2,y2,z2\n0,0,0,0,1,0,0,2,0\n");
  std::string error;
  EXPECT_FALSE(writeVtkSeries(dir_.string(), (dir_ / "vtk").string(), error));
  EXPECT_NE(error.find("particles.csv:2"), std::string::npos) << error;
  EXPECT_NE(error.find("expected 10 values"), std::string::npos) << error;
}

TEST_F(VtkExportTest, NamesAMissingModel) {
  fs::remove(dir_ / "model.json");
  std::string error;
  EXPECT_FALSE(writeVtkSeries(dir_.string(), (dir_ / "vtk").string(), error));
  EXPECT_NE(error.find("model.json"), std::string::npos) << error;
}

}  // namespace
}  // namespace robophi
