// One meaning of dt (issue 10): a generated object's default stiffness comes
// from a natural frequency of the model (ω = 2500 rad/s by default, the scene
// key "naturalFrequency"), never from the scene's time step.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>

#include "build/model_compare.h"
#include "robophi/build/objects.h"
#include "robophi/scene/scene.h"
#include "run/runner.h"
#include "scene/json_locator.h"

namespace robophi {
namespace {

// The built-in arm (the arm of scenes/arm_reach.json) hanging under gravity,
// its joints passive, with `runDt` as the step (the first trial of the adaptive
// step, the default mode).
Scene armUnderGravity(double runDt, const char* extraKeys = "") {
  SceneLoadResult result =
      loadSceneText(fmt::format(R"({{"run": {{"duration": 3.0, "dt": {}}}, "gravity": [0, 0, -9.81],
          "objects": [{{"name": "arm", "type": "arm", "base": [0, 0, 0], "direction": [1, 0, 0],
                        "links": [0.5, 0.4], "axes": [0, 0, 1], "mass": 2.0, "width": 0.08,
                        "linearDamping": 1.0{}}}]}})",
                                runDt, extraKeys),
                    "arm.json");
  for (const auto& e : result.errors) ADD_FAILURE() << e.format();
  if (!result.ok()) return Scene{};
  return std::move(*result.scene);
}

Vec3 finalTool(const Scene& scene) {
  RunOptions options;
  options.settings = scene.run;
  State final;
  const RunReport report = runScene(scene, options, &final);
  EXPECT_TRUE(report.ok()) << report.failure;
  return final.position.back();  // the tool is the arm's last particle
}

// Issue 10 must-show: before, the tool ended at z = -0.848 m with run.dt 1e-3
// and at -0.001 m with 2e-5 (the stiffness followed ω·dt = 0.25); now at
// z = -0.175 m with both, 2.4e-10 m apart.
TEST(NaturalFrequency, ArmUnderGravityEndsInTheSamePlaceWithRunDt1e3And2e5) {
  const Scene coarse = armUnderGravity(1e-3);
  const Scene fine = armUnderGravity(2e-5);
  ASSERT_EQ(coarse.run.stepMode, StepMode::kAdaptive);
  // One model whatever the step.
  testing::expectSameStart(coarse.model, coarse.initial, fine.model, fine.initial);
  const Vec3 a = finalTool(coarse), b = finalTool(fine);
  EXPECT_LT(norm(a - b), 1e-3) << "tool at [" << a.x << ", " << a.y << ", " << a.z << "] and ["
                               << b.x << ", " << b.y << ", " << b.z << "]";
  EXPECT_LT(a.z, -0.01);  // it does hang: gravity bends the links out of their plane
}

TEST(NaturalFrequency, SceneKeySetsTheDefaultStiffness) {
  const Scene standard = armUnderGravity(1e-4);
  const Scene soft = armUnderGravity(1e-4, R"(, "naturalFrequency": 1250)");
  ASSERT_FALSE(standard.model.linearSprings.empty());
  // κ ∝ ω²: half the frequency is a quarter of the stiffness.
  EXPECT_DOUBLE_EQ(soft.model.linearSprings[0].stiffness,
                   0.25 * standard.model.linearSprings[0].stiffness);
  // The default is 2500 rad/s: ω·δ = 0.25 at δ = 1e-4 s, the old value there.
  const Scene explicitDefault = armUnderGravity(1e-4, R"(, "naturalFrequency": 2500)");
  testing::expectSameModel(standard.model, explicitDefault.model);
  EXPECT_EQ(build::kDefaultNaturalFrequency, 0.25 / 1e-4);
}

TEST(NaturalFrequency, StiffnessAndFrequencyTogetherAreRejected) {
  const SceneLoadResult result = loadSceneText(
      R"({"objects": [{"name": "r", "type": "rope", "start": [0, 0, 0], "end": [1, 0, 0],
          "particles": 4, "mass": 1, "stiffness": 100, "naturalFrequency": 50}]})",
      "both.json");
  ASSERT_EQ(result.errors.size(), 1u);
  EXPECT_EQ(result.errors[0].pointer, "/objects/0/naturalFrequency");
  EXPECT_NE(result.errors[0].message.find("give one of them"), std::string::npos);
}

// The shipped scenes keep the stiffness they had when it followed ω·dt = 0.25:
// every generated object that takes the default stiffness either states
// naturalFrequency = 0.25 / run.dt or runs at the default step 1e-4 s.
TEST(NaturalFrequency, ShippedScenesKeepTheirStiffness) {
  const std::filesystem::path folder = std::string(ROBOPHI_SOURCE_DIR) + "/scenes";
  int checked = 0;
  for (const auto& file : std::filesystem::directory_iterator(folder)) {
    if (file.path().extension() != ".json") continue;
    std::ifstream in(file.path());
    const std::string text{std::istreambuf_iterator<char>(in), {}};
    const scene::JsonReadResult json = scene::readLocatedJson(text);  // comments allowed
    ASSERT_TRUE(json.json.has_value()) << file.path();
    const nlohmann::json& root = json.json->value;
    const double dt = root.contains("run") ? root["run"].value("dt", 1e-4) : 1e-4;
    for (const auto& object : root["objects"]) {
      const std::string type = object.value("type", "");
      // (A rigid object or robot has no connectors: no stiffness of it follows dt.)
      const bool takesDefault = type != "particles" && !object.value("rigid", false) &&
                                !object.contains("stiffness") && !object.contains("youngModulus");
      if (!takesDefault) continue;
      ++checked;
      if (object.contains("naturalFrequency")) {
        EXPECT_EQ(object["naturalFrequency"].get<double>(), 0.25 / dt)
            << file.path().filename() << " " << object.value("name", "");
      } else {
        EXPECT_EQ(dt, 1e-4) << file.path().filename() << " " << object.value("name", "")
                            << ": give it \"naturalFrequency\": " << 0.25 / dt;
      }
    }
  }
  EXPECT_GT(checked, 5);
}

}  // namespace
}  // namespace robophi
