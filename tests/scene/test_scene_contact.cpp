// The contact keys of a scene file (docs/contact.md), read on the loader's one
// diagnostics path: file:line:column, JSON pointer, "did you mean".
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "robophi/scene/scene.h"
#include "scene/scene_test_util.h"

namespace robophi {
namespace {

// Two objects (a wheel-like ball and a cube-like ball) and the given contact keys.
std::string sceneWith(const std::string& keys) {
  return R"({"objects": [
  {"name": "wheel", "type": "ball", "center": [0, 0, 1], "radius": 0.1, "mass": 1},
  {"name": "cube", "type": "ball", "center": [1, 0, 1], "radius": 0.1, "mass": 1}],
)" + keys +
         "}";
}

TEST(SceneContact, ReadsMaterialsEnvironmentMediumAndPairs) {
  const std::string text = R"({
    "materials": [{"name": "rubber", "contactStiffness": 2e4, "contactDamping": 5,
                   "staticFriction": 0.9, "kineticFriction": 0.7}],
    "objects": [
      {"name": "wheel", "type": "ball", "center": [0, 0, 1], "radius": 0.1, "mass": 1,
       "material": "rubber"},
      {"name": "cube", "type": "ball", "center": [1, 0, 1], "radius": 0.1, "mass": 1}],
    "environment": {
      "ground": {"point": [0, 0, -1], "normal": [0, 0, 2], "material": "rubber"},
      "heightfield": {"origin": [0, 0], "cellSize": 0.5, "heights": [[0, 0.1], [0.2, 0.3]]},
      "boxes": [{"center": [1, 2, 3], "size": [0.2, 0.4, 0.6], "rotation": [0, 0, 1, 1.5707963267948966]}],
      "spheres": [{"center": [0, 0, 5], "radius": 0.5}]
    },
    "medium": {"viscosity": 0.3},
    "contact": {"stickVelocity": 1e-3, "stribeckVelocity": 0.05, "selfCollision": false,
                "leafSize": 8},
    "contactPairs": [{"objects": ["wheel", "environment"], "staticFriction": 1.2,
                      "kineticFriction": 1.0}]
  })";
  const SceneLoadResult result = loadSceneText(text, "contact.json");
  ASSERT_TRUE(result.ok()) << test::allErrors(result);
  const Model& model = result.scene->model;
  ASSERT_EQ(model.materials.size(), 2u);
  EXPECT_EQ(model.objects[0].material, 1);
  EXPECT_EQ(model.objects[1].material, 0);
  ASSERT_EQ(model.environment.planes.size(), 1u);
  EXPECT_DOUBLE_EQ(model.environment.planes[0].normal.z, 1.0);
  EXPECT_EQ(model.environment.planes[0].material, 1);
  ASSERT_EQ(model.environment.heightfields.size(), 1u);
  EXPECT_DOUBLE_EQ(model.environment.heightfields[0].heightAt(0.5, 0.5), 0.3);
  ASSERT_EQ(model.environment.boxes.size(), 1u);
  EXPECT_NEAR(model.environment.boxes[0].axisX.y, 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(model.environment.boxes[0].halfExtents.z, 0.3);
  EXPECT_DOUBLE_EQ(model.environment.spheres[0].radius, 0.5);
  EXPECT_DOUBLE_EQ(model.environment.viscosity, 0.3);
  EXPECT_FALSE(model.contact.selfCollision);
  EXPECT_DOUBLE_EQ(model.contact.stickVelocity, 1e-3);
  EXPECT_DOUBLE_EQ(model.contact.stribeckVelocity, 0.05);
  EXPECT_EQ(model.contact.leafSize, 8);
  ASSERT_EQ(model.contact.pairOverrides.size(), 1u);
  EXPECT_EQ(model.contact.pairOverrides[0].objectB, -1);
  EXPECT_DOUBLE_EQ(model.contact.pairOverrides[0].staticFriction, 1.2);
  EXPECT_DOUBLE_EQ(model.contact.pairOverrides[0].stiffness, 1e4);  // rubber with itself
}

TEST(SceneContact, RedefinesTheDefaultMaterialAndGroundTrue) {
  const SceneLoadResult result =
      loadSceneText(sceneWith(R"("materials": [{"name": "default", "staticFriction": 0.8}],
                   "environment": {"ground": true, "planes": [{"normal": [1, 0, 0]}]})"),
                    "default.json");
  ASSERT_TRUE(result.ok()) << test::allErrors(result);
  const Model& model = result.scene->model;
  ASSERT_EQ(model.materials.size(), 1u);
  EXPECT_DOUBLE_EQ(model.materials[0].staticFriction, 0.8);
  EXPECT_DOUBLE_EQ(model.materials[0].contactStiffness, Material{}.contactStiffness);
  ASSERT_EQ(model.environment.planes.size(), 2u);
  EXPECT_DOUBLE_EQ(model.environment.planes[0].normal.z, 1.0);
  EXPECT_DOUBLE_EQ(model.environment.planes[1].normal.x, 1.0);
}

TEST(SceneContact, HeightfieldFromAPgmFileRelativeToTheScene) {
  const std::string directory = ::testing::TempDir();
  {
    std::ofstream out(directory + "/hills.pgm");
    out << "P2\n2 2\n10\n0 10\n5 0\n";
  }
  {
    std::ofstream out(directory + "/hills.json");
    out << sceneWith(R"("environment": {"heightfield": {"pgm": "hills.pgm", "cellSize": [2, 3],
                        "minHeight": -1, "maxHeight": 1}})");
  }
  const SceneLoadResult result = loadSceneFile(directory + "/hills.json");
  ASSERT_TRUE(result.ok()) << test::allErrors(result);
  const Heightfield& field = result.scene->model.environment.heightfields.at(0);
  EXPECT_EQ(field.columns, 2);
  EXPECT_DOUBLE_EQ(field.cellSizeY, 3.0);
  EXPECT_DOUBLE_EQ(field.heightAt(2.0, 3.0), 1.0);  // image row 0, column 1
  EXPECT_DOUBLE_EQ(field.heightAt(0.0, 0.0), 0.0);  // image row 1, column 0: 5/10

  const SceneLoadResult missing = loadSceneText(
      sceneWith(R"("environment": {"heightfield": {"pgm": "/nonexistent/hills.pgm"}})"),
      "pgm.json");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(test::allErrors(missing).find("/nonexistent/hills.pgm: cannot open the file"),
            std::string::npos)
      << test::allErrors(missing);
  EXPECT_EQ(missing.errors[0].pointer, "/environment/heightfield/pgm");
}

// A misspelt or bad contact key and what its (first matching) error must say.
struct BadContactKey {
  const char* label;
  const char* keys;
  const char* fragment;
  const char* pointer;
};

const BadContactKey kBadKeys[] = {
    {"material key", R"("materials": [{"name": "ice", "contactStiffnes": 2e4}])",
     "unknown key 'contactStiffnes' in material 'ice'; did you mean 'contactStiffness'?",
     "/materials/0/contactStiffnes"},
    {"pair key", R"("contactPairs": [{"objects": ["wheel", "cube"], "staticFricton": 1}])",
     "unknown key 'staticFricton' in contact pair /contactPairs/0; did you mean "
     "'staticFriction'?",
     "/contactPairs/0/staticFricton"},
    {"environment key", R"("environment": {"sphere": [{"radius": 1}]})",
     "unknown key 'sphere' in 'environment'; did you mean 'spheres'?", "/environment/sphere"},
    {"box key", R"("environment": {"boxes": [{"size": [1, 1, 1], "centre": [0, 0, 0]}]})",
     "unknown key 'centre' in box /environment/boxes/0; did you mean 'center'?",
     "/environment/boxes/0/centre"},
    {"sphere key", R"("environment": {"spheres": [{"radus": 1}]})",
     "unknown key 'radus' in sphere /environment/spheres/0; did you mean 'radius'?",
     "/environment/spheres/0/radus"},
    {"plane key", R"("environment": {"ground": {"normall": [0, 0, 1]}})",
     "unknown key 'normall' in the ground plane; did you mean 'normal'?",
     "/environment/ground/normall"},
    {"heightfield key",
     R"("environment": {"heightfield": {"heights": [[0, 0], [0, 0]], "cellsize": 1}})",
     "unknown key 'cellsize' in heightfield /environment/heightfield; did you mean 'cellSize'?",
     "/environment/heightfield/cellsize"},
    {"medium key", R"("medium": {"viscosty": 1})",
     "unknown key 'viscosty' in 'medium'; did you mean 'viscosity'?", "/medium/viscosty"},
    {"contact key", R"("contact": {"selfColision": false})",
     "unknown key 'selfColision' in 'contact'; did you mean 'selfCollision'?",
     "/contact/selfColision"},
    {"top-level key", R"("contactPair": [])",
     "unknown key 'contactPair' in the scene; did you mean 'contactPairs'?", "/contactPair"},
    {"material name", R"("materials": [{"name": "rubber"}], "environment": {"ground":
       {"material": "rubbr"}})",
     "'material': no material named 'rubbr' in /materials; did you mean 'rubber'?",
     "/environment/ground/material"},
    {"pair object", R"("contactPairs": [{"objects": ["wheel", "cub"]}])",
     "no object named 'cub'; did you mean 'cube'?", "/contactPairs/0/objects/1"},
    {"negative stiffness", R"("materials": [{"name": "bad", "contactStiffness": -1}])",
     "'contactStiffness' must be > 0 N/m, got -1", "/materials/0/contactStiffness"},
    {"friction order",
     R"("materials": [{"name": "ice", "staticFriction": 0.1, "kineticFriction": 0.2}])",
     "'kineticFriction' 0.2 must not exceed 'staticFriction' 0.1", "/materials/0/kineticFriction"},
    {"twice", R"("materials": [{"name": "ice"}, {"name": "ice"}])",
     "material 'ice' is defined twice (first at /materials/0)", "/materials/1/name"},
    {"sphere radius", R"("environment": {"spheres": [{"center": [0, 0, 0]}]})",
     "missing required key 'radius'", "/environment/spheres/0"},
    {"leaf size", R"("contact": {"leafSize": 0})", "'leafSize' must be an integer in [1,",
     "/contact/leafSize"},
    {"Stribeck velocity", R"("contact": {"stribeckVelocity": -0.1})",
     "'stribeckVelocity' must be >= 0 m/s, got -0.1", "/contact/stribeckVelocity"},
    {"viscosity", R"("medium": {"viscosity": -2})", "'viscosity' must be >= 0 N·s/m, got -2",
     "/medium/viscosity"},
    {"ground type", R"("environment": {"ground": 1})", "'ground': expected true, false or a plane",
     "/environment/ground"},
    {"heights and pgm",
     R"("environment": {"heightfield": {"heights": [[0, 0], [0, 0]], "pgm": "x.pgm"}})",
     "needs exactly one of 'heights' (m) or 'pgm'", "/environment/heightfield"},
    {"box orientation",
     R"("environment": {"boxes": [{"size": [1, 1, 1], "rotation": [0, 0, 1, 1], "rpy": [0, 0, 1]}]})",
     "either as 'rotation' or as 'rpy', not both", "/environment/boxes/0/rpy"},
    {"material of an object",
     R"("materials": [{"name": "steel"}], "objects": [
       {"name": "b", "type": "ball", "center": [0, 0, 1], "radius": 0.1, "mass": 1,
        "material": "stel"}])",
     "no material named 'stel' in /materials; did you mean 'steel'?", "/objects/0/material"},
};

class SceneContactBadKeys : public ::testing::TestWithParam<BadContactKey> {};

TEST_P(SceneContactBadKeys, AreReportedWithASuggestionAndTheirPlace) {
  const BadContactKey& c = GetParam();
  // A case with its own "objects" list is a whole scene.
  const std::string keys = c.keys;
  const std::string text =
      keys.find("\"objects\": [\n") != std::string::npos ? "{" + keys + "}" : sceneWith(keys);
  const SceneLoadResult result = loadSceneText(text, "bad.json");
  ASSERT_FALSE(result.ok());
  const Diagnostic* match = test::findError(result, c.fragment);
  ASSERT_NE(match, nullptr) << "no error contains \"" << c.fragment << "\"; got:\n"
                            << test::allErrors(result);
  EXPECT_EQ(match->pointer, c.pointer) << match->format();
  EXPECT_EQ(match->file, "bad.json");
  EXPECT_GT(match->line, 0) << match->format();
  EXPECT_GT(match->column, 0) << match->format();
}

INSTANTIATE_TEST_SUITE_P(Scene, SceneContactBadKeys, ::testing::ValuesIn(kBadKeys),
                         test::LabelName());

// The misspelt key is pointed at on its own line and column, in the same form as
// every other loader message.
TEST(SceneContact, MisspeltKeyHasFileLineColumnAndPointer) {
  const std::string text = sceneWith(R"("materials": [
  {"name": "rubber",
   "contactStiffnes": 2e4}])");
  const SceneLoadResult result = loadSceneText(text, "rubber.json");
  ASSERT_EQ(result.errors.size(), 1u) << test::allErrors(result);
  EXPECT_EQ(result.errors[0].format(),
            "rubber.json:6:4: error: unknown key 'contactStiffnes' in material 'rubber'; did you "
            "mean 'contactStiffness'? (at /materials/0/contactStiffnes)");
}

TEST(SceneContact, ReportsEveryProblemNotOnlyTheFirst) {
  const std::string text = R"({
    "materials": [{"name": "ice", "staticFriction": 0.1, "kineticFriction": 0.2},
                  {"name": "bad", "contactStiffness": -1}],
    "objects": [{"name": "wheel", "type": "ball", "center": [0, 0, 1], "radius": 0.1,
                 "mass": 1, "material": "steel"}],
    "environment": {"spheres": [{"center": [0, 0, 0]}], "lava": true},
    "contactPairs": [{"objects": ["wheel", "ghost"]}]
  })";
  const SceneLoadResult result = loadSceneText(text, "many.json");
  std::vector<std::string> pointers;
  for (const auto& e : result.errors) pointers.push_back(e.pointer);
  const std::vector<std::string> expected = {"/materials/0/kineticFriction",
                                             "/materials/1/contactStiffness",
                                             "/objects/0/material",
                                             "/environment/spheres/0",
                                             "/environment/lava",
                                             "/contactPairs/0/objects/1"};
  EXPECT_EQ(pointers, expected) << test::allErrors(result);
}

}  // namespace
}  // namespace robophi
