// MODEL §3.2: the sphere hierarchy and the broad phase find exactly the contacts
// that testing all pairs finds, on deformed objects, with self-collision; and
// they test far fewer pairs than all of them.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <utility>

#include "collision/contact_test_util.h"
#include "robophi/evaluation.h"

namespace robophi {
namespace {

using PairSet = std::set<std::pair<int, int>>;

// All touching pairs not tied by a connector and not both fixed.
PairSet bruteForce(const Model& model, const State& state) {
  std::set<std::pair<int, int>> tied;
  const auto tie = [&tied](int a, int b) { tied.insert({std::min(a, b), std::max(a, b)}); };
  for (const auto& s : model.linearSprings) tie(s.a, s.b);
  PairSet pairs;
  const int n = model.particleCount();
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) {
      const double reach = model.radius[a] + model.radius[b];
      if (squaredNorm(state.position[a] - state.position[b]) >= reach * reach) continue;
      if (model.isFixed(a) && model.isFixed(b)) continue;
      if (tied.count({a, b}) != 0) continue;
      pairs.insert({a, b});
    }
  }
  return pairs;
}

PairSet found(const Evaluation& evaluation) {
  PairSet pairs;
  for (const Contact& c : evaluation.contacts) {
    if (c.other >= 0) pairs.insert({c.a, c.other});
  }
  return pairs;
}

// Random deformable blobs (random particles tied to near neighbours), small
// single balls, one large ball, and a fixed object, overlapping each other.
void buildRandomScene(std::uint64_t seed, Model& model, State& state) {
  test::TestRandom random{seed};
  for (int blob = 0; blob < 4; ++blob) {
    const std::int32_t object = model.addObject("blob", "particles");
    const Vec3 center{0.3 * random.symmetric(), 0.3 * random.symmetric(), 0.3 * random.symmetric()};
    const int first = model.particleCount();
    const int count = 40 + static_cast<int>(random.uniform() * 80);
    for (int k = 0; k < count; ++k) {
      model.addParticle(0.01, 0.01 + 0.02 * random.uniform(), blob == 3, object);
      state.position.push_back(
          center + Vec3{random.symmetric(), random.symmetric(), random.symmetric()} * 0.2);
    }
    for (int k = first; k + 1 < first + count; k += 2) {
      model.linearSprings.push_back({k, k + 1, 0.05, 100.0, 0.0});
    }
  }
  for (int k = 0; k < 300; ++k) {
    test::addBall(model, state,
                  Vec3{random.symmetric(), random.symmetric(), random.symmetric()} * 0.5, 0.01,
                  0.015 + 0.01 * random.uniform());
  }
  test::addBall(model, state, {0.1, 0.0, 0.0}, 1.0, 0.25);  // large: gets its own tree
  state.velocity.assign(state.position.size(), Vec3{});
}

TEST(SphereTree, FindsExactlyTheBruteForceContactsOnDeformedObjects) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    Model model;
    State state;
    buildRandomScene(seed, model, state);
    test::Evaluator evaluator(model);
    EXPECT_EQ(found(evaluator(state)), bruteForce(model, state)) << "seed " << seed;
    // Deform every object a lot: the trees built on the first positions are
    // refitted, not rebuilt, and must still find everything.
    test::TestRandom random{seed * 7919};
    for (Vec3& p : state.position) {
      p += Vec3{random.symmetric(), random.symmetric(), random.symmetric()} * 0.15;
    }
    const Evaluation& deformed = evaluator(state);
    const PairSet expected = bruteForce(model, state);
    EXPECT_EQ(found(deformed), expected) << "seed " << seed << " after deformation";
    EXPECT_GT(expected.size(), 100u);
    EXPECT_TRUE(
        std::is_sorted(deformed.contacts.begin(), deformed.contacts.end(),
                       [](const Contact& x, const Contact& y) { return x.key() < y.key(); }));
  }
}

TEST(SphereTree, HashedGridMatchesBruteForceWhenParticlesSpreadFar) {
  // Particles spread over a large box: the grid switches to hashed cells.
  Model model;
  State state;
  test::TestRandom random{42};
  for (int k = 0; k < 2000; ++k) {
    const double scale = k % 2 == 0 ? 1000.0 : 0.2;
    test::addBall(model, state,
                  Vec3{random.symmetric(), random.symmetric(), random.symmetric()} * scale, 0.01,
                  0.02);
  }
  test::Evaluator evaluator(model);
  const PairSet expected = bruteForce(model, state);
  EXPECT_EQ(found(evaluator(state)), expected);
  EXPECT_GT(expected.size(), 50u);
}

TEST(SphereTree, SelfCollisionSkipsConnectedPairsAndCanBeTurnedOff) {
  Model model;
  State state;
  const std::int32_t object = model.addObject("rope", "rope");
  for (int k = 0; k < 3; ++k) {
    model.addParticle(0.01, 0.02, false, object);
    state.position.push_back({0.03 * k, 0.0, 0.0});  // neighbours 3 cm apart, reach 4 cm
  }
  state.position[2] = {0.03, 0.03, 0.0};  // folds back: 0 and 2 are 4.2 cm apart
  state.position[2] = {0.0, 0.035, 0.0};  // 0 and 2 now 3.5 cm apart: touching
  model.linearSprings.push_back({0, 1, 0.03, 100.0, 0.0});
  model.linearSprings.push_back({1, 2, 0.03, 100.0, 0.0});
  state.velocity.assign(3, Vec3{});
  test::Evaluator evaluator(model);
  EXPECT_EQ(found(evaluator(state)), (PairSet{{0, 2}}));
  model.contact.selfCollision = false;
  test::Evaluator without(model);
  EXPECT_TRUE(found(without(state)).empty());
}

TEST(SphereTree, PileOfTenThousandTestsFarFewerPairsThanAll) {
  // 10 000 balls of 1 cm on a 2 cm lattice, jittered: about half the neighbours touch.
  Model model;
  State state;
  test::TestRandom random{7};
  const int side = 22;  // 22³ = 10 648
  for (int k = 0; k < side * side * side; ++k) {
    const Vec3 lattice{static_cast<double>(k % side), static_cast<double>((k / side) % side),
                       static_cast<double>(k / (side * side))};
    test::addBall(
        model, state,
        lattice * 0.02 + Vec3{random.symmetric(), random.symmetric(), random.symmetric()} * 0.002,
        0.004, 0.01);
  }
  test::Evaluator evaluator(model);
  const Evaluation& evaluation = evaluator(state);
  const ContactStats stats = evaluation.contactStats;
  const double n = model.particleCount();
  const double allPairs = 0.5 * n * (n - 1.0);
  std::printf("pile of %.0f: %lld pair tests, %lld contacts, all pairs / tests = %.0f\n", n,
              static_cast<long long>(stats.pairTests),
              static_cast<long long>(stats.particleContacts),
              allPairs / static_cast<double>(stats.pairTests));
  EXPECT_GE(allPairs / static_cast<double>(stats.pairTests), 10.0);
  EXPECT_GT(stats.particleContacts, 1000);
}

TEST(SphereTree, OneObjectOfManyParticlesUsesItsTreeEfficiently) {
  Model model;
  State state;
  test::TestRandom random{9};
  const std::int32_t object = model.addObject("cloud", "particles");
  const int side = 22;
  for (int k = 0; k < side * side * side; ++k) {
    model.addParticle(0.004, 0.01, false, object);
    const Vec3 lattice{static_cast<double>(k % side), static_cast<double>((k / side) % side),
                       static_cast<double>(k / (side * side))};
    state.position.push_back(
        lattice * 0.02 + Vec3{random.symmetric(), random.symmetric(), random.symmetric()} * 0.002);
  }
  state.velocity.assign(state.position.size(), Vec3{});
  test::Evaluator evaluator(model);
  const Evaluation& evaluation = evaluator(state);
  const ContactStats stats = evaluation.contactStats;
  const double n = model.particleCount();
  const double allPairs = 0.5 * n * (n - 1.0);
  std::printf("one object of %.0f: %lld pair tests, %lld node tests, all pairs / tests = %.0f\n", n,
              static_cast<long long>(stats.pairTests), static_cast<long long>(stats.nodeTests),
              allPairs / static_cast<double>(stats.pairTests));
  EXPECT_GE(allPairs / static_cast<double>(stats.pairTests), 10.0);
  EXPECT_EQ(found(evaluation), bruteForce(model, state));
}

}  // namespace
}  // namespace robophi
