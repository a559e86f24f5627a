// A CompiledModel is read-only: threads may evaluate states of one model at the
// same time, each in its own workspace, and get what one thread gets, bit for bit.
#include <gtest/gtest.h>

#include <cstring>
#include <thread>
#include <vector>

#include "robophi/evaluation.h"
#include "robophi/scene/scene.h"
#include "robophi/world.h"

namespace robophi {
namespace {

TEST(ConcurrentEvaluation, ThreadsSharingAModelGetTheSingleThreadedResults) {
  const SceneLoadResult loaded = loadSceneFile(ROBOPHI_SOURCE_DIR "/scenes/wheel_cube_ramp.json");
  ASSERT_TRUE(loaded.ok());
  const Scene& scene = *loaded.scene;
  // Eight states along a run (contacts and friction history included).
  World world(scene.model, scene.initial, scene.run.integrator);
  std::vector<State> states;
  for (int k = 0; k < 8; ++k) {
    for (int s = 0; s < 300; ++s) world.step(5e-5);
    states.push_back(world.state());
  }
  const CompiledModel& model = world.compiled();
  std::vector<Evaluation> alone(states.size());
  for (std::size_t k = 0; k < states.size(); ++k) {
    Workspace workspace;
    alone[k] = evaluate(model, states[k], workspace);
  }
  std::vector<Evaluation> together(states.size());
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      Workspace workspace;  // one per thread, reused across its states
      for (std::size_t k = static_cast<std::size_t>(t); k < states.size(); k += 4) {
        together[k] = evaluate(model, states[k], workspace);
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  for (std::size_t k = 0; k < states.size(); ++k) {
    ASSERT_EQ(alone[k].force.size(), together[k].force.size());
    EXPECT_EQ(std::memcmp(alone[k].force.data(), together[k].force.data(),
                          alone[k].force.size() * sizeof(Vec3)),
              0)
        << "state " << k;
    EXPECT_EQ(alone[k].contacts.size(), together[k].contacts.size()) << "state " << k;
    EXPECT_EQ(alone[k].energy.total(), together[k].energy.total()) << "state " << k;
  }
  EXPECT_GT(alone.back().contacts.size(), 0u);
}

}  // namespace
}  // namespace robophi
