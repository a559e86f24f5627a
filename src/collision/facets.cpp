// Flat faces (MODEL §3.8): surface vertices embedded in the particles, the
// closest-triangle search behind the sphere trees, and the facet contacts'
// kinematics and force distribution.
#include "collision/facets.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "collision/edges.h"
#include "collision/environment.h"

namespace robophi {

namespace {

// x = Σ w_k p_k over a vertex's particles (also for velocities).
inline Vec3 embedded(const SurfaceVertex& v, const std::vector<Vec3>& p) {
  Vec3 x;
  for (int k = 0; k < SurfaceVertex::kMaxParticles; ++k) {
    if (v.particle[k] >= 0) x += p[v.particle[k]] * v.weight[k];
  }
  return x;
}

// The point of triangle (a, b, c) closest to p, as barycentric weights
// (Ericson, Real-Time Collision Detection §5.1.5).
Vec3 closestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {1.0, 0.0, 0.0};
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return {0.0, 1.0, 0.0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double t = d1 / (d1 - d3);
    return {1.0 - t, t, 0.0};
  }
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return {0.0, 0.0, 1.0};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double t = d2 / (d2 - d6);
    return {1.0 - t, 0.0, t};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0.0, 1.0 - t, t};
  }
  const double denominator = 1.0 / (va + vb + vc);
  const double v = vb * denominator, w = vc * denominator;
  return {1.0 - v - w, v, w};
}

// The touching side of a facet contact as surface vertices and weights: its
// vertex (weight 1), or the two ends of its edge (1 - s, s).
struct TouchingVertices {
  std::int32_t count = 0;
  std::int32_t vertex[2] = {-1, -1};
  double weight[2] = {0.0, 0.0};
};
inline TouchingVertices touchingVertices(const Contact& c) {
  if (c.edgeVertex < 0) return {1, {c.vertex, -1}, {1.0, 0.0}};
  return {2, {c.vertex, c.edgeVertex}, {1.0 - c.edgeWeight, c.edgeWeight}};
}

inline const SurfaceVertex& vertexOf(const Model& model, const SurfaceTriangle& t, int j) {
  return model.surfaceVertices[static_cast<std::size_t>(t.vertex[static_cast<std::size_t>(j)])];
}

inline double weightOf(const Vec3& beta, int j) {
  return j == 0 ? beta.x : j == 1 ? beta.y : beta.z;
}

// A triangle's point at barycentric weights beta, from vertex positions x(v).
template <typename VertexPoint>
inline Vec3 trianglePoint(const SurfaceTriangle& t, const Vec3& beta, VertexPoint x) {
  return x(t.vertex[0]) * beta.x + x(t.vertex[1]) * beta.y + x(t.vertex[2]) * beta.z;
}

// The point at s along a contact's touching edge, from the vertices' embeddings
// in `p` (positions or velocities).
inline Vec3 edgePoint(const Model& model, const Contact& c, double s, const std::vector<Vec3>& p) {
  return embedded(model.surfaceVertices[static_cast<std::size_t>(c.vertex)], p) * (1.0 - s) +
         embedded(model.surfaceVertices[static_cast<std::size_t>(c.edgeVertex)], p) * s;
}

void addTriangles(ContactScratch& cache, std::int32_t probe, std::int32_t object,
                  std::int32_t carrier) {
  const ContactTables& t = *cache.tables;
  for (std::int32_t k = t.ownedTriangleStart[carrier]; k < t.ownedTriangleStart[carrier + 1]; ++k)
    cache.facetCandidates.push_back({probe, object, t.ownedTriangle[k]});
}

}  // namespace

Vec3 surfaceVertexPoint(const Model& model, std::int32_t vertex, const std::vector<Vec3>& values) {
  return embedded(model.surfaceVertices[static_cast<std::size_t>(vertex)], values);
}

Vec3 touchingPoint(const Model& model, const Contact& c, const std::vector<Vec3>& values) {
  return c.edgeVertex < 0 ? surfaceVertexPoint(model, c.vertex, values)
                          : edgePoint(model, c, c.edgeWeight, values);
}

double facetTreeMargin(const Model& model, const std::vector<Vec3>& position,
                       const ContactTables& tables, const std::vector<std::int32_t>& members) {
  double margin = 0.0;
  double sheet = 0.0;
  for (const std::int32_t i : members) {
    const Vec3& p = position[i];
    for (std::int32_t k = tables.ownedVertexStart[i]; k < tables.ownedVertexStart[i + 1]; ++k) {
      const Vec3 x = embedded(model.surfaceVertices[tables.ownedVertex[k]], position);
      margin = std::max(margin, norm(x - p) - model.radius[i]);
    }
    for (std::int32_t k = tables.ownedTriangleStart[i]; k < tables.ownedTriangleStart[i + 1]; ++k) {
      const SurfaceTriangle& t = model.surfaceTriangles[tables.ownedTriangle[k]];
      sheet = std::max(sheet, model.objects[static_cast<std::size_t>(t.object)].surfaceRadius);
      for (int j = 0; j < 3; ++j) {
        const Vec3 x = embedded(vertexOf(model, t, j), position);
        margin = std::max(margin, norm(x - p) - model.radius[i]);
      }
    }
  }
  return 1.25 * (std::max(margin, 0.0) + sheet);
}

void updateSurfacePositions(const Model& model, const std::vector<Vec3>& position,
                            ContactScratch& cache) {
  cache.vertexPosition.resize(model.surfaceVertices.size());
  for (std::size_t v = 0; v < model.surfaceVertices.size(); ++v)
    cache.vertexPosition[v] = embedded(model.surfaceVertices[v], position);
  // Each faceted triangle's unit normal once (the closest-triangle search and
  // the edges read it; a box's 72 edges share its 48 triangles); zero for a
  // degenerate triangle.
  cache.triangleNormal.resize(model.surfaceTriangles.size());
  for (std::size_t t = 0; t < model.surfaceTriangles.size(); ++t) {
    const SurfaceTriangle& tri = model.surfaceTriangles[t];
    if (cache.tables->objectFaceted[static_cast<std::size_t>(tri.object)] == 0) continue;
    const Vec3& x0 = cache.vertexPosition[static_cast<std::size_t>(tri.vertex[0])];
    const Vec3 n = cross(cache.vertexPosition[static_cast<std::size_t>(tri.vertex[1])] - x0,
                         cache.vertexPosition[static_cast<std::size_t>(tri.vertex[2])] - x0);
    const double area = norm(n);
    cache.triangleNormal[t] = area > 0.0 ? n / area : Vec3{};
  }
}

void leavesWithFacets(const Model& model, const std::vector<Vec3>& position, ContactScratch& cache,
                      const TreeNode& a, const TreeNode& b) {
  const ContactTables& t = *cache.tables;
  const bool facetedA = a.object >= 0 && t.objectFaceted[a.object] != 0;
  const bool facetedB = b.object >= 0 && t.objectFaceted[b.object] != 0;
  // Probes of `from` against the triangles of `to` (faceted): only a probe whose
  // sphere reaches the leaf's sphere (which encloses the leaf's triangles).
  const auto reaches = [&](const Vec3& x, double r, const TreeNode& to) {
    const double reach = r + outerRadius(cache, to);
    return squaredNorm(x - to.center) < reach * reach;
  };
  const auto probe = [&](const TreeNode& from, bool fromFaceted, const TreeNode& to) {
    const double sheet =
        fromFaceted ? model.objects[static_cast<std::size_t>(from.object)].surfaceRadius : 0.0;
    for (std::int32_t p = from.first; p < from.first + from.count; ++p) {
      const std::int32_t i = cache.treeParticles[p];
      if (!fromFaceted) {
        if (!reaches(position[i], model.radius[i], to)) continue;
        for (std::int32_t q = to.first; q < to.first + to.count; ++q)
          addTriangles(cache, i, to.object, cache.treeParticles[q]);
        continue;
      }
      for (std::int32_t k = t.ownedVertexStart[i]; k < t.ownedVertexStart[i + 1]; ++k) {
        const std::int32_t v = t.ownedVertex[k];
        if (!reaches(cache.vertexPosition[v], sheet, to)) continue;
        for (std::int32_t q = to.first; q < to.first + to.count; ++q)
          addTriangles(cache, -1 - v, to.object, cache.treeParticles[q]);
      }
    }
  };
  if (facetedB) probe(a, facetedA, b);
  if (facetedA) probe(b, facetedB, a);
  if (facetedA && facetedB && !t.edges.empty()) leafEdgesOnLeafEdges(model, cache, a, b);
}

void particleOnLeafFacets(ContactScratch& cache, const TreeNode& leaf, std::int32_t particle) {
  // (The caller has tested the particle's sphere against the leaf's.)
  for (std::int32_t q = leaf.first; q < leaf.first + leaf.count; ++q)
    addTriangles(cache, particle, leaf.object, cache.treeParticles[q]);
}

void leafVerticesOnEnvironment(const Model& model, ContactScratch& cache, const TreeNode& leaf,
                               std::int32_t item) {
  const ContactTables& t = *cache.tables;
  const double radius = model.objects[static_cast<std::size_t>(leaf.object)].surfaceRadius;
  for (std::int32_t p = leaf.first; p < leaf.first + leaf.count; ++p) {
    const std::int32_t i = cache.treeParticles[p];
    for (std::int32_t k = t.ownedVertexStart[i]; k < t.ownedVertexStart[i + 1]; ++k) {
      const std::int32_t v = t.ownedVertex[k];
      ++cache.stats.environmentTests;
      Contact c;
      if (touchesEnvironment(model.environment, i, cache.vertexPosition[v], radius, item, c)) {
        c.vertex = v;
        cache.treeContacts.push_back(c);
      }
    }
  }
}

namespace {

// The closest of a probe's candidate triangles [begin, end) of one object:
// smallest |p - q|, the lowest index on a tie; its signed distance (m), normal
// and barycentric weights. `faceToFace`: whether the probe (a vertex) presses
// on it with a face of its own (FacesOfVertex).
struct ClosestFacet {
  std::int32_t triangle = -1;
  double distance = std::numeric_limits<double>::infinity();
  double signedDistance = 0.0;
  Vec3 beta, normal;
  bool faceToFace = false;
};

// A face of a vertex probe's own body and a face it is behind are face to face
// when their outward normals are opposed within about 25° (cos 25° ≈ 0.9): a
// box set on another, or tilted a little on it.
constexpr double kFaceToFace = 0.9;
// How deep behind the face it presses (as a fraction of its particle's radius:
// a resting contact's depth, the step's penetration bound) a vertex may be for
// that face to take it. The force is then the face's normal times the closest
// face's depth, which is not the gradient of that depth's energy: the work it
// does beyond that energy, as the vertex leaves, is at most κ h²/4 for a depth
// h behind the pressed face, so h is kept small; deeper (bodies set
// overlapping, a crushed body) the closest face takes it.
constexpr double kPressedDepth = 0.1;

// The outward normals of the triangles a vertex is a corner of, at this
// evaluation (the first kMax distinct ones: a box's corner has three, a
// smooth mesh's vertex a fan).
struct FacesOfVertex {
  static constexpr int kMax = 16;
  std::array<Vec3, kMax> normal;
  int count = 0;
  // Whether a face of normal n (unit, outward) is opposed to one of these.
  bool opposes(const Vec3& n) const {
    for (int k = 0; k < count; ++k)
      if (dot(normal[static_cast<std::size_t>(k)], n) < -kFaceToFace) return true;
    return false;
  }
};

// The distinct unit normals of a vertex's triangles (this evaluation's,
// ContactScratch::triangleNormal).
FacesOfVertex facesOfVertex(const ContactScratch& cache, std::int32_t vertex) {
  const ContactTables& t = *cache.tables;
  FacesOfVertex faces;
  const auto v = static_cast<std::size_t>(vertex);
  for (std::int32_t k = t.vertexTriangleStart[v]; k < t.vertexTriangleStart[v + 1]; ++k) {
    const Vec3& n = cache.triangleNormal[static_cast<std::size_t>(
        t.vertexTriangle[static_cast<std::size_t>(k)])];
    if (squaredNorm(n) == 0.0) continue;  // a degenerate triangle
    bool known = false;
    for (int j = 0; j < faces.count; ++j)
      known = known || dot(faces.normal[static_cast<std::size_t>(j)], n) > 1.0 - 1e-9;
    if (known) continue;
    faces.normal[static_cast<std::size_t>(faces.count++)] = n;
    if (faces.count == FacesOfVertex::kMax) break;
  }
  return faces;
}

// Candidate triangle `triangle` against the best so far (closest); and, for a
// vertex probe (`faces` not null) behind it over it, against the face to face
// triangle it is least behind (`pressed`: its signedDistance is the probe's
// height over that face's plane, negative; -inf while there is none).
void tryFacet(const Model& model, const ContactScratch& cache, const Vec3& p, double sheet,
              const FacesOfVertex* faces, std::int32_t triangle, ClosestFacet& closest,
              ClosestFacet& pressed) {
  const auto vertexAt = [&](std::int32_t v) -> const Vec3& {
    return cache.vertexPosition[static_cast<std::size_t>(v)];
  };
  const SurfaceTriangle& tri = model.surfaceTriangles[triangle];
  const Vec3 &x0 = vertexAt(tri.vertex[0]), &x1 = vertexAt(tri.vertex[1]),
             &x2 = vertexAt(tri.vertex[2]);
  const Vec3 beta = closestOnTriangle(p, x0, x1, x2);
  const Vec3 q = x0 * beta.x + x1 * beta.y + x2 * beta.z;
  const double distance = norm(p - q);
  const bool closer = distance < closest.distance;
  if (!closer && faces == nullptr) return;
  // This evaluation's unit normal (updateSurfacePositions); zero if degenerate.
  const Vec3& faceNormal = cache.triangleNormal[static_cast<std::size_t>(triangle)];
  if (squaredNorm(faceNormal) == 0.0) return;
  if (sheet > 0.0) {
    if (!closer) return;
    // A sheet is touched from either side at its half thickness.
    closest.distance = distance;
    closest.triangle = triangle;
    closest.beta = beta;
    closest.signedDistance = distance - sheet;
    closest.normal = distance > 0.0 ? (p - q) / distance : faceNormal;
    return;
  }
  // A closed surface: outside, the direction from the surface point; inside
  // (behind the face), the face's normal. Behind only over the face, where
  // the closest point is the foot on the face's plane: a point beside the
  // face and below its plane is outside (the candidates are the triangles
  // near the probe, not all of them: a particle just above a box's top,
  // whose top triangles were not candidates, counted as 2 cm inside it
  // by a side's triangle, whose closest point is on its edge).
  const double height = dot(p - x0, faceNormal);
  const bool outside = height >= 0.0 || distance * (1.0 - 1e-9) > -height;
  const bool faceToFace = !outside && faces != nullptr && faces->opposes(faceNormal);
  if (faceToFace && height > pressed.signedDistance) {
    pressed.triangle = triangle;
    pressed.signedDistance = height;
    pressed.beta = beta;
    pressed.normal = faceNormal;
  }
  if (!closer) return;
  closest.distance = distance;
  closest.triangle = triangle;
  closest.beta = beta;
  closest.signedDistance = outside ? distance : -distance;
  closest.normal = outside && distance > 0.0 ? (p - q) / distance : faceNormal;
  closest.faceToFace = faceToFace;
}

// One probe (a particle, or a vertex: probe < 0) against one faceted object's
// candidates [begin, end): its contact with the closest triangle, when it
// touches. MODEL §3.8 "Which face": a rigid body's vertex inside another rigid
// body's closed surface that is
// behind a face it is face to face with (a face of its own body opposed to it:
// a box's bottom corner on another box's top) and nearer another face (the
// side, where the boxes' sides are flush, or the corner has slid a fraction of
// a millimetre past the edge) pushes out through the face it presses with, at
// the closest face's depth: the face's normal and point, the depth that
// changes continuously as the corner crosses the edge.
void resolveProbe(const Model& model, const std::vector<Vec3>& position, ContactScratch& cache,
                  std::size_t begin, std::size_t end) {
  const auto& candidates = cache.facetCandidates;
  const ContactTables& t = *cache.tables;
  const std::int32_t probe = candidates[begin].probe, object = candidates[begin].object;
  const bool isVertex = probe < 0;
  const std::int32_t vertex = isVertex ? -1 - probe : -1;
  const std::int32_t probeObject =
      isVertex ? model.surfaceVertices[static_cast<std::size_t>(vertex)].object
               : t.particleObject[probe];
  const bool probeFixed = isVertex ? t.objectFixed[probeObject] != 0 : t.movable[probe] == 0;
  if (probeFixed && t.objectFixed[object] != 0) return;
  const Vec3 p =
      isVertex ? cache.vertexPosition[static_cast<std::size_t>(vertex)] : position[probe];
  const double probeRadius =
      isVertex ? model.objects[static_cast<std::size_t>(probeObject)].surfaceRadius
               : model.radius[probe];
  const double sheet = model.objects[static_cast<std::size_t>(object)].surfaceRadius;
  FacesOfVertex faces;
  // Faces that keep their shape: two rigid bodies (a lattice's faces bend and
  // ring under load, and the rule's work beyond the energy pumped a stack of
  // lattice boxes: docs/contact.md "Stacks").
  const bool pressing = isVertex && sheet <= 0.0 && probeObject != object &&
                        model.objects[static_cast<std::size_t>(probeObject)].rigid &&
                        model.objects[static_cast<std::size_t>(object)].rigid;
  if (pressing) faces = facesOfVertex(cache, vertex);
  ClosestFacet closest, pressed;
  pressed.signedDistance = -std::numeric_limits<double>::infinity();
  for (std::size_t c = begin; c < end; ++c) {
    if (c > begin && candidates[c].triangle == candidates[c - 1].triangle) continue;
    ++cache.stats.facetTests;
    tryFacet(model, cache, p, sheet, pressing ? &faces : nullptr, candidates[c].triangle, closest,
             pressed);
  }
  const double depth = closest.signedDistance - probeRadius;
  if (closest.triangle < 0 || !(depth < 0.0)) return;
  Contact c;
  c.a = isVertex ? t.vertexOwner[static_cast<std::size_t>(vertex)] : probe;
  c.other = model.objects[static_cast<std::size_t>(object)].firstParticle;
  c.vertex = vertex;
  const bool turn = pressed.triangle >= 0 && !closest.faceToFace && closest.signedDistance < 0.0 &&
                    -pressed.signedDistance <= kPressedDepth * model.radius[c.a];
  const ClosestFacet& face = turn ? pressed : closest;
  c.facet = face.triangle;
  c.facetWeights = face.beta;
  c.depth = depth;
  c.normal = face.normal;
  cache.treeContacts.push_back(c);
}

}  // namespace

void resolveFacetCandidates(const Model& model, const std::vector<Vec3>& position,
                            ContactScratch& cache) {
  auto& candidates = cache.facetCandidates;
  if (candidates.empty()) return;
  using Candidate = ContactScratch::FacetCandidate;
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& x, const Candidate& y) {
    if (x.probe != y.probe) return x.probe < y.probe;
    if (x.object != y.object) return x.object < y.object;
    return x.triangle < y.triangle;
  });
  std::size_t k = 0;
  while (k < candidates.size()) {
    std::size_t end = k;
    while (end < candidates.size() && candidates[end].probe == candidates[k].probe &&
           candidates[end].object == candidates[k].object)
      ++end;
    resolveProbe(model, position, cache, k, end);
    k = end;
  }
}

FacetCarrier vertexCarrier(const Model& model, const ContactTables& tables,
                           const std::vector<Vec3>& position, const Contact& c) {
  FacetCarrier out;
  const auto v = static_cast<std::size_t>(c.vertex);
  const auto owner = static_cast<std::size_t>(tables.vertexOwner[v]);
  out.tree = tables.vertexOnBody[v] != 0 ? tables.treeOf[owner] : -1;
  out.body = tables.treeBodyOf[owner];
  const SurfaceVertex& vertex = model.surfaceVertices[v];
  out.point = embedded(vertex, position) -
              c.normal * model.objects[static_cast<std::size_t>(vertex.object)].surfaceRadius;
  out.inverseMass = tables.vertexInverseMass[v];
  return out;
}

void facetKinematics(const Model& model, const ContactTables& tables,
                     const std::vector<Vec3>& position, const std::vector<Vec3>& velocity,
                     const Contact* before, const Contact& c, FacetKinematics& out) {
  // The touching side: particle a, or the vertex; the inverse masses are the
  // contact law's (ContactTables: a rigid body's at the point).
  Vec3 x = position[c.a], xDot = velocity[c.a];
  double inverseMass = tables.contactInverseMass[c.a];
  if (c.vertex >= 0 && c.edgeVertex < 0) {
    const SurfaceVertex& v = model.surfaceVertices[static_cast<std::size_t>(c.vertex)];
    x = embedded(v, position);
    xDot = embedded(v, velocity);
    inverseMass = tables.vertexInverseMass[static_cast<std::size_t>(c.vertex)];
  } else if (c.vertex >= 0) {  // an edge's point (1 - s) x_0 + s x_1
    x = edgePoint(model, c, c.edgeWeight, position);
    xDot = edgePoint(model, c, c.edgeWeight, velocity);
    inverseMass = 0.0;
    const TouchingVertices side = touchingVertices(c);
    for (int j = 0; j < 2; ++j)
      inverseMass += side.weight[j] * side.weight[j] *
                     tables.vertexInverseMass[static_cast<std::size_t>(side.vertex[j])];
  }
  out.radius = model.radius[c.a];
  out.hasPrevious = before != nullptr;
  if (before != nullptr) out.previous = *before;
  if (c.facet < 0) {  // a vertex on the environment: absolute, as a particle's
    out.relative = x;
    out.relativeVelocity = xDot;
    out.reducedMass = 1.0 / std::max(inverseMass, 1e-300);
    return;
  }
  const SurfaceTriangle& t = model.surfaceTriangles[static_cast<std::size_t>(c.facet)];
  const auto at = [&](std::int32_t v) {
    return embedded(model.surfaceVertices[static_cast<std::size_t>(v)], position);
  };
  const auto rate = [&](std::int32_t v) {
    return embedded(model.surfaceVertices[static_cast<std::size_t>(v)], velocity);
  };
  const Vec3 q = trianglePoint(t, c.facetWeights, at);
  const Vec3 qDot = trianglePoint(t, c.facetWeights, rate);
  double targetInverseMass = 0.0;
  for (int j = 0; j < 3; ++j) {
    const double b = weightOf(c.facetWeights, j);
    targetInverseMass += b * b * tables.vertexInverseMass[static_cast<std::size_t>(t.vertex[j])];
  }
  out.relative = x - q;
  out.relativeVelocity = xDot - qDot;
  out.reducedMass = 1.0 / std::max(inverseMass + targetInverseMass, 1e-300);
  // The anchor refers to the body point the contact had last time; carry it to
  // the current contact point: x - q_now = (x - q_old) + (q_old - q_now).
  if (before != nullptr && before->facet >= 0) {
    const SurfaceTriangle& old = model.surfaceTriangles[static_cast<std::size_t>(before->facet)];
    const Vec3 qOld = trianglePoint(old, before->facetWeights, at);
    out.previous.anchor = before->anchor + (qOld - q);
    // An edge's touching point moves along its edge too: x - q_now =
    // (x_old - q_old) + (q_old - q_now) - (x_old - x_now).
    if (before->edgeVertex >= 0 && c.edgeVertex >= 0)
      out.previous.anchor -= edgePoint(model, c, before->edgeWeight, position) - x;
  }
}

void distributeFacetForce(const Model& model, const Contact& c, const Vec3& onA,
                          std::vector<Vec3>& force) {
  const auto spread = [&](const SurfaceVertex& v, const Vec3& f) {
    for (int k = 0; k < SurfaceVertex::kMaxParticles; ++k) {
      if (v.particle[k] >= 0) force[v.particle[k]] += f * v.weight[k];
    }
  };
  if (c.vertex >= 0 && c.edgeVertex < 0) {
    spread(model.surfaceVertices[static_cast<std::size_t>(c.vertex)], onA);
  } else if (c.vertex >= 0) {
    const TouchingVertices side = touchingVertices(c);
    for (int j = 0; j < 2; ++j)
      spread(model.surfaceVertices[static_cast<std::size_t>(side.vertex[j])], onA * side.weight[j]);
  } else {
    force[c.a] += onA;
  }
  if (c.facet < 0) return;
  const SurfaceTriangle& t = model.surfaceTriangles[static_cast<std::size_t>(c.facet)];
  for (int j = 0; j < 3; ++j) spread(vertexOf(model, t, j), onA * -weightOf(c.facetWeights, j));
}

void addTriangleRates(const Model& model, const Contact& c, const law::Rates& rates,
                      std::vector<law::Rates>& sums) {
  const SurfaceTriangle& t = model.surfaceTriangles[static_cast<std::size_t>(c.facet)];
  // The row's reach: Σ|w| of the touching side (1 for a particle) and of the
  // triangle's particles (Σ_j |β_j| Σ_k |w_jk|).
  double reach = 1.0;
  if (c.vertex >= 0) {
    reach = 0.0;
    const TouchingVertices side = touchingVertices(c);
    for (int j = 0; j < side.count; ++j) {
      const SurfaceVertex& v = model.surfaceVertices[static_cast<std::size_t>(side.vertex[j])];
      for (int k = 0; k < SurfaceVertex::kMaxParticles; ++k)
        reach += std::abs(side.weight[j] * v.weight[k]);
    }
  }
  for (int j = 0; j < 3; ++j) {
    const SurfaceVertex& v = vertexOf(model, t, j);
    for (int k = 0; k < SurfaceVertex::kMaxParticles; ++k)
      reach += std::abs(weightOf(c.facetWeights, j) * v.weight[k]);
  }
  for (int j = 0; j < 3; ++j) {
    const SurfaceVertex& v = vertexOf(model, t, j);
    for (int k = 0; k < SurfaceVertex::kMaxParticles; ++k) {
      if (v.particle[k] < 0) continue;
      const double share = 0.5 * reach * std::abs(weightOf(c.facetWeights, j) * v.weight[k]);
      sums[static_cast<std::size_t>(v.particle[k])].add(rates, share);
    }
  }
}

double facetExtraStiffness(const Model& model, double stiffness, const Contact& c) {
  if (c.vertex < 0 || model.inverseMass[c.a] == 0.0) return 0.0;
  double sum = 0.0, own = 0.0;
  const TouchingVertices side = touchingVertices(c);
  for (int j = 0; j < side.count; ++j) {
    const SurfaceVertex& v = model.surfaceVertices[static_cast<std::size_t>(side.vertex[j])];
    for (int k = 0; k < SurfaceVertex::kMaxParticles; ++k) {
      if (v.particle[k] < 0) continue;
      sum += std::abs(side.weight[j] * v.weight[k]);
      if (v.particle[k] == c.a) own += std::abs(side.weight[j] * v.weight[k]);
    }
  }
  const double extra = sum * own - 1.0;
  return extra > 0.0 ? extra * stiffness : 0.0;
}

}  // namespace robophi
