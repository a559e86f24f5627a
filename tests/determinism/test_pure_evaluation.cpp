// Force evaluation is a pure function of (model, state): evaluating any number
// of times, in any workspace, changes nothing (issue 10, docs/architecture.md).
#include <gtest/gtest.h>

#include <cstring>

#include "determinism/scene_steps.h"
#include "robophi/evaluation.h"

namespace robophi {
namespace {

constexpr std::int64_t kPureEvaluationSteps = 1500;

bool sameBits(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0;
}

TEST(PureEvaluation, FiveExtraEvaluationsBeforeEveryStepOfEveryShippedSceneChangeNothing) {
  for (const std::string& path : testing::shippedScenes()) {
    const SceneLoadResult loaded = loadSceneFile(path);
    ASSERT_TRUE(loaded.ok()) << path;
    const RunReport plain = testing::runSteps(*loaded.scene, kPureEvaluationSteps);
    Workspace spare;
    int mismatches = 0;
    const RunReport probed = testing::runSteps(*loaded.scene, kPureEvaluationSteps, [&](World& world) {
      // Five evaluations in a workspace of our own, then five through the
      // world (the first brings its evaluation up to date after the tasks'
      // edits; the others must find nothing to do).
      for (int k = 0; k < 5; ++k) {
        const Evaluation& e = evaluate(world.compiled(), world.state(), spare);
        if (k > 0 && !sameBits(e.force, spare.result().force)) ++mismatches;
      }
      for (int k = 0; k < 5; ++k) {
        world.refresh();
        (void)world.evaluation();
      }
    });
    ASSERT_TRUE(plain.sound()) << path << ": " << plain.failure;  // a goal may be missed
    EXPECT_GT(plain.steps, 0) << path;
    EXPECT_EQ(probed.steps, plain.steps) << path;
    EXPECT_EQ(probed.stateHash, plain.stateHash) << path;
    EXPECT_EQ(probed.finalTotal, plain.finalTotal) << path;
    EXPECT_EQ(mismatches, 0) << path;
  }
}

// An evaluation in a fresh workspace (sphere trees built at this state, not at
// the first) finds the same forces and contacts, bit for bit, as the world's.
TEST(PureEvaluation, AFreshWorkspaceGivesTheWorldsEvaluation) {
  for (const char* name : {"wheel_cube_ramp.json", "vehicle_hills.json", "wheel_cube.json"}) {
    const SceneLoadResult loaded = loadSceneFile(std::string(ROBOPHI_SOURCE_DIR "/scenes/") + name);
    ASSERT_TRUE(loaded.ok()) << name;
    const Scene& scene = *loaded.scene;
    World world(scene.model, scene.initial, scene.run.integrator);
    for (int s = 0; s < 400; ++s) world.step(scene.run.dt);
    // On, to a state with contacts (a wheel's rim may be in the air for a step).
    for (int s = 0; s < 1000 && world.contacts().empty(); ++s) world.step(scene.run.dt);
    // The state's own evaluation (not the step's, which for Verlet used the
    // half-step velocities): re-evaluate through a no-op of the edit API.
    Workspace fresh;
    const Evaluation& e = evaluate(world.compiled(), world.state(), fresh);
    Workspace again;
    const Evaluation& f = evaluate(world.compiled(), world.state(), again);
    EXPECT_TRUE(sameBits(e.force, f.force)) << name;
    ASSERT_EQ(e.contacts.size(), f.contacts.size()) << name;
    EXPECT_GT(e.contacts.size(), 0u) << name;
    for (std::size_t k = 0; k < e.contacts.size(); ++k) {
      EXPECT_EQ(e.contacts[k].key(), f.contacts[k].key()) << name;
      EXPECT_EQ(e.contacts[k].anchorEnergy, f.contacts[k].anchorEnergy) << name;
    }
    EXPECT_EQ(e.energy.total(), f.energy.total()) << name;
    EXPECT_EQ(e.releasedAnchorEnergy, f.releasedAnchorEnergy) << name;
    // Evaluating did not touch the world.
    const std::uint64_t before = stateHash(world.state());
    (void)evaluate(world.compiled(), world.state(), fresh);
    EXPECT_EQ(stateHash(world.state()), before) << name;
  }
}

// The symplectic schemes evaluate at the state's own velocities, so there the
// world's cached evaluation is exactly a fresh one.
TEST(PureEvaluation, TheWorldsCachedEvaluationIsAFreshOneForSymplecticEuler) {
  const SceneLoadResult loaded = loadSceneFile(ROBOPHI_SOURCE_DIR "/scenes/default.json");
  ASSERT_TRUE(loaded.ok());
  const Scene& scene = *loaded.scene;
  World world(scene.model, scene.initial, Integrator::kSymplecticEuler);
  for (int s = 0; s < 2000; ++s) world.step(1e-4);
  Workspace fresh;
  const Evaluation& e = evaluate(world.compiled(), world.state(), fresh);
  EXPECT_TRUE(sameBits(e.force, world.forces()));
  EXPECT_EQ(e.contacts.size(), world.contacts().size());
  EXPECT_EQ(e.energy.total(), world.energy().total());
}

}  // namespace
}  // namespace robophi
