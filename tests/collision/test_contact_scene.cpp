// The contact keys of a scene file (docs/contact.md).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "collision/contact_scene.h"

namespace robophi {
namespace {

struct Errors {
  std::vector<std::string> pointers, messages;
  ContactErrorSink sink() {
    return [this](const std::string& p, const std::string& m) {
      pointers.push_back(p);
      messages.push_back(m);
    };
  }
};

TEST(ContactScene, ReadsMaterialsEnvironmentMediumAndPairs) {
  Model model;
  model.addObject("wheel", "wheel");
  model.addObject("cube", "box");
  const auto root = nlohmann::json::parse(R"({
    "materials": [{"name": "rubber", "contactStiffness": 2e4, "contactDamping": 5,
                   "staticFriction": 0.9, "kineticFriction": 0.7}],
    "objects": [{"name": "wheel", "material": "rubber"}, {"name": "cube"}],
    "environment": {
      "ground": {"point": [0, 0, -1], "normal": [0, 0, 2], "material": "rubber"},
      "heightfield": {"origin": [0, 0], "cellSize": 0.5, "heights": [[0, 0.1], [0.2, 0.3]]},
      "boxes": [{"center": [1, 2, 3], "size": [0.2, 0.4, 0.6], "rotation": [0, 0, 1, 1.5707963267948966]}],
      "spheres": [{"center": [0, 0, 5], "radius": 0.5}]
    },
    "medium": {"viscosity": 0.3},
    "contact": {"stickVelocity": 1e-3, "selfCollision": false},
    "contactPairs": [{"objects": ["wheel", "environment"], "staticFriction": 1.2,
                      "kineticFriction": 1.0}]
  })");
  Errors errors;
  EXPECT_TRUE(parseContactScene(root, ".", model, errors.sink()));
  EXPECT_TRUE(errors.messages.empty());
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
  ASSERT_EQ(model.contact.pairOverrides.size(), 1u);
  EXPECT_EQ(model.contact.pairOverrides[0].objectB, -1);
  EXPECT_DOUBLE_EQ(model.contact.pairOverrides[0].staticFriction, 1.2);
  EXPECT_DOUBLE_EQ(model.contact.pairOverrides[0].stiffness, 1e4);  // rubber with itself
}

TEST(ContactScene, ReportsEveryProblemWithItsPointer) {
  Model model;
  model.addObject("wheel", "wheel");
  const auto root = nlohmann::json::parse(R"({
    "materials": [{"name": "ice", "staticFriction": 0.1, "kineticFriction": 0.2},
                  {"name": "bad", "contactStiffness": -1}],
    "objects": [{"name": "wheel", "material": "steel"}],
    "environment": {"spheres": [{"center": [0, 0, 0]}], "lava": true},
    "contactPairs": [{"objects": ["wheel", "ghost"]}]
  })");
  Errors errors;
  EXPECT_FALSE(parseContactScene(root, ".", model, errors.sink()));
  const std::vector<std::string> expected = {
      "/materials/0/kineticFriction",  "/materials/1/contactStiffness",
      "/objects/0/material",           "/environment/lava",
      "/environment/spheres/0/radius", "/contactPairs/0/objects"};
  EXPECT_EQ(errors.pointers, expected);
  for (const auto& m : errors.messages) std::printf("  %s\n", m.c_str());
}

}  // namespace
}  // namespace robophi
