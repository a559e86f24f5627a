// The run's energy account and its constant step (MODEL §2.4, §4.1; issue 12):
// the divergence verdict does not depend on where z = 0 is, and a constant step
// lands on the duration exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "robophi/scene/scene.h"
#include "robotics/tasks.h"
#include "run/runner.h"

namespace robophi {
namespace {

std::string sceneText(const std::string& name) {
  std::ifstream in(ROBOPHI_SOURCE_DIR "/scenes/" + name);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string pendulumText() { return sceneText("pendulum.json"); }

// The shipped pendulum with its pivot (and everything else) moved so that the
// pivot sits at z = `pivotZ` (it is at 1.5 m in the file).
std::string pendulumAt(double pivotZ) {
  std::string text = pendulumText();
  // Positions written as [x, y, z]: the pivot and the axis particle at 1.5, the
  // down reference at 0.5, the bob's centre at 1.5.
  // Plain text replacement (std::regex trips GCC 12's -Wmaybe-uninitialized in
  // the sanitizer build).
  const auto replaceAll = [&text](const std::string& from, const std::string& to) {
    for (std::size_t at = text.find(from); at != std::string::npos;
         at = text.find(from, at + to.size())) {
      text.replace(at, from.size(), to);
    }
  };
  replaceAll("[0, 0, 1.5]", "[0, 0, " + std::to_string(pivotZ) + "]");
  replaceAll("[0, 0, 0.5]", "[0, 0, " + std::to_string(pivotZ - 1.0) + "]");
  replaceAll("[0, 0.2, 1.5]", "[0, 0.2, " + std::to_string(pivotZ) + "]");
  replaceAll("[1, 0, 1.5]", "[1, 0, " + std::to_string(pivotZ) + "]");
  return text;
}

RunReport runText(const std::string& text, StepMode mode, double duration, double dt,
                  State* last = nullptr, const std::string& name = "pendulum.json") {
  const SceneLoadResult loaded = loadSceneText(text, name);
  EXPECT_TRUE(loaded.ok());
  RunOptions options;
  options.settings = loaded.scene->run;
  options.settings.stepMode = mode;
  options.settings.duration = duration;
  options.settings.dt = dt;
  options.tasks = {robotics::makeSceneTasks(*loaded.scene)};
  return runScene(*loaded.scene, options, last);
}

TEST(RunEnergyScale, PendulumVerdictDoesNotDependOnTheDatum) {
  const std::string atZero = pendulumAt(0.0), atTwo = pendulumAt(2.0);
  ASSERT_NE(atZero, pendulumText());
  for (StepMode mode : {StepMode::kAdaptive, StepMode::kConstant}) {
    const RunReport zero = runText(atZero, mode, 2.0, 1e-4);
    const RunReport two = runText(atTwo, mode, 2.0, 1e-4);
    EXPECT_EQ(zero.status, "ok") << zero.failure;
    EXPECT_EQ(two.status, "ok") << two.failure;
    // The drift is E_total's change over a datum-free scale (m g L here); the
    // two runs differ only by the round-off of positions near 0 and near 2 m.
    EXPECT_NEAR(zero.energyDrift, two.energyDrift, 0.05 * std::abs(two.energyDrift) + 1e-9);
    EXPECT_LT(std::abs(zero.energyDrift), 1e-2);
  }
}

TEST(RunEnergyScale, PendulumAtZAndAtTwoExitZeroFromTheCommandLine) {
  const auto dir = std::filesystem::temp_directory_path() / "robophi_pendulum_datum";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  for (double z : {0.0, 2.0}) {
    const auto scene = dir / ("pendulum_" + std::to_string(static_cast<int>(z)) + ".json");
    std::ofstream(scene) << pendulumAt(z);
    const auto out = dir / ("out_" + std::to_string(static_cast<int>(z)));
    const std::string command = std::string(ROBOPHI_BINARY) + " run " + scene.string() + " --out " +
                                out.string() + " --quiet --duration 1 > /dev/null 2>&1";
    EXPECT_EQ(std::system(command.c_str()), 0) << command;
  }
  std::filesystem::remove_all(dir);
}

TEST(RunEnergyScale, ASceneThatStartsWithNoEnergyIsNotCalledDiverged) {
  // The hand grasp with a larger, heavier ball that starts just out of reach:
  // no gravity, nothing moving, nothing touching, so the initial scale is 0.
  // The fingers' drives then do work on the hand and the ball; the account moves
  // by about 1 % of that work (a healthy run), which the runaway check must
  // weigh against the work, not against the zero it started from.
  std::string text = sceneText("hand_grasp.json");
  const std::string from = R"("center": [-0.0098, 0, 0.095], "radius": 0.05, "mass": 0.1)";
  const auto at = text.find(from);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, from.size(), R"("center": [-0.0098, 0, 0.090], "radius": 0.045, "mass": 0.15)");
  const RunReport report = runText(text, StepMode::kAdaptive, 4.0, 2e-4, nullptr, "hand.json");
  EXPECT_LT(report.initialScale, 1e-200);
  EXPECT_GT(report.externalWork, 1e-4);
  EXPECT_EQ(report.status, "ok") << report.failure;
  EXPECT_LT(std::abs(report.finalTotal - report.initialTotal), 0.05 * report.externalWork);
}

TEST(RunEnergyScale, ConstantStepLandsOnTheDurationExactly) {
  // 1 s at 1e-4 s (10 000 steps: summed, t drifts off 1 by ~1e-12) and 0.05 s
  // at 3e-4 s (the last step clipped).
  for (const auto& [duration, dt] : {std::pair{1.0, 1e-4}, std::pair{0.05, 3e-4}}) {
    State last;
    const RunReport report = runText(pendulumText(), StepMode::kConstant, duration, dt, &last);
    EXPECT_EQ(report.status, "ok");
    EXPECT_EQ(last.time, duration) << "dt " << dt;
    EXPECT_EQ(report.simulatedTime, duration);
  }
}

}  // namespace
}  // namespace robophi
