// A movable palm (scenes/hand_lift.json, docs/robots.md "Moving bases"): the
// hand closes on a free ball (no gravity), and when (after 0.5 s) the fingers'
// contact force on it exceeds 0.15 N a control phase lifts the hand's fixed particles by 5 cm
// over 1 s. The base lands exactly on its keyframe; the ball, held by the
// fingers alone, rides up with it (3.9 cm of the 5: it slips about 1 cm).
#include <gtest/gtest.h>

#include <cmath>
#include <utility>
#include <vector>

#include "robotics/scene_files.h"
#include "robotics/tasks.h"
#include "run/runner.h"

namespace robophi {
namespace {

TEST(HandLift, ThePalmMovesOnItsKeyframesAndTheBallRidesUpInTheFingers) {
  const Scene scene = testing::loadSceneFromScenes("hand_lift.json");
  ASSERT_EQ(scene.robotics.control.phases.size(), 2u);
  RunOptions options;
  options.settings = scene.run;
  options.writeReplay = false;
  const robotics::SceneTaskHook hook = robotics::makeSceneTaskHook(scene);
  // The ball's centre height (m) after each step, to read it where the lift began.
  const ObjectInfo& ball = scene.model.objects[1];
  std::vector<std::pair<double, double>> height;
  options.tasks = {hook.task, [&](World& world, std::vector<std::string>&) {
                     double z = 0.0, m = 0.0;
                     for (ParticleIndex i = ball.firstParticle;
                          i < ball.firstParticle + ball.particleCount; ++i) {
                       z += world.model().mass[i] * world.state().position[i].z;
                       m += world.model().mass[i];
                     }
                     height.emplace_back(world.state().time, z / m);
                     return true;
                   }};
  State last;
  const RunReport report = runScene(scene, options, &last);
  ASSERT_EQ(report.status, "ok") << report.failure;
  const nlohmann::json& phase = report.outcomes.at("control").at("phases").at(1);
  ASSERT_TRUE(phase.at("started").get<bool>()) << report.outcomes.dump();
  const double liftedAt = phase.at("started_s").get<double>();
  EXPECT_GT(liftedAt, 0.5);
  EXPECT_LT(liftedAt, 2.0) << "the grip force never reached 0.15 N before the timeout";
  EXPECT_EQ(phase.at("by").get<std::string>().find("timeout"), std::string::npos);
  // Every fixed particle of the hand is 5 cm higher, exactly where the keyframe put it.
  const ObjectInfo& hand = scene.model.objects[0];
  for (ParticleIndex i = hand.firstParticle; i < hand.firstParticle + hand.particleCount; ++i) {
    if (!scene.model.isFixed(i)) continue;
    EXPECT_NEAR(last.position[i].z - scene.initial.position[i].z, 0.05, 1e-9) << i;
    EXPECT_NEAR(last.position[i].x, scene.initial.position[i].x, 1e-12);
  }
  // The ball went up with it, held by the fingers (no gravity, nothing else
  // holds it): from where it was when the lift began (the closing fingers had
  // pressed it 1.5 cm towards the palm) to the end.
  double atLift = height.front().second;
  for (const auto& [t, z] : height)
    if (t <= liftedAt) atLift = z;
  const double rise = height.back().second - atLift;
  // Measured: 3.9 cm of the palm's 5 cm; the soft grip (0.2 N, skin κ_c = 2e3 N/m)
  // lets it slip about 1 cm.
  EXPECT_GT(rise, 0.035) << "the ball rose " << rise << " m";
  EXPECT_LT(rise, 0.055) << "the ball rose " << rise << " m";
  EXPECT_LT(report.energyDrift, 0.05);
}

}  // namespace
}  // namespace robophi
