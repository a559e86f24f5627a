// The grid particles' Verlet neighbour list (docs/contact.md "Neighbour list"):
// over a run in which the particles move many skins, every evaluation finds
// exactly the brute-force contacts, in the order of a grid search at every
// evaluation (the run is bit-identical to one without the list); the list is
// rebuilt only when some particle has moved more than half the skin.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "collision/contact_test_util.h"
#include "robophi/world.h"

namespace robophi {
namespace {

using PairSet = std::set<std::pair<int, int>>;

// All touching particle pairs, not both fixed.
PairSet bruteForce(const Model& model, const std::vector<Vec3>& position) {
  PairSet pairs;
  const int n = model.particleCount();
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) {
      const double reach = model.radius[a] + model.radius[b];
      if (squaredNorm(position[a] - position[b]) >= reach * reach) continue;
      if (model.isFixed(a) && model.isFixed(b)) continue;
      pairs.insert({a, b});
    }
  }
  return pairs;
}

PairSet found(const std::vector<Contact>& contacts) {
  PairSet pairs;
  for (const Contact& c : contacts) {
    if (c.other >= 0) pairs.insert({c.a, c.other});
  }
  return pairs;
}

// A closed 12 cm box of planes (material 1): ground, four walls and a lid.
void addClosedBox(Model& model) {
  model.environment.planes.push_back(GroundPlane{{0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, 1});
  model.environment.planes.push_back(GroundPlane{{0.06, 0.0, 0.0}, {-1.0, 0.0, 0.0}, 1});
  model.environment.planes.push_back(GroundPlane{{-0.06, 0.0, 0.0}, {1.0, 0.0, 0.0}, 1});
  model.environment.planes.push_back(GroundPlane{{0.0, 0.06, 0.0}, {0.0, -1.0, 0.0}, 1});
  model.environment.planes.push_back(GroundPlane{{0.0, -0.06, 0.0}, {0.0, 1.0, 0.0}, 1});
  model.environment.planes.push_back(GroundPlane{{0.0, 0.0, 0.12}, {0.0, 0.0, -1.0}, 1});
}

// A gas of 400 balls of two sizes (radius 5 and 8 mm) in a 12 cm box with
// ground and walls, no gravity, random speeds up to 2 m/s: at a step of 1e-4 s
// a fast ball moves half the default skin (0.1 × 16 mm) in 4 steps.
Model gasModel(State& state, double skin) {
  Model model;
  model.gravity = {};
  model.contact.neighbourSkin = skin;
  Material material;
  material.contactStiffness = 2.0e3;
  material.contactDamping = 0.5;
  material.staticFriction = 0.5;
  material.kineticFriction = 0.4;
  model.materials.push_back(material);
  test::TestRandom random{2026};
  for (int k = 0; k < 400; ++k) {
    const Vec3 p{0.05 * random.symmetric(), 0.05 * random.symmetric(),
                 0.06 + 0.05 * random.symmetric()};
    test::addBall(model, state, p, 0.002, k % 3 == 0 ? 0.008 : 0.005, 1, k == 7);
    state.velocity.back() =
        Vec3{random.symmetric(), random.symmetric(), random.symmetric()} * (k == 7 ? 0.0 : 1.2);
  }
  addClosedBox(model);
  return model;
}

TEST(NeighbourList, FindsExactlyTheBruteForceContactsWhileParticlesMovePastTheSkin) {
  State start;
  const Model model = gasModel(start, 0.1);
  State startWithout;
  const Model without = gasModel(startWithout, 0.0);
  World world(model, start, Integrator::kSymplecticEuler);
  World reference(without, startWithout, Integrator::kSymplecticEuler);
  const double skin = 0.1 * 0.016;
  std::vector<Vec3> atBuild = start.position;
  std::int64_t builds = 0, referenceBuilds = 0;
  double travelled = 0.0;  // the farthest any ball moved from its start (m)
  std::size_t mostContacts = 0;
  constexpr int kSteps = 600;
  for (int step = 0; step <= kSteps; ++step) {
    const Evaluation& e = world.evaluation();
    const std::vector<Vec3>& p = world.state().position;
    ASSERT_EQ(found(e.contacts), bruteForce(model, p)) << "step " << step;
    // In the order of a grid search at every evaluation.
    const std::vector<Contact>& expected = reference.evaluation().contacts;
    ASSERT_EQ(e.contacts.size(), expected.size()) << "step " << step;
    for (std::size_t k = 0; k < expected.size(); ++k) {
      ASSERT_TRUE(e.contacts[k].key() == expected[k].key()) << "step " << step << ", contact " << k;
    }
    mostContacts = std::max(mostContacts, e.contacts.size());
    // Rebuilt exactly when some ball has moved more than half the skin since the last build.
    double moved = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) moved = std::max(moved, norm(p[i] - atBuild[i]));
    if (step > 0) {
      EXPECT_EQ(e.contactStats.neighbourListBuilds, moved > 0.5 * skin ? 1 : 0)
          << "step " << step << ", moved " << moved << " m since the last build";
    }
    if (e.contactStats.neighbourListBuilds != 0) atBuild = p;
    builds += e.contactStats.neighbourListBuilds;
    referenceBuilds += reference.evaluation().contactStats.neighbourListBuilds;
    for (std::size_t i = 0; i < p.size(); ++i) {
      travelled = std::max(travelled, norm(p[i] - start.position[i]));
    }
    // So the runs stay bit-identical.
    ASSERT_EQ(world.state().position, reference.state().position) << "step " << step;
    ASSERT_EQ(world.state().velocity, reference.state().velocity) << "step " << step;
    if (step == kSteps) break;
    ASSERT_EQ(world.step(1.0e-4), StepStatus::kOk);
    ASSERT_EQ(reference.step(1.0e-4), StepStatus::kOk);
  }
  std::printf(
      "neighbour list: %lld builds in %d evaluations, balls moved up to %.1f skins, "
      "up to %zu contacts\n",
      static_cast<long long>(builds), kSteps + 1, travelled / skin, mostContacts);
  EXPECT_GT(travelled, 20.0 * skin);
  EXPECT_GT(mostContacts, 50u);
  EXPECT_GT(builds, 10);                   // rebuilt as the balls move on
  EXPECT_LT(builds, kSteps / 3);           // but kept for several steps
  EXPECT_EQ(referenceBuilds, kSteps + 1);  // skin 0: the grid at every evaluation
}

TEST(NeighbourList, IsRebuiltOnlyWhenAParticleMovesMoreThanHalfTheSkin) {
  Model model;
  State state;
  model.gravity = {};
  model.contact.neighbourSkin = 0.1;  // of h = 2 cm: 2 mm
  for (int k = 0; k < 8; ++k) {
    test::addBall(model, state, {0.019 * k, 0.0, 0.0}, 0.01, 0.01);  // each touches the next
  }
  test::Evaluator evaluator(model);
  const auto evaluateAt = [&](const State& s) {
    const Evaluation& e = evaluator(s);
    EXPECT_EQ(found(e.contacts), bruteForce(model, s.position));
    return e.contactStats.neighbourListBuilds;
  };
  EXPECT_EQ(evaluateAt(state), 1);  // the first build
  State moved = state;
  moved.position[3].y += 0.00099;  // 0.99 mm < 1 mm: kept
  EXPECT_EQ(evaluateAt(moved), 0);
  moved.position[5] += Vec3{0.0007, -0.0007, 0.0};  // 0.99 mm: kept
  EXPECT_EQ(evaluateAt(moved), 0);
  moved.position[6].x -= 0.00101;  // 1.01 mm: rebuilt
  EXPECT_EQ(evaluateAt(moved), 1);
  EXPECT_EQ(evaluateAt(moved), 0);
  // Ball 4 pushed 1.5 mm towards ball 3 in two moves of 0.75 mm from the new
  // build: the first keeps the list, the second (1.5 mm) rebuilds it.
  moved.position[4].x -= 0.00075;
  EXPECT_EQ(evaluateAt(moved), 0);
  moved.position[4].x -= 0.00075;
  EXPECT_EQ(evaluateAt(moved), 1);
  // Two balls 25 mm apart (5 mm gap) moved 0.99 mm each towards each other are
  // not listed and do not touch; a second such move rebuilds and finds them.
  moved.position[7] = {0.2, 0.0, 0.0};
  moved.position[0] = {0.225, 0.0, 0.0};
  EXPECT_EQ(evaluateAt(moved), 1);
  for (int again = 0; again < 2; ++again) {
    moved.position[7].x += 0.00099;
    moved.position[0].x -= 0.00099;
    const std::int64_t builds = evaluateAt(moved);
    EXPECT_EQ(builds, again == 0 ? 0 : 1);
  }
  moved.position[7].x += 0.0011;  // 21.04 mm - 2.2 mm apart: touching
  moved.position[0].x -= 0.0011;
  EXPECT_EQ(evaluateAt(moved), 1);
  EXPECT_EQ(found(evaluator(moved).contacts).count({0, 7}), 1u);
}

// Tree objects (docs/contact.md "Neighbour list", TreePairList): 40 soft
// clusters of four particles (two sizes, tied by springs: each object is a
// sphere tree, with self-collision) tumbling in a closed box, no gravity. The
// pair list finds exactly what the tree search at every evaluation finds (the
// run with skin 0), bit for bit, and is kept for several steps at a time.
Model clusterModel(State& state, double skin) {
  Model model;
  model.gravity = {};
  model.contact.neighbourSkin = skin;
  model.contact.selfCollision = true;
  Material material;
  material.contactStiffness = 2.0e3;
  material.contactDamping = 0.2;
  material.staticFriction = 0.5;
  material.kineticFriction = 0.4;
  model.materials.push_back(material);
  test::TestRandom random{77};
  for (int k = 0; k < 40; ++k) {
    const std::int32_t object = model.addObject("cluster", "cluster", 1);
    const Vec3 centre{0.045 * random.symmetric(), 0.045 * random.symmetric(),
                      0.06 + 0.045 * random.symmetric()};
    const Vec3 velocity = Vec3{random.symmetric(), random.symmetric(), random.symmetric()} * 0.8;
    const double radius = k % 2 == 0 ? 0.004 : 0.006;
    const auto first = model.particleCount();
    const Vec3 corners[4] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    for (const Vec3& corner : corners) {
      model.addParticle(0.002, radius, false, object);
      state.position.push_back(centre + corner * (1.1 * radius));
      state.velocity.push_back(velocity);
    }
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b)
        model.linearSprings.push_back({first + a, first + b,
                                       norm(state.position[first + a] - state.position[first + b]),
                                       200.0, 0.01});
  }
  addClosedBox(model);
  return model;
}

TEST(NeighbourList, TreeObjectsFindWhatTheTreeSearchFindsAndKeepTheirListForSteps) {
  State start;
  const Model model = clusterModel(start, 0.1);
  State startWithout;
  const Model without = clusterModel(startWithout, 0.0);
  World world(model, start, Integrator::kSymplecticEuler);
  World reference(without, startWithout, Integrator::kSymplecticEuler);
  std::int64_t builds = 0, referenceBuilds = 0;
  std::size_t mostPairContacts = 0;
  constexpr int kSteps = 1500;
  for (int step = 0; step <= kSteps; ++step) {
    const std::vector<Contact>& got = world.evaluation().contacts;
    const std::vector<Contact>& expected = reference.evaluation().contacts;
    ASSERT_EQ(got.size(), expected.size()) << "step " << step;
    for (std::size_t k = 0; k < expected.size(); ++k)
      ASSERT_TRUE(got[k].key() == expected[k].key()) << "step " << step << ", contact " << k;
    mostPairContacts = std::max(mostPairContacts, found(got).size());
    builds += world.evaluation().contactStats.treePairListBuilds;
    referenceBuilds += reference.evaluation().contactStats.treePairListBuilds;
    ASSERT_EQ(world.state().position, reference.state().position) << "step " << step;
    ASSERT_EQ(world.state().velocity, reference.state().velocity) << "step " << step;
    if (step == kSteps) break;
    ASSERT_EQ(world.step(1.0e-4), StepStatus::kOk);
    ASSERT_EQ(reference.step(1.0e-4), StepStatus::kOk);
  }
  std::printf("tree pair list: %lld builds in %d evaluations, up to %zu pair contacts\n",
              static_cast<long long>(builds), kSteps + 1, mostPairContacts);
  EXPECT_GT(mostPairContacts, 10u);  // clusters touch each other and themselves
  EXPECT_GT(builds, 5);              // rebuilt as they move on
  EXPECT_LT(builds, kSteps / 3);     // but kept for several steps
  EXPECT_EQ(referenceBuilds, 0);     // skin 0: the tree search at every evaluation
}

TEST(NeighbourList, ASkinThatIsNegativeOrNotFiniteIsRefused) {
  for (const double skin :
       {-0.1, std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN()}) {
    Model model;
    State state;
    test::addBall(model, state, {0.0, 0.0, 0.0}, 0.01, 0.01);
    model.contact.neighbourSkin = skin;
    try {
      const CompiledModel compiled(model);
      ADD_FAILURE() << "skin " << skin << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("neighbourSkin"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace robophi
