// Scene files: every error is reported with its place; valid scenes load.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "robophi/connector_forces.h"
#include "robophi/joints.h"
#include "robophi/scene/scene.h"
#include "scene/scene_test_util.h"

namespace robophi {
namespace {

// The source line `line` of `text` with a caret under `column`, for failure messages.
std::string showPlace(const std::string& text, int line, int column) {
  std::size_t begin = 0;
  for (int l = 1; l < line && begin != std::string::npos; ++l) {
    begin = text.find('\n', begin);
    if (begin != std::string::npos) ++begin;
  }
  if (begin == std::string::npos || line < 1) return "(no place)";
  const std::size_t end = text.find('\n', begin);
  return "\n" + text.substr(begin, end == std::string::npos ? end : end - begin) + "\n" +
         std::string(static_cast<std::size_t>(std::max(column - 1, 0)), ' ') + "^\n";
}

// A broken scene and what its (first matching) error must say.
struct BrokenSceneCase {
  const char* label;
  const char* text;
  const char* fragment;
  int line;  // 0: not checked
  int column;
  const char* pointer;  // nullptr: not checked
};

// Valid header lines shared by the table (2 lines: the objects start on line 3).
#define HEAD "{\"robophi\": 1,\n\"objects\": [\n"

const BrokenSceneCase kBroken[] = {
    {"syntax", "{\n  \"robophi\": 1,\n  \"objects\": [ }\n", "JSON syntax error", 3, 16, nullptr},
    {"trailing comma", "{\"objects\": [],\n}", "trailing comma", 2, 1, nullptr},
    {"unterminated", "{\"objects\": [\n", "unterminated array", 1, 13, nullptr},
    {"nan", "{\"gravity\": [0, 0, NaN], \"objects\": []}", "NaN is not a JSON number", 1, 20,
     nullptr},
    {"infinity", "{\"gravity\": [0, 0, -Infinity]}", "-Infinity is not a JSON number", 1, 20,
     nullptr},
    {"overflow", "{\"gravity\": [0, 0, 1e999]}", "too large for a double", 1, 20, nullptr},
    {"duplicate key", "{\"objects\": [],\n \"objects\": []}", "duplicate key 'objects'", 2, 2,
     nullptr},
    {"unknown top key", "{\"objects\": [], \"gravty\": [0,0,-9.81]}",
     "unknown key 'gravty' in the scene; did you mean 'gravity'?", 1, 17, "/gravty"},
    {"unknown nested key",
     HEAD "{\"name\": \"r\", \"type\": \"rope\", \"start\": [0,0,0], \"end\": [1,0,0],\n"
          " \"particles\": 5, \"mass\": 1, \"stifness\": 100}]}",
     "unknown key 'stifness' in rope 'r'; did you mean 'stiffness'?", 4, 29, "/objects/0/stifness"},
    {"wrong type",
     HEAD "{\"name\": \"b\", \"type\": \"ball\", \"center\": [0,0,0], \"radius\": 0.1, \"mass\": "
          "\"abc\"}]}",
     "'mass': expected a number (kg), got string \"abc\"", 3, 73, "/objects/0/mass"},
    {"negative mass",
     HEAD
     "{\"name\": \"b\", \"type\": \"ball\", \"center\": [0,0,0], \"radius\": 0.1, \"mass\": -2}]}",
     "'mass' must be > 0 kg, got -2", 3, 73, "/objects/0/mass"},
    {"zero mass",
     HEAD
     "{\"name\": \"b\", \"type\": \"ball\", \"center\": [0,0,0], \"radius\": 0.1, \"mass\": 0}]}",
     "'mass' must be > 0 kg, got 0", 3, 73, nullptr},
    {"non-positive radius",
     HEAD
     "{\"name\": \"b\", \"type\": \"ball\", \"center\": [0,0,0], \"radius\": 0, \"mass\": 1}]}",
     "'radius' must be > 0 m, got 0", 3, 60, "/objects/0/radius"},
    {"negative stiffness",
     HEAD "{\"name\": \"r\", \"type\": \"rope\", \"start\": [0,0,0], \"end\": [1,0,0],\n"
          " \"particles\": 5, \"mass\": 1, \"stiffness\": -5}]}",
     "'stiffness' must be >= 0 N/m, got -5", 4, 42, "/objects/0/stiffness"},
    {"negative damping",
     HEAD "{\"name\": \"r\", \"type\": \"rope\", \"start\": [0,0,0], \"end\": [1,0,0],\n"
          " \"particles\": 5, \"mass\": 1, \"damping\": -0.1}]}",
     "'damping' must be >= 0 N·s/m, got -0.1", 4, 40, nullptr},
    {"vector length",
     HEAD
     "{\"name\": \"b\", \"type\": \"ball\", \"center\": [0,0], \"radius\": 0.1, \"mass\": 1}]}",
     "'center': expected an array of 3 numbers [x, y, z] (m), got an array of 2 values", 3, 41,
     "/objects/0/center"},
    {"missing key", HEAD "{\"name\": \"b\", \"type\": \"ball\", \"radius\": 0.1, \"mass\": 1}]}",
     "ball 'b': missing required key 'center'", 3, 1, "/objects/0"},
    {"unknown type",
     HEAD "{\"name\": \"b\", \"type\": \"rop\", \"start\": [0,0,0], \"end\": [1,0,0]}]}",
     "unknown object type \"rop\"; did you mean 'rope'?", 3, 23, "/objects/0/type"},
    {"duplicate object",
     HEAD
     "{\"name\": \"b\", \"type\": \"ball\", \"center\": [0,0,0], \"radius\": 0.1, \"mass\": 1},\n"
     "{\"name\": \"b\", \"type\": \"ball\", \"center\": [1,0,0], \"radius\": 0.1, \"mass\": 1}]}",
     "duplicate object name 'b' (first defined at /objects/0)", 4, 10, "/objects/1/name"},
    {"fixed out of range",
     HEAD "{\"name\": \"r\", \"type\": \"rope\", \"start\": [0,0,0], \"end\": [1,0,0],\n"
          " \"particles\": 5, \"mass\": 1, \"fixed\": [0, 7]}]}",
     "'fixed[1]': index 7 is out of range: rope 'r' has 5 particles", 4, 42, "/objects/0/fixed/1"},
    {"dt", "{\"run\": {\"dt\": 0}, \"objects\": []}", "'dt' must be > 0 s, got 0", 1, 16,
     "/run/dt"},
    {"duration", "{\"run\": {\"duration\": -1}, \"objects\": []}", "'duration' must be > 0 s", 1,
     22, nullptr},
    {"integrator", "{\"run\": {\"integrator\": \"verlett\"}, \"objects\": []}",
     "unknown integrator \"verlett\"; did you mean 'verlet'?", 1, 24, "/run/integrator"},
    {"step mode", "{\"run\": {\"step\": \"adaptve\"}, \"objects\": []}",
     "unknown step mode \"adaptve\"; did you mean 'adaptive'?", 1, 18, "/run/step"},
    {"version", "{\"robophi\": 2, \"objects\": []}", "format version 2 is not supported", 1, 13,
     nullptr},
    {"connector object count",
     HEAD "{\"name\": \"chain\", \"type\": \"rope\", \"start\": [0,0,0], \"end\": [1,0,0],\n"
          " \"particles\": 20, \"mass\": 1}],\n"
          "\"connectors\": [{\"type\": \"LS\", \"particles\": [\"chain:0\", \"chain:25\"], "
          "\"stiffness\": 1}]}",
     "'chain:25': object 'chain' has 20 particles", 5, 56, "/connectors/0/particles/1"},
    {"connector unknown object",
     HEAD "{\"name\": \"chain\", \"type\": \"rope\", \"start\": [0,0,0], \"end\": [1,0,0],\n"
          " \"particles\": 20, \"mass\": 1}],\n"
          "\"connectors\": [{\"type\": \"LS\", \"particles\": [\"chian:0\", \"chain:2\"], "
          "\"stiffness\": 1}]}",
     "'chian:0': no object named 'chian'; did you mean 'chain'?", 5, 45, nullptr},
    {"connector arity",
     HEAD "{\"name\": \"chain\", \"type\": \"rope\", \"start\": [0,0,0], \"end\": [1,0,0],\n"
          " \"particles\": 20, \"mass\": 1}],\n"
          "\"connectors\": [{\"type\": \"TS\", \"particles\": [\"chain:0\", \"chain:2\"], "
          "\"stiffness\": 1}]}",
     "TS needs 3 particles [a, centre, b], got an array of 2 values", 5, 44,
     "/connectors/0/particles"},
    {"connector type",
     HEAD "{\"name\": \"chain\", \"type\": \"rope\", \"start\": [0,0,0], \"end\": [1,0,0],\n"
          " \"particles\": 20, \"mass\": 1}],\n"
          "\"connectors\": [{\"type\": \"Ls\", \"particles\": [\"chain:0\", \"chain:2\"], "
          "\"stiffness\": 1}]}",
     "unknown connector type \"Ls\"; did you mean 'LS'?", 5, 25, nullptr},
    {"rest length",
     HEAD "{\"name\": \"chain\", \"type\": \"rope\", \"start\": [0,0,0], \"end\": [1,0,0],\n"
          " \"particles\": 20, \"mass\": 1}],\n"
          "\"connectors\": [{\"type\": \"LS\", \"particles\": [\"chain:0\", \"chain:2\"], "
          "\"stiffness\": 1, \"restLength\": 0}]}",
     "'restLength' must be > 0 m, got 0", 5, 98, "/connectors/0/restLength"},
    {"bad reference",
     HEAD "{\"name\": \"chain\", \"type\": \"rope\", \"start\": [0,0,0], \"end\": [1,0,0],\n"
          " \"particles\": 20, \"mass\": 1}],\n"
          "\"connectors\": [{\"type\": \"LS\", \"particles\": [\"chain\", 3], \"stiffness\": 1}]}",
     "particle reference \"chain\" must be \"object:index\"", 5, 45, nullptr},
    {"duplicate joint",
     HEAD "{\"name\": \"c\", \"type\": \"rope\", \"start\": [0,0,0], \"end\": [1,0,0],\n"
          " \"particles\": 5, \"mass\": 1}],\n"
          "\"joints\": [{\"name\": \"j\", \"type\": \"revolute\", \"a\": \"c:0\", \"center\": "
          "\"c:1\", \"b\": \"c:2\", \"axis\": \"c:3\"},\n"
          "{\"name\": \"j\", \"type\": \"revolute\", \"a\": \"c:0\", \"center\": "
          "\"c:1\", \"b\": \"c:2\", \"axis\": \"c:3\"}]}",
     "duplicate joint name 'j' (first defined at /joints/0)", 6, 10, "/joints/1/name"},
    {"joint type",
     HEAD "{\"name\": \"c\", \"type\": \"rope\", \"start\": [0,0,0], \"end\": [1,0,0],\n"
          " \"particles\": 5, \"mass\": 1}],\n"
          "\"joints\": [{\"name\": \"j\", \"type\": \"revolut\"}]}",
     "unknown joint type \"revolut\"; did you mean 'revolute'?", 5, 34, nullptr},
    {"joint unknown key",
     HEAD
     "{\"name\": \"c\", \"type\": \"rope\", \"start\": [0,0,0], \"end\": [1,0,0],\n"
     " \"particles\": 5, \"mass\": 1}],\n"
     "\"joints\": [{\"name\": \"j\", \"type\": \"prismatic\", \"origin\": \"c:0\", \"slider\": "
     "\"c:2\", \"end\": \"c:4\", \"stiffness\": 1, \"drive\": {\"stifness\": 3}}]}",
     "unknown key 'stifness' in drive of joint 'j'; did you mean 'stiffness'?", 5, 121,
     "/joints/0/drive/stifness"},
    {"particles local index",
     HEAD "{\"name\": \"p\", \"type\": \"particles\", \"particles\": [\n"
          "  {\"position\": [0,0,0], \"mass\": 1, \"radius\": 0.1},\n"
          "  {\"position\": [1,0,0], \"mass\": 1, \"radius\": 0.1}],\n"
          " \"connectors\": [{\"type\": \"LS\", \"particles\": [0, 2], \"stiffness\": 1}]}]}",
     "'2': object 'p' has 2 particles", 6, 49, "/objects/0/connectors/0/particles/1"},
};

class SceneBrokenTable : public ::testing::TestWithParam<BrokenSceneCase> {};

TEST_P(SceneBrokenTable, IsRejectedWithTheRightMessageAndPlace) {
  const BrokenSceneCase& c = GetParam();
  const SceneLoadResult result = loadSceneText(c.text, "broken.json");
  EXPECT_FALSE(result.ok());
  EXPECT_FALSE(result.scene.has_value());
  const Diagnostic* match = test::findError(result, c.fragment);
  ASSERT_NE(match, nullptr) << "no error contains \"" << c.fragment << "\"; got:\n"
                            << test::allErrors(result);
  EXPECT_EQ(match->file, "broken.json");
  if (c.line > 0) {
    EXPECT_EQ(match->line, c.line)
        << match->format() << showPlace(c.text, match->line, match->column);
    EXPECT_EQ(match->column, c.column)
        << match->format() << showPlace(c.text, match->line, match->column);
  }
  if (c.pointer != nullptr) {
    EXPECT_EQ(match->pointer, c.pointer) << match->format();
  }
}

INSTANTIATE_TEST_SUITE_P(Scene, SceneBrokenTable, ::testing::ValuesIn(kBroken), test::LabelName());

TEST(SceneLoader, ReportsEveryErrorNotOnlyTheFirst) {
  const char* text = R"({
  "robophi": 1,
  "run": {"dt": -1, "integrator": "rk4"},
  "objects": [
    {"name": "a", "type": "ball", "center": [0, 0, 0], "radius": -1, "mass": 1},
    {"name": "b", "type": "rope", "start": [0, 0], "end": [1, 0, 0], "particles": 4, "mass": 0},
    {"name": "c", "type": "plate", "center": [0, 0, 0], "size": [1, 1], "cells": [4, 4],
     "mass": 1, "colour": "red"}
  ],
  "connectors": [{"type": "LS", "particles": ["c:0", "zz:1"], "stiffness": 10}]
})";
  const SceneLoadResult result = loadSceneText(text, "many.json");
  EXPECT_FALSE(result.ok());
  const std::vector<std::string> expected = {"'dt' must be > 0",     "unknown integrator \"rk4\"",
                                             "'radius' must be > 0", "'start': expected an array",
                                             "'mass' must be > 0",   "unknown key 'colour'",
                                             "no object named 'zz'"};
  for (const auto& fragment : expected) {
    bool found = false;
    for (const auto& e : result.errors)
      found = found || e.message.find(fragment) != std::string::npos;
    EXPECT_TRUE(found) << fragment << " missing from:\n" << test::allErrors(result);
  }
  EXPECT_EQ(result.errors.size(), expected.size()) << test::allErrors(result);
  // Sorted by position in the text.
  for (std::size_t i = 1; i < result.errors.size(); ++i)
    EXPECT_LE(result.errors[i - 1].line, result.errors[i].line);
}

TEST(SceneLoader, FormatNamesFileLineColumnAndPointer) {
  const Diagnostic d{"s.json", 3, 7, "/objects/0/mass", "'mass' must be > 0 kg, got -1"};
  EXPECT_EQ(d.format(), "s.json:3:7: error: 'mass' must be > 0 kg, got -1 (at /objects/0/mass)");
}

TEST(SceneLoader, CommentsAndHugeNumbersAreAccepted) {
  const char* text = R"({
  // a line comment
  "robophi": 1, /* a block
  comment */ "name": "ok",
  "gravity": [0, 0, -1e300],
  "run": {"duration": 0.5, "dt": 1e-4},
  "objects": [{"name": "p", "type": "ball", "center": [0, 0, 1], "radius": 0.1, "mass": 2,
               "velocity": [1, 0, 0]}]
})";
  const SceneLoadResult result = loadSceneText(text, "ok.json");
  ASSERT_TRUE(result.ok()) << test::allErrors(result);
  const Scene& scene = *result.scene;
  EXPECT_EQ(scene.name, "ok");
  EXPECT_DOUBLE_EQ(scene.model.gravity.z, -1e300);
  EXPECT_DOUBLE_EQ(scene.run.duration, 0.5);
  ASSERT_EQ(scene.model.particleCount(), 1);
  EXPECT_DOUBLE_EQ(scene.model.mass[0], 2.0);
  EXPECT_DOUBLE_EQ(scene.model.radius[0], 0.1);
  EXPECT_EQ(scene.initial.velocity[0], (Vec3{1, 0, 0}));
}

TEST(SceneLoader, MissingFileIsAnError) {
  const SceneLoadResult result = loadSceneFile("/nonexistent/scene.json");
  ASSERT_EQ(result.errors.size(), 1u);
  EXPECT_NE(result.errors[0].message.find("cannot open"), std::string::npos);
}

TEST(SceneLoader, FixedAndLocalConnectors) {
  const char* text = R"({"objects": [
    {"name": "r", "type": "rope", "start": [0, 0, 0], "end": [1, 0, 0], "particles": 5,
     "mass": 1, "fixed": [0, -1], "velocity": [0, 0, 1]},
    {"name": "p", "type": "particles", "fixed": true, "particles": [
      {"position": [0, 0, 2], "mass": 1, "radius": 0.1},
      {"position": [0, 0, 3], "mass": 1, "radius": 0.1}],
     "connectors": [{"type": "LS", "particles": [0, -1], "stiffness": 7, "damping": 0.5}]}
  ]})";
  const SceneLoadResult result = loadSceneText(text, "fixed.json");
  ASSERT_TRUE(result.ok()) << test::allErrors(result);
  const Model& m = result.scene->model;
  ASSERT_EQ(m.particleCount(), 7);
  EXPECT_TRUE(m.isFixed(0));
  EXPECT_FALSE(m.isFixed(1));
  EXPECT_TRUE(m.isFixed(4));
  EXPECT_TRUE(m.isFixed(5));
  EXPECT_TRUE(m.isFixed(6));
  EXPECT_EQ(result.scene->initial.velocity[0], Vec3{});  // fixed particles do not move
  EXPECT_EQ(result.scene->initial.velocity[2], (Vec3{0, 0, 1}));
  const LinearSpring& s = m.linearSprings.back();
  EXPECT_EQ(s.a, 5);
  EXPECT_EQ(s.b, 6);
  EXPECT_DOUBLE_EQ(s.restLength, 1.0);
  EXPECT_DOUBLE_EQ(s.stiffness, 7.0);
  EXPECT_DOUBLE_EQ(s.damping, 0.5);
  ASSERT_EQ(m.objects.size(), 2u);
  EXPECT_EQ(m.objects[1].firstParticle, 5);
  EXPECT_EQ(m.objects[1].kind, "particles");
}

// An L-shaped pair of links: the revolute joint's value is the geometric angle.
TEST(SceneJoints, RevoluteValueIsTheGeometricAngle) {
  const char* text = R"({"objects": [
    {"name": "l1", "type": "particles", "particles": [
      {"position": [0, 0, 0], "mass": 1, "radius": 0.05},
      {"position": [1, 0, 0], "mass": 1, "radius": 0.05},
      {"position": [1, 0, 1], "mass": 1, "radius": 0.05}]},
    {"name": "l2", "type": "particles", "particles": [
      {"position": [1, 1, 0], "mass": 1, "radius": 0.05}]}],
   "joints": [{"name": "elbow", "type": "revolute", "a": "l1:0", "center": "l1:1", "b": "l2:0",
               "axis": "l1:2", "stiffness": 3, "damping": 0.1},
              {"name": "servo", "type": "revolute", "a": "l1:0", "center": "l1:1", "b": "l2:0",
               "axis": "l1:2", "stiffness": 3, "target": -1.5707963267948966}]})";
  const SceneLoadResult result = loadSceneText(text, "rev.json");
  ASSERT_TRUE(result.ok()) << test::allErrors(result);
  const Scene& scene = *result.scene;
  ASSERT_EQ(scene.model.joints.size(), 2u);
  EXPECT_EQ(scene.model.joints[0].name, "elbow");
  EXPECT_EQ(scene.model.joints[0].kind, JointKind::kRevolute);
  // u = (-1,0,0), w = (0,1,0), n = +z: from u to w counter-clockwise about z is 3π/2.
  const double geometric = 1.5 * M_PI;
  EXPECT_NEAR(jointValue(scene.model, scene.initial, 0), geometric, 1e-12);
  const JointSpring& s =
      scene.model.jointSprings[static_cast<std::size_t>(scene.model.joints[0].connector)];
  EXPECT_NEAR(s.restAngle, geometric, 1e-12);  // default target: the initial angle
  EXPECT_DOUBLE_EQ(s.stiffness, 3.0);
  // A negative target wraps into [0, 2π).
  const JointSpring& servo =
      scene.model.jointSprings[static_cast<std::size_t>(scene.model.joints[1].connector)];
  EXPECT_NEAR(servo.restAngle, 1.5 * M_PI, 1e-12);
}

TEST(SceneJoints, PrismaticHasATorsionSpringAndADriveSpring) {
  const char* text = R"({"objects": [
    {"name": "rail", "type": "rope", "start": [0, 0, 0], "end": [1, 0, 0], "particles": 2,
     "mass": 1, "fixed": true},
    {"name": "cart", "type": "ball", "center": [0.25, 0, 0], "radius": 0.05, "mass": 0.5}],
   "joints": [{"name": "slide", "type": "prismatic", "origin": "rail:0", "slider": "cart:0",
               "end": "rail:-1", "stiffness": 50, "damping": 1,
               "drive": {"stiffness": 200, "damping": 5, "target": 0.6}},
              {"name": "free", "type": "prismatic", "origin": "rail:0", "slider": "cart:0",
               "end": "rail:1", "stiffness": 50}]})";
  const SceneLoadResult result = loadSceneText(text, "prism.json");
  ASSERT_TRUE(result.ok()) << test::allErrors(result);
  const Model& m = result.scene->model;
  ASSERT_EQ(m.joints.size(), 2u);
  const Joint& j = m.joints[0];
  EXPECT_EQ(j.kind, JointKind::kPrismatic);
  const TorsionSpring& ts = m.torsionSprings[static_cast<std::size_t>(j.connector)];
  EXPECT_EQ(ts.a, 0);
  EXPECT_EQ(ts.c, 2);
  EXPECT_EQ(ts.b, 1);
  EXPECT_DOUBLE_EQ(ts.restAngle, M_PI);
  EXPECT_DOUBLE_EQ(ts.stiffness, 50.0);
  ASSERT_GE(j.driveSpring, 0);
  const LinearSpring& drive = m.linearSprings[static_cast<std::size_t>(j.driveSpring)];
  EXPECT_EQ(drive.a, 0);
  EXPECT_EQ(drive.b, 2);
  EXPECT_DOUBLE_EQ(drive.restLength, 0.6);
  EXPECT_DOUBLE_EQ(drive.stiffness, 200.0);
  EXPECT_DOUBLE_EQ(drive.damping, 5.0);
  EXPECT_EQ(m.joints[1].driveSpring, -1);
  EXPECT_NEAR(jointValue(m, result.scene->initial, 0), 0.25, 1e-12);
}

TEST(SceneJoints, PrismaticSliderOffTheSegmentIsAnError) {
  const char* text = R"({"objects": [
    {"name": "rail", "type": "rope", "start": [0, 0, 0], "end": [1, 0, 0], "particles": 2,
     "mass": 1},
    {"name": "cart", "type": "ball", "center": [0.5, 0.3, 0], "radius": 0.05, "mass": 0.5}],
   "joints": [{"name": "slide", "type": "prismatic", "origin": "rail:0", "slider": "cart:0",
               "end": "rail:-1", "stiffness": 50}]})";
  const SceneLoadResult result = loadSceneText(text, "prism.json");
  ASSERT_FALSE(result.ok());
  EXPECT_NE(test::allErrors(result).find("the slider must start on the segment"), std::string::npos)
      << test::allErrors(result);
}

TEST(SceneFiles, EverySceneInScenesLoadsWithoutError) {
  const std::filesystem::path dir = std::filesystem::path(ROBOPHI_SOURCE_DIR) / "scenes";
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".json") continue;
    ++count;
    const SceneLoadResult result = loadSceneFile(entry.path().string());
    EXPECT_TRUE(result.ok()) << entry.path() << ":\n" << test::allErrors(result);
    // A URDF as published names elements robophi does not model, and a rigid robot
    // lists what its import adjusted (docs/robots.md): those warnings are by design,
    // every other one is a failure.
    for (const auto& w : result.warnings)
      if (w.message.find("(robophi does not model it") == std::string::npos &&
          w.message.find(": adjusted: ") == std::string::npos && !w.message.starts_with("adjusted: "))
        ADD_FAILURE() << w.format("warning");
    if (!result.ok()) continue;
    const Scene& scene = *result.scene;
    EXPECT_GT(scene.model.particleCount(), 0) << entry.path();
    EXPECT_FALSE(scene.name.empty()) << entry.path();
    EXPECT_FALSE(scene.description.empty()) << entry.path();
    EXPECT_EQ(checkModel(scene.model), "") << entry.path();
  }
  EXPECT_GE(count, 5);
}

// Every prefix of a valid scene is rejected with a positioned error, never a crash.
TEST(SceneLoader, EveryTruncationIsRejectedCleanly) {
  const std::string path = std::string(ROBOPHI_SOURCE_DIR) + "/scenes/revolute_arm.json";
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(text.size(), 100u);
  // The document ends at its last '}'; any shorter prefix is incomplete.
  const std::size_t end = text.rfind('}');
  for (std::size_t n = 0; n < end; n += 7) {
    const SceneLoadResult result = loadSceneText(text.substr(0, n), "cut.json");
    ASSERT_FALSE(result.ok()) << "prefix of " << n << " characters was accepted";
    ASSERT_FALSE(result.errors.empty());
    EXPECT_GT(result.errors[0].line, 0) << result.errors[0].format();
  }
}

TEST(SceneFiles, DefaultSceneHasAChainABarAndAJoint) {
  const SceneLoadResult result =
      loadSceneFile(std::string(ROBOPHI_SOURCE_DIR) + "/scenes/default.json");
  ASSERT_TRUE(result.ok()) << test::allErrors(result);
  const Model& m = result.scene->model;
  EXPECT_GE(m.objects.size(), 3u);
  EXPECT_EQ(m.objects[0].name, "bar");
  EXPECT_EQ(m.objects[1].name, "chain");
  EXPECT_TRUE(m.isFixed(m.objects[0].firstParticle));
  EXPECT_FALSE(m.joints.empty());
  EXPECT_EQ(m.environment.planes.size(), 1u);  // the ground
  EXPECT_TRUE(m.contact.enabled);
  EXPECT_DOUBLE_EQ(result.scene->run.duration, 3.0);
}

}  // namespace
}  // namespace robophi
