// The rigid Panda picks a 0.5 kg box and holds it through a 2 g shake
// (scenes/panda_shake_rigid.json, issue 35; docs/robots.md "Rigid bodies"): the
// pick of scenes/panda_pick_rigid.json with a heavier box and a 20 N grip, then
// the shoulder follows a 3 Hz sine for 2 s.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "robophi/multibody.h"
#include "robophi/scene/scene.h"
#include "robotics/tasks.h"
#include "run/runner.h"
#include "test_files.h"

namespace robophi {
namespace {

using testing::kRobots;  // ROBOPHI_ROBOTS_DIR (test_files.h)

std::int32_t shakenObjectNamed(const Model& model, const std::string& name) {
  for (std::size_t o = 0; o < model.objects.size(); ++o)
    if (model.objects[o].name == name) return static_cast<std::int32_t>(o);
  return -1;
}

// Mass centre (m) and its velocity (m/s) of an object's particles.
void shakenCenterOf(const Model& model, const State& state, std::int32_t object, Vec3& position,
                    Vec3& velocity) {
  const ObjectInfo& o = model.objects[static_cast<std::size_t>(object)];
  Vec3 p{}, v{};
  double mass = 0.0;
  for (ParticleIndex i = o.firstParticle; i < o.firstParticle + o.particleCount; ++i) {
    p += state.position[static_cast<std::size_t>(i)] * model.mass[i];
    v += state.velocity[static_cast<std::size_t>(i)] * model.mass[i];
    mass += model.mass[i];
  }
  position = p / mass;
  velocity = v / mass;
}

struct ShakeRun {
  double shakeStart = 0.0, restStart = 0.0;
  // The box's largest acceleration (m/s², its mass centre's velocity differenced
  // over 10 ms) in the shake, and its largest displacement relative to the
  // fingers (its mass centre in the left finger's frame) from the shake's start to
  // the end of the run (m). (In the world's axes the vector from the fingers to
  // the box turns with the hand: the shoulder's 0.08 rad swing moves it by about
  // 1 mm with no slip at all, which this measure once counted as slip.)
  double peakAcceleration = 0.0, slip = 0.0, wall = 0.0, end = 0.0;
  // Its displacement relative to the fingers at the end of the run (m): what stays.
  double finalSlip = 0.0;
};

// `scene`: the shake scene's text, with the box's size and mass replaced.
ShakeRun runShake(const std::string& text) {
  ShakeRun out;
  setenv("ROBOPHI_ROBOTS_DIR", kRobots.c_str(), 0);
  SceneLoadResult result =
      loadSceneText(text, std::string(ROBOPHI_SOURCE_DIR) + "/scenes/panda_shake_rigid.json");
  for (const auto& e : result.errors) ADD_FAILURE() << e.format();
  if (!result.ok()) return out;
  const Scene& scene = *result.scene;
  const Model& model = scene.model;
  const std::int32_t box = shakenObjectNamed(model, "box");
  EXPECT_GE(box, 0);
  if (box < 0) return out;
  struct Sample {
    double t;
    Vec3 velocity, relative;
  };
  std::vector<Sample> samples;
  // X_WF of the left finger (its body on the robot's rigid tree).
  std::size_t tree = 0;
  std::int32_t finger = -1;
  for (std::size_t t = 0; t < model.rigidTrees.size() && finger < 0; ++t) {
    finger = model.rigidTrees[t].multibody.bodyIndex("panda.panda_leftfinger");
    tree = t;
  }
  EXPECT_GE(finger, 0);
  if (finger < 0) return out;
  const Multibody& mb = model.rigidTrees[tree].multibody;
  MultibodyKinematics kin;
  const auto fingerPose = [&](const State& s) {
    updateKinematics(mb, s.treePositions[tree].data(), kin);
    return kin.X_WB[static_cast<std::size_t>(finger)];
  };
  RunOptions options;
  options.settings = scene.run;
  options.writeReplay = false;
  options.threads = 1;
  const robotics::SceneTaskHook hook = robotics::makeSceneTaskHook(scene);
  options.tasks = {hook.task, [&](World& world, std::vector<std::string>&) {
                     const State& s = world.state();
                     Vec3 b, v;
                     shakenCenterOf(model, s, box, b, v);
                     samples.push_back({s.time, v, inverse(fingerPose(s)) * b});
                     return true;
                   }};
  const auto start = std::chrono::steady_clock::now();
  const RunReport report = runScene(scene, options);
  out.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(report.status, "ok") << report.failure;
  const nlohmann::json& phases = report.outcomes.at("control").at("phases");
  EXPECT_EQ(phases.size(), 6u);
  if (phases.size() != 6u || samples.empty()) return out;
  for (const nlohmann::json& phase : phases) {
    EXPECT_TRUE(phase.at("started").get<bool>()) << report.outcomes.dump();
    EXPECT_EQ(phase.at("by").get<std::string>().find("timeout"), std::string::npos) << phase.dump();
  }
  out.shakeStart = phases.at(4).at("started_s").get<double>();
  out.restStart = phases.at(5).at("started_s").get<double>();
  out.end = samples.back().t;
  Vec3 reference{};
  bool referenced = false;
  std::size_t back = 0;  // the sample 10 ms before
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const Sample& s = samples[k];
    while (samples[back].t < s.t - 0.01) ++back;
    if (s.t < out.shakeStart) continue;
    if (!referenced) {
      reference = s.relative;
      referenced = true;
    }
    out.slip = std::max(out.slip, norm(s.relative - reference));
    out.finalSlip = norm(s.relative - reference);
    const Sample& before = samples[back == 0 ? 0 : back - 1];
    if (s.t <= out.restStart && before.t >= out.shakeStart && s.t > before.t)
      out.peakAcceleration =
          std::max(out.peakAcceleration, norm(s.velocity - before.velocity) / (s.t - before.t));
  }
  return out;
}

std::string shakeScene() {
  const std::string path = std::string(ROBOPHI_SOURCE_DIR) + "/scenes/panda_shake_rigid.json";
  FILE* file = std::fopen(path.c_str(), "rb");
  EXPECT_NE(file, nullptr) << path;
  std::string text;
  if (file == nullptr) return text;
  char buffer[4096];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, file)) > 0;) text.append(buffer, n);
  std::fclose(file);
  return text;
}

void replace(std::string& text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  ASSERT_NE(at, std::string::npos) << from;
  text.replace(at, from.size(), to);
}

// The must-show: through the shake the box reaches 2 g and slips less than 2 mm
// relative to the fingers (to the end of the run).
TEST(UrdfShake, ThePandaHoldsA500gBoxThroughA2gShake) {
  const ShakeRun run = runShake(shakeScene());
  std::printf(
      "panda shake: shake %.3f-%.3f s; box peak acceleration %.2f m/s² (%.2f g), slip "
      "relative to the fingers %.3f mm to %.1f s (%.3f mm at the end); %.1f s wall\n",
      run.shakeStart, run.restStart, run.peakAcceleration, run.peakAcceleration / 9.81,
      1e3 * run.slip, run.end, 1e3 * run.finalSlip, run.wall);
  EXPECT_GT(run.peakAcceleration, 2.0 * 9.81);
  EXPECT_LT(run.slip, 2e-3);
}

// A box it was not tuned to: 4 cm (0.5 kg).
TEST(UrdfShake, ASmallerBoxToo) {
  std::string text = shakeScene();
  replace(text, "\"size\": [0.05, 0.05, 0.05]", "\"size\": [0.04, 0.04, 0.04]");
  replace(text, "\"center\": [0.5, 0, 0.025]", "\"center\": [0.5, 0, 0.02]");
  const ShakeRun run = runShake(text);
  std::printf(
      "panda shake, 4 cm box: box peak acceleration %.2f m/s² (%.2f g), slip %.3f mm (%.3f mm at "
      "the end); %.1f s wall\n",
      run.peakAcceleration, run.peakAcceleration / 9.81, 1e3 * run.slip, 1e3 * run.finalSlip,
      run.wall);
  // Measured in the finger's frame: well under 1 mm (2.4 mm in the world's axes,
  // most of it the hand turning, not the box slipping). The box turns by up to
  // 2.4° about the grip axis at the peaks and back.
  EXPECT_GT(run.peakAcceleration, 2.0 * 9.81);
  EXPECT_LT(run.slip, 2e-3);
  EXPECT_LT(run.finalSlip, 1e-3);
}

}  // namespace
}  // namespace robophi
