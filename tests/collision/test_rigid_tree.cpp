// MODEL §3.2 for rigid objects: a rigid object's sphere tree moves as a whole
// with the frame of three reference particles (no refit). It finds exactly the
// contacts a refitted tree finds after a large rigid motion and under small
// deviations, and the search cost for two rigid cubes in contact grows no faster
// than the particle count.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "collision/contact_test_util.h"
#include "robophi/build/objects.h"

namespace robophi {
namespace {

// R p + t: a rotation by `angle` about the unit `axis`, then a shift.
Vec3 moved(const Vec3& p, const Vec3& axis, double angle, const Vec3& shift) {
  const double c = std::cos(angle), s = std::sin(angle);
  return p * c + cross(axis, p) * s + axis * (dot(axis, p) * (1.0 - c)) + shift;
}

// Two cubes of cells³ particles (no connectors), the second rotated 10° about x
// and pressed onto the first's +x face by a fifth of a cell (as `robophi bench
// --filter RIGID`).
Model rigidPair(int cells, bool rigid, State& state) {
  constexpr double kCell = 0.01;
  Model model;
  model.gravity = {};
  model.contact.selfCollision = false;
  const double side = kCell * cells;
  state = State{};
  // The particles of a cells³ box lattice (cell centres, radius half a cell,
  // 1 kg in all), without its connectors: the contact search is what is timed,
  // and a 46³ lattice's connectors are above the builders' size budget.
  for (int body = 0; body < 2; ++body) {
    const Vec3 center{body * (side - 0.2 * kCell), 0.0, 0.0};
    const std::int32_t object = model.addObject(body == 0 ? "a" : "b", "box");
    model.objects[static_cast<std::size_t>(object)].rigid = rigid;
    const double mass = 1.0 / (static_cast<double>(cells) * cells * cells);
    for (int i = 0; i < cells; ++i) {
      for (int j = 0; j < cells; ++j) {
        for (int k = 0; k < cells; ++k) {
          Vec3 p = center + Vec3{(i + 0.5) * kCell, (j + 0.5) * kCell, (k + 0.5) * kCell} -
                   Vec3{side, side, side} * 0.5;
          if (body == 1) p = center + moved(p - center, {1.0, 0.0, 0.0}, 10.0 * M_PI / 180.0, {});
          model.addParticle(mass, 0.5 * kCell, false, object);
          state.position.push_back(p);
        }
      }
    }
  }
  state.velocity.assign(state.position.size(), Vec3{});
  return model;
}

TEST(RigidTree, FindsTheContactsOfARefittedTree) {
  State state;
  Model rigidModel = rigidPair(6, true, state);
  Model refitModel = rigidPair(6, false, state);
  test::Evaluator rigid(rigidModel), refit(refitModel);
  rigid(state);  // builds the trees at the starting positions
  refit(state);
  // A large rigid motion of both cubes, then a deviation of each particle up to
  // a tenth of its radius (within the default margin of half the radius).
  const Vec3 axis = Vec3{1.0, 2.0, 3.0} / std::sqrt(14.0);
  test::TestRandom random{7};
  State later = state;
  for (Vec3& p : later.position) {
    p = moved(p, axis, 1.3, {0.4, -0.2, 0.7});
    p += Vec3{random.symmetric(), random.symmetric(), random.symmetric()} * (0.1 * 0.005 / 1.8);
  }
  const Evaluation& a = rigid(later);
  const Evaluation& b = refit(later);
  std::printf("rigid pair 6³: %zu contacts (rigid tree), %zu (refit); node tests %lld / %lld\n",
              a.contacts.size(), b.contacts.size(),
              static_cast<long long>(a.contactStats.nodeTests),
              static_cast<long long>(b.contactStats.nodeTests));
  ASSERT_GT(b.contacts.size(), 10u);
  ASSERT_EQ(a.contacts.size(), b.contacts.size());
  for (std::size_t k = 0; k < a.contacts.size(); ++k) {
    EXPECT_EQ(a.contacts[k].a, b.contacts[k].a);
    EXPECT_EQ(a.contacts[k].other, b.contacts[k].other);
  }
  for (std::size_t i = 0; i < a.force.size(); ++i) EXPECT_EQ(a.force[i], b.force[i]);
}

// A rigid row of particles (a thin rod: every particle on one line) has no frame of
// three references: its tree is refitted, never moved by a frame taken from the
// 1e-17 m that rounding leaves off the line (which turned at random: a PR2
// gripper's pole missed its ground contact until the step stalled). Tumbled and
// lowered onto a plane, it finds the contacts a refitted tree finds.
TEST(RigidTree, ARowOfParticlesFindsItsContactsAsItTurns) {
  const auto row = [](bool rigid, State& state) {
    Model model;
    model.gravity = {};
    state = State{};
    const std::int32_t object = model.addObject("rod", "link");
    model.objects[static_cast<std::size_t>(object)].rigid = rigid;
    for (int k = 0; k < 19; ++k) {
      model.addParticle(0.01, 0.01, false, object);
      // On a turned line, as a robot's placement puts them: rounding leaves them
      // some 1e-17 m off it.
      state.position.push_back(moved({0.01 + 0.01 * k, 0.0, 0.0}, Vec3{0.6, 0.0, 0.8}, 0.7, {0.0, 0.0, 0.0267}));
    }
    state.velocity.assign(state.position.size(), Vec3{});
    model.environment.planes.push_back(GroundPlane{{0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, 0});
    return model;
  };
  State state;
  Model rigidModel = row(true, state);
  Model refitModel = row(false, state);
  test::Evaluator rigid(rigidModel), refit(refitModel);
  rigid(state);
  refit(state);
  std::size_t touching = 0;
  for (int turn = 1; turn <= 40; ++turn) {
    // Turned about a tilted axis and lowered until its lower end dips into the plane.
    State later = state;
    const Vec3 axis = Vec3{0.3, 1.0, 0.2} / std::sqrt(1.13);
    for (Vec3& p : later.position) p = moved(p, axis, 0.05 * turn, {0.1, 0.0, 0.1});
    double lowest = 1e300;
    for (const Vec3& p : later.position) lowest = std::min(lowest, p.z);
    for (Vec3& p : later.position) p.z += 0.0095 - lowest;  // 0.5 mm into the plane
    const Evaluation& a = rigid(later);
    const Evaluation& b = refit(later);
    ASSERT_EQ(a.contacts.size(), b.contacts.size()) << "turn " << turn;
    for (std::size_t k = 0; k < a.contacts.size(); ++k) EXPECT_EQ(a.contacts[k].a, b.contacts[k].a);
    touching += a.contacts.size();
  }
  EXPECT_GE(touching, 40u);
}

TEST(RigidTree, DetectionCostGrowsLinearlyAtMost) {
  std::vector<double> logN, logTests;
  for (const int cells : {10, 22, 46}) {  // 1000, 10 648 and 97 336 particles per object
    State state;
    Model model = rigidPair(cells, true, state);
    test::Evaluator evaluator(model);
    evaluator(state);
    const Evaluation& e = evaluator(state);
    const double n = static_cast<double>(cells) * cells * cells;
    const double tests = static_cast<double>(e.contactStats.nodeTests + e.contactStats.pairTests);
    std::printf("rigid pair %d³: node tests %lld, pair tests %lld, contacts %lld\n", cells,
                static_cast<long long>(e.contactStats.nodeTests),
                static_cast<long long>(e.contactStats.pairTests),
                static_cast<long long>(e.contactStats.particleContacts));
    logN.push_back(std::log(n));
    logTests.push_back(std::log(tests));
  }
  double meanN = 0.0, meanT = 0.0;
  for (std::size_t k = 0; k < logN.size(); ++k) {
    meanN += logN[k] / 3.0;
    meanT += logTests[k] / 3.0;
  }
  double covariance = 0.0, variance = 0.0;
  for (std::size_t k = 0; k < logN.size(); ++k) {
    covariance += (logN[k] - meanN) * (logTests[k] - meanT);
    variance += (logN[k] - meanN) * (logN[k] - meanN);
  }
  const double slope = covariance / variance;
  std::printf("rigid pair: log-log slope of node + pair tests against n (1e3..1e5) = %.3f\n",
              slope);
  EXPECT_LE(slope, 1.1);
}

}  // namespace
}  // namespace robophi
