// The world description written for the replay (output/world_view.h): the
// environment as the model holds it, the security distance of the robotics
// obstacles, goals, paths, which springs are attractors, and the virtual
// obstacles added during the run with their time.

#include <gtest/gtest.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "output/world_view.h"
#include "robophi/scene/scene.h"

namespace robophi {
namespace {

// A ground, a 3x2 heightfield, a box, a ball on a line path and an arm-tip-like
// particle pulled to a goal behind a sphere obstacle (radius 0.1 m, security 0.02 m).
constexpr const char* kScene = R"({
  "robophi": 1, "name": "world view",
  "run": {"duration": 0.1, "dt": 1e-4},
  "gravity": [0, 0, -9.81],
  "environment": {
    "ground": true,
    "heightfield": {"origin": [2, -1], "cellSize": [0.5, 0.25],
                    "heights": [[0, 0.1, 0], [0, 0.2, 0.05]]},
    "boxes": [{"center": [-2, 0, 0.25], "size": [0.5, 0.5, 0.5]}]
  },
  "objects": [
    {"name": "rope", "type": "rope", "start": [0, 0, 1], "end": [0.4, 0, 1], "particles": 5,
     "mass": 0.5, "radius": 0.02}
  ],
  "robotics": {
    "obstacles": [{"type": "sphere", "center": [0.6, 0.3, 1], "radius": 0.1,
                   "securityDistance": 0.02}],
    "goals": [{"name": "reach", "particles": ["rope:-1"], "targets": [[0.5, 0.6, 1]],
               "stiffness": 20, "damping": 1, "tolerance": 0.01}],
    "paths": [{"type": "line", "particle": "rope:0", "from": [-1, 0, 1], "to": [1, 0, 1],
               "stiffness": 5}]
  }
})";

Scene loadScene() {
  SceneLoadResult result = loadSceneText(kScene, "world_view.json");
  for (const Diagnostic& d : result.errors) ADD_FAILURE() << d.format();
  return std::move(*result.scene);
}

TEST(WorldView, DescribesTheEnvironmentGoalsAndPaths) {
  const Scene scene = loadScene();
  const nlohmann::json j = nlohmann::json::parse(output::WorldView(scene).json());
  const nlohmann::json& env = j["environment"];
  ASSERT_EQ(env["planes"].size(), 1u);
  EXPECT_EQ(env["planes"][0]["normal"], nlohmann::json::parse("[0.0, 0.0, 1.0]"));
  ASSERT_EQ(env["heightfields"].size(), 1u);
  const nlohmann::json& h = env["heightfields"][0];
  EXPECT_EQ(h["columns"], 3);
  EXPECT_EQ(h["rows"], 2);
  EXPECT_EQ(h["cellSize"][0].get<double>(), 0.5);
  EXPECT_EQ(h["heights"][4].get<double>(), 0.2);  // row 1, column 1
  ASSERT_EQ(env["boxes"].size(), 1u);
  EXPECT_EQ(env["boxes"][0]["halfExtents"][2].get<double>(), 0.25);
  EXPECT_EQ(env["boxes"][0]["securityDistance"].get<double>(), 0.0);
  // The obstacle: the environment holds it grown by its security distance.
  ASSERT_EQ(env["spheres"].size(), 1u);
  EXPECT_DOUBLE_EQ(env["spheres"][0]["radius"].get<double>(), 0.12);
  EXPECT_EQ(env["spheres"][0]["securityDistance"].get<double>(), 0.02);
  EXPECT_FALSE(env["spheres"][0].contains("addedAt"));

  ASSERT_EQ(j["goals"].size(), 1u);
  EXPECT_EQ(j["goals"][0]["name"], "reach");
  EXPECT_EQ(j["goals"][0]["particles"][0], 4);
  EXPECT_EQ(j["goals"][0]["positions"][0][1].get<double>(), 0.6);
  ASSERT_EQ(j["paths"].size(), 1u);
  EXPECT_EQ(j["paths"][0]["type"], "line");
  EXPECT_EQ(j["paths"][0]["from"][0].get<double>(), -1.0);

  // Attractors: the goal's LS to its virtual copy, not the rope's 4 connectors.
  const std::vector<int> attractors = j["attractors"].get<std::vector<int>>();
  ASSERT_EQ(attractors.size(), 1u);
  const LinearSpring& pull = scene.model.linearSprings[static_cast<std::size_t>(attractors[0])];
  EXPECT_EQ(pull.a, 4);
  EXPECT_EQ(scene.model.objects[static_cast<std::size_t>(scene.model.objectOf[pull.b])].kind,
            "virtual");
  for (std::size_t s = 0; s < 4; ++s)
    EXPECT_EQ(std::count(attractors.begin(), attractors.end(), static_cast<int>(s)), 0);
  // Objects: the rope, the goal's and the path's virtual objects (fixed).
  ASSERT_GE(j["objects"].size(), 2u);
  EXPECT_EQ(j["objects"][0]["fixed"], false);
  EXPECT_EQ(j["objects"][1]["virtual"], true);
  EXPECT_EQ(j["objects"][1]["fixed"], true);
}

TEST(WorldView, GivesVirtualObstaclesTheTimeTheyAppear) {
  const Scene scene = loadScene();
  output::WorldView view(scene);
  World world(scene.model, scene.initial);
  view.observe(world);
  for (int k = 0; k < 10; ++k) world.step(1e-4);
  view.observe(world);  // nothing new yet
  world.addSphereObstacle({Vec3{0.3, 0.5, 1.0}, 0.05, 0});
  for (int k = 0; k < 5; ++k) world.step(1e-4);
  view.observe(world);  // the first frame that sees it
  const double seenAt = world.state().time;
  world.step(1e-4);
  view.observe(world);
  const nlohmann::json spheres = nlohmann::json::parse(view.json())["environment"]["spheres"];
  ASSERT_EQ(spheres.size(), 2u);
  EXPECT_FALSE(spheres[0].contains("addedAt"));
  EXPECT_EQ(spheres[1]["addedAt"].get<double>(), seenAt);
  EXPECT_EQ(spheres[1]["virtual"], true);
  EXPECT_EQ(spheres[1]["radius"].get<double>(), 0.05);
}

TEST(WorldView, FingerTipAttractorsAreNotConnectors) {
  Model model;
  model.addObject("hand", "hand");
  for (int i = 0; i < 3; ++i) model.addParticle(0.1, 0.01, false, 0);
  model.linearSprings.push_back({0, 1, 0.05, 100.0, 0.0});
  model.linearSprings.push_back({1, 2, 1e-9, 30.0, 0.0});  // build::addTipAttractors' rest length
  EXPECT_EQ(output::attractorSprings(model), std::vector<int>{1});
}

}  // namespace
}  // namespace robophi
