// The lean contact stage's lanes (collision/pair_lanes.h) give the scalar
// stage's results bit for bit: balls of two sizes and two materials thrown
// spinning into a box, a fixed ball among them, stepped side by side with the
// lanes and without; every contact, force and state the same bits at every
// step, through contacts that stick, break away, slide and stick again. And the
// lean stage on threads (its loads gathered by particle) gives one thread's.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "collision/pair_lanes.h"
#include "core/parallel.h"
#include "contact_test_util.h"
#include "same_bits.h"

namespace robophi {
namespace {

using testing::sameBits;
using testing::sameContact;

// Uniform in [-1, 1).
double symmetric(test::TestRandom& random) { return 2.0 * random.uniform() - 1.0; }

struct Box {
  Model model;
  State initial;
};

// 6 × 6 × 5 balls (radius 8 or 10 mm; a grippy and a slippery material) thrown
// sideways and spinning into a box 14 cm wide, onto a fixed ball in the middle.
Box makeBox(bool rolling) {
  Box box;
  Model& model = box.model;
  model.gravity = {0.0, 0.0, -9.81};
  model.contact.rolling = rolling;
  Material grippy;
  grippy.name = "grippy";
  grippy.contactStiffness = 4.0e4;
  grippy.contactDamping = 4.0;
  grippy.staticFriction = 0.8;
  grippy.kineticFriction = 0.6;
  Material slippery = grippy;
  slippery.name = "slippery";
  slippery.staticFriction = 0.2;
  slippery.kineticFriction = 0.15;
  model.materials = {grippy, slippery};
  test::TestRandom random{42};
  test::addBall(model, box.initial, {0.0, 0.0, 0.01}, 0.005, 0.01, 0, true);
  for (int k = 0; k < 5; ++k) {
    for (int j = 0; j < 6; ++j) {
      for (int i = 0; i < 6; ++i) {
        const bool small = (i + j + k) % 3 == 0;
        const Vec3 p{-0.05 + 0.021 * i + 0.002 * symmetric(random),
                     -0.05 + 0.021 * j + 0.002 * symmetric(random), 0.03 + 0.021 * k};
        const ParticleIndex ball = test::addBall(model, box.initial, p, small ? 0.003 : 0.005,
                                                 small ? 0.008 : 0.01, (i + 2 * j + k) % 2);
        box.initial.velocity[static_cast<std::size_t>(ball)] = {0.4 * symmetric(random),
                                                                0.4 * symmetric(random), -0.2};
      }
    }
  }
  model.environment.planes.push_back(GroundPlane{{0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, 0});
  for (int side = 0; side < 4; ++side) {
    BoxObstacle wall;
    wall.material = side % 2;
    const double sign = side % 2 == 0 ? 1.0 : -1.0;
    wall.center = side < 2 ? Vec3{sign * 0.095, 0.0, 0.1} : Vec3{0.0, sign * 0.095, 0.1};
    wall.halfExtents = side < 2 ? Vec3{0.025, 0.12, 0.1} : Vec3{0.12, 0.025, 0.1};
    model.environment.boxes.push_back(wall);
  }
  box.initial.spin.assign(box.initial.position.size(), Vec3{});
  for (Vec3& w : box.initial.spin) w = {20.0 * symmetric(random), 20.0 * symmetric(random), 5.0};
  return box;
}

// Steps the box with and without the lanes, comparing as it goes; counts the
// regimes the contacts went through with the lanes.
void compareWithAndWithoutLanes(bool rolling) {
  if (!detail::pairLanesAvailable()) GTEST_SKIP() << "no AVX2 here: only the scalar stage runs";
  const Box box = makeBox(rolling);
  World withLanes(box.model, box.initial, Integrator::kSymplecticEuler);
  World without(box.model, box.initial, Integrator::kSymplecticEuler);
  withLanes.setThreadCount(1);
  without.setThreadCount(1);
  std::map<int, int> regimes;
  int environment = 0, pairs = 0;
  constexpr int kSteps = 3000;
  for (int step = 0; step < kSteps; ++step) {
    detail::allowPairLanes(true);
    ASSERT_EQ(withLanes.step(5.0e-5), StepStatus::kOk);
    detail::allowPairLanes(false);
    ASSERT_EQ(without.step(5.0e-5), StepStatus::kOk);
    detail::allowPairLanes(true);
    const std::vector<Contact>& a = withLanes.contacts();
    const std::vector<Contact>& b = without.contacts();
    ASSERT_EQ(a.size(), b.size()) << "step " << step;
    for (std::size_t k = 0; k < a.size(); ++k) {
      ASSERT_TRUE(sameContact(a[k], b[k])) << "step " << step << ", contact " << k;
      ++regimes[a[k].sliding];
      ++(a[k].other >= 0 ? pairs : environment);
    }
    const Evaluation& ea = withLanes.evaluation();
    const Evaluation& eb = without.evaluation();
    for (std::size_t i = 0; i < ea.force.size(); ++i) {
      ASSERT_TRUE(sameBits(ea.force[i], eb.force[i])) << "step " << step << ", particle " << i;
      ASSERT_TRUE(sameBits(ea.torque[i], eb.torque[i])) << "step " << step << ", particle " << i;
    }
    ASSERT_TRUE(sameBits(ea.energy.contact, eb.energy.contact)) << "step " << step;
    ASSERT_TRUE(sameBits(ea.dissipativePower, eb.dissipativePower)) << "step " << step;
    ASSERT_TRUE(sameBits(ea.releasedAnchorEnergy, eb.releasedAnchorEnergy)) << "step " << step;
    ASSERT_TRUE(sameBits(ea.contactCriticalStep, eb.contactCriticalStep)) << "step " << step;
  }
  EXPECT_EQ(stateHash(withLanes.state()), stateHash(without.state()));
  // The run went through every regime, against the environment and between balls.
  EXPECT_GT(regimes[0], 1000);
  EXPECT_GT(regimes[1], 100);
  EXPECT_GT(regimes[2], 100);
  EXPECT_GT(environment, 1000);
  EXPECT_GT(pairs, 1000);
}

TEST(PairLanes, SpinningBallsInABoxGiveTheScalarStagesBitsAtEveryStep) {
  compareWithAndWithoutLanes(true);
}

TEST(PairLanes, BallsThatDoNotRollGiveTheScalarStagesBitsAtEveryStep) {
  compareWithAndWithoutLanes(false);
}

// A dense pile of spinning balls pressed together, each its own object (enough
// contacts that the lean stage runs in many chunks, and on threads records its
// loads for the gather by particle).
World makeBallPile(int threads) {
  Model model;
  State initial;
  double mass = 0.0;
  test::addBallPile(model, initial, 18, 14, 0.005, 0.0098, mass);
  World world(model, initial, Integrator::kSymplecticEuler);
  world.setThreadCount(threads);
  return world;
}

// The lean stage on threads (its loads recorded and gathered by particle) and on
// one (added as it goes), with the lanes and without: one state, bit for bit.
TEST(PairLanes, ABallPileOnOneTwoAndFourThreadsWithAndWithoutTheLanesGivesOneState) {
  struct Run {
    int threads;
    bool lanes;
  };
  std::vector<std::uint64_t> hashes;
  std::vector<std::vector<Contact>> contacts;
  for (const Run run : {Run{1, true}, Run{2, true}, Run{4, true}, Run{1, false}, Run{2, false}}) {
    detail::allowPairLanes(run.lanes);
    World world = makeBallPile(run.threads);
    for (int step = 0; step < 30; ++step) ASSERT_EQ(world.step(5.0e-5), StepStatus::kOk);
    hashes.push_back(stateHash(world.state()));
    contacts.push_back(world.contacts());
  }
  detail::allowPairLanes(true);
  // Enough that the stage runs on the threads (and in many chunks).
  EXPECT_GT(contacts[0].size(), static_cast<std::size_t>(detail::kParallelMinimum));
  for (std::size_t r = 1; r < hashes.size(); ++r) {
    EXPECT_EQ(hashes[r], hashes[0]) << "run " << r;
    ASSERT_EQ(contacts[r].size(), contacts[0].size()) << "run " << r;
    for (std::size_t k = 0; k < contacts[0].size(); ++k)
      ASSERT_TRUE(sameContact(contacts[r][k], contacts[0][k])) << "run " << r << ", contact " << k;
  }
}

}  // namespace
}  // namespace robophi
