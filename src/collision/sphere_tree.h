#pragma once
// The sphere hierarchy of MODEL §3.2: an octree over each object's particles,
// every node enclosed by a sphere refitted bottom-up at every step, and the
// recursive tree-vs-tree, self and tree-vs-environment searches.

#include <vector>

#include "collision/contact_tables.h"

namespace robophi {

/// Builds the octree topology of every tree object from the positions.
void buildSphereTrees(const Model& model, const std::vector<Vec3>& position, ContactScratch& cache);

/// Refits every node's sphere to the current positions, leaves first: each
/// sphere encloses its particles' spheres, so a deforming object misses nothing.
void refitSphereTrees(const Model& model, const std::vector<Vec3>& position, ContactScratch& cache);

/// Refits one (non-rigid) tree's spheres, leaves first.
void refitTree(const Model& model, const std::vector<Vec3>& position, ContactScratch& cache,
               const TreeObject& tree);
/// A rigid tree (ObjectInfo::rigid): chooses its three reference particles,
/// stores every node centre in their frame and grows the spheres by
/// ContactSettings::rigidTreeMargin × the smallest radius; refitSphereTrees
/// then moves the nodes by the frame's motion instead of refitting them.
void setUpRigidTree(const Model& model, const std::vector<Vec3>& position, ContactScratch& cache,
                    TreeObject& tree);
/// The orthonormal frame of a rigid tree's reference particles at `position`.
void referenceFrame(const std::vector<Vec3>& position, const TreeObject& tree, Vec3 axes[3]);
void moveRigidTree(const std::vector<Vec3>& position, ContactScratch& cache,
                   const TreeObject& tree);

/// The particles a, b (a != b) that may touch: appended to cache.treeContacts
/// as (min, max) when |p_a - p_b| < r_a + r_b and no connector ties them.
void treeVersusTree(const Model& model, const std::vector<Vec3>& position, ContactScratch& cache,
                    std::int32_t nodeA, std::int32_t nodeB);
/// Pairs inside one object (self-collision).
void treeSelf(const Model& model, const std::vector<Vec3>& position, ContactScratch& cache,
              std::int32_t node);
/// The tree objects' pair list (TreePairList): whether it applies (trees, a
/// skin, no faceted tree), its skin (ContactSettings::neighbourSkin × the
/// largest tree particle's diameter), whether it still holds at `position`, and
/// its build: startTreePairList, then listTreeVersusTree and listTreeSelf where
/// the tree search would call treeVersusTree and treeSelf. testTreePairs runs
/// the narrow phase over the list: the same finds as the tree search.
bool treePairListApplies(const Model& model, const ContactScratch& cache);
double treePairSkin(const Model& model, const ContactScratch& cache);
bool treePairListHolds(const Model& model, const std::vector<Vec3>& position,
                       const ContactScratch& cache);
void startTreePairList(const Model& model, const std::vector<Vec3>& position, double skin,
                       ContactScratch& cache);
void listTreeVersusTree(const Model& model, const std::vector<Vec3>& position,
                        ContactScratch& cache, std::int32_t nodeA, std::int32_t nodeB);
void listTreeSelf(const Model& model, const std::vector<Vec3>& position, ContactScratch& cache,
                  std::int32_t node);
void testTreePairs(const Model& model, const std::vector<Vec3>& position, ContactScratch& cache);

/// Pairs between a tree and one particle outside it.
void treeVersusParticle(const Model& model, const std::vector<Vec3>& position,
                        ContactScratch& cache, std::int32_t node, std::int32_t particle);
/// Contacts between a tree's particles and environment item `item`.
void treeVersusEnvironment(const Model& model, const std::vector<Vec3>& position,
                           ContactScratch& cache, std::int32_t node, std::int32_t item);

/// The narrow-phase test of particles a, b: appends a contact when they touch.
inline void testParticlePair(const Model& model, const std::vector<Vec3>& position,
                             ContactScratch& cache, std::int32_t a, std::int32_t b) {
  if (a > b) std::swap(a, b);
  ++cache.stats.pairTests;
  const Vec3 r = position[a] - position[b];
  const double reach = model.radius[a] + model.radius[b];
  if (squaredNorm(r) >= reach * reach) return;
  // Two particles that do not move under loads never touch (a rigid tree's carried
  // particles move with their body: ContactTables::movable).
  if (cache.tables->movable[a] == 0 && cache.tables->movable[b] == 0) return;
  if (excluded(*cache.tables, a, b) || sameRigidBody(*cache.tables, a, b)) return;
  Contact c;
  c.a = a;
  c.other = b;
  cache.treeContacts.push_back(c);
}

}  // namespace robophi
