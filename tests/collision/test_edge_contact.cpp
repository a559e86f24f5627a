// Edge contacts between faceted bodies (MODEL §3.8 "Edges", docs/contact.md
// "Edges", collision/edges.h): two cubes resting on crossed ridges touch where
// no vertex of either is inside the other, so before the edges touched they
// passed through each other until a vertex met a face (16.8 mm for a 1 kg
// cube on a fixed one at κ_c 1e5; the issue's pair sank 22 mm).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "collision/edges.h"
#include "collision/facets.h"
#include "collision/scene_world.h"

namespace robophi {
namespace {

constexpr double kHalfDiagonal = 0.0707106781186548;  // of a 0.1 m cube's face

// A fixed 0.1 m cube (3 cells) turned 45° about x, its top a ridge along x at
// z = 2 h (h the face's half diagonal), and a 1 kg cube (`top` keys) turned 45°
// about y (and `yaw` about z), its lowest ridge `gap` above the first.
std::string crossedCubes(const std::string& top, double yaw, double gap, double stiffness = 1e5) {
  char text[2048];
  std::snprintf(text, sizeof text, R"({
    "robophi": 1, "name": "crossed edges", "gravity": [0, 0, -9.81],
    "materials": [{"name": "m", "contactStiffness": %.17g, "contactDamping": %.17g,
                   "staticFriction": 0.5, "kineticFriction": 0.3}],
    "objects": [
      {"name": "low", "type": "cube", "center": [0, 0, %.17g], "size": 0.1, "cells": 3,
       "mass": 1, "material": "m", "fixed": true, "rpy": [0.7853981633974483, 0, 0]},
      {"name": "top", "type": "cube", "center": [0, 0, %.17g], "size": 0.1, "cells": 3,
       "mass": 1, "material": "m", "rpy": [0, 0.7853981633974483, %.17g] %s}]
  })",
                stiffness, 60.0 * std::sqrt(stiffness / 1e5), kHalfDiagonal,
                3.0 * kHalfDiagonal + gap, yaw, top.c_str());
  return text;
}

// The deepest edge contact (m, > 0 inside) and how many there are.
std::pair<double, int> edgeContacts(const World& world) {
  double deepest = 0.0;
  int count = 0;
  for (const Contact& c : world.contacts()) {
    if (c.edgeVertex < 0) continue;
    ++count;
    deepest = std::max(deepest, -c.depth);
  }
  return {deepest, count};
}

TEST(EdgeContact, CrossedEdgesTouchAtTheirClosestPointsAlongTheirCommonNormal) {
  const double s = std::sqrt(0.5);
  // Edge A along y, 2 mm below edge B along x; A's faces face down, B's up.
  const Vec3 a1{s, 0, -s}, a2{-s, 0, -s}, b1{0, s, s}, b2{0, -s, s};
  EdgeHit hit;
  ASSERT_TRUE(edgesTouch({0.01, -0.05, -0.002}, {0.01, 0.05, -0.002}, a1, a2, {-0.05, 0, 0},
                         {0.05, 0, 0}, b1, b2, 0.0, hit));
  EXPECT_NEAR(hit.depth, -0.002, 1e-15);
  EXPECT_NEAR(hit.s, 0.5, 1e-15);
  EXPECT_NEAR(hit.t, 0.6, 1e-15);
  EXPECT_NEAR(hit.normal.z, 1.0, 1e-15);
  // Apart: no contact; a sheet's half thickness counts.
  EXPECT_FALSE(edgesTouch({0, -0.05, 0.001}, {0, 0.05, 0.001}, a1, a2, {-0.05, 0, 0}, {0.05, 0, 0},
                          b1, b2, 0.0, hit));
  EXPECT_TRUE(edgesTouch({0, -0.05, 0.001}, {0, 0.05, 0.001}, a1, a2, {-0.05, 0, 0}, {0.05, 0, 0},
                         b1, b2, 0.002, hit));
  EXPECT_NEAR(hit.depth, -0.001, 1e-15);
  // Closest points beyond an end: a vertex's contact, not the edges'.
  EXPECT_FALSE(edgesTouch({0.06, -0.05, -0.002}, {0.06, 0.05, -0.002}, a1, a2, {-0.05, 0, 0},
                          {0.05, 0, 0}, b1, b2, 0.0, hit));
  // Parallel edges, and an edge between two faces of one plane (a diagonal).
  EXPECT_FALSE(edgesTouch({-0.05, 0.0, -0.002}, {0.05, 0.0, -0.002}, a1, a2, {-0.05, 0, 0},
                          {0.05, 0, 0}, b1, b2, 0.0, hit));
  EXPECT_FALSE(edgesTouch({0, -0.05, -0.002}, {0, 0.05, -0.002}, a1, a2, {-0.05, 0, 0},
                          {0.05, 0, 0}, {0, 0, 1}, {0, 0, 1}, 0.0, hit));
  // An edge of a face lying flat on the other body's face pair (the normal
  // on the border of its cone): not an edge contact (the face's vertices touch).
  EXPECT_FALSE(edgesTouch({0, -0.05, -0.002}, {0, 0.05, -0.002}, {0, 0, -1}, {-1, 0, 0},
                          {-0.05, 0, 0}, {0.05, 0, 0}, b1, b2, 0.0, hit));
}

TEST(EdgeContact, ACubeOnACrossedRidgeRestsOnItsEdgeNotInside) {
  for (const double yaw : {0.0, 0.5}) {
    World world = test::sceneWorld(crossedCubes(R"(, "rigid": true)", yaw, 0.002));
    test::advance(world, 0.8, 1e-4);
    const auto [deepest, count] = edgeContacts(world);
    // Its centre 3 h above the ground when the ridges just touch.
    const double sink = 3.0 * kHalfDiagonal - test::centerOfMass(world, 1).z;
    std::printf(
        "rigid cube on a crossed ridge (yaw %.1f): sinks %.3f mm, deepest edge contact "
        "%.3f mm, %d edge contacts of %zu\n",
        yaw, 1e3 * sink, 1e3 * deepest, count, world.contacts().size());
    EXPECT_EQ(count, 1);
    EXPECT_LT(std::abs(sink), 1e-3);
    EXPECT_LT(deepest, 1e-3);
    EXPECT_GT(deepest, 0.0);
    // Standing on the ridge (it tips later: the rest is unstable).
    const Vec3 at = test::centerOfMass(world, 1);
    EXPECT_LT(std::hypot(at.x, at.y), 1e-4);
  }
}

TEST(EdgeContact, ALatticeCubeOnACrossedRidgeAndAStifferContact) {
  World lattice = test::sceneWorld(crossedCubes("", 0.0, 0.002));
  test::advance(lattice, 1.5, 1e-4);
  const auto [deepLattice, countLattice] = edgeContacts(lattice);
  World stiff = test::sceneWorld(crossedCubes(R"(, "rigid": true)", 0.0, 0.002, 1e7));
  test::advance(stiff, 0.5, 1e-5);
  const auto [deepStiff, countStiff] = edgeContacts(stiff);
  std::printf(
      "crossed ridges: lattice cube's deepest edge contact %.3f mm (%d); rigid at "
      "kappa_c 1e7 %.4f mm (%d)\n",
      1e3 * deepLattice, countLattice, 1e3 * deepStiff, countStiff);
  EXPECT_GE(countLattice, 1);
  EXPECT_LT(deepLattice, 1e-3);
  EXPECT_EQ(countStiff, 1);
  EXPECT_LT(deepStiff, 2e-5);
}

TEST(EdgeContact, AnEdgeContactsForceSumsToZeroWithTheTorqueOfItsTwoPoints) {
  World world = test::sceneWorld(crossedCubes(R"(, "rigid": true)", 0.3, 0.0));
  test::advance(world, 0.05, 1e-4);
  const Model& model = world.model();
  const std::vector<Vec3>& p = world.state().position;
  const auto edge = std::find_if(world.contacts().begin(), world.contacts().end(),
                                 [](const Contact& c) { return c.edgeVertex >= 0; });
  ASSERT_NE(edge, world.contacts().end());
  const Vec3 onA{0.3, -0.2, 1.5};  // any force, friction's part too
  std::vector<Vec3> force(p.size());
  distributeFacetForce(model, *edge, onA, force);
  Vec3 net, torque;
  for (std::size_t i = 0; i < p.size(); ++i) {
    net += force[i];
    torque += cross(p[i], force[i]);
  }
  // The points: (1 - s) x_0 + s x_1 on the edge, Σ β_j x_j on the other's.
  const auto vertexAt = [&](std::int32_t v) {
    const SurfaceVertex& sv = model.surfaceVertices[static_cast<std::size_t>(v)];
    Vec3 x;
    for (int k = 0; k < SurfaceVertex::kMaxParticles; ++k)
      if (sv.particle[k] >= 0) x += p[static_cast<std::size_t>(sv.particle[k])] * sv.weight[k];
    return x;
  };
  const Vec3 pointA = vertexAt(edge->vertex) * (1.0 - edge->edgeWeight) +
                      vertexAt(edge->edgeVertex) * edge->edgeWeight;
  const SurfaceTriangle& t = model.surfaceTriangles[static_cast<std::size_t>(edge->facet)];
  const Vec3 pointB = vertexAt(t.vertex[0]) * edge->facetWeights.x +
                      vertexAt(t.vertex[1]) * edge->facetWeights.y +
                      vertexAt(t.vertex[2]) * edge->facetWeights.z;
  EXPECT_LT(norm(net), 1e-12);
  EXPECT_LT(norm(torque - cross(pointA - pointB, onA)), 1e-12);
  // The two points lie along the contact's normal, as far apart as its depth.
  EXPECT_NEAR(dot(pointA - pointB, edge->normal), edge->depth, 1e-12);
  EXPECT_LT(norm(cross(pointA - pointB, edge->normal)), 1e-9);
}

TEST(EdgeContact, OneStateHashAtAnyThreadCount) {
  std::uint64_t first = 0;
  for (const int threads : {1, 2, 4}) {
    World world = test::sceneWorld(crossedCubes("", 0.4, 0.0));
    world.setThreadCount(threads);
    test::advance(world, 0.2, 1e-4);
    ASSERT_GE(edgeContacts(world).second, 1);
    const std::uint64_t hash = stateHash(world.state());
    if (threads == 1) first = hash;
    EXPECT_EQ(hash, first) << threads << " threads";
  }
}

}  // namespace
}  // namespace robophi
