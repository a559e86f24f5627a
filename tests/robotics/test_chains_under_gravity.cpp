// Issue 37: the chain builders (arm, hand) under gravity at other sizes than the
// shipped scenes' (which run without gravity). A link body's structure must hold
// while the chain hangs and swings: every LS within a few percent of its rest
// length. Arms of 2 to 6 links of 0.2 m, 2 to 5 particles a link, released
// horizontal from a fixed base, swing under gravity with their bodies intact.
//
// Known limit, measured and left open: a chain's joint shares two particles
// between its bodies (the centre and the axis particle, `width` apart), so every
// moment across the joint's axis passes as a couple over that lever, stiffness
// about κ w²; with κ from the natural-frequency rule (a property of the masses,
// not of the loads), a chain's strength against its own weight falls with its
// size. The default hand (links 5, 4, 3 cm, w = 6 mm) folds under gravity at
// ω = 2500 rad/s (LS strains of 65 %, a joint's axis link crushed); it holds at
// ω = 5000 rad/s, or with w ≥ 9 mm; arms of 4 cm links fold likewise.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "robophi/scene/scene.h"
#include "run/runner.h"

namespace robophi {
namespace {

struct ChainRun {
  RunReport report;
  double largestStrain = 0.0;  // max over the run and the LS of |length − rest| / rest
};

ChainRun runWatchingStrains(const std::string& text) {
  ChainRun run;
  SceneLoadResult loaded = loadSceneText(text, "chain.json");
  for (const auto& e : loaded.errors) ADD_FAILURE() << e.format();
  if (!loaded.ok()) return run;
  const Scene& scene = *loaded.scene;
  RunOptions options;
  options.settings = scene.run;
  options.tasks.push_back([&run](World& world, std::vector<std::string>&) {
    const State& s = world.state();
    for (const LinearSpring& spring : world.model().linearSprings) {
      const double length = norm(s.position[static_cast<std::size_t>(spring.b)] -
                                 s.position[static_cast<std::size_t>(spring.a)]);
      run.largestStrain =
          std::max(run.largestStrain, std::abs(length - spring.restLength) / spring.restLength);
    }
    return true;
  });
  run.report = runScene(scene, options);
  return run;
}

struct ArmCase {
  int links;
  int particlesPerLink;
};

class ArmUnderGravity : public ::testing::TestWithParam<ArmCase> {};

TEST_P(ArmUnderGravity, SwingsFromHorizontalWithItsLinksIntact) {
  const ArmCase c = GetParam();
  std::string links;
  for (int k = 0; k < c.links; ++k) links += std::string(k > 0 ? ", " : "") + "0.2";
  const ChainRun run = runWatchingStrains(R"({
    "run": {"duration": 1.0, "dt": 1e-4},
    "gravity": [0, 0, -9.81],
    "objects": [{"name": "arm", "type": "arm", "base": [0, 0, 2], "direction": [1, 0, 0],
                 "axes": [0, 1, 0], "links": [)" + links + R"(], "mass": )" +
                                          std::to_string(0.5 * c.links) +
                                          R"(, "particlesPerLink": )" +
                                          std::to_string(c.particlesPerLink) +
                                          R"(, "jointDamping": 0.01}]})");
  ASSERT_TRUE(run.report.ok()) << run.report.failure;
  std::printf("arm of %d links, %d particles a link: largest LS strain %.4f (%.2f s, %lld steps)\n",
              c.links, c.particlesPerLink, run.largestStrain, run.report.simulatedTime,
              static_cast<long long>(run.report.steps));
  EXPECT_NEAR(run.report.simulatedTime, 1.0, 1e-9);
  // Measured 0.4 % to 3.7 % over 3 s (the 6-link arm whipping round).
  EXPECT_LT(run.largestStrain, 0.05);
}

INSTANTIATE_TEST_SUITE_P(LinkCounts, ArmUnderGravity,
                         ::testing::Values(ArmCase{2, 2}, ArmCase{3, 3}, ArmCase{4, 4},
                                           ArmCase{5, 2}, ArmCase{6, 5}));

// The hand stands its fingers up on their servos under gravity where its links
// are stiff enough for its size (the known limit above): the shipped hand's size
// at ω = 5000 rad/s, and twice its size at the default 2500 rad/s.
TEST(HandUnderGravity, StandsItsFingersUpWhereItsLinksAreStiffEnoughForItsSize) {
  const auto hand = [](double scale, double naturalFrequency, double jointStiffness) {
    char links[96];
    std::snprintf(links, sizeof links, "[%.3f, %.3f, %.3f]", 0.05 * scale, 0.04 * scale,
                  0.03 * scale);
    return runWatchingStrains(std::string(R"({
      "run": {"duration": 1.5, "dt": 1e-4},
      "gravity": [0, 0, -9.81],
      "objects": [{"name": "hand", "type": "hand", "center": [0, 0, 0.5], "palmRadius": 0.06,
                   "links": )") + links + R"(, "mass": 0.3, "jointStiffness": )" +
                              std::to_string(jointStiffness) + R"(, "naturalFrequency": )" +
                              std::to_string(naturalFrequency) + "}]}");
  };
  const ChainRun stiff = hand(1.0, 5000.0, 0.2);
  const ChainRun large = hand(2.0, 2500.0, 5.0);
  ASSERT_TRUE(stiff.report.ok()) << stiff.report.failure;
  ASSERT_TRUE(large.report.ok()) << large.report.failure;
  std::printf("hand at 5000 rad/s: largest LS strain %.4f; twice the size: %.4f\n",
              stiff.largestStrain, large.largestStrain);
  EXPECT_LT(stiff.largestStrain, 0.02);  // measured 0.4 % (2 s)
  EXPECT_LT(large.largestStrain, 0.02);  // measured 0.8 % (3 s)
}

}  // namespace
}  // namespace robophi
