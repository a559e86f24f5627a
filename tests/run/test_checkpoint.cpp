// Checkpoint and restart (docs/output-format.md "Checkpoint and restart"): a run
// stopped at a checkpoint and resumed ends bit-identically to an uninterrupted
// run — the same state hash and the same frames, energy rows and contacts.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>

#include "robophi/scene/scene.h"
#include "robotics/tasks.h"
#include "run/checkpoint.h"
#include "run/runner.h"
#include "same_bits.h"
#include "test_files.h"

namespace robophi {
namespace {

namespace fs = std::filesystem;
using testing::readText;

const std::string kScenes = ROBOPHI_SOURCE_DIR "/scenes/";

using testing::sameBits;

TEST(Checkpoint, StateAndContactsReadBackBitExactly) {
  Model model;
  const int object = model.addObject("pair", "particles");
  model.addParticle(1.0, 0.1, false, object);
  model.addParticle(2.0, 0.1, false, object);
  State state = State::sizedFor(model);
  state.time = 0.1 + 0.2;  // not a short decimal
  state.stepCount = 123456789012;
  state.position[0] = {-0.0, 5e-324, 1.0 / 3.0};
  state.position[1] = {1e300, -2.5e-310, std::nextafter(1.0, 2.0)};
  state.velocity[1] = {M_PI, -M_E, 1e-17};
  Contact c;
  c.a = 0;
  c.other = 1;
  c.depth = -1.0 / 7.0;
  c.normalForce = 12.345678901234567;
  c.frictionForce = {0.1, -0.2, 0.3};
  c.anchorEnergy = 1e-30;
  c.normal = {0.0, 0.6, 0.8};
  c.slip = {std::numeric_limits<double>::denorm_min(), 0.0, -0.0};
  c.anchor = {1.0 / 9.0, 2.0 / 9.0, 4.0 / 9.0};
  c.sliding = 1;
  state.frictionHistory = {c};
  state.dissipated = 0.7;
  state.external = -0.3;
  // Through text, as a checkpoint file holds it.
  const nlohmann::json j = nlohmann::json::parse(stateToJson(state).dump());
  const State back = stateFromJson(j, model);
  EXPECT_EQ(stateHash(back), stateHash(state));
  ASSERT_EQ(back.frictionHistory.size(), 1u);
  const Contact& d = back.frictionHistory[0];
  EXPECT_EQ(d.a, c.a);
  EXPECT_EQ(d.other, c.other);
  EXPECT_TRUE(sameBits(d.frictionForce, c.frictionForce));  // not in the hash
  EXPECT_TRUE(sameBits(d.slip, c.slip));
  EXPECT_TRUE(sameBits(back.position[0], state.position[0]));
  // A state of another size is refused.
  Model bigger = model;
  bigger.addParticle(1.0, 0.1, false, object);
  EXPECT_THROW(stateFromJson(j, bigger), std::runtime_error);
}

TEST(Checkpoint, AnEdgeContactReadsBackAndAHistoryOutsideTheModelIsRefused) {
  // Two faceted cubes resting on crossed ridges: one edge contact.
  SceneLoadResult loaded =
      loadSceneFile(ROBOPHI_SOURCE_DIR "/tests/scene/stress/crossed_cubes_rest.json");
  ASSERT_TRUE(loaded.scene);
  const Model& model = loaded.scene->model;
  State state = loaded.scene->initial;
  Contact c;
  c.a = 0;
  c.other = model.objects[1].firstParticle;
  c.vertex = 3;
  c.edgeVertex = 7;
  c.edgeWeight = 1.0 / 3.0;
  c.facet = 5;
  c.facetWeights = {0.25, 0.75, 0.0};
  state.frictionHistory = {c};
  const nlohmann::json j = nlohmann::json::parse(stateToJson(state).dump());
  const State back = stateFromJson(j, model);
  EXPECT_EQ(stateHash(back), stateHash(state));
  EXPECT_EQ(back.frictionHistory[0].edgeVertex, 7);
  EXPECT_TRUE(sameBits(back.frictionHistory[0].edgeWeight, c.edgeWeight));
  // An index past the model's surface, and two records out of order.
  nlohmann::json bad = j;
  bad["friction_history"][0]["edge_vertex"] = static_cast<int>(model.surfaceVertices.size());
  try {
    stateFromJson(bad, model);
    ADD_FAILURE() << "an edge vertex past the model's was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("friction_history[0].edge_vertex"), std::string::npos)
        << e.what();
  }
  bad = j;
  bad["friction_history"].push_back(j["friction_history"][0]);
  EXPECT_THROW(stateFromJson(bad, model), std::runtime_error);
}

TEST(Checkpoint, NonFiniteNumbersReadBack) {
  Evaluation e;
  e.force = {{1.0, 2.0, 3.0}};
  e.contactCriticalStep = std::numeric_limits<double>::infinity();
  const Evaluation back = evaluationFromJson(nlohmann::json::parse(evaluationToJson(e).dump()));
  EXPECT_TRUE(std::isinf(back.contactCriticalStep));
}

// A run of `scene` into `dir`: uninterrupted, or stopped at `stopAfter` with a
// checkpoint and resumed from it (as robophi run --stop-after, robophi resume).
RunReport runInto(const Scene& scene, const fs::path& dir, double stopAfter, double every) {
  RunOptions options;
  options.settings = scene.run;
  options.outDir = dir.string();
  options.writeReplay = false;
  options.checkpointEvery = every;
  options.stopAfter = stopAfter;
  options.tasks = {robotics::makeSceneTasks(scene)};
  RunReport report = runScene(scene, options);
  if (stopAfter <= 0.0) return report;
  EXPECT_EQ(report.status, "stopped");
  const nlohmann::json checkpoint = readCheckpoint(dir.string());
  const CheckpointedRun saved = checkpointedRun(checkpoint);
  EXPECT_GE(saved.time, stopAfter * (1.0 - 1e-9));
  RunOptions resumed;
  resumed.settings = saved.settings;
  resumed.energyRate = saved.energyRate;
  resumed.checkpointEvery = saved.checkpointEvery;
  resumed.outDir = dir.string();
  resumed.writeReplay = false;
  resumed.resume = &checkpoint;
  resumed.tasks = {robotics::makeSceneTasks(scene)};  // fresh tasks: restored from the file
  return runScene(scene, resumed);
}

class CheckpointRun : public ::testing::TestWithParam<const char*> {
 protected:
  void SetUp() override { root_ = testing::makeTempFolder("robophi_checkpoint_"); }
  void TearDown() override { fs::remove_all(root_); }
  fs::path root_;
};

TEST_P(CheckpointRun, ResumedRunEndsAsAnUninterruptedOne) {
  SceneLoadResult loaded = loadSceneFile(kScenes + GetParam());
  ASSERT_TRUE(loaded.ok());
  Scene scene = *loaded.scene;
  scene.run.duration = std::min(scene.run.duration, 2.5);
  const RunReport whole = runInto(scene, root_ / "whole", 0.0, 0.4);
  const RunReport cut = runInto(scene, root_ / "cut", 1.1, 0.4);
  EXPECT_EQ(whole.status, cut.status);
  EXPECT_EQ(whole.stateHash, cut.stateHash) << GetParam();
  EXPECT_EQ(whole.steps, cut.steps);
  EXPECT_DOUBLE_EQ(cut.resumedFrom >= 1.1 ? 1.0 : 0.0, 1.0);
  EXPECT_EQ(whole.events, cut.events);
  for (const char* file :
       {"particles.csv", "energy.csv", "objects.csv", "contacts.csv", "joints.csv"}) {
    if (!fs::exists(root_ / "whole" / file)) continue;
    EXPECT_EQ(readText(root_ / "whole" / file), readText(root_ / "cut" / file))
        << GetParam() << ": " << file;
  }
  const auto summary = nlohmann::json::parse(readText(root_ / "cut" / "summary.json"));
  EXPECT_EQ(summary["state_hash"],
            nlohmann::json::parse(readText(root_ / "whole" / "summary.json"))["state_hash"]);
  EXPECT_EQ(summary["outcomes"],
            nlohmann::json::parse(readText(root_ / "whole" / "summary.json"))["outcomes"]);
}

// default: contacts with friction, velocity Verlet, adaptive step; arm_obstacle:
// robotics tasks whose escape adds virtual obstacles (model edits); pendulum:
// symplectic Euler with a joint; wheel_cube: rolling contacts; hand_lift: a
// control sequence whose phase (started by a contact force) moves the palm
// across the checkpoint; vehicle_drive: wheel motors (joint drives).
INSTANTIATE_TEST_SUITE_P(Scenes, CheckpointRun,
                         ::testing::Values("default.json", "arm_obstacle.json", "pendulum.json",
                                           "wheel_cube.json", "hand_lift.json",
                                           "vehicle_drive.json"));

TEST(Checkpoint, ConstantStepResumesToo) {
  SceneLoadResult loaded = loadSceneFile(kScenes + "default.json");
  ASSERT_TRUE(loaded.ok());
  Scene scene = *loaded.scene;
  scene.run.stepMode = StepMode::kConstant;
  scene.run.dt = 2e-4;
  scene.run.duration = 1.0;
  const fs::path root = testing::makeTempFolder("robophi_checkpoint_cts_");
  const RunReport whole = runInto(scene, root / "whole", 0.0, 0.0);
  const RunReport cut = runInto(scene, root / "cut", 0.45, 0.0);
  EXPECT_EQ(whole.stateHash, cut.stateHash);
  EXPECT_EQ(readText(root / "whole" / "particles.csv"), readText(root / "cut" / "particles.csv"));
  fs::remove_all(root);
}

}  // namespace
}  // namespace robophi
