// The sphere hierarchy (MODEL §3.2). Each tree object's particles are
// permuted so that every node covers a contiguous range; nodes are stored
// parents first with contiguous children, so a reverse sweep refits them.
#include "collision/sphere_tree.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "collision/environment.h"
#include "collision/facets.h"

namespace robophi {

namespace {

constexpr int kMaxDepth = 20;

// Splits treeParticles[first, first + count) of node `index` into octants about
// its box centre and recurses (pre-order, children appended contiguously).
void buildNode(const std::vector<Vec3>& position, ContactScratch& cache, std::int32_t index,
               std::int32_t leafSize, int depth) {
  const std::int32_t first = cache.nodes[index].first;
  const std::int32_t count = cache.nodes[index].count;
  if (count <= leafSize || depth >= kMaxDepth) return;
  Vec3 low = position[cache.treeParticles[first]], high = low;
  for (std::int32_t k = first; k < first + count; ++k) {
    const Vec3& p = position[cache.treeParticles[k]];
    low = {std::min(low.x, p.x), std::min(low.y, p.y), std::min(low.z, p.z)};
    high = {std::max(high.x, p.x), std::max(high.y, p.y), std::max(high.z, p.z)};
  }
  if (!(squaredNorm(high - low) > 0.0)) return;  // coincident particles: one leaf
  const Vec3 mid = (low + high) * 0.5;
  const auto octant = [&](std::int32_t particle) {
    const Vec3& p = position[particle];
    return (p.x >= mid.x ? 1 : 0) | (p.y >= mid.y ? 2 : 0) | (p.z >= mid.z ? 4 : 0);
  };
  // Stable counting sort of the range by octant.
  std::array<std::int32_t, 9> start{};
  for (std::int32_t k = first; k < first + count; ++k) ++start[octant(cache.treeParticles[k]) + 1];
  for (int o = 0; o < 8; ++o) start[o + 1] += start[o];
  std::vector<std::int32_t> sorted(static_cast<std::size_t>(count));
  std::array<std::int32_t, 8> fill{};
  for (int o = 0; o < 8; ++o) fill[o] = start[o];
  for (std::int32_t k = first; k < first + count; ++k) {
    const std::int32_t particle = cache.treeParticles[k];
    sorted[fill[octant(particle)]++] = particle;
  }
  std::copy(sorted.begin(), sorted.end(), cache.treeParticles.begin() + first);
  const auto firstChild = static_cast<std::int32_t>(cache.nodes.size());
  std::int32_t children = 0;
  for (int o = 0; o < 8; ++o) {
    if (start[o + 1] == start[o]) continue;
    TreeNode child;
    child.first = first + start[o];
    child.count = start[o + 1] - start[o];
    cache.nodes.push_back(child);
    ++children;
  }
  cache.nodes[index].firstChild = firstChild;
  cache.nodes[index].childCount = children;
  for (std::int32_t c = firstChild; c < firstChild + children; ++c) {
    buildNode(position, cache, c, leafSize, depth + 1);
  }
}

}  // namespace

void buildSphereTrees(const Model& model, const std::vector<Vec3>& position,
                      ContactScratch& cache) {
  cache.trees = cache.tables->trees;
  cache.nodes.clear();
  cache.treeParticles.clear();
  cache.objectMargin.assign(model.objects.size(), 0.0);
  const std::int32_t leafSize = std::max(1, model.contact.leafSize);
  for (std::size_t t = 0; t < cache.trees.size(); ++t) {
    TreeObject& tree = cache.trees[t];
    const auto& members = cache.tables->treeMembers[t];
    TreeNode root;
    root.first = static_cast<std::int32_t>(cache.treeParticles.size());
    root.count = static_cast<std::int32_t>(members.size());
    cache.treeParticles.insert(cache.treeParticles.end(), members.begin(), members.end());
    tree.rootNode = static_cast<std::int32_t>(cache.nodes.size());
    tree.nodeBegin = tree.rootNode;
    cache.nodes.push_back(root);
    buildNode(position, cache, tree.rootNode, leafSize, 0);
    tree.nodeEnd = static_cast<std::int32_t>(cache.nodes.size());
    for (std::int32_t k = tree.nodeBegin; k < tree.nodeEnd; ++k)
      cache.nodes[k].object = tree.object;
    if (tree.faceted) {
      tree.margin = facetTreeMargin(model, position, *cache.tables, members);
      cache.objectMargin[static_cast<std::size_t>(tree.object)] = tree.margin;
    }
  }
  // Every tree is refitted once; rigid ones then keep their spheres in their frame.
  std::vector<bool> rigid(cache.trees.size());
  for (std::size_t t = 0; t < cache.trees.size(); ++t) {
    rigid[t] = cache.trees[t].rigid;
    cache.trees[t].rigid = false;
  }
  refitSphereTrees(model, position, cache);
  for (std::size_t t = 0; t < cache.trees.size(); ++t) {
    if (rigid[t]) setUpRigidTree(model, position, cache, cache.trees[t]);
  }
}

// MODEL §3.2 for rigid objects: the tree's frame from its three reference
// particles, e1 along p1 - p0, e2 in the plane of p2, e3 = e1 × e2.
void referenceFrame(const std::vector<Vec3>& position, const TreeObject& tree, Vec3 axes[3]) {
  const Vec3& p0 = position[tree.reference[0]];
  axes[0] = position[tree.reference[1]] - p0;
  axes[0] = axes[0] / norm(axes[0]);
  axes[1] = position[tree.reference[2]] - p0;
  axes[1] = axes[1] - axes[0] * dot(axes[1], axes[0]);
  axes[1] = axes[1] / norm(axes[1]);
  axes[2] = cross(axes[0], axes[1]);
}

void setUpRigidTree(const Model& model, const std::vector<Vec3>& position, ContactScratch& cache,
                    TreeObject& tree) {
  const std::int32_t first = cache.nodes[tree.rootNode].first;
  const std::int32_t count = cache.nodes[tree.rootNode].count;
  const std::int32_t* members = cache.treeParticles.data() + first;
  // References: a member, the member farthest from it, the one farthest from their line.
  std::int32_t r0 = members[0], r1 = members[0], r2 = members[0];
  double smallest = model.radius[members[0]], far = -1.0;
  for (std::int32_t q = 0; q < count; ++q) {
    smallest = std::min(smallest, model.radius[members[q]]);
    if (members[q] < r0) r0 = members[q];
  }
  for (std::int32_t q = 0; q < count; ++q) {
    const double d = squaredNorm(position[members[q]] - position[r0]);
    if (d > far) far = d, r1 = members[q];
  }
  const Vec3 line = (position[r1] - position[r0]) / std::max(std::sqrt(far), 1e-300);
  far = -1.0;
  for (std::int32_t q = 0; q < count; ++q) {
    const Vec3 d = position[members[q]] - position[r0];
    const double off = squaredNorm(d - line * dot(d, line));
    if (off > far) far = off, r2 = members[q];
  }
  // Collinear (a row of particles, a thin rod's): stays a refitted tree. The test is
  // relative: rounding leaves particles on a line some 1e-17 m off it, and a frame
  // from that offset turns at random from one evaluation to the next (a PR2
  // gripper's pole of 19 particles in a row: its spheres 16 cm off, a contact
  // missed until its depth stalled the step).
  if (r1 == r0 || !(far > 1e-12 * squaredNorm(position[r1] - position[r0]))) return;
  tree.reference[0] = r0;
  tree.reference[1] = r1;
  tree.reference[2] = r2;
  referenceFrame(position, tree, tree.restAxes);
  const double grow = model.contact.rigidTreeMargin * smallest;
  for (std::int32_t k = tree.nodeBegin; k < tree.nodeEnd; ++k) {
    TreeNode& node = cache.nodes[k];
    const Vec3 r = node.center - position[r0];
    node.restCenter = {dot(r, tree.restAxes[0]), dot(r, tree.restAxes[1]),
                       dot(r, tree.restAxes[2])};
    node.radius += grow;
  }
  tree.rigid = true;
}

// A rigid tree moves as a whole: c = p_ref0 + Σ_k c_rest,k e_k (no refit).
void moveRigidTree(const std::vector<Vec3>& position, ContactScratch& cache,
                   const TreeObject& tree) {
  Vec3 axes[3];
  referenceFrame(position, tree, axes);
  const Vec3& origin = position[tree.reference[0]];
  for (std::int32_t k = tree.nodeBegin; k < tree.nodeEnd; ++k) {
    TreeNode& node = cache.nodes[k];
    node.center = origin + axes[0] * node.restCenter.x + axes[1] * node.restCenter.y +
                  axes[2] * node.restCenter.z;
  }
}

void refitSphereTrees(const Model& model, const std::vector<Vec3>& position,
                      ContactScratch& cache) {
  for (const TreeObject& tree : cache.trees) {
    if (tree.rigid) {
      moveRigidTree(position, cache, tree);
    } else {
      refitTree(model, position, cache, tree);
    }
  }
}

void refitTree(const Model& model, const std::vector<Vec3>& position, ContactScratch& cache,
               const TreeObject& tree) {
  for (auto k = tree.nodeEnd - 1; k >= tree.nodeBegin; --k) {
    TreeNode& node = cache.nodes[k];
    Vec3 low, high;
    if (node.isLeaf()) {
      // Centre of the box around the particles' spheres; radius reaches the farthest sphere.
      const std::int32_t* particles = cache.treeParticles.data() + node.first;
      low = high = position[particles[0]];
      double rMax = 0.0;
      for (std::int32_t q = 0; q < node.count; ++q) {
        const Vec3& p = position[particles[q]];
        low = {std::min(low.x, p.x), std::min(low.y, p.y), std::min(low.z, p.z)};
        high = {std::max(high.x, p.x), std::max(high.y, p.y), std::max(high.z, p.z)};
        rMax = std::max(rMax, model.radius[particles[q]]);
      }
      node.center = (low + high) * 0.5;
      double reach = 0.0;
      for (std::int32_t q = 0; q < node.count; ++q) {
        const std::int32_t i = particles[q];
        reach = std::max(reach, norm(position[i] - node.center) + model.radius[i]);
      }
      node.radius = reach;
    } else {
      const TreeNode* children = cache.nodes.data() + node.firstChild;
      low = children[0].center - Vec3{children[0].radius, children[0].radius, children[0].radius};
      high = children[0].center + Vec3{children[0].radius, children[0].radius, children[0].radius};
      for (std::int32_t c = 1; c < node.childCount; ++c) {
        const Vec3 r{children[c].radius, children[c].radius, children[c].radius};
        const Vec3 lo = children[c].center - r, hi = children[c].center + r;
        low = {std::min(low.x, lo.x), std::min(low.y, lo.y), std::min(low.z, lo.z)};
        high = {std::max(high.x, hi.x), std::max(high.y, hi.y), std::max(high.z, hi.z)};
      }
      node.center = (low + high) * 0.5;
      double reach = 0.0;
      for (std::int32_t c = 0; c < node.childCount; ++c) {
        reach = std::max(reach, norm(children[c].center - node.center) + children[c].radius);
      }
      node.radius = reach;
    }
  }
}

namespace {

// Whether a node belongs to an object with a surface mesh (MODEL §3.8).
inline bool facetedNode(const ContactScratch& cache, const TreeNode& node) {
  return node.object >= 0 && cache.tables->objectFaceted[node.object] != 0;
}

// Whether two nodes' spheres, each grown by pad / 2, overlap.
inline bool spheresTouch(ContactScratch& cache, const TreeNode& a, const TreeNode& b, double pad) {
  ++cache.stats.nodeTests;
  // Between two objects a faceted node reaches its surface (MODEL §3.8).
  const double reach =
      (a.object == b.object ? a.radius + b.radius : outerRadius(cache, a) + outerRadius(cache, b)) +
      pad;
  return squaredNorm(a.center - b.center) < reach * reach;
}

// MODEL §3.2 Locate_Contact: descend the larger node while the spheres (grown
// by pad / 2) touch; leafPair(a, b) for each pair of touching leaves.
template <class LeafPair>
void descendPair(ContactScratch& cache, std::int32_t nodeA, std::int32_t nodeB, double pad,
                 const LeafPair& leafPair) {
  const TreeNode& a = cache.nodes[nodeA];
  const TreeNode& b = cache.nodes[nodeB];
  if (!spheresTouch(cache, a, b, pad)) return;
  if (a.isLeaf() && b.isLeaf()) {
    leafPair(a, b);
    return;
  }
  if (b.isLeaf() || (!a.isLeaf() && a.radius >= b.radius)) {
    const std::int32_t first = a.firstChild, count = a.childCount;
    for (std::int32_t c = first; c < first + count; ++c)
      descendPair(cache, c, nodeB, pad, leafPair);
  } else {
    const std::int32_t first = b.firstChild, count = b.childCount;
    for (std::int32_t c = first; c < first + count; ++c)
      descendPair(cache, nodeA, c, pad, leafPair);
  }
}

// The pairs inside one node: leafSelf(leaf) for each leaf, leafPair(a, b) for
// each pair of touching leaves of different children.
template <class LeafSelf, class LeafPair>
void descendSelf(ContactScratch& cache, std::int32_t node, double pad, const LeafSelf& leafSelf,
                 const LeafPair& leafPair) {
  const TreeNode& n = cache.nodes[node];
  if (n.isLeaf()) {
    leafSelf(n);
    return;
  }
  const std::int32_t first = n.firstChild, count = n.childCount;
  for (std::int32_t c = first; c < first + count; ++c) {
    descendSelf(cache, c, pad, leafSelf, leafPair);
    for (std::int32_t d = c + 1; d < first + count; ++d) descendPair(cache, c, d, pad, leafPair);
  }
}

// The narrow phase of two leaves of the tree search.
void testLeafPair(const Model& model, const std::vector<Vec3>& position, ContactScratch& cache,
                  const TreeNode& a, const TreeNode& b) {
  if (a.object != b.object && (facetedNode(cache, a) || facetedNode(cache, b))) {
    leavesWithFacets(model, position, cache, a,
                     b);  // MODEL §3.8: particles or vertices on triangles
    return;
  }
  for (std::int32_t p = a.first; p < a.first + a.count; ++p) {
    for (std::int32_t q = b.first; q < b.first + b.count; ++q) {
      testParticlePair(model, position, cache, cache.treeParticles[p], cache.treeParticles[q]);
    }
  }
}

void testLeafSelf(const Model& model, const std::vector<Vec3>& position, ContactScratch& cache,
                  const TreeNode& n) {
  for (std::int32_t p = n.first; p < n.first + n.count; ++p) {
    for (std::int32_t q = p + 1; q < n.first + n.count; ++q) {
      testParticlePair(model, position, cache, cache.treeParticles[p], cache.treeParticles[q]);
    }
  }
}

// Appends (min, max) to the pair list when particles a, b are closer than
// r_a + r_b + pad.
inline void listParticlePair(const Model& model, const std::vector<Vec3>& position,
                             ContactScratch& cache, std::int32_t a, std::int32_t b, double pad) {
  const double reach = model.radius[a] + model.radius[b] + pad;
  if (squaredNorm(position[a] - position[b]) >= reach * reach) return;
  cache.treePairs.pairs.push_back({std::min(a, b), std::max(a, b)});
}

// The pair list's share of two leaves, or of one leaf with itself.
void listLeafPair(const Model& model, const std::vector<Vec3>& position, ContactScratch& cache,
                  const TreeNode& a, const TreeNode& b) {
  const double pad = cache.treePairs.skin;
  for (std::int32_t p = a.first; p < a.first + a.count; ++p)
    for (std::int32_t q = b.first; q < b.first + b.count; ++q)
      listParticlePair(model, position, cache, cache.treeParticles[p], cache.treeParticles[q], pad);
}

void listLeafSelf(const Model& model, const std::vector<Vec3>& position, ContactScratch& cache,
                  const TreeNode& n) {
  const double pad = cache.treePairs.skin;
  for (std::int32_t p = n.first; p < n.first + n.count; ++p)
    for (std::int32_t q = p + 1; q < n.first + n.count; ++q)
      listParticlePair(model, position, cache, cache.treeParticles[p], cache.treeParticles[q], pad);
}

}  // namespace

void treeVersusTree(const Model& model, const std::vector<Vec3>& position, ContactScratch& cache,
                    std::int32_t nodeA, std::int32_t nodeB) {
  descendPair(cache, nodeA, nodeB, 0.0, [&](const TreeNode& a, const TreeNode& b) {
    testLeafPair(model, position, cache, a, b);
  });
}

void treeSelf(const Model& model, const std::vector<Vec3>& position, ContactScratch& cache,
              std::int32_t node) {
  descendSelf(
      cache, node, 0.0, [&](const TreeNode& n) { testLeafSelf(model, position, cache, n); },
      [&](const TreeNode& a, const TreeNode& b) { testLeafPair(model, position, cache, a, b); });
}

bool treePairListApplies(const Model& model, const ContactScratch& cache) {
  if (cache.trees.empty() || !(model.contact.neighbourSkin > 0.0)) return false;
  for (const TreeObject& tree : cache.trees)
    if (tree.faceted) return false;  // their leaves meet on triangles (MODEL §3.8)
  return true;
}

double treePairSkin(const Model& model, const ContactScratch& cache) {
  double largest = 0.0;
  for (const std::int32_t i : cache.treeParticles) largest = std::max(largest, model.radius[i]);
  return model.contact.neighbourSkin * 2.0 * largest;
}

bool treePairListHolds(const Model& model, const std::vector<Vec3>& position,
                       const ContactScratch& cache) {
  // The skin follows from neighbourSkin and the radii (treePairSkin): with both
  // as at the build, it is the list's.
  const TreePairList& list = cache.treePairs;
  if (list.revision != cache.revision || list.skinFraction != model.contact.neighbourSkin ||
      !(list.skin > 0.0) || list.reference.size() != cache.treeParticles.size()) {
    return false;
  }
  // (1 - 1e-9): rounding in the distances cannot let a pair through.
  const double limit = 0.25 * list.skin * list.skin * (1.0 - 1e-9);
  bool holds = true;
  for (std::size_t k = 0; k < cache.treeParticles.size(); ++k) {
    const std::int32_t i = cache.treeParticles[k];
    holds &= squaredNorm(position[i] - list.reference[k]) <= limit;
    holds &= model.radius[i] == list.referenceRadius[k];
  }
  return holds;
}

void startTreePairList(const Model& model, const std::vector<Vec3>& position, double skin,
                       ContactScratch& cache) {
  TreePairList& list = cache.treePairs;
  list.revision = cache.revision;
  list.skin = skin;
  list.skinFraction = model.contact.neighbourSkin;
  list.pairs.clear();
  list.reference.resize(cache.treeParticles.size());
  list.referenceRadius.resize(cache.treeParticles.size());
  for (std::size_t k = 0; k < cache.treeParticles.size(); ++k) {
    const std::int32_t i = cache.treeParticles[k];
    list.reference[k] = position[i];
    list.referenceRadius[k] = model.radius[i];
  }
  ++list.builds;
  ++cache.stats.treePairListBuilds;
}

void listTreeVersusTree(const Model& model, const std::vector<Vec3>& position,
                        ContactScratch& cache, std::int32_t nodeA, std::int32_t nodeB) {
  descendPair(cache, nodeA, nodeB, cache.treePairs.skin, [&](const TreeNode& a, const TreeNode& b) {
    listLeafPair(model, position, cache, a, b);
  });
}

void listTreeSelf(const Model& model, const std::vector<Vec3>& position, ContactScratch& cache,
                  std::int32_t node) {
  descendSelf(
      cache, node, cache.treePairs.skin,
      [&](const TreeNode& n) { listLeafSelf(model, position, cache, n); },
      [&](const TreeNode& a, const TreeNode& b) { listLeafPair(model, position, cache, a, b); });
}

void testTreePairs(const Model& model, const std::vector<Vec3>& position, ContactScratch& cache) {
  for (const auto& pair : cache.treePairs.pairs)
    testParticlePair(model, position, cache, pair[0], pair[1]);
}

void treeVersusParticle(const Model& model, const std::vector<Vec3>& position,
                        ContactScratch& cache, std::int32_t node, std::int32_t particle) {
  const TreeNode& n = cache.nodes[node];
  ++cache.stats.nodeTests;
  const double reach = outerRadius(cache, n) + model.radius[particle];
  if (squaredNorm(n.center - position[particle]) >= reach * reach) return;
  if (n.isLeaf()) {
    if (facetedNode(cache, n)) {
      particleOnLeafFacets(cache, n, particle);  // MODEL §3.8
      return;
    }
    for (std::int32_t p = n.first; p < n.first + n.count; ++p) {
      testParticlePair(model, position, cache, cache.treeParticles[p], particle);
    }
    return;
  }
  const std::int32_t first = n.firstChild, count = n.childCount;
  for (std::int32_t c = first; c < first + count; ++c) {
    treeVersusParticle(model, position, cache, c, particle);
  }
}

void treeVersusEnvironment(const Model& model, const std::vector<Vec3>& position,
                           ContactScratch& cache, std::int32_t node, std::int32_t item) {
  const TreeNode& n = cache.nodes[node];
  if (environmentFarFrom(model.environment, item, n.center, outerRadius(cache, n),
                         cache.tables->environmentReaches[item])) {
    return;
  }
  if (n.isLeaf()) {
    if (facetedNode(cache, n)) {
      leafVerticesOnEnvironment(model, cache, n, item);  // MODEL §3.8: the true surface
      return;
    }
    for (std::int32_t p = n.first; p < n.first + n.count; ++p) {
      const std::int32_t i = cache.treeParticles[p];
      if (cache.tables->movable[i] == 0 || cache.tables->rimOf[i] >= 0) continue;
      ++cache.stats.environmentTests;
      Contact c;
      if (touchesEnvironment(model.environment, i, position[i], model.radius[i], item, c))
        cache.treeContacts.push_back(c);
    }
    return;
  }
  const std::int32_t first = n.firstChild, count = n.childCount;
  for (std::int32_t c = first; c < first + count; ++c) {
    treeVersusEnvironment(model, position, cache, c, item);
  }
}

}  // namespace robophi
