// MODEL §5.3, paper experiment 4: the three-fingered hand closes on a free ball by
// attracting its finger tips to each other (passive joints); the grasp holds the
// ball under gravity and after a sideways kick, for the paper's 50 s.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "robophi/runner.h"
#include "robophi/scene.h"
#include "robotics/scene_files.h"

namespace robophi {
namespace {

TEST(Grasp, ThreeFingeredHandHoldsTheBallThroughADisturbance) {
  const Scene scene = testing::loadSceneFromScenes("hand_grasp.json");
  ASSERT_EQ(scene.model.joints.size(), 9u);  // three fingers, three joints each
  RunOptions options;
  options.settings = scene.run;
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
}

}  // namespace
}  // namespace robophi
