// Checked arguments (issue 10 item 5): a bad spec or argument gives a
// std::invalid_argument (build::SpecError) naming the field and its value,
// never a crash and never a half-built object.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include "build/checks.h"
#include "robophi/build/calibration.h"
#include "robophi/build/model_builder.h"
#include "robophi/build/robots.h"
#include "robophi/scene/scene.h"

namespace robophi::build {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

struct BadSpec {
  const char* label;
  std::function<void()> build;
  const char* field;
  const char* fragment;  // a part of the message: the field and the value
};

// A small placed rope, for the builder's own checks.
ObjectPlacement rope(const char* name) {
  GeneratedObject g = makeRope({{0, 0, 0}, {1, 0, 0}, 3, 1.0, 0.0});
  resolveSprings(g, {});
  return {.name = name, .kind = "rope", .geometry = g};
}

const BadSpec kBad[] = {
    {"arm mass", [] { makeArm({.mass = -2.0}); }, "mass", "'mass' must be > 0 kg, got -2"},
    {"arm no links", [] { makeArm({.links = {}}); }, "links", "non-empty"},
    {"arm link length",
     [] {
       makeArm({.links = {0.5, 0.0}});
     },
     "links", "got 0"},
    {"arm zero axis",
     [] {
       makeArm({.axes = {{0, 0, 0}}});
     },
     "axes", "joint 1 axis is zero"},
    {"arm roll axis",
     [] {
       makeArm({.axes = {{1, 0, 0}}});
     },
     "axes", "parallel to 'direction'"},
    {"arm axes count",
     [] {
       makeArm({.axes = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}}});
     },
     "axes", "or 2 of them, got 3"},
    {"arm direction nan",
     [] {
       makeArm({.direction = {kNaN, 0, 0}});
     },
     "direction", "nan"},
    {"arm direction zero",
     [] {
       makeArm({.direction = {0, 0, 0}});
     },
     "direction", "non-zero vector, got [0, 0, 0]"},
    {"arm particles per link", [] { makeArm({.particlesPerLink = 1}); }, "particlesPerLink",
     "must be >= 2, got 1"},
    {"arm width", [] { makeArm({.width = -0.1}); }, "width", "got -0.1"},
    {"arm frequency", [] { makeArm({.structure = {.naturalFrequency = 0.0}}); }, "naturalFrequency",
     "'naturalFrequency' must be > 0 rad/s, got 0"},
    {"arm stiffness", [] { makeArm({.structure = {.stiffness = -1.0}}); }, "stiffness", "got -1"},
    {"arm joint damping", [] { makeArm({.jointDamping = kInf}); }, "jointDamping", "got inf"},
    {"vehicle size",
     [] {
       makeVehicle({.size = {0.6, 0.0, 0.1}});
     },
     "size", "got [0.6, 0, 0.1]"},
    {"vehicle rim", [] { makeVehicle({.rimParticles = 3}); }, "rimParticles", "got 3"},
    {"vehicle wheel mass", [] { makeVehicle({.wheelMass = 0.0}); }, "wheelMass", "got 0"},
    {"vehicle suspension", [] { makeVehicle({.suspensionStiffness = kInf}); },
     "suspensionStiffness", "got inf"},
    {"vehicle track", [] { makeVehicle({.track = -1.0}); }, "track", "got -1"},
    {"hand palm", [] { makeHand({.palmRadius = 0.0}); }, "palmRadius", "got 0"},
    {"hand link",
     [] {
       makeHand({.links = {0.05, -0.04, 0.03}});
     },
     "links", "got -0.04"},
    {"hand spread", [] { makeHand({.spread = kNaN}); }, "spread", "got nan"},
    {"chain not unit",
     [] {
       GeneratedObject g;
       appendChain(g, {.direction = {2, 0, 0}});
     },
     "direction", "unit vector, got [2, 0, 0]"},
    {"rope particles", [] { makeRope({.particles = 1}); }, "particles", "must be >= 2, got 1"},
    {"rope same ends",
     [] {
       makeRope({.start = {1, 0, 0}, .end = {1, 0, 0}});
     },
     "end", "'end' equals 'start'"},
    {"rope mass nan", [] { makeRope({.mass = kNaN}); }, "mass", "got nan"},
    {"box cells",
     [] {
       makeBox({.cells = {2, 0, 2}});
     },
     "cells", "got 0"},
    {"box size",
     [] {
       makeBox({.size = {0.1, -0.1, 0.1}});
     },
     "size", "got [0.1, -0.1, 0.1]"},
    {"box too many",
     [] {
       makeBox({.cells = {1000, 1000, 1000}});
     },
     "cells", "1000×1000×1000 makes 1000000000 particles"},
    {"plate thickness", [] { makePlate({.thickness = -1.0}); }, "thickness", "got -1"},
    {"ball cells", [] { makeBall({.cells = 401}); }, "cells", "must be <= 400, got 401"},
    {"wheel axis",
     [] {
       makeWheel({.axis = {0, 0, 0}});
     },
     "axis", "got [0, 0, 0]"},
    {"wheel rim", [] { makeWheel({.rimParticles = 2}); }, "rimParticles", "got 2"},
    {"rotation axis",
     [] {
       GeneratedObject g = makeBox({});
       rotateObject(g, {}, {0, 0, 0}, 1.0);
     },
     "axis", "non-zero"},
    {"springs frequency",
     [] {
       GeneratedObject g = makeBox({});
       resolveSprings(g, {.naturalFrequency = -5.0});
     },
     "naturalFrequency", "got -5"},
    {"springs damping",
     [] {
       GeneratedObject g = makeBox({});
       resolveSprings(g, {.damping = kNaN});
     },
     "damping", "got nan"},
    {"calibration young",
     [] {
       const BoxSpec spec{{}, {0.2, 0.03, 0.03}, {20, 3, 3}, 1.0, 0.0};
       GeneratedObject g = makeBox(spec);
       calibrateLattice(g, spec, -1.0);
     },
     "youngModulus", "'youngModulus' must be > 0 Pa, got -1"},
    {"calibration shear",
     [] {
       const BoxSpec spec{{}, {0.2, 0.03, 0.03}, {20, 3, 3}, 1.0, 0.0};
       GeneratedObject g = makeBox(spec);
       calibrateLattice(g, spec, 1e6, 8e5);
     },
     "shearModulus", "'shearModulus' 800000 Pa is too large for 'youngModulus' 1000000 Pa"},
    {"calibration other box",
     [] {
       GeneratedObject g = makeBox({});
       calibrateLattice(g, {{}, {0.2, 0.03, 0.03}, {20, 3, 3}, 1.0, 0.0}, 1e6);
     },
     "youngModulus", "not a full box lattice of 20×3×3 cells"},
    {"builder empty name", [] { ModelBuilder().addObject(rope("")); }, "name", "not be empty"},
    {"builder colon", [] { ModelBuilder().addObject(rope("a:b")); }, "name", "must not contain"},
    {"builder duplicate",
     [] {
       ModelBuilder b;
       b.addObject(rope("r"));
       b.addObject(rope("r"));
     },
     "name", "duplicate object name 'r'"},
    {"builder velocities",
     [] {
       ObjectPlacement r = rope("r");
       r.velocity.assign(2, Vec3{});
       ModelBuilder().addObject(r);
     },
     "geometry", "3 positions but 3 masses, 3 radii, 0 fixed flags and 2 velocities"},
    {"builder velocity nan",
     [] {
       ObjectPlacement r = rope("r");
       r.velocity.assign(3, Vec3{0, kNaN, 0});
       ModelBuilder().addObject(r);
     },
     "velocity", "got [0, nan, 0]"},
    {"builder material",
     [] {
       ObjectPlacement r = rope("r");
       r.material = 3;
       ModelBuilder().addObject(r);
     },
     "material", "'material' 3 is not a material (1 defined)"},
    {"builder damping",
     [] {
       ObjectPlacement r = rope("r");
       r.linearDamping = -1.0;
       ModelBuilder().addObject(r);
     },
     "linearDamping", "got -1"},
    {"builder spring index",
     [] {
       ObjectPlacement r = rope("r");
       r.geometry.linearSprings[0].b = 7;
       ModelBuilder().addObject(r);
     },
     "linearSprings", "particle 7 is out of range (3 particles)"},
    {"builder connector",
     [] {
       ModelBuilder b;
       b.addObject(rope("r"));
       b.addConnector(LinearSpring{0, 5, 1.0, 10.0, 0.0});
     },
     "linearSprings", "particle 5 is out of range"},
    {"builder connector ends",
     [] {
       ModelBuilder b;
       b.addObject(rope("r"));
       b.addConnector(TorsionSpring{0, 1, 1, 3.0, 1.0, 0.0});
     },
     "torsionSprings", "particle 1 appears twice"},
    {"builder friction",
     [] {
       ModelBuilder().addMaterial({"m", 1e4, 1.0, 0.3, 0.5});
     },
     "kineticFriction", "'kineticFriction' 0.5 must not exceed 'staticFriction' 0.3"},
    {"builder material twice",
     [] {
       ModelBuilder b;
       b.addMaterial({"m"});
       b.addMaterial({"m"});
     },
     "name", "material 'm' is defined twice"},
    {"builder plane",
     [] {
       ModelBuilder().addPlane({{0, 0, 0}, {0, 0, 0}, 0});
     },
     "normal", "got [0, 0, 0]"},
    {"builder heightfield",
     [] {
       Heightfield h;
       h.columns = 3;
       h.rows = 2;
       h.heights = {0, 0, 0, 0};
       ModelBuilder().addHeightfield(h);
     },
     "heights", "4 samples for 2 rows × 3 columns"},
    {"builder box axes",
     [] {
       BoxObstacle box;
       box.axisY = {1, 0, 0};
       ModelBuilder().addBox(box);
     },
     "axisX", "orthonormal"},
    {"builder gravity",
     [] {
       ModelBuilder().setGravity({0, 0, kInf});
     },
     "gravity", "got [0, 0, inf]"},
    {"placed particle",
     [] {
       ModelBuilder b;
       b.addObject(rope("r")).particle(3);
     },
     "local", "index 3 is out of range: the object has 3 particles"},
};

class BadSpecs : public ::testing::TestWithParam<BadSpec> {};

TEST_P(BadSpecs, ThrowInvalidArgumentNamingTheFieldAndValue) {
  const BadSpec& bad = GetParam();
  try {
    bad.build();
    FAIL() << "no exception";
  } catch (const SpecError& e) {
    EXPECT_EQ(e.field(), bad.field) << e.what();
    EXPECT_NE(e.message().find(bad.fragment), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()), e.spec() + ": " + e.message());
    const std::invalid_argument& base = e;  // what callers catch
    EXPECT_NE(std::string(base.what()).find(bad.field), std::string::npos) << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(Build, BadSpecs, ::testing::ValuesIn(kBad),
                         [](const ::testing::TestParamInfo<BadSpec>& param) {
                           std::string name = param.param.label;
                           for (char& ch : name)
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           return name;
                         });

TEST(BadSpecs, ARefusedObjectLeavesTheBuilderUnchanged) {
  ModelBuilder builder;
  builder.addObject(rope("a"));
  ObjectPlacement bad = rope("b");
  bad.geometry.mass[2] = 0.0;
  EXPECT_THROW(builder.addObject(bad), std::invalid_argument);
  EXPECT_EQ(builder.model().particleCount(), 3);
  EXPECT_EQ(builder.model().objects.size(), 1u);
  EXPECT_EQ(builder.positions().size(), 3u);
}

// A scene's object whose spec the builder refuses gets the builder's message at
// the key of the same name.
TEST(BadSpecs, SceneFilesReportThemAtTheirKey) {
  struct Case {
    const char* entry;
    const char* pointer;
    const char* fragment;
  };
  const Case cases[] = {
      {R"({"name": "a", "type": "arm", "base": [0, 0, 0], "direction": [0, 0, 0],
           "links": [0.5], "mass": 1})",
       "/objects/0/direction", "'direction' must be a non-zero vector, got [0, 0, 0]"},
      {R"({"name": "a", "type": "arm", "base": [0, 0, 0], "links": [0.5, 0.4],
           "axes": [[0, 0, 1], [1, 0, 0]], "mass": 1})",
       "/objects/0/axes", "joint 2 axis is zero or parallel to 'direction'"},
      {R"({"name": "v", "type": "vehicle", "center": [0, 0, 0], "size": [0.6, 0, 0.1],
           "mass": 8, "wheelRadius": 0.1, "wheelWidth": 0.05, "wheelMass": 0.5,
           "suspensionStiffness": 1000})",
       "/objects/0/size", "'size' must be > 0 m in each direction, got [0.6, 0, 0.1]"},
      {R"({"name": "w", "type": "wheel", "center": [0, 0, 0], "radius": 0.1, "width": 0.04,
           "axis": [0, 0, 0], "mass": 1})",
       "/objects/0/axis", "'axis' must be a non-zero vector"},
      {R"({"name": "r", "type": "rope", "start": [1, 0, 0], "end": [1, 0, 0], "particles": 3,
           "mass": 1})",
       "/objects/0/end", "'end' equals 'start'"},
  };
  for (const Case& c : cases) {
    const SceneLoadResult result =
        loadSceneText(std::string("{\"objects\": [") + c.entry + "]}", "bad.json");
    ASSERT_EQ(result.errors.size(), 1u) << c.entry;
    EXPECT_EQ(result.errors[0].pointer, c.pointer);
    EXPECT_NE(result.errors[0].message.find(c.fragment), std::string::npos)
        << result.errors[0].message;
    EXPECT_GT(result.errors[0].line, 0);
  }
}

// Builder messages print numbers as the scene reader (fmt) does.
TEST(BadSpecs, NumbersReadAsTheSceneReaderWritesThem) {
  for (double x : {800000.0, 1e6, 2e-5, 1e16, 1e-4, 1e-5, 3.2e9, 123.456, -2.0, 0.1, 1.5e-300,
                   12345678901234567.0})
    EXPECT_EQ(check::number(x), fmt::format("{}", x));
}

}  // namespace
}  // namespace robophi::build
