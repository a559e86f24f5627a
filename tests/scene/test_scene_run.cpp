// The scene's "run" section: the adaptive step's settings as scene keys
// (run.adaptive, docs/scene-format.md#runadaptive), with their ranges and units.
#include <gtest/gtest.h>

#include <string>

#include "run/runner.h"
#include "robophi/scene/scene.h"
#include "scene/scene_test_util.h"

namespace robophi {
namespace {

// A rope hanging from its first particle, released horizontal; `adaptive` is the
// text of run.adaptive (empty: none).
std::string swingingRope(const std::string& adaptive) {
  return R"({"run": {"duration": 0.1, "dt": 1e-4)" +
         (adaptive.empty() ? std::string() : ",\n  \"adaptive\": " + adaptive) + R"(},
"objects": [{"name": "rope", "type": "rope", "start": [0, 0, 1], "end": [1, 0, 1],
             "particles": 8, "mass": 0.5, "fixed": [0]}]})";
}

TEST(SceneRun, AdaptiveKeysSetTheControllersSettings) {
  const SceneLoadResult result = loadSceneText(swingingRope(R"({
    "energyTolerance": 1e-4, "minStep": 1e-9, "maxStep": 5e-5, "lossToleranceFactor": 2,
    "energyFloor": 1e-6, "shrinkFactor": 0.3, "growFactor": 1.5, "safety": 0.7,
    "errorOrder": 2, "maxPenetrationFraction": 0.05, "stabilitySafety": 0.5,
    "maxRejectionsInARow": 40})"),
                                               "adaptive.json");
  ASSERT_TRUE(result.ok()) << test::allErrors(result);
  const AdaptiveStepSettings& a = result.scene->run.adaptive;
  EXPECT_DOUBLE_EQ(a.energyTolerance, 1e-4);
  EXPECT_DOUBLE_EQ(a.minStep, 1e-9);
  EXPECT_DOUBLE_EQ(a.maxStep, 5e-5);
  EXPECT_DOUBLE_EQ(a.lossToleranceFactor, 2.0);
  EXPECT_DOUBLE_EQ(a.energyFloor, 1e-6);
  EXPECT_DOUBLE_EQ(a.shrinkFactor, 0.3);
  EXPECT_DOUBLE_EQ(a.growFactor, 1.5);
  EXPECT_DOUBLE_EQ(a.safety, 0.7);
  EXPECT_DOUBLE_EQ(a.errorOrder, 2.0);
  EXPECT_DOUBLE_EQ(a.maxPenetrationFraction, 0.05);
  EXPECT_DOUBLE_EQ(a.stabilitySafety, 0.5);
  EXPECT_EQ(a.maxRejectionsInARow, 40);
  // initialStep is not a scene key: the first trial step is run.dt.
  EXPECT_DOUBLE_EQ(a.initialStep, AdaptiveStepSettings{}.initialStep);
}

TEST(SceneRun, WithoutAdaptiveKeysTheDefaultsHold) {
  const SceneLoadResult result = loadSceneText(swingingRope(""), "plain.json");
  ASSERT_TRUE(result.ok()) << test::allErrors(result);
  const AdaptiveStepSettings& a = result.scene->run.adaptive;
  const AdaptiveStepSettings defaults;
  EXPECT_EQ(a.energyTolerance, defaults.energyTolerance);
  EXPECT_EQ(a.maxStep, defaults.maxStep);
  EXPECT_EQ(a.maxRejectionsInARow, defaults.maxRejectionsInARow);
}

// A scene's maxStep caps the steps the run takes.
TEST(SceneRun, AdaptiveMaxStepTakesEffectInARun) {
  const SceneLoadResult free = loadSceneText(swingingRope(""), "free.json");
  const SceneLoadResult capped = loadSceneText(swingingRope(R"({"maxStep": 5e-5})"), "capped.json");
  ASSERT_TRUE(free.ok()) << test::allErrors(free);
  ASSERT_TRUE(capped.ok()) << test::allErrors(capped);
  RunOptions options;
  options.settings = free.scene->run;
  const RunReport freeRun = runScene(*free.scene, options);
  options.settings = capped.scene->run;
  const RunReport cappedRun = runScene(*capped.scene, options);
  ASSERT_TRUE(freeRun.ok()) << freeRun.failure;
  ASSERT_TRUE(cappedRun.ok()) << cappedRun.failure;
  EXPECT_GT(freeRun.adaptive.largestStep, 5e-5);  // else the test shows nothing
  EXPECT_LE(cappedRun.adaptive.largestStep, 5e-5);
  EXPECT_GT(cappedRun.adaptive.accepted, freeRun.adaptive.accepted);
}

struct BadAdaptive {
  const char* label;
  const char* adaptive;
  const char* fragment;
  const char* pointer;
};

const BadAdaptive kBadAdaptive[] = {
    {"misspelt", R"({"energyTolerence": 1e-4})",
     "unknown key 'energyTolerence' in 'run.adaptive'; did you mean 'energyTolerance'?",
     "/run/adaptive/energyTolerence"},
    {"misspelt step", R"({"maxstep": 1e-3})",
     "unknown key 'maxstep' in 'run.adaptive'; did you mean 'maxStep'?", "/run/adaptive/maxstep"},
    {"initial step", R"({"initialStep": 1e-3})",
     "'initialStep' is not a key of 'run.adaptive': the first trial step is 'run.dt'",
     "/run/adaptive/initialStep"},
    {"tolerance", R"({"energyTolerance": 0})", "'energyTolerance' must be > 0, got 0",
     "/run/adaptive/energyTolerance"},
    {"min step", R"({"minStep": -1e-9})", "'minStep' must be > 0 s, got -1e-09",
     "/run/adaptive/minStep"},
    {"energy floor", R"({"energyFloor": 0})", "'energyFloor' must be > 0 J, got 0",
     "/run/adaptive/energyFloor"},
    {"shrink", R"({"shrinkFactor": 0.05})", "'shrinkFactor' must be in [0.1, 1), got 0.05",
     "/run/adaptive/shrinkFactor"},
    {"shrink one", R"({"shrinkFactor": 1})", "'shrinkFactor' must be in [0.1, 1), got 1",
     "/run/adaptive/shrinkFactor"},
    {"grow", R"({"growFactor": 0.9})", "'growFactor' must be > 1, got 0.9",
     "/run/adaptive/growFactor"},
    {"safety", R"({"safety": 1.5})", "'safety' must be in (0, 1), got 1.5", "/run/adaptive/safety"},
    {"stability safety", R"({"stabilitySafety": 1.2})",
     "'stabilitySafety' must be in (0, 1], got 1.2", "/run/adaptive/stabilitySafety"},
    {"error order", R"({"errorOrder": -1})", "'errorOrder' must be >= 0, got -1",
     "/run/adaptive/errorOrder"},
    {"penetration", R"({"maxPenetrationFraction": -0.1})",
     "'maxPenetrationFraction' must be >= 0, got -0.1", "/run/adaptive/maxPenetrationFraction"},
    {"rejections", R"({"maxRejectionsInARow": 0})",
     "'maxRejectionsInARow' must be an integer in [1, 10000000], got 0",
     "/run/adaptive/maxRejectionsInARow"},
    {"type", R"({"maxStep": "1ms"})", "'maxStep': expected a number (s), got string \"1ms\"",
     "/run/adaptive/maxStep"},
    {"order of steps", R"({"minStep": 1e-3, "maxStep": 1e-4})",
     "'maxStep' 0.0001 s must not be below 'minStep' 0.001 s", "/run/adaptive/maxStep"},
    {"not an object", R"(1e-5)", "'run.adaptive': expected an object {...}, got number 1e-05",
     "/run/adaptive"},
};

class SceneRunBadAdaptive : public ::testing::TestWithParam<BadAdaptive> {};

TEST_P(SceneRunBadAdaptive, IsRejectedWithItsPlaceAndRange) {
  const BadAdaptive& c = GetParam();
  const SceneLoadResult result = loadSceneText(swingingRope(c.adaptive), "bad.json");
  ASSERT_FALSE(result.ok());
  ASSERT_EQ(result.errors.size(), 1u) << test::allErrors(result);
  const Diagnostic& e = result.errors[0];
  EXPECT_NE(e.message.find(c.fragment), std::string::npos) << e.format();
  EXPECT_EQ(e.pointer, c.pointer) << e.format();
  EXPECT_EQ(e.line, 2) << e.format();  // run.adaptive is on the scene's second line
  EXPECT_GT(e.column, 0) << e.format();
}

INSTANTIATE_TEST_SUITE_P(Scene, SceneRunBadAdaptive, ::testing::ValuesIn(kBadAdaptive),
                         test::LabelName());

}  // namespace
}  // namespace robophi
