// Edges (MODEL §3.8 "Edges"): the edge pairs of two faceted bodies' surface
// meshes that touch, found behind the sphere trees as the vertices' contacts
// with triangles are (facets.cpp), and turned into facet contacts.
#include "collision/edges.h"

#include "collision/facets.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

namespace robophi {

namespace {

// An edge of a face pair bent by less than this (sin of the angle between the
// faces' normals, ~5.7°) is flat: a triangulation's diagonal, not a ridge.
constexpr double kFlatEdge = 0.1;
// Two edges in line: cos² of the angle between them above this (~2.6°).
constexpr double kInLine = 0.998;

// Whether unit n lies inside the cone of the unit normals c1, c2 by kEdgeConeMargin.
bool insideCone(const Vec3& n, const Vec3& c1, const Vec3& c2) {
  Vec3 axis = cross(c1, c2);
  const double bend = norm(axis);
  if (!(bend > kFlatEdge)) return false;
  axis = axis / bend;
  return dot(cross(c1, n), axis) > kEdgeConeMargin && dot(cross(n, c2), axis) > kEdgeConeMargin;
}

// An edge as the detection sees it: its ends and its faces' outward normals,
// and whether it is a convex ridge (updateEdgeShapes).
struct EdgeShape {
  Vec3 x0, x1, n1, n2;
  bool ridge = false;
};

EdgeShape edgeShape(const ContactScratch& cache, std::int32_t e) {
  const ContactTables::SurfaceEdge& edge = cache.tables->edges[static_cast<std::size_t>(e)];
  return {cache.vertexPosition[static_cast<std::size_t>(edge.vertex[0])],
          cache.vertexPosition[static_cast<std::size_t>(edge.vertex[1])],
          cache.triangleNormal[static_cast<std::size_t>(edge.triangle[0])],
          cache.triangleNormal[static_cast<std::size_t>(edge.triangle[1])],
          cache.edgeRidge[static_cast<std::size_t>(e)] != 0};
}

// A bounding sphere of an edge: its midpoint and half its length.
inline bool spheresMeet(const EdgeShape& p, const EdgeShape& q, double radius) {
  const double reach = 0.5 * (norm(p.x1 - p.x0) + norm(q.x1 - q.x0)) + radius;
  return squaredNorm((p.x0 + p.x1) * 0.5 - (q.x0 + q.x1) * 0.5) < reach * reach;
}

// Whether an edge contact from v0 to v1 on the body of particle `other` goes
// on from last time: that edge's, or its neighbour's along the ridge (sharing
// an end and in line: the crossing passed from one edge of the ridge to the
// next; not a ridge across a corner, which would start deep).
bool goesOn(const ContactScratch& cache, std::int32_t v0, std::int32_t v1, std::int32_t other) {
  const auto& history = cache.edgeHistory;
  const auto at = [&](std::int32_t v) -> const Vec3& {
    return cache.vertexPosition[static_cast<std::size_t>(v)];
  };
  const Vec3 along = at(v1) - at(v0);
  for (const std::int32_t end : {v0, v1}) {
    const std::array<std::int32_t, 3> low{end, other, -1};
    for (auto it = std::lower_bound(history.begin(), history.end(), low);
         it != history.end() && (*it)[0] == end && (*it)[1] == other; ++it) {
      const std::int32_t far = (*it)[2];
      if (far == v0 || far == v1) return true;  // the same edge
      const Vec3 before = at(end) - at(far);
      const double c = dot(before, along);
      if (c * c > kInLine * squaredNorm(before) * squaredNorm(along)) return true;
    }
  }
  return false;
}

// How fast (m/s) the point s of edge `mine` and the point t of edge `theirs`
// approach along `normal` (from theirs to mine).
double closingSpeed(const Model& model, const std::vector<Vec3>& velocity,
                    const ContactTables::SurfaceEdge& mine,
                    const ContactTables::SurfaceEdge& theirs, double s, double t,
                    const Vec3& normal) {
  const auto rate = [&](std::int32_t v) { return surfaceVertexPoint(model, v, velocity); };
  const Vec3 a = rate(mine.vertex[0]) * (1.0 - s) + rate(mine.vertex[1]) * s;
  const Vec3 b = rate(theirs.vertex[0]) * (1.0 - t) + rate(theirs.vertex[1]) * t;
  return -dot(a - b, normal);
}

// The time (s) to close `distance` (m) from the closing speed v (m/s) under an
// acceleration up to a (m/s²): v t + a t²/2 = distance.
double closingTime(double distance, double v, double a) {
  if (a > 0.0) return 2.0 * distance / (v + std::sqrt(v * v + 2.0 * a * distance));
  return v > 0.0 ? distance / v : std::numeric_limits<double>::infinity();
}

}  // namespace

bool edgePair(const Vec3& x0, const Vec3& x1, const Vec3& a1, const Vec3& a2, const Vec3& y0,
              const Vec3& y1, const Vec3& b1, const Vec3& b2, double radius, EdgeHit& out) {
  const Vec3 dA = x1 - x0, dB = y1 - y0;
  const double a = dot(dA, dA), e = dot(dB, dB), b = dot(dA, dB);
  const double denominator = a * e - b * b;         // |dA × dB|²
  if (!(denominator > 1e-6 * a * e)) return false;  // parallel within 0.06°
  Vec3 n = cross(dA, dB) / std::sqrt(denominator);
  if (dot(n, b1 + b2) < 0.0) n = n * -1.0;
  if (!insideCone(n, b1, b2) || !insideCone(n * -1.0, a1, a2)) return false;
  const Vec3 r = x0 - y0;
  const double c = dot(dA, r), f = dot(dB, r);
  const double s = (b * f - c * e) / denominator, t = (a * f - b * c) / denominator;
  if (!(s > 0.0 && s < 1.0 && t > 0.0 && t < 1.0)) return false;
  const double gap = dot((x0 + dA * s) - (y0 + dB * t), n) - radius;
  out = {s, t, gap, std::sqrt(std::min(a, e)), n};
  return true;
}

bool edgesTouch(const Vec3& x0, const Vec3& x1, const Vec3& a1, const Vec3& a2, const Vec3& y0,
                const Vec3& y1, const Vec3& b1, const Vec3& b2, double radius, EdgeHit& out) {
  return edgePair(x0, x1, a1, a2, y0, y1, b1, b2, radius, out) && out.depth < 0.0 &&
         -out.depth < 0.5 * out.shorter;
}

void updateEdgeShapes(ContactScratch& cache) {
  const std::vector<ContactTables::SurfaceEdge>& edges = cache.tables->edges;
  const auto at = [&](std::int32_t v) -> const Vec3& {
    return cache.vertexPosition[static_cast<std::size_t>(v)];
  };
  // (The triangles' normals: updateSurfacePositions, once a triangle.)
  cache.edgeRidge.resize(edges.size());
  for (std::size_t k = 0; k < edges.size(); ++k) {
    const ContactTables::SurfaceEdge& edge = edges[k];
    const Vec3& n1 = cache.triangleNormal[static_cast<std::size_t>(edge.triangle[0])];
    const Vec3& n2 = cache.triangleNormal[static_cast<std::size_t>(edge.triangle[1])];
    const Vec3& x0 = at(edge.vertex[0]);
    cache.edgeRidge[k] = norm(cross(n1, n2)) > kFlatEdge &&
                         dot(n1, at(edge.opposite[1]) - x0) < 0.0 &&
                         dot(n2, at(edge.opposite[0]) - x0) < 0.0;
  }
}

void leafEdgesOnLeafEdges(const Model& model, ContactScratch& cache, const TreeNode& a,
                          const TreeNode& b) {
  const ContactTables& tables = *cache.tables;
  const TreeNode& low = a.object < b.object ? a : b;
  const TreeNode& high = a.object < b.object ? b : a;
  if (tables.objectFixed[low.object] != 0 && tables.objectFixed[high.object] != 0) return;
  const double radius = model.objects[static_cast<std::size_t>(low.object)].surfaceRadius +
                        model.objects[static_cast<std::size_t>(high.object)].surfaceRadius;
  // Each leaf's ridges whose bounding sphere reaches the other leaf's sphere.
  const auto ridgesNear = [&](const TreeNode& leaf, const TreeNode& other,
                              std::vector<std::int32_t>& out) {
    out.clear();
    const double reach = outerRadius(cache, other) + radius;
    for (std::int32_t p = leaf.first; p < leaf.first + leaf.count; ++p) {
      const std::int32_t i = cache.treeParticles[p];
      for (std::int32_t k = tables.ownedEdgeStart[i]; k < tables.ownedEdgeStart[i + 1]; ++k) {
        const std::int32_t e = tables.ownedEdge[k];
        if (cache.edgeRidge[static_cast<std::size_t>(e)] == 0) continue;  // (most are flat)
        const EdgeShape shape = edgeShape(cache, e);
        const double r = reach + 0.5 * norm(shape.x1 - shape.x0);
        if (squaredNorm((shape.x0 + shape.x1) * 0.5 - other.center) < r * r) out.push_back(e);
      }
    }
  };
  ridgesNear(low, high, cache.lowRidges);
  if (cache.lowRidges.empty()) return;
  ridgesNear(high, low, cache.highRidges);
  for (const std::int32_t e : cache.lowRidges) {
    const EdgeShape p = edgeShape(cache, e);
    for (const std::int32_t f : cache.highRidges) {
      const EdgeShape q = edgeShape(cache, f);
      if (!spheresMeet(p, q, radius)) continue;
      ++cache.stats.facetTests;
      EdgeHit hit;
      // (Pairs still apart too: their approach bounds the step, edgeApproachStep.)
      if (edgePair(p.x0, p.x1, p.n1, p.n2, q.x0, q.x1, q.n1, q.n2, radius, hit) &&
          -hit.depth < 0.5 * hit.shorter)
        cache.edgeCandidates.push_back(
            {e, high.object, f, hit.s, hit.t, hit.depth, hit.shorter, hit.normal});
    }
  }
}

void resolveEdgeCandidates(const Model& model, const std::vector<Vec3>& velocity,
                           const std::vector<Contact>& previous, ContactScratch& cache) {
  auto& candidates = cache.edgeCandidates;
  cache.edgeApproachStep = std::numeric_limits<double>::infinity();
  if (candidates.empty()) return;
  // (Twice gravity: a symplectic Euler step, as a rigid tree's, moves v dt + a
  // dt², not v dt + a dt²/2; with g alone, a cube bouncing on a ridge closed
  // 0.54 mm past the bound in its step back down and fell to its vertices.)
  const double gravity = 2.0 * norm(model.gravity);
  const ContactTables& tables = *cache.tables;
  // The surface vertices of the edge contacts that touched last time, with the
  // body they touched and the edge's other end: (vertex, other, far end), sorted.
  auto& history = cache.edgeHistory;
  history.clear();
  for (const Contact& c : previous) {
    if (c.edgeVertex < 0) continue;
    history.push_back({c.vertex, c.other, c.edgeVertex});
    history.push_back({c.edgeVertex, c.other, c.vertex});
  }
  std::sort(history.begin(), history.end());
  using Candidate = ContactScratch::EdgeCandidate;
  // (The shallowest first: depth descending.)
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& x, const Candidate& y) {
    return std::tie(x.edge, x.object, y.depth, x.otherEdge) <
           std::tie(y.edge, y.object, x.depth, y.otherEdge);
  });
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    const Candidate& hit = candidates[k];
    if (!(hit.depth < 0.0)) {  // apart: how long until it may close past the onset
      const double closing = closingSpeed(
          model, velocity, tables.edges[static_cast<std::size_t>(hit.edge)],
          tables.edges[static_cast<std::size_t>(hit.otherEdge)], hit.s, hit.t, hit.normal);
      cache.edgeApproachStep =
          std::min(cache.edgeApproachStep,
                   closingTime(hit.depth + 0.5 * kEdgeOnset * hit.shorter, closing, gravity));
      continue;
    }
    if (k > 0 && candidates[k].edge == candidates[k - 1].edge &&
        candidates[k].object == candidates[k - 1].object && candidates[k - 1].depth < 0.0)
      continue;  // (the shallowest touching came first)
    const ContactTables::SurfaceEdge& mine = tables.edges[static_cast<std::size_t>(hit.edge)];
    const ContactTables::SurfaceEdge& theirs =
        tables.edges[static_cast<std::size_t>(hit.otherEdge)];
    Contact c;
    c.a = tables.vertexOwner[static_cast<std::size_t>(mine.vertex[0])];
    c.other = model.objects[static_cast<std::size_t>(hit.object)].firstParticle;
    c.vertex = mine.vertex[0];
    c.edgeVertex = mine.vertex[1];
    c.edgeWeight = hit.s;
    c.facet = theirs.triangle[0];
    const SurfaceTriangle& t = model.surfaceTriangles[static_cast<std::size_t>(c.facet)];
    double beta[3] = {0.0, 0.0, 0.0};
    for (int j = 0; j < 3; ++j) {
      if (t.vertex[static_cast<std::size_t>(j)] == theirs.vertex[0]) beta[j] = 1.0 - hit.t;
      if (t.vertex[static_cast<std::size_t>(j)] == theirs.vertex[1]) beta[j] = hit.t;
    }
    c.facetWeights = {beta[0], beta[1], beta[2]};
    c.depth = hit.depth;
    c.normal = hit.normal;
    if (-hit.depth > kEdgeOnset * hit.shorter && !goesOn(cache, c.vertex, c.edgeVertex, c.other))
      continue;  // (it would start deep)
    cache.treeContacts.push_back(c);
  }
}

}  // namespace robophi
