// The scene's "robotics" section read into the build layer's specs: what a
// builder refuses comes back as a positioned scene error.
#include <gtest/gtest.h>

#include <string>

#include "robophi/scene/scene.h"
#include "scene/scene_test_util.h"

namespace robophi {
namespace {

std::string robotWith(const std::string& robotics) {
  return R"({"objects": [
  {"name": "robot", "type": "particles", "particles": [
    {"position": [0, 0, 0], "mass": 1, "radius": 0.05},
    {"position": [1, 0, 0], "mass": 1, "radius": 0.05}]}],
"robotics": )" +
         robotics + "}";
}

struct BadRobotics {
  const char* label;
  const char* robotics;
  const char* fragment;
  const char* pointer;
};

const BadRobotics kBadRobotics[] = {
    {"off the line",
     R"({"paths": [{"type": "line", "particle": "robot:0", "from": [0, 1, 0], "to": [2, 1, 0],
        "stiffness": 10}]})",
     "line path: the particle must start on the segment from 'from' to 'to'", "/robotics/paths/0"},
    {"on the centre",
     R"({"paths": [{"type": "arc", "particle": "robot:0", "from": [0, 0, 0], "to": [0, 0, 0], "stiffness": 1}]})",
     "arc path: 'from' and 'to' must differ", "/robotics/paths/0"},
    {"goal key", R"({"goals": [{"name": "g", "particles": ["robot:0"], "stifness": 1}]})",
     "unknown key 'stifness' in goal /robotics/goals/0; did you mean 'stiffness'?",
     "/robotics/goals/0/stifness"},
    {"escape key",
     R"({"goals": [{"name": "g", "particles": ["robot:0"], "stiffness": 1,
        "escape": {"windw": 0.3}}]})",
     "unknown key 'windw' in escape; did you mean 'window'?", "/robotics/goals/0/escape/windw"},
    {"targets count",
     R"({"goals": [{"name": "g", "particles": ["robot:0", "robot:1"], "stiffness": 1,
        "targets": [[0, 0, 1]]}]})",
     "'targets': expected 2 positions [x, y, z], one per particle", "/robotics/goals/0/targets"},
    {"obstacle type", R"({"obstacles": [{"type": "sphear", "center": [0, 0, 0]}]})",
     "unknown obstacle type \"sphear\"; did you mean 'sphere'?", "/robotics/obstacles/0/type"},
    {"grasp object", R"({"grasps": [{"object": "robto"}]})",
     "no object named 'robto'; did you mean 'robot'?", "/robotics/grasps/0/object"},
    {"section key", R"({"goal": []})", "unknown key 'goal' in 'robotics'; did you mean 'goals'?",
     "/robotics/goal"},
};

class SceneRoboticsBad : public ::testing::TestWithParam<BadRobotics> {};

TEST_P(SceneRoboticsBad, IsReportedAtItsPlace) {
  const BadRobotics& c = GetParam();
  const SceneLoadResult result = loadSceneText(robotWith(c.robotics), "robot.json");
  ASSERT_FALSE(result.ok());
  const Diagnostic* match = test::findError(result, c.fragment);
  ASSERT_NE(match, nullptr) << "no error contains \"" << c.fragment << "\"; got:\n"
                            << test::allErrors(result);
  EXPECT_EQ(match->pointer, c.pointer) << match->format();
  EXPECT_GT(match->line, 0) << match->format();
}

INSTANTIATE_TEST_SUITE_P(Scene, SceneRoboticsBad, ::testing::ValuesIn(kBadRobotics),
                         test::LabelName());

TEST(SceneRobotics, GoalWithEscapeAndLimitFillTheTasks) {
  const SceneLoadResult result = loadSceneText(
      robotWith(R"({"obstacles": [{"type": "box", "center": [5, 0, 0], "size": [1, 1, 1],
                      "securityDistance": 0.1}],
                    "goals": [{"name": "g", "particles": ["robot:1"], "translation": [0, 1, 0],
                               "stiffness": 3, "escape": {"maxObstacles": 2}}]})"),
      "robot.json");
  ASSERT_TRUE(result.ok()) << test::allErrors(result);
  const Scene& scene = *result.scene;
  ASSERT_EQ(scene.robotics.goals.size(), 1u);
  EXPECT_EQ(scene.robotics.goals[0].goalPositions[0], (Vec3{1, 1, 0}));
  ASSERT_EQ(scene.robotics.escapes.size(), 1u);
  EXPECT_EQ(scene.robotics.escapes[0].goal, 0u);
  EXPECT_EQ(scene.robotics.escapes[0].maxObstacles, 2);
  ASSERT_EQ(scene.model.environment.boxes.size(), 1u);
  EXPECT_DOUBLE_EQ(scene.model.environment.boxes[0].halfExtents.x, 0.6);
  EXPECT_EQ(scene.model.objects.back().name, "g");
  EXPECT_EQ(scene.model.particleCount(), 3);
}

}  // namespace
}  // namespace robophi
