// MODEL §5.3, paper experiment 4: the three-fingered hand closes on a free ball by
// attracting its finger tips to each other (passive joints); the grasp holds the
// ball under gravity and after a sideways kick.
#include <gtest/gtest.h>

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
  bool judgedStable = false;
  for (const std::string& e : report.events) {
    if (e.rfind("grasp stable", 0) == 0) judgedStable = true;
  }
  EXPECT_TRUE(judgedStable) << (report.events.empty() ? "" : report.events.back());
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
