// MODEL §5.3, paper experiment 4: the three-fingered hand closes on a free ball by
// attracting its finger tips to each other (passive joints); the grasp holds the
// ball under gravity and after a sideways kick, for the paper's 50 s.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <string>

#include "robophi/evaluation.h"
#include "robophi/scene/scene.h"
#include "robotics/scene_files.h"
#include "robotics/tasks.h"
#include "run/runner.h"

namespace robophi {
namespace {

TEST(Grasp, ThreeFingeredHandHoldsTheBallThroughADisturbance) {
  const Scene scene = testing::loadSceneFromScenes("hand_grasp.json");
  ASSERT_EQ(scene.model.joints.size(), 9u);  // three fingers, three joints each
  RunOptions options;
  options.settings = scene.run;
  options.tasks = {robotics::makeSceneTasks(scene)};
  State last;
  const RunReport report = runScene(scene, options, &last);
  ASSERT_TRUE(report.ok()) << report.failure;
  EXPECT_DOUBLE_EQ(report.simulatedTime, 50.0);
  bool judgedStable = false;
  double drift = -1.0;
  for (const std::string& e : report.events) {
    if (e.rfind("grasp stable", 0) == 0) {
      judgedStable = true;
      drift = std::stod(e.substr(e.find("largest drift ") + 14));
    }
  }
  EXPECT_TRUE(judgedStable) << (report.events.empty() ? "" : report.events.back());
  // The 0.3 m/s kick moves the ball by millimetres only (tolerance 1 cm).
  EXPECT_GT(drift, 0.0);
  EXPECT_LT(drift, 0.005);
  // A held object at rest for 50 s: the energy account closes (no friction
  // chatter, no marginal contact oscillation).
  EXPECT_LT(std::abs(report.energyDrift), 0.01);
  // The ball (the last object) is still in the hand: above the palm, within its radius.
  const ObjectInfo& ball = scene.model.objects.back();
  Vec3 centre;
  for (ParticleIndex i = ball.firstParticle; i < ball.firstParticle + ball.particleCount; ++i) {
    centre += last.position[i] / static_cast<double>(ball.particleCount);
  }
  EXPECT_GT(centre.z, 0.0);
  EXPECT_LT(std::hypot(centre.x, centre.y), 0.06);
  // A power grasp: the palm and the fingers' links hold the ball through many
  // contacts at once, and it is at rest in them.
  const ObjectInfo& hand = scene.model.objects.front();
  const auto inBall = [&](std::int32_t i) {
    return i >= ball.firstParticle && i < ball.firstParticle + ball.particleCount;
  };
  const auto inHand = [&](std::int32_t i) {
    return i >= hand.firstParticle && i < hand.firstParticle + hand.particleCount;
  };
  int holding = 0;
  std::set<std::int32_t> touchingHandParticles;
  // The contacts at the final state: a pure evaluation of it.
  Workspace workspace;
  const CompiledModel model(scene.model);
  for (const Contact& c : evaluate(model, last, workspace).contacts) {
    if (c.other < 0) continue;
    if ((inBall(c.a) && inHand(c.other)) || (inHand(c.a) && inBall(c.other))) {
      ++holding;
      touchingHandParticles.insert(inHand(c.a) ? c.a : c.other);
    }
  }
  std::printf("hand grasp at 50 s: %d ball-hand contacts, %zu hand particles touching\n", holding,
              touchingHandParticles.size());
  EXPECT_GE(holding, 10);
  EXPECT_GE(touchingHandParticles.size(), 8u);
  double fastest = 0.0;
  for (ParticleIndex i = ball.firstParticle; i < ball.firstParticle + ball.particleCount; ++i)
    fastest = std::max(fastest, norm(last.velocity[i]));
  EXPECT_LT(fastest, 1e-3);
}

}  // namespace
}  // namespace robophi
