// MODEL §3.8 flat faces: a lattice box touches by its true faces. A cube on a
// slowly tilting plane tips where the gravity line passes its edge (tan α = 1,
// not the particles' 0.5); a box sliding on the ground keeps its normal force
// flat; a parallel gripper of two flat plates holds a box by its faces.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

#include "collision/contact_tables.h"
#include "collision/contact_test_util.h"
#include "collision/facets.h"
#include "robophi/build/model_builder.h"
#include "robophi/build/objects.h"

namespace robophi {
namespace {

constexpr double kFacetsG = 9.81;
constexpr double kFacetsDegree = M_PI / 180.0;

// The surface mesh of a lattice box: vertices on the true faces, weights summing
// to 1 and reproducing the vertex from the particles.
TEST(Facets, BoxSurfaceLiesOnItsTrueFaces) {
  for (const int n : {2, 3}) {
    build::BoxSpec spec;
    spec.size = {0.1, 0.2, 0.3};
    spec.cells = {n, n, n};
    const build::GeneratedObject box = build::makeBox(spec);
    ASSERT_EQ(box.surfaceVertices.size(),
              static_cast<std::size_t>((n + 1) * (n + 1) * (n + 1) - (n - 1) * (n - 1) * (n - 1)));
    EXPECT_EQ(box.surfaceTriangles.size(), static_cast<std::size_t>(12 * n * n));
    double area = 0.0;
    std::vector<Vec3> x;
    for (const SurfaceVertex& v : box.surfaceVertices) {
      Vec3 p;
      double sum = 0.0;
      for (int k = 0; k < SurfaceVertex::kMaxParticles; ++k) {
        if (v.particle[k] < 0) continue;
        p += box.position[static_cast<std::size_t>(v.particle[k])] * v.weight[k];
        sum += v.weight[k];
      }
      EXPECT_NEAR(sum, 1.0, 1e-12);
      // On a face: one coordinate at ± half the size.
      const double q = std::max({std::abs(p.x) / 0.05, std::abs(p.y) / 0.1, std::abs(p.z) / 0.15});
      EXPECT_NEAR(q, 1.0, 1e-12);
      x.push_back(p);
    }
    for (const SurfaceTriangle& t : box.surfaceTriangles) {
      const Vec3 a = x[static_cast<std::size_t>(t.vertex[0])];
      const Vec3 b = x[static_cast<std::size_t>(t.vertex[1])];
      const Vec3 c = x[static_cast<std::size_t>(t.vertex[2])];
      const Vec3 normal = cross(b - a, c - a);
      area += 0.5 * norm(normal);
      EXPECT_GT(dot(normal, (a + b + c) / 3.0), 0.0);  // wound outwards
    }
    EXPECT_NEAR(area, 2.0 * (0.1 * 0.2 + 0.2 * 0.3 + 0.3 * 0.1), 1e-12);
  }
}

// The closest-triangle rule sees only the triangles near the probe (those its
// tree leaf meets). A particle 5 mm above a box's top face and 5 mm in from its
// side, offered only the side's triangles (the top's leaf out of reach), is
// beside the side face and below its plane: outside, not 2.6 cm inside (the
// contact that stalled a cloth draped over a box, its step falling to 1e-12 s).
// A particle just under the top face, offered every triangle, is inside, by the
// top's normal.
TEST(Facets, APointBesideAFaceAndBelowItsPlaneIsOutside) {
  build::ModelBuilder builder;
  builder.setGravity({});
  build::BoxSpec spec;
  spec.cells = {3, 3, 3};
  spec.size = {0.1, 0.1, 0.1};
  build::GeneratedObject box = build::makeBox(spec);
  build::resolveSprings(box, {});
  builder.addObject({.name = "box", .kind = "box", .geometry = box});
  build::GeneratedObject ball;
  build::addParticle(ball, {0.0, -0.045, 0.065}, 0.01, 0.01);
  builder.addObject({.name = "ball", .kind = "particles", .geometry = ball});
  build::BuiltModel built = std::move(builder).build();
  const Model& model = built.model;
  const CompiledModel compiled(model);
  const auto probe = static_cast<std::int32_t>(model.particleCount() - 1);
  const auto offer = [&](const std::vector<Vec3>& position, double sideOnly) {
    ContactScratch scratch;
    scratch.tables = &compiled.contactTables();
    updateSurfacePositions(model, position, scratch);
    for (std::size_t t = 0; t < model.surfaceTriangles.size(); ++t) {
      const SurfaceTriangle& tri = model.surfaceTriangles[t];
      const Vec3& x0 = scratch.vertexPosition[static_cast<std::size_t>(tri.vertex[0])];
      const Vec3 normal = cross(scratch.vertexPosition[static_cast<std::size_t>(tri.vertex[1])] - x0,
                                scratch.vertexPosition[static_cast<std::size_t>(tri.vertex[2])] - x0);
      if (sideOnly && !(normal.y < 0.0 && std::abs(normal.x) + std::abs(normal.z) == 0.0))
        continue;
      scratch.facetCandidates.push_back({probe, 0, static_cast<std::int32_t>(t)});
    }
    EXPECT_FALSE(scratch.facetCandidates.empty());
    resolveFacetCandidates(model, position, scratch);
    return scratch.treeContacts;
  };
  std::vector<Vec3> position = built.initial.position;
  EXPECT_TRUE(offer(position, true).empty());
  EXPECT_TRUE(offer(position, false).empty());
  position.back() = {0.0, -0.045, 0.045};  // 5 mm under the top: 1.5 cm deep
  const std::vector<Contact> inside = offer(position, false);
  ASSERT_EQ(inside.size(), 1u);
  EXPECT_NEAR(inside[0].depth, -0.015, 1e-12);
  EXPECT_NEAR(inside[0].normal.z, 1.0, 1e-12);
}

// A contact with a triangle loads the stability sums of the triangle's own
// particles (addTriangleRates), not the touched object's first particle, the
// contact's label. Heavy balls resting on a light faceted plate, far from its
// first particle: nine of them, on nine triangles apart, leave the stability
// limit about where one leaves it (each triangle carries one contact), where
// the label took all nine (the limit 3x shorter) and the plate's corner
// particle, untouched, set it.
TEST(Facets, ATrianglesContactLoadsItsOwnParticlesStabilitySums) {
  const auto criticalStep = [](int balls) {
    build::ModelBuilder builder;
    builder.setGravity({0.0, 0.0, -9.81});
    build::PlateSpec spec;
    spec.sizeX = spec.sizeY = 0.4;
    spec.cells = {12, 12};
    spec.mass = 0.0144;  // 1e-4 kg a particle
    spec.thickness = 0.01;
    build::GeneratedObject plate = build::makePlate(spec);
    build::resolveSprings(plate, {});
    builder.addObject({.name = "plate", .kind = "plate", .geometry = plate});
    build::GeneratedObject weights;
    for (int k = 0; k < balls; ++k) {
      const double x = 0.1 * (k % 3) - 0.05, y = 0.1 * (k / 3) - 0.05;
      build::addParticle(weights, {x + 0.003, y + 0.002, 0.0139}, 0.05, 0.01);
    }
    builder.addObject({.name = "weights", .kind = "particles", .geometry = weights});
    build::BuiltModel built = std::move(builder).build();
    test::Evaluator evaluate(built.model);
    const Evaluation& e = evaluate(built.initial);
    int onTriangles = 0;
    for (const Contact& c : e.contacts) onTriangles += c.facet >= 0 ? 1 : 0;
    EXPECT_EQ(onTriangles, balls);
    return e.contactCriticalStep;
  };
  const double one = criticalStep(1), nine = criticalStep(9);
  std::printf("stability limit with one ball on the plate %.3e s, with nine %.3e s\n", one, nine);
  EXPECT_GT(nine, 0.8 * one);
}

// A particle thrown at a free faceted box (no gravity, friction or damping):
// the facet force, spread over the box's particles by the vertices' weights,
// keeps the momentum exactly and the energy to the integrator's accuracy.
TEST(Facets, ParticleOnAFaceKeepsMomentumAndEnergy) {
  build::ModelBuilder builder;
  builder.setGravity({});
  build::BoxSpec spec;
  spec.cells = {3, 3, 3};
  spec.size = {0.1, 0.1, 0.1};
  build::GeneratedObject box = build::makeBox(spec);
  build::resolveSprings(box, {});
  for (auto& spring : box.linearSprings) spring.damping = 0.0;
  builder.addObject({.name = "box", .kind = "box", .geometry = box});
  build::GeneratedObject ball;
  build::addParticle(ball, {0.02, 0.013, 0.08}, 0.2, 0.01);
  builder.addObject({.name = "ball",
                     .kind = "particles",
                     .geometry = ball,
                     .velocity = {Vec3{-0.1, 0.05, -1.0}}});
  ContactSettings contact;
  contact.pairOverrides.push_back(ContactPairOverride{0, 1, 1.0e5, 0.0, 0.0, 0.0});
  builder.setContactSettings(contact);
  build::BuiltModel built = std::move(builder).build();
  World world(std::move(built.model), std::move(built.initial));
  const auto momentum = [&] {
    Vec3 sum;
    for (ParticleIndex i = 0; i < world.model().particleCount(); ++i)
      sum += world.state().velocity[i] * world.model().mass[i];
    return sum;
  };
  const Vec3 p0 = momentum();
  const double e0 = world.energy().total();
  int facetSteps = 0;
  for (int step = 0; step < 5000; ++step) {  // 0.05 s: reaches the face at 0.02 s
    world.step(1.0e-5);
    for (const Contact& c : world.contacts()) facetSteps += c.facet >= 0 ? 1 : 0;
  }
  const Vec3 drift = momentum() - p0;
  const double e1 = world.energy().total();
  std::printf(
      "particle on a face: %d facet-contact steps, momentum drift %.3e kg·m/s, energy "
      "%.9f -> %.9f J, ball speed now %.4f m/s\n",
      facetSteps, norm(drift), e0, e1, world.state().velocity[27].z);
  EXPECT_GT(facetSteps, 50);
  EXPECT_LT(norm(drift), 1e-12);
  EXPECT_NEAR(e1 / e0, 1.0, 1e-3);
  EXPECT_GT(world.state().velocity[27].z, 0.0);  // bounced back
}

struct BoxOnGround {
  int cells = 2;
  double size = 0.1, mass = 1.0;
  double stiffness = 1.0e5, damping = 100.0, staticFriction = 1.5, kineticFriction = 1.2;
  bool facets = true;
  Vec3 velocity{};
  /// The lattice's springs: natural frequency (rad/s) and damping (N·s/m; unset: default).
  double naturalFrequency = build::kDefaultNaturalFrequency;
  std::optional<double> springDamping{};
};

// A cube standing on the plane z = 0 at its equilibrium depth.
build::BuiltModel boxOnGround(const BoxOnGround& s) {
  build::ModelBuilder builder;
  build::BoxSpec spec;
  spec.cells = {s.cells, s.cells, s.cells};
  spec.size = {s.size, s.size, s.size};
  spec.mass = s.mass;
  spec.facets = s.facets;
  const int bottom = s.facets ? (s.cells + 1) * (s.cells + 1) : s.cells * s.cells;
  spec.center = {0.0, 0.0, 0.5 * s.size - s.mass * kFacetsG / (bottom * s.stiffness)};
  build::GeneratedObject box = build::makeBox(spec);
  build::SpringSettings springs;
  springs.naturalFrequency = s.naturalFrequency;
  springs.damping = s.springDamping;
  build::resolveSprings(box, springs);
  const std::vector<Vec3> velocity(box.size(), s.velocity);
  builder.addObject({.name = "box", .kind = "box", .geometry = box, .velocity = velocity});
  builder.addPlane(GroundPlane{});
  ContactSettings contact;
  contact.pairOverrides.push_back(
      ContactPairOverride{0, -1, s.stiffness, s.damping, s.staticFriction, s.kineticFriction});
  builder.setContactSettings(contact);
  return std::move(builder).build();
}

// The box's tilt (rad): the angle of its first lattice column from +z.
double tilt(const World& world) {
  const Vec3 up = world.state().position[1] - world.state().position[0];
  return std::acos(std::clamp(up.z / norm(up), -1.0, 1.0));
}

// Tilts gravity about y from `start` at `rate` (rad/s) until the cube has turned
// by 3°; returns the tilt of gravity then (rad).
double tippingAngle(int cells, bool facets, double start, double rate) {
  BoxOnGround s;
  s.cells = cells;
  s.facets = facets;
  build::BuiltModel built = boxOnGround(s);
  built.model.gravity = Vec3{std::sin(start), 0.0, -std::cos(start)} * kFacetsG;
  World world(std::move(built.model), std::move(built.initial));
  constexpr double kStep = 1.0e-4;
  double angle = start;
  for (int step = 0; step < 400'000; ++step) {
    angle = start + rate * step * kStep;
    world.setGravity(Vec3{std::sin(angle), 0.0, -std::cos(angle)} * kFacetsG);
    world.step(kStep);
    if (tilt(world) > 3.0 * kFacetsDegree) return angle;
  }
  return angle;
}

TEST(Facets, LatticeCubeTipsAtItsTrueGeometry) {
  for (const int cells : {2, 3}) {
    const double tip = tippingAngle(cells, true, 41.0 * kFacetsDegree, 1.0 * kFacetsDegree);
    std::printf("%d×%d×%d cube with facets tips at %.2f° (tan α = %.4f; 45° expected)\n", cells,
                cells, cells, tip / kFacetsDegree, std::tan(tip));
    EXPECT_NEAR(tip / kFacetsDegree, 45.0, 2.0);
  }
}

TEST(Facets, SlidingBoxNormalForceIsSteady) {
  BoxOnGround s;
  s.cells = 3;
  s.staticFriction = 0.2;
  s.kineticFriction = 0.2;
  s.velocity = {1.0, 0.0, 0.0};
  // A lattice damped near critical (its springs' default 10% lets the friction
  // at its base drive its lowest shear mode, 33 Hz, into a rocking that swings
  // the normal force by ±50%, faceted or not).
  s.springDamping = 20.0;
  build::BuiltModel built = boxOnGround(s);
  World world(std::move(built.model), std::move(built.initial));
  constexpr double kStep = 5.0e-5;
  const double weight = s.mass * kFacetsG;
  double low = 1e300, high = -1e300, mean = 0.0;
  int samples = 0;
  for (int step = 1; step <= 8000; ++step) {  // 0.4 s; stops after v0 / (μ g) = 0.51 s
    world.step(kStep);
    if (step * kStep < 0.05) continue;
    double normal = 0.0;
    for (const Contact& c : world.contacts()) normal += c.normalForce * c.normal.z;
    low = std::min(low, normal);
    high = std::max(high, normal);
    mean += normal;
    ++samples;
  }
  mean /= samples;
  const double speed = world.state().velocity[0].x;
  std::printf(
      "sliding box: normal force %.5f..%.5f N (mean %.5f, weight %.5f): ripple %.3f%% of "
      "the weight; speed %.3f m/s\n",
      low, high, mean, weight, 100.0 * (high - low) / weight, speed);
  EXPECT_LT((high - low) / weight, 0.02);
  EXPECT_GT(speed, 0.05);  // still sliding
  EXPECT_NEAR(mean / weight, 1.0, 0.01);
}

// A parallel gripper: two fixed (kinematic) plates with their faces along ±x
// close on a 5 cm box resting on the ground, squeeze it, lift it 10 cm.
TEST(Facets, ParallelGripperHoldsABoxByItsFaces) {
  constexpr double kSide = 0.05, kBoxMass = 0.1, kThickness = 0.01, kGap = 0.002;
  constexpr double kStiffness = 2.0e4, kGrip = 6.0;  // N/m per contact, N per finger
  build::ModelBuilder builder;
  build::BoxSpec boxSpec;
  boxSpec.cells = {3, 3, 3};
  boxSpec.size = {kSide, kSide, kSide};
  boxSpec.mass = kBoxMass;
  boxSpec.center = {0.0, 0.0, 0.5 * kSide};
  build::GeneratedObject box = build::makeBox(boxSpec);
  build::resolveSprings(box, {});
  builder.addObject({.name = "box", .kind = "box", .geometry = box});
  for (const double side : {-1.0, 1.0}) {
    build::PlateSpec plate;
    plate.center = {side * (0.5 * kSide + 0.5 * kThickness + kGap), 0.0, 0.045};
    plate.sizeX = 0.08;
    plate.sizeY = 0.08;
    plate.thickness = kThickness;
    plate.cells = {5, 5};
    plate.mass = 0.05;
    build::GeneratedObject finger = build::makePlate(plate);
    build::resolveSprings(finger, {}, 0.1);
    build::rotateObject(finger, plate.center, {0.0, 1.0, 0.0}, 0.5 * M_PI);  // face along x
    finger.fixed.assign(finger.size(), true);
    builder.addObject({.name = side < 0 ? "left" : "right", .kind = "plate", .geometry = finger});
  }
  builder.addPlane(GroundPlane{});
  ContactSettings contact;
  contact.pairOverrides.push_back(ContactPairOverride{0, -1, kStiffness, 5.0, 0.5, 0.4});
  contact.pairOverrides.push_back(ContactPairOverride{0, 1, kStiffness, 5.0, 0.8, 0.7});
  contact.pairOverrides.push_back(ContactPairOverride{0, 2, kStiffness, 5.0, 0.8, 0.7});
  builder.setContactSettings(contact);
  build::BuiltModel built = std::move(builder).build();
  const Model& model = built.model;
  const ObjectInfo boxInfo = model.objects[0], left = model.objects[1], right = model.objects[2];
  World world(std::move(built.model), std::move(built.initial));
  const auto moveFinger = [&](const ObjectInfo& finger, const Vec3& velocity) {
    for (ParticleIndex i = finger.firstParticle; i < finger.firstParticle + finger.particleCount;
         ++i)
      world.setVelocity(i, velocity);
  };
  const auto boxCentre = [&] {
    Vec3 c;
    for (ParticleIndex i = boxInfo.firstParticle; i < boxInfo.firstParticle + boxInfo.particleCount;
         ++i)
      c += world.state().position[i] / static_cast<double>(boxInfo.particleCount);
    return c;
  };
  // The normal force finger object `finger` puts on the box (object 0) (N).
  const auto grip = [&](std::int32_t finger) {
    double force = 0.0;
    for (const Contact& c : world.contacts()) {
      const std::int32_t objectA = world.model().objectOf[c.a];
      const std::int32_t objectB = c.other >= 0 ? world.model().objectOf[c.other] : -1;
      if ((objectA == 0 && objectB == finger) || (objectB == 0 && objectA == finger))
        force += c.normalForce;
    }
    return force;
  };
  constexpr double kStep = 5.0e-5, kClose = 0.01;  // s, m/s
  // Settle on the ground, then close until each finger squeezes with kGrip.
  for (int step = 0; step < 1000; ++step) world.step(kStep);
  moveFinger(left, {kClose, 0.0, 0.0});
  moveFinger(right, {-kClose, 0.0, 0.0});
  bool leftDone = false, rightDone = false;
  for (int step = 0; step < 10'000 && !(leftDone && rightDone); ++step) {
    world.step(kStep);
    if (!leftDone && grip(1) >= kGrip) {
      moveFinger(left, {});
      leftDone = true;
    }
    if (!rightDone && grip(2) >= kGrip) {
      moveFinger(right, {});
      rightDone = true;
    }
  }
  ASSERT_TRUE(leftDone && rightDone);
  for (int step = 0; step < 1000; ++step) world.step(kStep);
  const Vec3 before = boxCentre();
  const double fingerBefore = world.state().position[left.firstParticle].z;
  // Lift 10 cm in 0.6 s (speeds up at 2 m/s² to 0.2 m/s, and slows down again
  // the same way), then hold for 0.3 s.
  constexpr double kSpeed = 0.2, kRamp = 0.1;  // m/s, s
  for (int step = 0; step < 12000; ++step) {
    const double t = (step + 0.5) * kStep;  // mid-step: the steps add up to 10 cm exactly
    const double speed = kSpeed * std::min({1.0, t / kRamp, (0.6 - t) / kRamp});
    moveFinger(left, {0.0, 0.0, speed});
    moveFinger(right, {0.0, 0.0, speed});
    world.step(kStep);
  }
  moveFinger(left, {});
  moveFinger(right, {});
  for (int step = 0; step < 6000; ++step) world.step(kStep);
  const Vec3 after = boxCentre();
  const double lift = world.state().position[left.firstParticle].z - fingerBefore;
  const double slip = lift - (after.z - before.z);
  const double drift = std::hypot(after.x - before.x, after.y - before.y);
  std::printf(
      "gripper: fingers lifted %.5f m, box %.5f m: slip %.3f mm, sideways drift %.4f mm; "
      "grip %.3f / %.3f N\n",
      lift, after.z - before.z, 1e3 * slip, 1e3 * drift, grip(1), grip(2));
  EXPECT_NEAR(lift, 0.1, 1e-6);
  EXPECT_LT(std::abs(slip), 2.0e-3);
  EXPECT_LT(drift, 1.0e-3);
}

}  // namespace
}  // namespace robophi
