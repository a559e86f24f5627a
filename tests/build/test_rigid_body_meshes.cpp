// Rigid bodies from the real robots' meshes (ROBOPHI_ROBOTS_DIR, ../shared/robots):
// every collision mesh loads, and a body filled from it carries the URDF's
// <inertial> (read here with tinyxml2) at 30 and 100 particles.

#include <gtest/gtest.h>
#include <tinyxml2.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "build/shape_fill.h"
#include "robophi/build/rigid_body.h"

namespace robophi::build {
namespace {

namespace fs = std::filesystem;

const fs::path kRobots = ROBOPHI_ROBOTS_DIR;

Vec3 readVec3(const char* text, const Vec3& fallback) {
  if (text == nullptr) return fallback;
  std::istringstream in(text);
  Vec3 v;
  in >> v.x >> v.y >> v.z;
  return v;
}

Frame originOf(const tinyxml2::XMLElement* parent) {
  const tinyxml2::XMLElement* origin = parent->FirstChildElement("origin");
  if (origin == nullptr) return {};
  return Frame::fromXyzRpy(readVec3(origin->Attribute("xyz"), {}),
                           readVec3(origin->Attribute("rpy"), {}));
}

// A URDF link as RigidBodySpec: <inertial> and the <collision> shapes (meshes by
// path relative to the URDF, "package://" taken as the URDF's folder).
struct Link {
  std::string name;
  RigidBodySpec spec;
};

std::vector<Link> readLinks(const fs::path& urdf) {
  tinyxml2::XMLDocument doc;
  EXPECT_EQ(doc.LoadFile(urdf.string().c_str()), tinyxml2::XML_SUCCESS) << urdf;
  std::vector<Link> links;
  const auto* robot = doc.FirstChildElement("robot");
  if (robot == nullptr) return links;
  for (const auto* link = robot->FirstChildElement("link"); link != nullptr;
       link = link->NextSiblingElement("link")) {
    const auto* inertial = link->FirstChildElement("inertial");
    if (inertial == nullptr) continue;
    Link out{link->Attribute("name"), {}};
    const Frame frame = originOf(inertial);
    out.spec.mass = inertial->FirstChildElement("mass")->DoubleAttribute("value");
    out.spec.centerOfMass = frame.origin;
    const auto* i = inertial->FirstChildElement("inertia");
    out.spec.inertia = rotateInertia(
        {i->DoubleAttribute("ixx"), i->DoubleAttribute("iyy"), i->DoubleAttribute("izz"),
         i->DoubleAttribute("ixy"), i->DoubleAttribute("ixz"), i->DoubleAttribute("iyz")},
        frame);
    for (const auto* c = link->FirstChildElement("collision"); c != nullptr;
         c = c->NextSiblingElement("collision")) {
      const auto* g = c->FirstChildElement("geometry");
      ShapeSpec shape;
      shape.frame = originOf(c);
      if (const auto* mesh = g->FirstChildElement("mesh")) {
        std::string file = mesh->Attribute("filename");
        if (file.rfind("package://", 0) == 0) file = file.substr(10);
        shape.kind = ShapeSpec::Kind::kMesh;
        shape.mesh = loadMesh((urdf.parent_path() / file).string(),
                              readVec3(mesh->Attribute("scale"), {1, 1, 1}));
      } else if (const auto* box = g->FirstChildElement("box")) {
        shape.kind = ShapeSpec::Kind::kBox;
        shape.size = readVec3(box->Attribute("size"), {});
      } else if (const auto* cyl = g->FirstChildElement("cylinder")) {
        shape.kind = ShapeSpec::Kind::kCylinder;
        shape.radius = cyl->DoubleAttribute("radius");
        shape.length = cyl->DoubleAttribute("length");
      } else if (const auto* sphere = g->FirstChildElement("sphere")) {
        shape.kind = ShapeSpec::Kind::kSphere;
        shape.radius = sphere->DoubleAttribute("radius");
      }
      out.spec.shapes.push_back(std::move(shape));
    }
    links.push_back(std::move(out));
  }
  return links;
}

void skipWithoutRobots() {
  if (!fs::exists(kRobots)) GTEST_SKIP() << "no robot data at " << kRobots;
}

TEST(MeshLoad, EveryRobotMeshLoads) {
  skipWithoutRobots();
  int count = 0;
  for (const auto& entry : fs::recursive_directory_iterator(kRobots)) {
    const std::string ext = entry.path().extension().string();
    if (ext != ".stl" && ext != ".STL" && ext != ".obj" && ext != ".dae") continue;
    const TriangleMesh mesh = loadMesh(entry.path().string());
    EXPECT_GT(mesh.triangles.size(), 10u) << entry.path();
    ++count;
  }
  EXPECT_EQ(count, 48);  // 22 STL + 26 OBJ
}

TEST(MeshLoad, ScaleAndBadFilesNameTheFile) {
  skipWithoutRobots();
  const std::string finger = (kRobots / "pr2_gripper" / "l_finger_collision.stl").string();
  const TriangleMesh one = loadMesh(finger), two = loadMesh(finger, {2, -1, 0.5});
  ASSERT_EQ(one.vertices.size(), two.vertices.size());
  EXPECT_DOUBLE_EQ(two.vertices[5].x, 2 * one.vertices[5].x);
  EXPECT_DOUBLE_EQ(two.vertices[5].y, -one.vertices[5].y);
  // A mirroring scale keeps the mesh wound outwards: its volume stays positive.
  ShapeSpec s;
  s.kind = ShapeSpec::Kind::kMesh;
  s.mesh = two;
  EXPECT_GT(uniformMassProperties({s}, 1.0).inertia.xx, 0.0);

  const auto message = [](const std::string& path) {
    try {
      loadMesh(path);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("/nonexistent/arm.stl"), "mesh '/nonexistent/arm.stl': no such file");
  const fs::path junk = fs::temp_directory_path() / "robophi_junk_mesh.stl";
  std::ofstream(junk) << "this is not a mesh\n";
  const std::string got = message(junk.string());
  EXPECT_EQ(got.rfind("mesh '" + junk.string() + "': cannot be read", 0), 0u) << got;
  fs::remove(junk);
}

// Every link of the iiwa and the Panda with a mass: the URDF's mass, centre of
// mass and inertia at 30 and 100 particles (the fit's tolerances: mass 1e-9
// relative, centre 1e-6 m, principal moments 1%).
void expectRobotFits(const fs::path& urdf, int expectedLinks) {
  const std::vector<Link> links = readLinks(urdf);
  int fitted = 0;
  for (const Link& link : links) {
    if (!(link.spec.mass > 0.0)) continue;
    for (const int count : {30, 100}) {
      RigidBodySpec spec = link.spec;
      spec.particleCount = count;
      const RigidBody body = makeRigidBody(spec);
      SCOPED_TRACE(link.name + " at " + std::to_string(count) + " particles");
      EXPECT_TRUE(body.fitted);
      const MassProperties got = massProperties(body.object.position, body.object.mass);
      EXPECT_NEAR(got.mass, spec.mass, 1e-9 * spec.mass);
      EXPECT_NEAR(norm(got.centerOfMass - spec.centerOfMass), 0.0, 1e-6);
      const auto a = principalMoments(got.inertia), b = principalMoments(spec.inertia);
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], 0.01 * b[k]);
      // The lattice is near the count asked for (carriers and thin parts aside).
      const auto lattice = static_cast<int>(body.object.size() - body.carriers.size());
      EXPECT_GE(lattice, count / 2);
      EXPECT_LE(lattice, 2 * count);
      const double mean = spec.mass / static_cast<double>(body.object.size());
      const double smallest = *std::min_element(body.object.mass.begin(), body.object.mass.end());
      EXPECT_GE(smallest, 0.2 * mean * (1 - 1e-9));
      for (const auto& note : body.notes)
        std::cout << "  " << link.name << " (" << count << "): " << note << "\n";
      ++fitted;
    }
  }
  EXPECT_EQ(fitted, 2 * expectedLinks);
}

TEST(RigidBodyMeshes, KukaIiwaLinksCarryTheirInertials) {
  skipWithoutRobots();
  expectRobotFits(kRobots / "kuka_iiwa" / "model.urdf", 7);  // link_0 has mass 0
}

TEST(RigidBodyMeshes, FrankaPandaLinksCarryTheirInertials) {
  skipWithoutRobots();
  expectRobotFits(kRobots / "franka_panda" / "panda.urdf", 11);  // link8 has mass 0
}

TEST(RigidBodyMeshes, EveryRobotsLinksFit) {
  skipWithoutRobots();
  for (const char* urdf : {"husky/husky.urdf", "r2d2/r2d2.urdf", "pr2_gripper/pr2_gripper.urdf",
                           "cartpole/cartpole.urdf"}) {
    SCOPED_TRACE(urdf);
    for (const Link& link : readLinks(kRobots / urdf)) {
      if (!(link.spec.mass > 0.0)) continue;
      const RigidBody body = makeRigidBody(link.spec);
      EXPECT_TRUE(body.fitted) << link.name;
      for (const auto& note : body.notes) std::cout << "  " << link.name << ": " << note << "\n";
    }
  }
}

}  // namespace
}  // namespace robophi::build
