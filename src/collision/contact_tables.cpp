// The contact tables: what the contact stage derives once from the Model
// (exclusion lists, material table, which particles go to the grid and which
// objects get a sphere tree), and the scratch that one evaluation works in.
#include "collision/contact_tables.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <limits>
#include <tuple>

#include "collision/environment.h"
#include "collision/sphere_tree.h"

namespace robophi {

namespace {

PairParameters combine(const ContactSettings& settings, double stiffness, double damping,
                       double staticFriction, double kineticFriction, double rolling = 0.0) {
  PairParameters p;
  p.rollingResistance = rolling;
  p.stiffness = stiffness;
  p.damping = damping;
  p.staticFriction = staticFriction;
  p.kineticFriction = std::min(kineticFriction, staticFriction);
  p.tangentialStiffness = settings.tangentialStiffnessRatio * stiffness;
  p.tangentialDampingRatio = settings.tangentialDampingRatio;
  p.stribeckVelocity = settings.stribeckVelocity;
  return p;
}

void buildExclusions(const Model& model, ContactTables& cache) {
  std::vector<std::pair<std::int32_t, std::int32_t>> pairs;
  const auto add = [&pairs](std::int32_t i, std::int32_t j) {
    if (i == j || i < 0 || j < 0) return;
    pairs.emplace_back(std::min(i, j), std::max(i, j));
  };
  for (const LinearSpring& s : model.linearSprings) add(s.a, s.b);
  for (const TorsionSpring& s : model.torsionSprings) {
    add(s.a, s.c);
    add(s.b, s.c);
    add(s.a, s.b);
  }
  for (const JointSpring& s : model.jointSprings) {
    add(s.a, s.c);
    add(s.b, s.c);
    add(s.a, s.b);
    add(s.d, s.a);
    add(s.d, s.b);
    add(s.d, s.c);
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  const auto n = static_cast<std::size_t>(model.particleCount());
  cache.exclusionStart.assign(n + 1, 0);
  for (const auto& [i, j] : pairs) ++cache.exclusionStart[static_cast<std::size_t>(i) + 1];
  for (std::size_t i = 0; i < n; ++i) cache.exclusionStart[i + 1] += cache.exclusionStart[i];
  cache.exclusionPartner.resize(pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    cache.exclusionPartner[k] = pairs[k].second;  // sorted by (i, j): rows are contiguous
  }
}

// The largest eigenvalue of a symmetric positive semi-definite 3×3 matrix (the
// trigonometric solution).
double largestEigenvalue(const Mat3& a) {
  const double p1 = a.m[0][1] * a.m[0][1] + a.m[0][2] * a.m[0][2] + a.m[1][2] * a.m[1][2];
  if (p1 == 0.0) return std::max({a.m[0][0], a.m[1][1], a.m[2][2]});
  const double q = (a.m[0][0] + a.m[1][1] + a.m[2][2]) / 3.0;
  const double p2 = (a.m[0][0] - q) * (a.m[0][0] - q) + (a.m[1][1] - q) * (a.m[1][1] - q) +
                    (a.m[2][2] - q) * (a.m[2][2] - q) + 2.0 * p1;
  const double p = std::sqrt(p2 / 6.0);
  const Mat3 b = (1.0 / p) * (a - Mat3::diagonal({q, q, q}));
  const double det = b.m[0][0] * (b.m[1][1] * b.m[2][2] - b.m[1][2] * b.m[2][1]) -
                     b.m[0][1] * (b.m[1][0] * b.m[2][2] - b.m[1][2] * b.m[2][0]) +
                     b.m[0][2] * (b.m[1][0] * b.m[2][1] - b.m[1][1] * b.m[2][0]);
  const double phi = std::acos(std::clamp(det / 2.0, -1.0, 1.0)) / 3.0;
  return q + 2.0 * p * std::cos(phi);
}

// The inverse of a symmetric positive definite 3×3 matrix (its adjugate over its
// determinant); a singular one's inverse is taken as infinite (1e300).
Mat3 inverseOf(const Mat3& a) {
  const auto& m = a.m;
  Mat3 adj;
  adj.m[0][0] = m[1][1] * m[2][2] - m[1][2] * m[2][1];
  adj.m[0][1] = m[0][2] * m[2][1] - m[0][1] * m[2][2];
  adj.m[0][2] = m[0][1] * m[1][2] - m[0][2] * m[1][1];
  adj.m[1][0] = m[1][2] * m[2][0] - m[1][0] * m[2][2];
  adj.m[1][1] = m[0][0] * m[2][2] - m[0][2] * m[2][0];
  adj.m[1][2] = m[0][2] * m[1][0] - m[0][0] * m[1][2];
  adj.m[2][0] = m[1][0] * m[2][1] - m[1][1] * m[2][0];
  adj.m[2][1] = m[0][1] * m[2][0] - m[0][0] * m[2][1];
  adj.m[2][2] = m[0][0] * m[1][1] - m[0][1] * m[1][0];
  const double det = m[0][0] * adj.m[0][0] + m[0][1] * adj.m[1][0] + m[0][2] * adj.m[2][0];
  if (!(det > 0.0)) return Mat3::diagonal({1e300, 1e300, 1e300});
  return (1.0 / det) * adj;
}

// Which particles move under the contacts' loads and the inverse mass the contact
// law sees at each (ContactTables::movable, contactInverseMass): a rigid tree's
// particles move with their body, whose inverse effective mass at a point r from
// its centre, along a direction n, is 1/m + (r × n)ᵀ I⁻¹ (r × n) for the body
// alone, at most 1/m + λ_max([r]×ᵀ I⁻¹ [r]×) over n; joints to other bodies only
// lower it.
// A rigid body's inverse effective mass at offset r from its mass centre, the
// largest over directions: 1/m + λ_max([r]×ᵀ I⁻¹ [r]×) (1/kg).
double bodyPointInverseMass(const BodyMassProperties& mp, const Vec3& offset) {
  const Mat3 r = Mat3::crossMatrix(offset);
  return 1.0 / mp.mass + largestEigenvalue(transpose(r) * inverseOf(mp.inertia) * r);
}

void classifyCarriers(const Model& model, ContactTables& cache) {
  const auto n = static_cast<std::size_t>(model.particleCount());
  cache.treeOf.assign(n, -1);
  cache.treeBodyOf.assign(n, -1);
  cache.movable.resize(n);
  cache.contactInverseMass = model.inverseMass;
  for (std::size_t i = 0; i < n; ++i) cache.movable[i] = model.inverseMass[i] != 0.0 ? 1 : 0;
  for (std::size_t t = 0; t < model.rigidTrees.size(); ++t) {
    const RigidTree& tree = model.rigidTrees[t];
    for (const BodyParticle& bp : tree.particles) {
      const auto i = static_cast<std::size_t>(bp.particle);
      const BodyMassProperties& mp = tree.multibody.bodies[static_cast<std::size_t>(bp.body)].mass;
      cache.treeOf[i] = static_cast<std::int32_t>(t);
      cache.treeBodyOf[i] = bp.body;
      cache.movable[i] = 1;
      cache.contactInverseMass[i] = bodyPointInverseMass(mp, bp.p_BP - mp.centerOfMass);
    }
  }
}

// Whether particle i's object touches nothing (ContactRole::touches: goal
// copies, path ends, inertia carriers; docs/robotics.md).
inline bool touchesNothing(const Model& model, const ContactTables& cache, ParticleIndex i) {
  const std::int32_t object = cache.particleObject[i];
  return object >= 0 && !model.objects[object].contact.touches;
}

// Each particle's object, its object's contact role and material; the objects'
// sizes (returned); whether every contact body is one particle.
std::vector<std::int32_t> classifyObjects(const Model& model, ContactTables& cache) {
  const ParticleIndex n = model.particleCount();
  const auto objectCount = static_cast<std::int32_t>(model.objects.size());
  cache.particleObject.assign(static_cast<std::size_t>(n), -1);
  cache.frictionAlone.assign(static_cast<std::size_t>(n), 0);
  cache.noTurning.assign(static_cast<std::size_t>(n), 0);
  cache.particleMaterial.assign(static_cast<std::size_t>(n), 0);
  std::vector<std::int32_t> objectSize(static_cast<std::size_t>(objectCount), 0);
  for (ParticleIndex i = 0; i < n; ++i) {
    const std::int32_t object = model.objectOf[i];
    if (object < 0 || object >= objectCount) continue;
    cache.particleObject[i] = object;
    const ContactRole& role = model.objects[object].contact;
    cache.frictionAlone[i] = role.frictionPerParticle ? 1 : 0;
    cache.noTurning[i] = role.turns ? 0 : 1;
    const std::int32_t material = model.objects[object].material;
    cache.particleMaterial[i] = material >= 0 && material < cache.materialCount ? material : 0;
    ++objectSize[object];
  }
  cache.singleParticleBodies = true;
  for (std::int32_t object = 0; object < objectCount; ++object) {
    if (objectSize[object] > 1 && !model.objects[object].contact.frictionPerParticle)
      cache.singleParticleBodies = false;
  }
  return objectSize;
}

// MODEL §3.3 rolling: a particle no LS ties to another spins on its own, a
// solid sphere with J = 2/5 m r²; the others turn with their LS neighbours.
// Only LS within one object make a neighbourhood: an attractor (a goal's LS to
// a virtual particle) or a tie to another body does not turn the particle. A
// rigid tree's particles turn with their body (docs/model.md §7): no spin of
// their own. Also each rim particle's rim.
void classifyTurning(const Model& model, ContactTables& cache) {
  const ParticleIndex n = model.particleCount();
  const auto sameBody = [&](const LinearSpring& s) {
    return s.a >= 0 && s.b >= 0 && s.a < n && s.b < n && s.a != s.b &&
           cache.particleObject[s.a] >= 0 && cache.particleObject[s.a] == cache.particleObject[s.b];
  };
  cache.rollNeighbourStart.assign(static_cast<std::size_t>(n) + 1, 0);
  for (const LinearSpring& s : model.linearSprings) {
    if (!sameBody(s)) continue;
    ++cache.rollNeighbourStart[static_cast<std::size_t>(s.a) + 1];
    ++cache.rollNeighbourStart[static_cast<std::size_t>(s.b) + 1];
  }
  for (ParticleIndex i = 0; i < n; ++i)
    cache.rollNeighbourStart[i + 1] += cache.rollNeighbourStart[i];
  cache.rollNeighbour.assign(static_cast<std::size_t>(cache.rollNeighbourStart[n]), 0);
  std::vector<std::int32_t> fill(cache.rollNeighbourStart.begin(), cache.rollNeighbourStart.end() - 1);
  for (const LinearSpring& s : model.linearSprings) {
    if (!sameBody(s)) continue;
    cache.rollNeighbour[static_cast<std::size_t>(fill[s.a]++)] = s.b;
    cache.rollNeighbour[static_cast<std::size_t>(fill[s.b]++)] = s.a;
  }
  cache.rimOf.assign(static_cast<std::size_t>(n), -1);
  for (std::size_t r = 0; r < model.rims.size(); ++r) {
    const RimRing& rim = model.rims[r];
    for (std::int32_t k = 0; k < rim.count; ++k)
      cache.rimOf[static_cast<std::size_t>(rim.first + k)] = static_cast<std::int32_t>(r);
  }
  cache.inverseSpinInertia.assign(static_cast<std::size_t>(n), 0.0);
  for (ParticleIndex i = 0; i < n; ++i) {
    if (cache.treeOf[static_cast<std::size_t>(i)] >= 0) continue;
    const double inertia = 0.4 * model.mass[i] * model.radius[i] * model.radius[i];
    if (model.contact.rolling && !touchesNothing(model, cache, i) && inertia > 0.0 &&
        cache.rollNeighbourStart[i + 1] == cache.rollNeighbourStart[i]) {
      cache.inverseSpinInertia[i] = 1.0 / inertia;
    }
  }
}

// Single particles go to the grid unless they are much larger than the
// typical one (4 × the median radius: they would make the cells too large):
// those are returned, for trees of their own.
std::vector<std::int32_t> gridSingles(const Model& model, ContactTables& cache,
                                      const std::vector<std::int32_t>& objectSize) {
  std::vector<std::int32_t> singles;
  for (ParticleIndex i = 0; i < model.particleCount(); ++i) {
    if (touchesNothing(model, cache, i)) continue;
    const std::int32_t object = cache.particleObject[i];
    if (object < 0 || objectSize[object] == 1) singles.push_back(i);
  }
  double limit = 0.0;
  if (!singles.empty()) {
    std::vector<double> radii;
    radii.reserve(singles.size());
    for (std::int32_t i : singles) radii.push_back(model.radius[i]);
    std::nth_element(radii.begin(), radii.begin() + static_cast<std::ptrdiff_t>(radii.size() / 2),
                     radii.end());
    limit = 4.0 * radii[radii.size() / 2];
  }
  cache.gridParticles.clear();
  cache.cellSize = 0.0;
  std::vector<std::int32_t> largeSingles;
  for (std::int32_t i : singles) {
    if (model.radius[i] <= limit) {
      cache.gridParticles.push_back(i);
      cache.cellSize = std::max(cache.cellSize, 2.0 * model.radius[i]);
    } else {
      largeSingles.push_back(i);
    }
  }
  return largeSingles;
}

// The sphere trees' objects: in object order (objects of two or more particles
// that touch), then the large single particles.
void classifyTrees(const Model& model, ContactTables& cache,
                   const std::vector<std::int32_t>& objectSize,
                   const std::vector<std::int32_t>& largeSingles) {
  const auto objectCount = static_cast<std::int32_t>(model.objects.size());
  std::vector<std::vector<std::int32_t>> members(static_cast<std::size_t>(objectCount));
  for (ParticleIndex i = 0; i < model.particleCount(); ++i) {
    const std::int32_t object = cache.particleObject[i];
    if (object >= 0 && objectSize[object] >= 2 && !touchesNothing(model, cache, i))
      members[object].push_back(i);
  }
  cache.trees.clear();
  cache.treeMembers.clear();
  for (std::int32_t object = 0; object < objectCount; ++object) {
    if (members[object].empty()) continue;
    cache.treeMembers.push_back(std::move(members[object]));
    cache.trees.push_back(TreeObject{object, 0, 0, 0, false});
  }
  for (std::int32_t i : largeSingles) {
    cache.treeMembers.push_back({i});
    cache.trees.push_back(TreeObject{cache.particleObject[i], 0, 0, 0, false});
  }
  for (std::size_t t = 0; t < cache.trees.size(); ++t) {
    bool allFixed = true;
    for (std::int32_t i : cache.treeMembers[t]) allFixed = allFixed && cache.movable[i] == 0;
    cache.trees[t].allFixed = allFixed;
    const std::int32_t object = cache.trees[t].object;
    if (object >= 0 && cache.treeMembers[t].size() >= 2) {
      cache.trees[t].faceted = cache.objectFaceted[object] != 0;
      cache.trees[t].rigid = model.objects[object].rigid;
    }
  }
}

void classifyParticles(const Model& model, ContactTables& cache) {
  const std::vector<std::int32_t> objectSize = classifyObjects(model, cache);
  classifyTurning(model, cache);
  const std::vector<std::int32_t> largeSingles = gridSingles(model, cache, objectSize);
  classifyTrees(model, cache, objectSize, largeSingles);
}

// ContactTables::vertexTriangleStart/vertexTriangle: each vertex's triangles.
void vertexTriangles(const Model& model, ContactTables& cache) {
  const std::size_t n = model.surfaceVertices.size();
  cache.vertexTriangleStart.assign(n + 1, 0);
  for (const SurfaceTriangle& t : model.surfaceTriangles)
    for (const std::int32_t v : t.vertex)
      ++cache.vertexTriangleStart[static_cast<std::size_t>(v) + 1];
  for (std::size_t v = 0; v < n; ++v)
    cache.vertexTriangleStart[v + 1] += cache.vertexTriangleStart[v];
  cache.vertexTriangle.resize(3 * model.surfaceTriangles.size());
  std::vector<std::int32_t> fill(cache.vertexTriangleStart.begin(),
                                 cache.vertexTriangleStart.end() - 1);
  for (std::size_t t = 0; t < model.surfaceTriangles.size(); ++t)
    for (const std::int32_t v : model.surfaceTriangles[t].vertex)
      cache.vertexTriangle[static_cast<std::size_t>(fill[static_cast<std::size_t>(v)]++)] =
          static_cast<std::int32_t>(t);
}

// How each surface vertex moves under the contacts' loads (ContactTables::
// vertexInverseMass, vertexOnBody): a vertex whose particles all ride one rigid
// tree body is a point of that body (its offset Σ w_k p_BP,k: the embedding is
// exact for a rigid motion); the others move with their particles.
void vertexCarriers(const Model& model, ContactTables& cache) {
  const auto n = static_cast<std::size_t>(model.particleCount());
  std::vector<Vec3> offset(n);  // p_BP of each tree particle
  for (const RigidTree& tree : model.rigidTrees)
    for (const BodyParticle& bp : tree.particles) offset[static_cast<std::size_t>(bp.particle)] = bp.p_BP;
  const std::size_t vertices = model.surfaceVertices.size();
  cache.vertexInverseMass.assign(vertices, 0.0);
  cache.vertexOnBody.assign(vertices, 0);
  for (std::size_t v = 0; v < vertices; ++v) {
    const SurfaceVertex& vertex = model.surfaceVertices[v];
    const auto owner = static_cast<std::size_t>(cache.vertexOwner[v]);
    const std::int32_t tree = cache.treeOf[owner], body = cache.treeBodyOf[owner];
    bool onBody = tree >= 0;
    double spread = 0.0;
    Vec3 at;
    for (int k = 0; k < SurfaceVertex::kMaxParticles; ++k) {
      if (vertex.particle[k] < 0) continue;
      const auto i = static_cast<std::size_t>(vertex.particle[k]);
      spread += vertex.weight[k] * vertex.weight[k] * cache.contactInverseMass[i];
      at += offset[i] * vertex.weight[k];
      onBody = onBody && cache.treeOf[i] == tree && cache.treeBodyOf[i] == body;
    }
    cache.vertexOnBody[v] = onBody ? 1 : 0;
    if (!onBody) {
      cache.vertexInverseMass[v] = spread;
      continue;
    }
    const BodyMassProperties& mp =
        model.rigidTrees[static_cast<std::size_t>(tree)].multibody.bodies[static_cast<std::size_t>(body)].mass;
    cache.vertexInverseMass[v] = bodyPointInverseMass(mp, at - mp.centerOfMass);
  }
}

// MODEL §3.8: which objects touch by their surface mesh, and which particle
// carries each vertex and triangle (CSR lists by particle).

// The edges two triangles of one faceted object's closed surface share, in
// (vertex, vertex) order (ContactTables::SurfaceEdge). An edge of one triangle
// only or of more than two is not listed: its side has no normal pair.
std::vector<ContactTables::SurfaceEdge> sharedEdges(const Model& model, const ContactTables& tables) {
  struct Side {
    std::int32_t low, high, triangle, opposite;
  };
  std::vector<Side> sides;
  for (std::size_t t = 0; t < model.surfaceTriangles.size(); ++t) {
    const SurfaceTriangle& tri = model.surfaceTriangles[t];
    // (A sheet, touched from both sides, has no outward normals: no ridges.)
    if (tables.objectFaceted[static_cast<std::size_t>(tri.object)] == 0 ||
        model.objects[static_cast<std::size_t>(tri.object)].surfaceRadius > 0.0)
      continue;
    for (int j = 0; j < 3; ++j) {
      const std::int32_t u = tri.vertex[static_cast<std::size_t>(j)];
      const std::int32_t w = tri.vertex[static_cast<std::size_t>((j + 1) % 3)];
      sides.push_back({std::min(u, w), std::max(u, w), static_cast<std::int32_t>(t),
                       tri.vertex[static_cast<std::size_t>((j + 2) % 3)]});
    }
  }
  std::sort(sides.begin(), sides.end(), [](const Side& x, const Side& y) {
    return std::tie(x.low, x.high, x.triangle) < std::tie(y.low, y.high, y.triangle);
  });
  std::vector<ContactTables::SurfaceEdge> edges;
  for (std::size_t k = 0; k < sides.size();) {
    std::size_t end = k;
    while (end < sides.size() && sides[end].low == sides[k].low && sides[end].high == sides[k].high)
      ++end;
    if (end - k == 2) {
      edges.push_back({{sides[k].low, sides[k].high},
                       {sides[k].triangle, sides[k + 1].triangle},
                       {sides[k].opposite, sides[k + 1].opposite}});
    }
    k = end;
  }
  return edges;
}

void classifySurfaces(const Model& model, ContactTables& cache) {
  const auto objects = model.objects.size();
  const auto n = static_cast<std::size_t>(model.particleCount());
  cache.objectFaceted.assign(objects, 0);
  cache.objectFixed.assign(objects, 1);
  for (ParticleIndex i = 0; i < model.particleCount(); ++i) {
    const std::int32_t object = model.objectOf[i];
    if (object >= 0 && static_cast<std::size_t>(object) < objects && cache.movable[i] != 0)
      cache.objectFixed[static_cast<std::size_t>(object)] = 0;
  }
  for (std::size_t o = 0; o < objects; ++o)
    cache.objectFaceted[o] =
        model.objects[o].triangleCount > 0 && model.objects[o].particleCount >= 2;
  const auto owner = [](const SurfaceVertex& v) {
    int best = 0;
    for (int k = 1; k < SurfaceVertex::kMaxParticles; ++k)
      if (v.particle[k] >= 0 && v.weight[k] > v.weight[best]) best = k;
    return v.particle[best];
  };
  cache.vertexOwner.resize(model.surfaceVertices.size());
  for (std::size_t v = 0; v < model.surfaceVertices.size(); ++v)
    cache.vertexOwner[v] = owner(model.surfaceVertices[v]);
  vertexCarriers(model, cache);
  std::vector<std::int32_t> triangleOwner(model.surfaceTriangles.size());
  for (std::size_t t = 0; t < model.surfaceTriangles.size(); ++t) {
    // The particle of largest summed weight over the three vertices.
    std::vector<std::pair<std::int32_t, double>> sums;
    for (const std::int32_t vertex : model.surfaceTriangles[t].vertex) {
      const SurfaceVertex& v = model.surfaceVertices[static_cast<std::size_t>(vertex)];
      for (int k = 0; k < SurfaceVertex::kMaxParticles; ++k) {
        if (v.particle[k] < 0) continue;
        auto it = std::find_if(sums.begin(), sums.end(),
                               [&](const auto& e) { return e.first == v.particle[k]; });
        if (it == sums.end())
          sums.emplace_back(v.particle[k], v.weight[k]);
        else
          it->second += v.weight[k];
      }
    }
    std::sort(sums.begin(), sums.end());
    std::size_t best = 0;
    for (std::size_t e = 1; e < sums.size(); ++e)
      if (sums[e].second > sums[best].second) best = e;
    triangleOwner[t] = sums.empty() ? 0 : sums[best].first;
  }
  const auto csr = [n](const std::vector<std::int32_t>& ownerOf, std::vector<std::int32_t>& start,
                       std::vector<std::int32_t>& items) {
    start.assign(n + 1, 0);
    for (const std::int32_t i : ownerOf) ++start[static_cast<std::size_t>(i) + 1];
    for (std::size_t i = 0; i < n; ++i) start[i + 1] += start[i];
    items.resize(ownerOf.size());
    std::vector<std::int32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t k = 0; k < ownerOf.size(); ++k)
      items[static_cast<std::size_t>(fill[static_cast<std::size_t>(ownerOf[k])]++)] =
          static_cast<std::int32_t>(k);
  };
  csr(cache.vertexOwner, cache.ownedVertexStart, cache.ownedVertex);
  csr(triangleOwner, cache.ownedTriangleStart, cache.ownedTriangle);
  vertexTriangles(model, cache);
  cache.edges = sharedEdges(model, cache);
  std::vector<std::int32_t> edgeOwner(cache.edges.size());
  for (std::size_t e = 0; e < cache.edges.size(); ++e)
    edgeOwner[e] = triangleOwner[static_cast<std::size_t>(cache.edges[e].triangle[0])];
  csr(edgeOwner, cache.ownedEdgeStart, cache.ownedEdge);
}

}  // namespace

ContactTables compileContactTables(const Model& model) {
  ContactTables tables;
  ContactTables* cache = &tables;
  tables.noContactPairs = model.noContactPairs;
  if (std::any_of(model.objects.begin(), model.objects.end(),
                  [](const ObjectInfo& o) { return o.contactGroup >= 0; }))
    for (const ObjectInfo& o : model.objects) tables.objectContactGroup.push_back(o.contactGroup);
  {
    const ContactSettings& settings = model.contact;
    // Material-pair table (combineMaterials: series κ_c and μ_c, geometric-mean friction).
    cache->materialCount = static_cast<std::int32_t>(model.materials.size());
    const auto m = static_cast<std::size_t>(cache->materialCount);
    cache->materialPairs.resize(m * m);
    for (std::size_t i = 0; i < m; ++i) {
      for (std::size_t j = 0; j < m; ++j) {
        const Material pair = combineMaterials(model.materials[i], model.materials[j]);
        cache->materialPairs[i * m + j] =
            combine(settings, pair.contactStiffness, pair.contactDamping, pair.staticFriction,
                    pair.kineticFriction, pair.rollingResistance);
      }
    }
    const std::int32_t items = model.environment.itemCount();
    cache->environmentMaterials.resize(static_cast<std::size_t>(items));
    cache->environmentReaches.resize(static_cast<std::size_t>(items));
    cache->environmentLow.resize(static_cast<std::size_t>(items));
    cache->environmentHigh.resize(static_cast<std::size_t>(items));
    for (std::int32_t e = 0; e < items; ++e) {
      const std::int32_t material = environmentMaterial(model.environment, e);
      cache->environmentMaterials[e] =
          material >= 0 && material < cache->materialCount ? material : 0;
      cache->environmentReaches[e] = environmentReach(model.environment, e);
      constexpr double kInfinity = std::numeric_limits<double>::infinity();
      if (!environmentBounds(model.environment, e, cache->environmentLow[e],
                             cache->environmentHigh[e])) {
        cache->environmentLow[e] = {-kInfinity, -kInfinity, -kInfinity};
        cache->environmentHigh[e] = {kInfinity, kInfinity, kInfinity};
      }
    }
    cache->overrides = settings.pairOverrides;
    for (ContactPairOverride& o : cache->overrides) {
      if (o.objectB >= 0 && o.objectB < o.objectA) std::swap(o.objectA, o.objectB);
      if (o.objectB < 0) o.objectB = -1;
    }
    std::sort(cache->overrides.begin(), cache->overrides.end(),
              [](const ContactPairOverride& x, const ContactPairOverride& y) {
                return std::tie(x.objectA, x.objectB) < std::tie(y.objectA, y.objectB);
              });
    classifyCarriers(model, *cache);
    buildExclusions(model, *cache);
    classifySurfaces(model, *cache);
    classifyParticles(model, *cache);
  }
  return tables;
}

ContactScratch& prepareContactScratch(const Model& model, const ContactTables& tables,
                                      std::int64_t revision, const std::vector<Vec3>& position,
                                      ContactScratch& scratch) {
  scratch.tables = &tables;
  if (scratch.revision != revision) {
    scratch.revision = revision;
    buildSphereTrees(model, position, scratch);
  }
  return scratch;
}

const PairParameters& overriddenPairParameters(const Model& model, const ContactTables& cache,
                                               std::int32_t a, std::int32_t other,
                                               const PairParameters& table,
                                               PairParameters& overrideOut) {
  std::int32_t objectA = cache.particleObject[a];
  std::int32_t objectB = other >= 0 ? cache.particleObject[other] : -1;
  if (objectA < 0) return table;
  if (objectB >= 0 && objectB < objectA) std::swap(objectA, objectB);
  if (objectB < 0 && other >= 0) return table;
  const auto it = std::lower_bound(
      cache.overrides.begin(), cache.overrides.end(), std::make_pair(objectA, objectB),
      [](const ContactPairOverride& o, const std::pair<std::int32_t, std::int32_t>& key) {
        return std::tie(o.objectA, o.objectB) < std::tie(key.first, key.second);
      });
  if (it == cache.overrides.end() || it->objectA != objectA || it->objectB != objectB) return table;
  overrideOut =
      combine(model.contact, it->stiffness, it->damping, it->staticFriction, it->kineticFriction);
  return overrideOut;
}

}  // namespace robophi
