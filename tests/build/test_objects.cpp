// Object generators: mass, centre of mass and size are respected, every
// particle is tied, the object starts at rest, lattices are rigid.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "robophi/build/objects.h"

namespace robophi::build {
namespace {

double totalMass(const GeneratedObject& o) {
  return std::accumulate(o.mass.begin(), o.mass.end(), 0.0);
}

Vec3 centreOfMass(const GeneratedObject& o) {
  Vec3 sum;
  for (std::size_t i = 0; i < o.size(); ++i) sum += o.position[i] * o.mass[i];
  return sum / totalMass(o);
}

// Extent of the particle spheres along each axis (m).
Vec3 sphereExtent(const GeneratedObject& o) {
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (std::size_t i = 0; i < o.size(); ++i) {
    const Vec3& p = o.position[i];
    const double r = o.radius[i];
    lo = {std::min(lo.x, p.x - r), std::min(lo.y, p.y - r), std::min(lo.z, p.z - r)};
    hi = {std::max(hi.x, p.x + r), std::max(hi.y, p.y + r), std::max(hi.z, p.z + r)};
  }
  return hi - lo;
}

// Every particle reachable from particle 0 through LS: nothing floats free.
bool allTied(const GeneratedObject& o) {
  std::vector<int> parent(o.size());
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&](int i) {
    while (parent[static_cast<std::size_t>(i)] != i) i = parent[static_cast<std::size_t>(i)];
    return i;
  };
  for (const auto& s : o.linearSprings) parent[static_cast<std::size_t>(find(s.a))] = find(s.b);
  const int root = find(0);
  for (std::size_t i = 0; i < o.size(); ++i)
    if (find(static_cast<int>(i)) != root) return false;
  return true;
}

// Zero spring energy at the start: rest values equal the initial geometry.
void expectAtRest(const GeneratedObject& o) {
  for (const auto& s : o.linearSprings) {
    EXPECT_GT(s.restLength, 0.0);
    EXPECT_NEAR(s.restLength, norm(o.position[s.a] - o.position[s.b]), 1e-12);
  }
  for (const auto& s : o.torsionSprings) {
    const Vec3 u = o.position[s.a] - o.position[s.c], w = o.position[s.b] - o.position[s.c];
    EXPECT_NEAR(s.restAngle, std::atan2(norm(cross(u, w)), dot(u, w)), 1e-9);
  }
}

void expectEqualMasses(const GeneratedObject& o) {
  for (const double m : o.mass) EXPECT_DOUBLE_EQ(m, o.mass[0]);
}

void expectNear(const Vec3& a, const Vec3& b, double tolerance) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

// Rank of the LS rigidity matrix (one row per LS: (p_a - p_b) at a, (p_b - p_a) at b).
// 3n - 6 means the LS alone hold the object rigid in 3-D.
int rigidityRank(const GeneratedObject& o) {
  const std::size_t cols = 3 * o.size();
  std::vector<std::vector<double>> rows;
  for (const auto& s : o.linearSprings) {
    std::vector<double> row(cols, 0.0);
    const Vec3 d = o.position[s.a] - o.position[s.b];
    for (int k = 0; k < 3; ++k) {
      row[3 * static_cast<std::size_t>(s.a) + static_cast<std::size_t>(k)] = d[k];
      row[3 * static_cast<std::size_t>(s.b) + static_cast<std::size_t>(k)] = -d[k];
    }
    rows.push_back(row);
  }
  int rank = 0;
  for (std::size_t c = 0; c < cols && static_cast<std::size_t>(rank) < rows.size(); ++c) {
    std::size_t pivot = static_cast<std::size_t>(rank);
    for (std::size_t r = pivot; r < rows.size(); ++r)
      if (std::fabs(rows[r][c]) > std::fabs(rows[pivot][c])) pivot = r;
    if (std::fabs(rows[pivot][c]) < 1e-9) continue;
    std::swap(rows[pivot], rows[static_cast<std::size_t>(rank)]);
    const auto& top = rows[static_cast<std::size_t>(rank)];
    for (std::size_t r = static_cast<std::size_t>(rank) + 1; r < rows.size(); ++r) {
      const double f = rows[r][c] / top[c];
      for (std::size_t k = c; k < cols; ++k) rows[r][k] -= f * top[k];
    }
    ++rank;
  }
  return rank;
}

TEST(GeneratorRope, MassCentreLengthAndLinks) {
  GeneratedObject rope = makeRope({{0, 0, 1}, {2, 0, 1}, 21, 0.5, 0.0});
  resolveSprings(rope, {});
  ASSERT_EQ(rope.size(), 21u);
  EXPECT_NEAR(totalMass(rope), 0.5, 1e-12);
  expectEqualMasses(rope);
  expectNear(centreOfMass(rope), {1, 0, 1}, 1e-12);
  expectNear(rope.position.front(), {0, 0, 1}, 0.0);
  expectNear(rope.position.back(), {2, 0, 1}, 1e-15);
  EXPECT_DOUBLE_EQ(rope.radius[0], 0.05);  // half the spacing
  EXPECT_EQ(rope.linearSprings.size(), 20u);
  EXPECT_TRUE(rope.torsionSprings.empty());  // no bend stiffness by default
  EXPECT_TRUE(allTied(rope));
  expectAtRest(rope);
  EXPECT_GT(rope.linearSprings[0].stiffness, 0.0);
  EXPECT_GT(rope.linearSprings[0].damping, 0.0);
}

TEST(GeneratorRope, BendStiffnessAddsStraightTorsionSprings) {
  GeneratedObject rope = makeRope({{0, 0, 0}, {0, 0, 1}, 5, 1.0, 0.01});
  SpringSettings springs;
  springs.stiffness = 100.0;
  springs.damping = 0.5;
  springs.bendStiffness = 2.0;
  resolveSprings(rope, springs);
  ASSERT_EQ(rope.torsionSprings.size(), 3u);
  for (const auto& s : rope.torsionSprings) {
    EXPECT_NEAR(s.restAngle, M_PI, 1e-12);
    EXPECT_DOUBLE_EQ(s.stiffness, 2.0);
  }
  EXPECT_DOUBLE_EQ(rope.linearSprings[0].stiffness, 100.0);
  EXPECT_DOUBLE_EQ(rope.linearSprings[0].damping, 0.5);
  EXPECT_DOUBLE_EQ(rope.radius[0], 0.01);
  expectAtRest(rope);
}

TEST(GeneratorBox, MassCentreSizeAndRigidity) {
  const BoxSpec spec{{1, 2, 3}, {0.4, 0.2, 0.2}, {4, 2, 2}, 3.0, 0.0};
  GeneratedObject box = makeBox(spec);
  resolveSprings(box, {});
  ASSERT_EQ(box.size(), 16u);
  EXPECT_NEAR(totalMass(box), 3.0, 1e-12);
  expectEqualMasses(box);
  expectNear(centreOfMass(box), spec.center, 1e-12);
  // Cubic cells of 0.1 m: spheres of radius 0.05 tile the size exactly.
  expectNear(sphereExtent(box), spec.size, 1e-12);
  EXPECT_TRUE(allTied(box));
  expectAtRest(box);
  EXPECT_EQ(rigidityRank(box), 3 * 16 - 6);
}

TEST(GeneratorBox, OneCellThickBarIsRigidWithBendSprings) {
  GeneratedObject bar = makeBox({{0, 0, 0}, {1.0, 0.1, 0.1}, {10, 1, 1}, 1.0, 0.0});
  SpringSettings springs;
  springs.bendStiffness = 5.0;
  resolveSprings(bar, springs);
  EXPECT_EQ(bar.linearSprings.size(), 9u);
  EXPECT_EQ(bar.torsionSprings.size(), 8u);  // a line: TS hold it straight
  expectNear(sphereExtent(bar), {1.0, 0.1, 0.1}, 1e-12);
  EXPECT_TRUE(allTied(bar));
  expectAtRest(bar);
  // Two cells across: the LS alone are rigid.
  GeneratedObject thick = makeBox({{0, 0, 0}, {1.0, 0.2, 0.2}, {10, 2, 2}, 1.0, 0.0});
  EXPECT_EQ(rigidityRank(thick), 3 * 40 - 6);
}

TEST(GeneratorBox, RotationKeepsCentreAndRestState) {
  GeneratedObject box = makeBox({{1, 1, 1}, {0.3, 0.2, 0.1}, {3, 2, 1}, 1.0, 0.0});
  rotateObject(box, {1, 1, 1}, {0, 0, 1}, M_PI / 2);
  expectNear(centreOfMass(box), {1, 1, 1}, 1e-12);
  expectNear(sphereExtent(box), {0.2, 0.3, 0.1}, 1e-12);
  expectAtRest(box);
}

TEST(GeneratorPlate, MassCentreSizeAndBending) {
  const PlateSpec spec{{0, 0, 1}, 1.0, 0.5, 0.0, {10, 5}, 0.2, 0.0};
  GeneratedObject plate = makePlate(spec);
  resolveSprings(plate, {}, 0.1);
  ASSERT_EQ(plate.size(), 50u);
  EXPECT_NEAR(totalMass(plate), 0.2, 1e-12);
  expectEqualMasses(plate);
  expectNear(centreOfMass(plate), spec.center, 1e-12);
  const Vec3 extent = sphereExtent(plate);
  EXPECT_NEAR(extent.x, 1.0, 1e-12);
  EXPECT_NEAR(extent.y, 0.5, 1e-12);
  for (const auto& p : plate.position) EXPECT_DOUBLE_EQ(p.z, 1.0);  // one layer
  // Structural (9·5 + 10·4) and shear (2·9·4) links.
  EXPECT_EQ(plate.linearSprings.size(), 45u + 40u + 72u);
  // Bending TS along both lines: 8·5 + 10·3.
  EXPECT_EQ(plate.torsionSprings.size(), 70u);
  EXPECT_GT(plate.torsionSprings[0].stiffness, 0.0);
  EXPECT_TRUE(allTied(plate));
  expectAtRest(plate);
}

TEST(GeneratorBall, SingleParticleHasTheBallsRadius) {
  const GeneratedObject ball = makeBall({{0, 0, 2}, 0.3, 1, 4.0, 0.0});
  ASSERT_EQ(ball.size(), 1u);
  EXPECT_DOUBLE_EQ(ball.radius[0], 0.3);
  EXPECT_DOUBLE_EQ(ball.mass[0], 4.0);
  expectNear(ball.position[0], {0, 0, 2}, 0.0);
  EXPECT_TRUE(ball.rims.empty());  // one particle: it spins, no round body needed
}

TEST(GeneratorBall, LatticeBallMassCentreAndSize) {
  GeneratedObject ball = makeBall({{1, 0, 0}, 0.5, 6, 2.0, 0.0});
  resolveSprings(ball, {});
  EXPECT_NEAR(totalMass(ball), 2.0, 1e-12);
  expectEqualMasses(ball);
  expectNear(centreOfMass(ball), {1, 0, 0}, 1e-12);
  const Vec3 extent = sphereExtent(ball);
  EXPECT_LE(extent.x, 1.0 + 1e-12);  // within the diameter
  EXPECT_GE(extent.x, 1.0 - 2.0 / 6.0);
  for (const auto& p : ball.position) EXPECT_LE(norm(p - Vec3{1, 0, 0}), 0.5 + 1e-12);
  EXPECT_TRUE(allTied(ball));
  expectAtRest(ball);
  EXPECT_EQ(rigidityRank(ball), 3 * static_cast<int>(ball.size()) - 6);
  // A round body: every particle, a sphere of the ball's radius (docs/contact.md).
  ASSERT_EQ(ball.rims.size(), 1u);
  EXPECT_EQ(ball.rims[0].first, 0);
  EXPECT_EQ(ball.rims[0].count, static_cast<std::int32_t>(ball.size()));
  EXPECT_EQ(ball.rims[0].hub, kNoParticle);
  EXPECT_DOUBLE_EQ(ball.rims[0].sphereRadius, 0.5);
  EXPECT_TRUE(makeBall({{1, 0, 0}, 0.5, 6, 2.0, 0.0, false}).rims.empty());
}

TEST(GeneratorWheel, MassCentreSizeAndRigidity) {
  const WheelSpec spec{{0, 0, 0.3}, 0.3, 0.08, {0, 1, 0}, 12, 1.5};
  GeneratedObject wheel = makeWheel(spec);
  resolveSprings(wheel, {});
  ASSERT_EQ(wheel.size(), 26u);
  EXPECT_NEAR(totalMass(wheel), 1.5, 1e-12);
  expectEqualMasses(wheel);
  expectNear(centreOfMass(wheel), spec.center, 1e-12);
  const Vec3 extent = sphereExtent(wheel);
  EXPECT_NEAR(extent.y, 0.08, 1e-12);  // width
  EXPECT_LE(extent.x, 0.6 + 1e-12);    // diameter
  EXPECT_GE(extent.x, 0.6 * std::cos(M_PI / 12) - 1e-12);
  for (std::size_t i = 0; i < 24; ++i) {
    const Vec3 d = wheel.position[i] - spec.center;
    EXPECT_NEAR(std::hypot(d.x, d.z) + wheel.radius[i], 0.3, 1e-12);  // rim reaches the radius
  }
  EXPECT_TRUE(allTied(wheel));
  expectAtRest(wheel);
  EXPECT_EQ(rigidityRank(wheel), 3 * 26 - 6);
}

TEST(GeneratorDefaults, StiffnessGivesTheFastestModeItsNaturalFrequency) {
  GeneratedObject box = makeBox({{0, 0, 0}, {0.3, 0.3, 0.3}, {3, 3, 3}, 1.0, 0.0});
  const double omega = kDefaultNaturalFrequency;
  const double k = defaultStiffness(box, omega);
  EXPECT_GT(k, 0.0);
  // Gershgorin bound at the centre particle (26 neighbours, equal masses).
  const double m = box.mass[0];
  const double omegaBound = std::sqrt(26.0 * k * 2.0 / m);
  EXPECT_NEAR(omegaBound / omega, 1.0, 1e-12);
  // The old rule ω·δ = 0.25 at the default step δ = 1e-4 s, bit for bit.
  EXPECT_EQ(kDefaultNaturalFrequency, 0.25 / 1e-4);
  // A higher frequency is a stiffer object: κ ∝ ω².
  EXPECT_NEAR(defaultStiffness(box, 2.0 * omega) / k, 4.0, 1e-12);
  // resolveSprings uses the settings' frequency when no stiffness is given.
  SpringSettings settings;
  settings.naturalFrequency = 2.0 * omega;
  resolveSprings(box, settings);
  EXPECT_DOUBLE_EQ(box.linearSprings[0].stiffness, defaultStiffness(box, 2.0 * omega));
}

}  // namespace
}  // namespace robophi::build
