// The paper's mechanisms on rigid robots (issue 37, docs/robotics.md "Links in
// goals"): a goal names a point of a link, the attractor's pull on the particle the
// link carries there moves the tree's joints; a run's trajectory.json replayed by
// position servors ("control": {"replay"}); and the errors of both.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "robophi/joints.h"
#include "robophi/scene/scene.h"
#include "robotics/tasks.h"
#include "run/runner.h"

namespace robophi {
namespace {

// A passive rigid planar arm (links 0.5, 0.4 m along +x from [0, 0, 1], joints
// about z), no gravity, its tool (the end of link l2) attracted to `target`.
std::string passiveArmScene(const std::string& tool, const std::string& target) {
  return R"({"robophi": 1, "run": {"duration": 4.0, "dt": 1e-3, "integrator": "symplectic",
                                   "adaptive": {"maxStep": 2e-3}},
    "gravity": [0, 0, 0],
    "objects": [{"name": "arm", "type": "arm", "rigid": true, "base": [0, 0, 1],
                 "links": [0.5, 0.4], "mass": 2, "jointStiffness": 0, "jointDamping": 0.5}],
    "robotics": {"goals": [{"name": "reach", "particles": [)" +
         tool + R"(], "targets": [)" + target +
         R"(], "stiffness": 100, "damping": 10, "tolerance": 0.002, "speedTolerance": 0.01}]}})";
}

State runToEnd(const Scene& scene) {
  RunOptions options;
  options.settings = scene.run;
  options.tasks = {robotics::makeSceneTasks(scene)};
  State final;
  const RunReport report = runScene(scene, options, &final);
  EXPECT_TRUE(report.sound()) << report.failure;
  return final;
}

TEST(LinkGoal, AnAttractorOnALinkPointTurnsAPassiveRigidArmToTheAnalyticPose) {
  // The tool 0.4 m along link l2 (its frame's z runs along the link).
  const SceneLoadResult loaded = loadSceneText(
      passiveArmScene(R"({"link": "arm.l2", "point": [0, 0, 0.4]})", "[0.6, 0.4, 1.0]"),
      "link_goal.json");
  for (const auto& e : loaded.errors) ADD_FAILURE() << e.format();
  ASSERT_TRUE(loaded.ok());
  const Scene& scene = *loaded.scene;
  const ObjectInfo& point = scene.model.objects.at(scene.model.objects.size() - 2);
  ASSERT_EQ(point.kind, "virtual");
  ASSERT_EQ(point.particleCount, 1);
  const ParticleIndex tool = point.firstParticle;
  ASSERT_TRUE(scene.model.isCarried(tool));
  EXPECT_LT(norm(scene.initial.position[tool] - Vec3{0.9, 0.0, 1.0}), 1e-12);
  const State final = runToEnd(scene);
  EXPECT_LT(norm(final.position[tool] - Vec3{0.6, 0.4, 1.0}), 0.002);
  // Two-link inverse kinematics: q2 = ±acos((x² + y² − a² − b²) / 2ab), q1 from it.
  const double a = 0.5, b = 0.4, x = 0.6, y = 0.4;
  const double q1 = jointPosition(scene.model, final, *findJoint(scene.model, "arm.j1"));
  const double q2 = jointPosition(scene.model, final, *findJoint(scene.model, "arm.j2"));
  const double elbow = std::acos((x * x + y * y - a * a - b * b) / (2 * a * b));
  const double sign = q2 >= 0.0 ? 1.0 : -1.0;
  const double shoulder =
      std::atan2(y, x) - std::atan2(b * std::sin(sign * elbow), a + b * std::cos(sign * elbow));
  EXPECT_NEAR(q2, sign * elbow, 5e-3);
  EXPECT_NEAR(q1, shoulder, 5e-3);
}

TEST(LinkGoal, ANamedPointAndALinksOriginAreTheSameParticleKinds) {
  const std::string text = R"({"robophi": 1, "gravity": [0, 0, 0],
    "objects": [{"name": "arm", "type": "arm", "rigid": true, "base": [0, 0, 1],
                 "links": [0.5, 0.4], "mass": 2}],
    "robotics": {"points": [{"name": "tool", "link": "arm.l2", "point": [0, 0, 0.4]}],
                 "goals": [{"name": "g", "particles": ["tool", "arm.l2"],
                            "targets": [[0.8, 0.2, 1], [0.4, 0.1, 1]], "stiffness": 10}]}})";
  const SceneLoadResult loaded = loadSceneText(text, "points.json");
  for (const auto& e : loaded.errors) ADD_FAILURE() << e.format();
  ASSERT_TRUE(loaded.ok());
  const Model& model = loaded.scene->model;
  const auto& goal = loaded.scene->robotics.goals.at(0);
  ASSERT_EQ(goal.particles.size(), 2u);
  const ObjectInfo& named = model.objects.at(static_cast<std::size_t>(model.objectOf[goal.particles[0]]));
  EXPECT_EQ(named.name, "tool");
  EXPECT_LT(norm(loaded.scene->initial.position[goal.particles[0]] - Vec3{0.9, 0, 1}), 1e-12);
  EXPECT_LT(norm(loaded.scene->initial.position[goal.particles[1]] - Vec3{0.5, 0, 1}), 1e-12);
  EXPECT_TRUE(model.isCarried(goal.particles[1]));
}

TEST(LinkGoal, AnUnknownLinkIsReportedWhereItIsNamed) {
  const SceneLoadResult loaded =
      loadSceneText(passiveArmScene(R"("arm.l9")", "[0.6, 0.4, 1.0]"), "bad_link.json");
  ASSERT_FALSE(loaded.ok());
  ASSERT_FALSE(loaded.errors.empty());
  const std::string message = loaded.errors[0].format();
  EXPECT_NE(message.find("/robotics/goals/0/particles/0"), std::string::npos) << message;
  EXPECT_NE(message.find("no rigid robot has a link or frame named 'arm.l9'"), std::string::npos)
      << message;
  EXPECT_NE(message.find("arm.l2"), std::string::npos) << message;  // the links it has
}

// A scene's LS connector may end on a link point: a passive arm tied by it to a
// fixed particle brings the point there (5 cm beyond the link's end, so that the
// link does not touch the particle).
TEST(LinkGoal, AConnectorOnALinkPointPullsTheLink) {
  // (maxStep: the stability estimate does not see an LS whose ends are fixed or
  // carried, docs/robotics.md "Links in goals", Open.)
  const std::string text = R"({"robophi": 1, "run": {"duration": 6.0, "dt": 1e-3,
      "integrator": "symplectic", "adaptive": {"maxStep": 2e-3}}, "gravity": [0, 0, 0],
    "objects": [{"name": "arm", "type": "arm", "rigid": true, "base": [0, 0, 1],
                 "links": [0.5, 0.4], "mass": 2, "jointStiffness": 0, "jointDamping": 0.5},
                {"name": "anchor", "type": "particles",
                 "particles": [{"position": [0.6, 0.4, 1], "mass": 1, "radius": 0.01, "fixed": true}]}],
    "connectors": [{"type": "LS", "particles": [{"link": "arm.l2", "point": [0, 0, 0.45]}, "anchor:0"],
                    "stiffness": 50, "damping": 5, "restLength": 1e-9}]})";
  const SceneLoadResult loaded = loadSceneText(text, "link_connector.json");
  for (const auto& e : loaded.errors) ADD_FAILURE() << e.format();
  ASSERT_TRUE(loaded.ok());
  const State final = runToEnd(*loaded.scene);
  const Model& model = loaded.scene->model;
  const LinearSpring& tie = model.linearSprings.back();
  ASSERT_TRUE(model.isCarried(tie.a));
  EXPECT_LT(norm(loaded.scene->initial.position[tie.a] - Vec3{0.95, 0, 1}), 1e-12);
  EXPECT_LT(norm(final.position[tie.a] - Vec3{0.6, 0.4, 1}), 2e-3);
  // A colon-less name that is no link of the scene's rigid robots is reported as one.
  std::string bad = text;
  bad.replace(bad.find(R"({"link": "arm.l2", "point": [0, 0, 0.45]})"), 41, R"("arm.l7")");
  const SceneLoadResult refused = loadSceneText(bad, "bad_connector.json");
  ASSERT_FALSE(refused.ok());
  const std::string message = refused.errors.at(0).format();
  EXPECT_NE(message.find("/connectors/0/particles/0"), std::string::npos) << message;
  EXPECT_NE(message.find("'arm.l7'"), std::string::npos) << message;
}

// The arm's joints follow a written trajectory by position servos and end on its
// last positions.
TEST(LinkGoal, ATrajectoryFileIsReplayedByPositionServos) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "robophi_test_link_goal_replay";
  std::filesystem::create_directories(dir);
  {
    std::ofstream out(dir / "trajectory.json");
    out << R"({"joints": ["arm.j1", "arm.j2"], "time": [0, 0.5, 1.0],
               "position": [[0, 0], [0.2, -0.3], [0.4, -0.6]],
               "velocity": [[0.4, -0.6], [0.4, -0.6], [0, 0]]})";
  }
  const std::string scene = R"({"robophi": 1, "run": {"duration": 2.0, "dt": 1e-3,
      "integrator": "symplectic"}, "gravity": [0, 0, 0],
    "objects": [{"name": "arm", "type": "arm", "rigid": true, "base": [0, 0, 1],
                 "links": [0.5, 0.4], "mass": 2}],
    "control": {"replay": {"file": "trajectory.json", "kp": 200, "kd": 20}}})";
  const SceneLoadResult loaded = loadSceneText(scene, (dir / "replay.json").string());
  for (const auto& e : loaded.errors) ADD_FAILURE() << e.format();
  ASSERT_TRUE(loaded.ok());
  const State final = runToEnd(*loaded.scene);
  const Model& model = loaded.scene->model;
  EXPECT_NEAR(jointPosition(model, final, *findJoint(model, "arm.j1")), 0.4, 1e-3);
  EXPECT_NEAR(jointPosition(model, final, *findJoint(model, "arm.j2")), -0.6, 1e-3);

  // A file that is not a trajectory: the error names the file and what is wrong.
  {
    std::ofstream out(dir / "broken.json");
    out << R"({"joints": ["arm.j1"], "time": [0, 0.5], "position": [[0], [0.1, 0.2]]})";
  }
  std::string broken = scene;
  broken.replace(broken.find("trajectory.json"), 15, "broken.json");
  const SceneLoadResult bad = loadSceneText(broken, (dir / "replay.json").string());
  ASSERT_FALSE(bad.ok());
  const std::string message = bad.errors.at(0).format();
  EXPECT_NE(message.find("broken.json: sample 1: expected a time and 1 positions"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("/control/replay/file"), std::string::npos) << message;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace robophi
