// Objects that start overlapping are named before the run (run/start_checks.h):
// two balls that start interpenetrating are thrown apart by the contact force.

#include <gtest/gtest.h>

#include "robophi/scene/scene.h"
#include "run/runner.h"
#include "run/start_checks.h"

namespace robophi {
namespace {

Scene twoBalls(double gap) {
  // Two balls of radius 0.1 m (cells 2) whose centres are 0.2 m + gap apart.
  const std::string text = R"({"robophi": 1, "name": "two balls", "gravity": [0, 0, 0],
    "environment": {"ground": {"point": [0, 0, -1]}},
    "objects": [
      {"name": "left", "type": "ball", "center": [0, 0, 0], "radius": 0.1, "mass": 1},
      {"name": "right", "type": "ball", "center": [)" +
                           std::to_string(0.2 + gap) + R"(, 0, 0], "radius": 0.1, "mass": 1}]})";
  SceneLoadResult result = loadSceneText(text, "two_balls.json");
  for (const Diagnostic& d : result.errors) ADD_FAILURE() << d.format();
  return std::move(*result.scene);
}

TEST(StartChecks, NamesObjectsThatStartOverlapping) {
  const Scene scene = twoBalls(-0.1);  // the balls' surfaces 0.1 m into each other
  const std::vector<std::string> warnings = startingOverlapWarnings(scene.model, scene.initial);
  ASSERT_EQ(warnings.size(), 1u);
  const std::string& w = warnings[0];
  EXPECT_NE(w.find("object 'left' and object 'right' start overlapping"), std::string::npos) << w;
  EXPECT_NE(w.find("the deepest by"), std::string::npos) << w;
}

TEST(StartChecks, SaysNothingForObjectsApartOrJustTouching) {
  for (const double gap : {0.05, 0.0}) {
    const Scene scene = twoBalls(gap);
    EXPECT_TRUE(startingOverlapWarnings(scene.model, scene.initial).empty()) << gap;
  }
}

TEST(StartChecks, NamesAnObjectThatStartsInsideTheEnvironment) {
  Scene scene = twoBalls(0.05);
  scene.model.environment.planes[0].point = Vec3{0.0, 0.0, -0.05};  // through the balls
  const std::vector<std::string> warnings = startingOverlapWarnings(scene.model, scene.initial);
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_NE(warnings[0].find("object 'left' starts inside environment plane 0"), std::string::npos)
      << warnings[0];
}

TEST(StartChecks, TheRunListsTheOverlapAmongItsWarnings) {
  Scene scene = twoBalls(-0.1);
  RunOptions options;
  options.settings = scene.run;
  options.settings.duration = 1e-3;
  const RunReport report = runScene(scene, options);
  ASSERT_FALSE(report.warnings.empty());
  EXPECT_NE(report.warnings[0].find("start overlapping"), std::string::npos) << report.warnings[0];
}

// The stability warning says what its number is: the critical step, 2/omega_max
// reduced for damping, with 2/omega_max beside it; only for a constant step.
TEST(StartChecks, TheStepWarningNamesTheCriticalStepAndOnlyForConstantSteps) {
  RunSettings settings;
  settings.dt = 1e-3;
  StabilityEstimate stability;
  stability.omegaMax = 4767.0;        // 2/omega_max = 4.196e-4 s
  stability.criticalStep = 5.145e-5;  // reduced for damping
  stability.limitingParticle = 3;
  settings.stepMode = StepMode::kConstant;
  const std::vector<std::string> warnings = preflightWarnings(settings, stability);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("exceeds the critical step 5.14e-05 s"), std::string::npos)
      << warnings[0];
  EXPECT_NE(warnings[0].find("2/omega_max = 0.00042 s for omega_max = 4767 rad/s, reduced for "
                             "damping"),
            std::string::npos)
      << warnings[0];
  settings.stepMode = StepMode::kAdaptive;  // its first trial step is capped below the limit
  EXPECT_TRUE(preflightWarnings(settings, stability).empty());
}

}  // namespace
}  // namespace robophi
