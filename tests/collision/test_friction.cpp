// MODEL §3.3: Coulomb friction realised with an anchor spring. A sliding block
// stops after v0²/(2 μ_k g); on a slope it sticks below atan(μ_s) without creep
// and slides above it at g (sin α - μ_k cos α). With a Stribeck velocity v_S
// the sliding coefficient falls from μ_s to μ_k with the slip speed
// (law::slidingCoefficient): the block stops after ∫ v dv / (g μ(v)), and a slip
// that starts slowly on a slope between atan μ_k and atan μ_s dies out.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "collision/contact_law.h"
#include "collision/contact_test_util.h"

namespace robophi {
namespace {

constexpr double kBallMass = 1.0, kRadius = 0.05, kStiffness = 1.0e6;
constexpr double kStaticFriction = 0.5, kKineticFriction = 0.4, kFrictionG = 9.81;

// A particle resting on the ground z = 0 at its equilibrium depth, with gravity
// tilted by `slope` (rad) about y: the ground acts as a slope rising towards -x.
// The particle is the paper's, which does not turn (contact.rolling off): a
// block that sticks or slides. (A particle that turns rolls: test_rolling.cpp.)
World restingParticle(double slope, const Vec3& velocity = {}, double stribeckVelocity = 0.0) {
  Model model;
  model.contact.rolling = false;
  model.contact.stribeckVelocity = stribeckVelocity;
  State state;
  const double damping = 2.0 * 0.5 * std::sqrt(kStiffness * kBallMass);  // ζ = 0.5
  model.gravity = Vec3{std::sin(slope), 0.0, -std::cos(slope)} * kFrictionG;
  test::addBall(model, state,
                {0.0, 0.0, kRadius - kBallMass * kFrictionG * std::cos(slope) / kStiffness},
                kBallMass, kRadius);
  state.velocity[0] = velocity;
  model.environment.planes.push_back(GroundPlane{});
  test::overrideWithEnvironment(model, 0, kStiffness, damping, kStaticFriction, kKineticFriction);
  return World(model, state, Integrator::kSymplecticEuler);
}

TEST(Friction, SlidingBlockStopsAfterTheCoulombDistance) {
  constexpr double kSpeed = 2.0;  // m/s
  World world = restingParticle(0.0, {kSpeed, 0.0, 0.0});
  const double expected = kSpeed * kSpeed / (2.0 * kKineticFriction * kFrictionG);
  constexpr double kStep = 1.0e-5;
  for (int step = 0; step < 120'000; ++step) world.step(kStep);  // 1.2 s; stops at 0.51 s
  const double travelled = world.state().position[0].x;
  std::printf("sliding block: travelled %.6f m, v0²/(2 μk g) = %.6f m (%.3f%%), speed %.2e\n",
              travelled, expected, 100.0 * (travelled / expected - 1.0),
              norm(world.state().velocity[0]));
  EXPECT_NEAR(travelled / expected, 1.0, 0.005);
  EXPECT_LT(norm(world.state().velocity[0]), 1e-3);
}

TEST(Friction, SticksJustBelowTheFrictionAngleWithoutCreep) {
  const double angle = std::atan(kStaticFriction) - 0.25 * M_PI / 180.0;
  World world = restingParticle(angle);
  constexpr double kStep = 1.0e-4;
  const double x0 = world.state().position[0].x;
  for (int step = 0; step < 50'000; ++step) world.step(kStep);
  const double x5 = world.state().position[0].x;
  for (int step = 0; step < 50'000; ++step) world.step(kStep);
  const double x10 = world.state().position[0].x;
  const double firstHalf = std::abs(x5 - x0), secondHalf = std::abs(x10 - x5);
  std::printf("stick at %.3f°: creep %.3e m in 0-5 s, %.3e m in 5-10 s\n", angle * 180.0 / M_PI,
              firstHalf, secondHalf);
  EXPECT_LT(std::abs(x10 - x0), 1e-3);
  EXPECT_LE(secondHalf, firstHalf);
  EXPECT_LT(secondHalf, 1e-6);
  EXPECT_EQ(world.contacts().size(), 1u);
  EXPECT_EQ(world.contacts()[0].sliding, 0);
}

TEST(Friction, SlidesJustAboveTheFrictionAngleAtTheKineticAcceleration) {
  const double angle = std::atan(kStaticFriction) + 0.25 * M_PI / 180.0;
  World world = restingParticle(angle);
  constexpr double kStep = 1.0e-4;
  for (int step = 0; step < 10'000; ++step) world.step(kStep);
  const double v1 = world.state().velocity[0].x;
  for (int step = 0; step < 10'000; ++step) world.step(kStep);
  const double v2 = world.state().velocity[0].x;
  const double acceleration = (v2 - v1) / 1.0;
  const double expected = kFrictionG * (std::sin(angle) - kKineticFriction * std::cos(angle));
  std::printf("slide at %.3f°: a = %.6f m/s², g (sin α - μk cos α) = %.6f m/s²\n",
              angle * 180.0 / M_PI, acceleration, expected);
  EXPECT_NEAR(acceleration / expected, 1.0, 1e-3);
  EXPECT_EQ(world.contacts()[0].sliding, 1);
}

TEST(Friction, EnergyAccountCloses) {
  // A sliding block: kinetic energy goes into the dissipated account.
  World world = restingParticle(0.0, {1.0, 0.5, 0.0});
  world.step(1.0e-5);
  const double initial = world.energy().total();
  for (int step = 0; step < 50'000; ++step) world.step(1.0e-5);
  const double final = world.energy().total();
  std::printf("sliding energy: total %.9f -> %.9f J (dissipated %.6f J)\n", initial, final,
              world.energy().dissipated);
  EXPECT_NEAR(final, initial, 1e-3 * 0.5 * 1.25);
}

TEST(Friction, TheSlidingCoefficientFallsFromStaticToKinetic) {
  EXPECT_EQ(law::slidingCoefficient(0.5, 0.3, 0.0, 0.05), 0.5);  // continuous with μ_s
  EXPECT_NEAR(law::slidingCoefficient(0.5, 0.3, 0.05, 0.05), 0.3 + 0.2 / M_E, 1e-15);
  EXPECT_EQ(law::slidingCoefficient(0.5, 0.3, 1.0, 0.05), 0.3);  // exp(-400) = 0
  EXPECT_EQ(law::slidingCoefficient(0.5, 0.3, 1e-6, 0.0), 0.3);  // v_S = 0: the paper's law
  double previous = 1.0;
  for (double v = 0.0; v < 0.3; v += 0.001) {  // monotone between the two
    const double mu = law::slidingCoefficient(0.5, 0.3, v, 0.05);
    EXPECT_LE(mu, previous);
    EXPECT_GE(mu, 0.3);
    previous = mu;
  }
}

// The block of SlidingBlockStopsAfterTheCoulombDistance with v_S = 0.2 m/s: it
// stops after ∫₀^v0 v dv / (g μ(v)) (Simpson's rule here), shorter than with μ_k
// alone, and its energy account closes.
TEST(Friction, WithAStribeckVelocityTheBlockStopsAfterTheIntegralDistance) {
  constexpr double kSpeed = 0.3, kStribeck = 0.2;
  World world = restingParticle(0.0, {kSpeed, 0.0, 0.0}, kStribeck);
  constexpr int kPanels = 20'000;
  const auto integrand = [](double v) {
    return v / (kFrictionG * law::slidingCoefficient(kStaticFriction, kKineticFriction, v, kStribeck));
  };
  double sum = integrand(0.0) + integrand(kSpeed);
  for (int k = 1; k < kPanels; ++k) sum += (k % 2 == 1 ? 4.0 : 2.0) * integrand(k * kSpeed / kPanels);
  const double expected = sum * kSpeed / kPanels / 3.0;
  const double coulomb = kSpeed * kSpeed / (2.0 * kKineticFriction * kFrictionG);
  world.step(1.0e-5);
  const double initial = world.energy().total();
  for (int step = 0; step < 60'000; ++step) world.step(1.0e-5);  // 0.6 s; stops at 0.07 s
  const double travelled = world.state().position[0].x;
  std::printf("Stribeck block: travelled %.6f m, integral %.6f m (%.3f%%), mu_k alone %.6f m\n",
              travelled, expected, 100.0 * (travelled / expected - 1.0), coulomb);
  EXPECT_NEAR(travelled / expected, 1.0, 0.005);
  EXPECT_LT(expected, 0.95 * coulomb);  // 0.912 of it
  EXPECT_LT(norm(world.state().velocity[0]), 1e-3);
  EXPECT_EQ(world.contacts()[0].sliding, 0);
  EXPECT_NEAR(world.energy().total(), initial, 1e-3 * 0.5 * kSpeed * kSpeed);
}

// A slip started at 2 cm/s down a slope between atan μ_k (21.8°) and atan μ_s
// (26.6°): with μ_k alone it never stops (tan 24° > μ_k), with v_S = 0.1 m/s
// friction near μ_s brings it back to sticking within a few millimetres.
TEST(Friction, ASlowSlipOnASlopeBelowTheStaticAngleDiesOutWithAStribeckVelocity) {
  const double angle = 24.0 * M_PI / 180.0;
  const Vec3 slip{0.02, 0.0, 0.0};
  World stribeck = restingParticle(angle, slip, 0.1);
  World coulomb = restingParticle(angle, slip, 0.0);
  for (int step = 0; step < 20'000; ++step) {  // 2 s
    stribeck.step(1.0e-4);
    coulomb.step(1.0e-4);
  }
  const double held = stribeck.state().position[0].x, slid = coulomb.state().position[0].x;
  std::printf("slow slip at 24 deg: %.3e m with v_S = 0.1 m/s (speed %.1e), %.3f m with mu_k\n",
              held, norm(stribeck.state().velocity[0]), slid);
  EXPECT_LT(held, 5e-3);
  EXPECT_LT(norm(stribeck.state().velocity[0]), 1e-6);
  EXPECT_EQ(stribeck.contacts()[0].sliding, 0);
  EXPECT_GT(slid, 0.5);
}

// A ball sliding down a wall (a box, environment item 1) lands on the ground (a
// plane, item 0): the wall's contact goes on through the landing, its friction
// history carried and nothing released (a ball touching two items lists them
// in key order, the last item first; docs/contact.md).
TEST(Friction, AWallContactKeepsItsHistoryWhenTheGroundContactStarts) {
  Model model;
  model.contact.rolling = false;
  State state;
  constexpr double kPush = 2.0;  // m/s², towards the wall
  model.gravity = {-kPush, 0.0, -kFrictionG};
  const double damping = 2.0 * 0.5 * std::sqrt(kStiffness * kBallMass);  // ζ = 0.5
  test::addBall(model, state, {kRadius - kBallMass * kPush / kStiffness, 0.0, 0.2}, kBallMass,
                kRadius);
  model.environment.planes.push_back(GroundPlane{});
  BoxObstacle wall;  // its face at x = 0
  wall.center = {-0.5, 0.0, 0.5};
  wall.halfExtents = {0.5, 1.0, 1.0};
  model.environment.boxes.push_back(wall);
  test::overrideWithEnvironment(model, 0, kStiffness, damping, kStaticFriction, kKineticFriction);
  World world(model, state, Integrator::kSymplecticEuler);
  const auto wallContact = [](const std::vector<Contact>& contacts) -> const Contact* {
    for (const Contact& c : contacts)
      if (c.withEnvironment() && c.environmentItem() == 1) return &c;
    return nullptr;
  };
  bool landed = false;
  for (int step = 0; step < 100'000 && !landed; ++step) {
    const std::vector<Contact> before = world.contacts();
    world.step(1.0e-5);
    const std::vector<Contact>& after = world.contacts();
    if (before.size() != 1 || after.size() != 2) continue;
    landed = true;
    const Contact* was = wallContact(before);
    const Contact* is = wallContact(after);
    ASSERT_NE(was, nullptr);
    ASSERT_NE(is, nullptr);
    EXPECT_EQ(was->sliding, 1);  // sliding down the wall, its anchor holding μ_k F_n
    EXPECT_GT(was->anchorEnergy, 0.0);
    // The wall's record goes on: still sliding, nothing released.
    EXPECT_EQ(is->sliding, 1);
    EXPECT_EQ(world.evaluation().releasedAnchorEnergy, 0.0);
    EXPECT_LT(after[0].key(), after[1].key());
  }
  EXPECT_TRUE(landed);
}

}  // namespace
}  // namespace robophi
