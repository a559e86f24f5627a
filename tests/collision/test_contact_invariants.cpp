// Contact forces obey action/reaction (MODEL §3.1), runs are bit-identical, and
// the environment items and the medium act as specified.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "collision/contact_stage.h"
#include "collision/contact_test_util.h"
#include "collision/environment.h"

namespace robophi {
namespace {

// A 3×3×3 lattice object tied by LS to axis neighbours.
void addLatticeObject(Model& model, State& state, const Vec3& center, const Vec3& velocity) {
  const std::int32_t object = model.addObject("block", "box");
  const int first = model.particleCount();
  for (int k = 0; k < 27; ++k) {
    model.addParticle(0.05, 0.02, false, object);
    state.position.push_back(center + Vec3{k % 3 - 1.0, (k / 3) % 3 - 1.0, k / 9 - 1.0} * 0.04);
    state.velocity.push_back(velocity);
  }
  for (int k = 0; k < 27; ++k) {
    const int x = k % 3, y = (k / 3) % 3, z = k / 9;
    if (x < 2) model.linearSprings.push_back({first + k, first + k + 1, 0.04, 5e3, 0.5});
    if (y < 2) model.linearSprings.push_back({first + k, first + k + 3, 0.04, 5e3, 0.5});
    if (z < 2) model.linearSprings.push_back({first + k, first + k + 9, 0.04, 5e3, 0.5});
  }
}

Vec3 momentum(const Model& model, const State& state) {
  Vec3 p;
  for (int i = 0; i < model.particleCount(); ++i) p += state.velocity[i] * model.mass[i];
  return p;
}

TEST(ContactInvariants, TwoFreeObjectsCollidingConserveMomentum) {
  Model model;
  State state;
  model.gravity = {};
  addLatticeObject(model, state, {-0.1, 0.0, 0.0}, {1.0, 0.2, 0.0});
  addLatticeObject(model, state, {0.1, 0.03, 0.01}, {-1.5, 0.0, 0.1});
  model.materials[0].staticFriction = 0.8;
  model.materials[0].kineticFriction = 0.6;
  World world(model, state, Integrator::kSymplecticEuler);
  const Vec3 initial = momentum(world.model(), world.state());
  std::size_t mostContacts = 0;
  for (int step = 0; step < 4000; ++step) {
    world.step(5e-5);
    mostContacts = std::max(mostContacts, world.contacts().size());
  }
  const Vec3 final = momentum(world.model(), world.state());
  const double error = norm(final - initial) / norm(initial);
  std::printf("momentum: relative change %.3e over 0.2 s, up to %zu contacts\n", error,
              mostContacts);
  EXPECT_GT(mostContacts, 3u);
  EXPECT_LT(error, 1e-12);
}

TEST(ContactInvariants, PileRunsAreBitIdentical) {
  const auto run = [] {
    Model model;
    State state;
    test::TestRandom random{3};
    for (int k = 0; k < 288; ++k) {  // 6 × 6 × 8 lattice, 2.5 cm, jittered
      const Vec3 lattice{k % 6 - 2.5, (k / 6) % 6 - 2.5, k / 36 + 0.6};
      test::addBall(model, state,
                    lattice * 0.025 +
                        Vec3{random.symmetric(), random.symmetric(), random.symmetric()} * 0.002,
                    0.004, 0.01);
    }
    model.environment.planes.push_back(GroundPlane{});
    for (const Vec3& n : {Vec3{1, 0, 0}, Vec3{-1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, -1, 0}}) {
      model.environment.planes.push_back(GroundPlane{n * -0.075, n, 0});
    }
    model.environment.boxes.push_back(BoxObstacle{{0.0, 0.0, 0.0}, {0.02, 0.02, 0.02}});
    model.materials[0].contactStiffness = 4e4;
    model.materials[0].contactDamping = 6.0;
    World world(model, state);
    for (int step = 0; step < 3000; ++step) world.step(1e-4);
    return std::make_pair(stateHash(world.state()), world.contacts().size());
  };
  const auto first = run();
  const auto second = run();
  std::printf("pile hash %016llx, %zu contacts\n", static_cast<unsigned long long>(first.first),
              first.second);
  EXPECT_EQ(first.first, second.first);
  EXPECT_GT(first.second, 100u);
}

TEST(ContactInvariants, EnvironmentItemsGiveDistanceAndNormal) {
  Model model;
  State state;
  const double r = 0.01;
  // Heightfield z = 0.1 x over [0, 1]², a box rotated 45° about z, a sphere.
  Heightfield field;
  field.columns = 3;
  field.rows = 3;
  field.cellSizeX = field.cellSizeY = 0.5;
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) field.heights.push_back(0.1 * 0.5 * i);
  }
  model.environment.heightfields.push_back(field);
  BoxObstacle box;
  box.center = {3.0, 0.0, 0.0};
  box.halfExtents = {0.1, 0.1, 0.1};
  box.axisX = Vec3{1.0, 1.0, 0.0} / std::sqrt(2.0);
  box.axisY = Vec3{-1.0, 1.0, 0.0} / std::sqrt(2.0);
  model.environment.boxes.push_back(box);
  model.environment.spheres.push_back(SphereObstacle{{5.0, 0.0, 0.0}, 0.5, 0});
  test::addBall(model, state, {0.5, 0.5, 0.05 + 0.005}, 0.01, r);  // 5 mm above terrain
  test::addBall(model, state, {3.0 + 0.1 * std::sqrt(2.0) + 0.005, 0.0, 0.0}, 0.01, r);
  test::addBall(model, state, {5.0, 0.0, 0.5 + 0.004}, 0.01, r);
  model.gravity = {};
  test::Evaluator evaluator(model);
  const std::vector<Contact>& contacts = evaluator(state).contacts;
  ASSERT_EQ(contacts.size(), 3u);
  const double slopeNormalZ = 1.0 / std::sqrt(1.01);
  EXPECT_NEAR(contacts[0].depth, 0.005 * slopeNormalZ - r, 1e-12);
  EXPECT_NEAR(contacts[0].normal.x, -0.1 * slopeNormalZ, 1e-12);
  EXPECT_NEAR(contacts[1].depth, 0.005 - r, 1e-12);  // at the box's corner
  EXPECT_NEAR(contacts[1].normal.x, 1.0, 1e-12);
  EXPECT_NEAR(contacts[2].depth, 0.004 - r, 1e-12);
  EXPECT_NEAR(contacts[2].normal.z, 1.0, 1e-12);
}

// A particle below the terrain surface has a contact depth (hence energy ½κd²)
// that is continuous as it crosses a cell edge, where the bilinear surface's
// slope jumps: the depth is measured along the smoothed normal (normalAt). The
// contact's normal is the depth's own gradient, made unit (so that the force
// κ d n is the energy's gradient, up to |∇d|): checked by central differences on
// either side of the edge (off the rows' edges), where it jumps with the
// surface's slope.
TEST(ContactInvariants, HeightfieldDepthIsContinuousAcrossCellEdges) {
  Environment environment;
  Heightfield field;
  field.columns = 4;
  field.rows = 3;
  field.heights = {0.0, 0.0, 0.3, 0.0, 0.0, 0.1, 0.4, 0.1, 0.0, 0.0, 0.2, 0.0};
  environment.heightfields.push_back(field);
  const auto distanceAt = [&](const Vec3& p) {
    double d = 0.0;
    Vec3 n;
    EXPECT_TRUE(environmentDistance(environment, 0, p, d, n));
    return d;
  };
  for (double edge : {1.0, 2.0}) {  // x of the inner cell edges (cell size 1 m)
    for (double y : {0.3, 1.0, 1.7}) {
      double before = 0.0, after = 0.0;
      Vec3 normalBefore, normalAfter;
      const double h = environment.heightfields[0].heightAt(edge, y);
      ASSERT_TRUE(
          environmentDistance(environment, 0, {edge - 1e-9, y, h - 0.05}, before, normalBefore));
      ASSERT_TRUE(
          environmentDistance(environment, 0, {edge + 1e-9, y, h - 0.05}, after, normalAfter));
      EXPECT_LT(before, -0.03);
      EXPECT_NEAR(before, after, 1e-8) << "x " << edge << " y " << y;
      EXPECT_NEAR(norm(normalBefore), 1.0, 1e-12);
      for (const double side : {-1e-3, 1e-3}) {
        const Vec3 p{edge + side, y + 1e-3, h - 0.05};  // (y = 1 is a row edge: off it)
        double d = 0.0;
        Vec3 n;
        ASSERT_TRUE(environmentDistance(environment, 0, p, d, n));
        constexpr double kStep = 1e-7;
        const Vec3 gradient{
            (distanceAt(p + Vec3{kStep, 0, 0}) - distanceAt(p - Vec3{kStep, 0, 0})) / (2 * kStep),
            (distanceAt(p + Vec3{0, kStep, 0}) - distanceAt(p - Vec3{0, kStep, 0})) / (2 * kStep),
            (distanceAt(p + Vec3{0, 0, kStep}) - distanceAt(p - Vec3{0, 0, kStep})) / (2 * kStep)};
        EXPECT_NEAR(norm(n - gradient / norm(gradient)), 0.0, 1e-6)
            << "x " << p.x << " y " << y;
      }
    }
  }
}

TEST(ContactInvariants, ViscosityGivesTheTerminalSpeed) {
  // A single particle falling in a medium: m g = k v at terminal speed.
  Model model;
  State state;
  test::addBall(model, state, {0.0, 0.0, 0.0}, 0.1, 0.01);
  model.environment.viscosity = 0.5;  // N·s/m
  World world(model, state);
  for (int step = 0; step < 20000; ++step) world.step(1e-3);
  const double terminal = 0.1 * 9.81 / 0.5;
  std::printf("terminal speed %.9f m/s, m g / k = %.9f m/s\n", -world.state().velocity[0].z,
              terminal);
  EXPECT_NEAR(-world.state().velocity[0].z / terminal, 1.0, 1e-6);
}

TEST(ContactInvariants, ViscosityActsOnlyWhereTheSurfaceFacesTheMotion) {
  // Two particles of one object moving along +x: only the front one feels drag.
  Model model;
  State state;
  const std::int32_t object = model.addObject("pair", "particles");
  for (int k = 0; k < 2; ++k) {
    model.addParticle(0.1, 0.01, false, object);
    state.position.push_back({0.1 * k, 0.0, 0.0});
    state.velocity.push_back({2.0, 0.0, 0.0});
  }
  model.gravity = {};
  model.environment.viscosity = 0.5;
  test::Evaluator evaluator(model);
  const std::vector<Vec3>& force = evaluator(state).force;
  EXPECT_DOUBLE_EQ(force[0].x, 0.0);   // rear: n = -x
  EXPECT_DOUBLE_EQ(force[1].x, -1.0);  // front: -k (V·n) V̂
}

}  // namespace
}  // namespace robophi
