// Goals, paths, obstacles and grasp attractors built from C++ (build/goals.h),
// without a scene file: what each builder adds, and the arguments it refuses.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "robophi/build/goals.h"

namespace robophi {
namespace {

// Free particles at the given positions in one object "robot".
void addRobot(Model& model, State& state, const std::vector<Vec3>& positions) {
  const std::int32_t id = model.addObject("robot", "particles");
  model.objects[static_cast<std::size_t>(id)].firstParticle = model.particleCount();
  for (const Vec3& p : positions) {
    model.addParticle(1.0, 0.05, false, id);
    state.position.push_back(p);
    state.velocity.push_back(Vec3{});
  }
  model.objects[static_cast<std::size_t>(id)].particleCount = model.particleCount();
}

// The message of the std::invalid_argument `run` throws ("" if none).
template <typename Run>
std::string refusal(Run run) {
  try {
    run();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(BuildGoals, MovedPoseRotatesAboutTheCentroidThenTranslates) {
  const std::vector<Vec3> x = {{1, 0, 0}, {3, 0, 0}, {9, 9, 9}};
  const auto pose = build::movedPose(x, {0, 1}, {0, 0, 1}, {0, 0, 2}, M_PI / 2.0);
  ASSERT_EQ(pose.size(), 2u);
  EXPECT_NEAR(pose[0].x, 2.0, 1e-12);
  EXPECT_NEAR(pose[0].y, -1.0, 1e-12);
  EXPECT_NEAR(pose[0].z, 1.0, 1e-12);
  EXPECT_NEAR(pose[1].y, 1.0, 1e-12);
  const auto still = build::movedPose(x, {2}, {1, 0, 0});  // no rotation
  EXPECT_EQ(still[0], (Vec3{10, 9, 9}));
}

TEST(BuildGoals, GoalAddsAVirtualCopyTiedByAttractors) {
  Model model;
  State state;
  addRobot(model, state, {{0, 0, 0}, {1, 0, 0}});
  build::AttractorGoalSpec spec;
  spec.name = "reach";
  spec.particles = {0, 1};
  spec.goalPositions = {{0, 2, 0}, {1, 2, 0}};
  spec.stiffness = 50.0;
  spec.damping = 2.0;
  spec.stopWhenReached = true;
  const build::GoalSpec goal = build::addGoal(model, state, spec);
  EXPECT_EQ(goal.name, "reach");
  EXPECT_TRUE(goal.stopWhenReached);
  EXPECT_EQ(goal.travelTime, 0.0);
  ASSERT_EQ(goal.targets.size(), 2u);
  ASSERT_EQ(model.particleCount(), 4);
  EXPECT_EQ(model.objects.back().kind, "virtual");
  EXPECT_EQ(model.objects.back().firstParticle, 2);
  EXPECT_EQ(model.objects.back().particleCount, 2);
  EXPECT_TRUE(model.isFixed(goal.targets[0]));
  EXPECT_EQ(state.position[goal.targets[1]], (Vec3{1, 2, 0}));
  ASSERT_EQ(model.linearSprings.size(), 2u);
  EXPECT_EQ(model.linearSprings[1].a, 1);
  EXPECT_EQ(model.linearSprings[1].b, goal.targets[1]);
  EXPECT_DOUBLE_EQ(model.linearSprings[1].restLength, build::kAttractorRestLength);
  EXPECT_DOUBLE_EQ(model.linearSprings[1].stiffness, 50.0);
  EXPECT_EQ(checkModel(model), "");
}

TEST(BuildGoals, AMovingGoalStartsOnTheRobotAndArrivesAtItsSpeed) {
  Model model;
  State state;
  addRobot(model, state, {{0, 0, 0}, {0, 1, 0}});
  build::AttractorGoalSpec spec;
  spec.particles = {0, 1};
  spec.goalPositions = {{2, 0, 0}, {1, 1, 0}};
  spec.speed = 0.5;
  const build::GoalSpec goal = build::addGoal(model, state, spec);
  EXPECT_DOUBLE_EQ(goal.travelTime, 4.0);  // the farthest, 2 m at 0.5 m/s
  EXPECT_EQ(state.position[goal.targets[0]], (Vec3{0, 0, 0}));
  EXPECT_DOUBLE_EQ(state.velocity[goal.targets[0]].x, 0.5);
  EXPECT_DOUBLE_EQ(state.velocity[goal.targets[1]].x, 0.25);
  EXPECT_EQ(goal.goalPositions[1], (Vec3{1, 1, 0}));
}

TEST(BuildGoals, PathsAddTheirConnectors) {
  Model model;
  State state;
  addRobot(model, state, {{1, 0, 0}, {1, 1, 0}});
  build::addLinePath(model, state, {"line", 0, {0, 0, 0}, {3, 0, 0}, 400.0, 5.0});
  ASSERT_EQ(model.torsionSprings.size(), 1u);
  EXPECT_EQ(model.torsionSprings[0].c, 0);
  EXPECT_DOUBLE_EQ(model.torsionSprings[0].restAngle, M_PI);
  // Arc (MODEL §5.1): a TS centred on the robot between two ends on the circle,
  // at the inscribed angle: from (1, 0), the ends (0, -1) and (0, 1) of a
  // diameter are seen at 90° (Thales).
  build::ArcPathSpec arc;
  arc.name = "arc";
  arc.particle = 0;
  arc.from = {0, -1, 0};
  arc.to = {0, 1, 0};
  arc.stiffness = 10.0;
  arc.heading = 1;
  build::addArcPath(model, state, arc);
  EXPECT_TRUE(model.linearSprings.empty());
  ASSERT_EQ(model.torsionSprings.size(), 3u);
  EXPECT_EQ(model.torsionSprings[1].c, 0);
  EXPECT_NEAR(model.torsionSprings[1].restAngle, M_PI / 2.0, 1e-12);
  EXPECT_DOUBLE_EQ(model.torsionSprings[2].restAngle, M_PI / 2.0);
  EXPECT_DOUBLE_EQ(model.torsionSprings[2].stiffness, 10.0);
  // The heading TS's end is the circle's centre.
  EXPECT_NEAR(norm(state.position[model.torsionSprings[2].a]), 0.0, 1e-12);
  EXPECT_EQ(model.objects.size(), 3u);
  EXPECT_EQ(checkModel(model), "");
}

TEST(BuildGoals, ObstaclesGrowByTheSecurityDistance) {
  Model model;
  build::ObstacleSpec sphere;
  sphere.center = {1, 0, 0};
  sphere.radius = 0.2;
  sphere.securityDistance = 0.05;
  build::addObstacle(model, sphere);
  build::ObstacleSpec box;
  box.shape = build::ObstacleShape::kBox;
  box.size = {0.2, 0.4, 0.6};
  box.securityDistance = 0.1;
  build::addObstacle(model, box);
  ASSERT_EQ(model.environment.spheres.size(), 1u);
  EXPECT_DOUBLE_EQ(model.environment.spheres[0].radius, 0.25);
  ASSERT_EQ(model.environment.boxes.size(), 1u);
  EXPECT_DOUBLE_EQ(model.environment.boxes[0].halfExtents.z, 0.4);
}

TEST(BuildGoals, TipAttractorsTieEveryTwoTips) {
  Model model;
  State state;
  addRobot(model, state, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  build::addTipAttractors(model, {0, 1, 2}, 30.0, 1.0);
  EXPECT_EQ(model.linearSprings.size(), 3u);
}

TEST(BuildGoals, BadArgumentsAreRefusedByNameBeforeAnythingIsAdded) {
  Model model;
  State state;
  addRobot(model, state, {{1, 1, 0}});
  build::AttractorGoalSpec goal;
  goal.particles = {3};
  goal.goalPositions = {{0, 0, 0}};
  EXPECT_NE(refusal([&] { build::addGoal(model, state, goal); }).find("addGoal: spec.particles[0]"),
            std::string::npos);
  goal.particles = {0};
  goal.goalPositions = {};
  EXPECT_NE(refusal([&] { build::addGoal(model, state, goal); }).find("spec.goalPositions"),
            std::string::npos);
  goal.goalPositions = {{0, 0, 0}};
  goal.stiffness = -1.0;
  EXPECT_NE(refusal([&] { build::addGoal(model, state, goal); }).find("spec.stiffness must be > 0"),
            std::string::npos);
  EXPECT_NE(refusal([&] {
              build::addLinePath(model, state, {"line", 0, {0, 0, 0}, {3, 0, 0}, 1.0, 0.0});
            }).find("the particle must start on the segment"),
            std::string::npos);
  build::ArcPathSpec arc;
  arc.from = {0, 0, 0};
  arc.to = {2, 2, 0};
  EXPECT_NE(refusal([&] { build::addArcPath(model, state, arc); }).find("not start on their line"),
            std::string::npos);
  build::ObstacleSpec sphere;
  sphere.radius = 0.0;
  EXPECT_NE(refusal([&] { build::addObstacle(model, sphere); }).find("spec.radius"),
            std::string::npos);
  EXPECT_NE(refusal([&] {
              build::addTipAttractors(model, {0, 5}, 1.0, 0.0);
            }).find("tips[1]"),
            std::string::npos);
  EXPECT_EQ(model.particleCount(), 1);
  EXPECT_EQ(model.objects.size(), 1u);
  EXPECT_TRUE(model.linearSprings.empty());
  EXPECT_TRUE(model.torsionSprings.empty());
  EXPECT_TRUE(model.environment.spheres.empty());
}

}  // namespace
}  // namespace robophi
