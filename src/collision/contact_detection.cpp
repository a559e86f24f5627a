// Contact detection (MODEL §3.2): a uniform grid over the single small
// particles (the broad phase of many one-particle objects) that builds their
// Verlet neighbour list (kept while no particle has moved half its skin), sort-and-sweep over
// the root spheres of the tree objects, and the sphere-tree searches between
// them. The result is sorted by (particle, partner): deterministic by construction.
#include <algorithm>
#include <cmath>
#include <limits>

#include "collision/contact_stage.h"
#include "collision/environment.h"
#include "collision/edges.h"
#include "collision/facets.h"
#include "collision/rim_contact.h"
#include "collision/sphere_tree.h"
#include "core/parallel.h"

namespace robophi {

namespace {

// Cells are addressed densely when the particles' box holds few enough cells,
// otherwise through a hash table (each entry keeps its cell key to reject
// collisions).
constexpr std::int64_t kCoordinateLimit = 1 << 20;

struct GridFrame {
  bool dense = true;
  Vec3 origin;
  double inverseCell = 0.0;
  std::int64_t nx = 0, ny = 0, nz = 0;
  std::uint64_t mask = 0;  // hash mode: table size - 1
};

inline std::int64_t cellCoordinate(double value, double origin, double inverseCell) {
  const double c = std::floor((value - origin) * inverseCell);
  return static_cast<std::int64_t>(
      std::clamp(c, -static_cast<double>(kCoordinateLimit), static_cast<double>(kCoordinateLimit)));
}

inline std::int64_t packCell(std::int64_t ix, std::int64_t iy, std::int64_t iz) {
  constexpr std::int64_t kMask = (1 << 21) - 1;
  return (ix & kMask) | ((iy & kMask) << 21) | ((iz & kMask) << 42);
}

inline std::uint64_t hashCell(std::int64_t key) {
  auto h = static_cast<std::uint64_t>(key);
  h ^= h >> 31;
  h *= 0x9E3779B97F4A7C15ULL;
  h ^= h >> 29;
  return h;
}

// Builds the grid of cache.tables->gridParticles, cells of `cellSize` (m):
// counting sort into cells.
GridFrame buildGrid(const Model& model, const std::vector<Vec3>& position, double cellSize,
                    ContactScratch& cache) {
  GridFrame g;
  const auto count = static_cast<std::int32_t>(cache.tables->gridParticles.size());
  if (count == 0 || !(cellSize > 0.0)) return g;
  g.inverseCell = 1.0 / cellSize;
  Vec3 low = position[cache.tables->gridParticles[0]], high = low;
  bool finite = true;
  for (std::int32_t k = 0; k < count; ++k) {
    const Vec3& p = position[cache.tables->gridParticles[k]];
    finite = finite && isFinite(p);
    low = {std::min(low.x, p.x), std::min(low.y, p.y), std::min(low.z, p.z)};
    high = {std::max(high.x, p.x), std::max(high.y, p.y), std::max(high.z, p.z)};
  }
  g.origin = low;
  const double cells = (std::floor((high.x - low.x) * g.inverseCell) + 1.0) *
                       (std::floor((high.y - low.y) * g.inverseCell) + 1.0) *
                       (std::floor((high.z - low.z) * g.inverseCell) + 1.0);
  const double denseLimit = std::max(8.0 * count, 4096.0);
  std::size_t tableSize = 0;
  if (finite && cells <= denseLimit) {
    g.dense = true;
    g.nx = static_cast<std::int64_t>(std::floor((high.x - low.x) * g.inverseCell)) + 1;
    g.ny = static_cast<std::int64_t>(std::floor((high.y - low.y) * g.inverseCell)) + 1;
    g.nz = static_cast<std::int64_t>(std::floor((high.z - low.z) * g.inverseCell)) + 1;
    tableSize = static_cast<std::size_t>(g.nx * g.ny * g.nz);
  } else {
    g.dense = false;
    tableSize = 1;
    while (tableSize < 2 * static_cast<std::size_t>(count)) tableSize <<= 1;
    g.mask = tableSize - 1;
  }
  cache.cellOfItem.resize(static_cast<std::size_t>(count));
  cache.sortedCell.resize(static_cast<std::size_t>(count));
  cache.cellStart.assign(tableSize + 1, 0);
  for (std::int32_t k = 0; k < count; ++k) {
    const Vec3& p = position[cache.tables->gridParticles[k]];
    const std::int64_t ix = cellCoordinate(p.x, g.origin.x, g.inverseCell);
    const std::int64_t iy = cellCoordinate(p.y, g.origin.y, g.inverseCell);
    const std::int64_t iz = cellCoordinate(p.z, g.origin.z, g.inverseCell);
    std::int64_t bucket = 0;
    if (g.dense) {
      bucket = (iz * g.ny + iy) * g.nx + ix;
      cache.sortedCell[k] = bucket;
    } else {
      const std::int64_t key = packCell(ix, iy, iz);
      cache.sortedCell[k] = key;
      bucket = static_cast<std::int64_t>(hashCell(key) & g.mask);
    }
    cache.cellOfItem[k] = bucket;
    ++cache.cellStart[static_cast<std::size_t>(bucket) + 1];
  }
  for (std::size_t c = 0; c < tableSize; ++c) cache.cellStart[c + 1] += cache.cellStart[c];
  // Scatter in particle order (stable): a cell lists its particles ascending.
  cache.sortedParticle.resize(static_cast<std::size_t>(count));
  cache.sortedData.resize(4 * static_cast<std::size_t>(count));
  std::vector<std::int64_t>& keyOfSlot = cache.sortedKey;
  keyOfSlot.resize(static_cast<std::size_t>(count));
  cache.sortedItem.assign(cache.cellStart.begin(), cache.cellStart.end() - 1);  // fill pointers
  for (std::int32_t k = 0; k < count; ++k) {
    const std::int32_t slot = cache.sortedItem[static_cast<std::size_t>(cache.cellOfItem[k])]++;
    const std::int32_t i = cache.tables->gridParticles[k];
    cache.sortedParticle[slot] = i;
    keyOfSlot[slot] = cache.sortedCell[k];
    double* data = cache.sortedData.data() + 4 * static_cast<std::size_t>(slot);
    data[0] = position[i].x;
    data[1] = position[i].y;
    data[2] = position[i].z;
    data[3] = model.radius[i];
  }
  return g;
}

// Appends to work.row the grid particles j > i in slots [begin, end) closer
// than r + r_j + skin to particle i (at p, radius r). In hash mode only slots of
// cell `key`.
inline void scanSlots(const ContactScratch& cache, GridChunk& work, std::int32_t i, const Vec3& p,
                      double r, double skin, std::int32_t begin, std::int32_t end, bool checkKey,
                      std::int64_t key) {
  const double* data = cache.sortedData.data();
  // Each slot is written and kept by the tests' outcome, not branched on:
  // whether a slot is a partner is a coin toss for the branch predictor.
  const std::size_t first = work.row.size();
  work.row.resize(first + static_cast<std::size_t>(std::max(end - begin, 0)));
  std::int32_t* out = work.row.data() + first;
  for (std::int32_t s = begin; s < end; ++s) {
    const std::int32_t j = cache.sortedParticle[s];
    const bool tested = j > i && (!checkKey || cache.sortedKey[s] == key);
    work.pairTests += static_cast<std::int64_t>(tested);
    const double* q = data + 4 * static_cast<std::size_t>(s);
    const double dx = p.x - q[0], dy = p.y - q[1], dz = p.z - q[2];
    const double reach = r + q[3] + skin;
    const bool near = !(dx * dx + dy * dy + dz * dz >= reach * reach);
    *out = j;
    out += static_cast<std::ptrdiff_t>(tested & near);
  }
  work.row.resize(static_cast<std::size_t>(out - work.row.data()));
}

// The partners j > i of grid particle i within r_i + r_j + skin, from its 27
// neighbour cells (cells of at least the largest diameter + skin), into
// work.row (unsorted).
void gridNeighbours(const Model& model, const GridFrame& g, const ContactScratch& cache,
                    GridChunk& work, std::int32_t i, const Vec3& p, double skin) {
  const double r = model.radius[i];
  const std::int64_t ix = cellCoordinate(p.x, g.origin.x, g.inverseCell);
  const std::int64_t iy = cellCoordinate(p.y, g.origin.y, g.inverseCell);
  const std::int64_t iz = cellCoordinate(p.z, g.origin.z, g.inverseCell);
  if (g.dense) {
    const std::int64_t x0 = std::max<std::int64_t>(ix - 1, 0), x1 = std::min(ix + 1, g.nx - 1);
    for (std::int64_t z = std::max<std::int64_t>(iz - 1, 0); z <= std::min(iz + 1, g.nz - 1); ++z) {
      for (std::int64_t y = std::max<std::int64_t>(iy - 1, 0); y <= std::min(iy + 1, g.ny - 1);
           ++y) {
        const std::int64_t row = (z * g.ny + y) * g.nx;
        scanSlots(cache, work, i, p, r, skin, cache.cellStart[static_cast<std::size_t>(row + x0)],
                  cache.cellStart[static_cast<std::size_t>(row + x1 + 1)], false, 0);
      }
    }
    return;
  }
  for (std::int64_t z = iz - 1; z <= iz + 1; ++z) {
    for (std::int64_t y = iy - 1; y <= iy + 1; ++y) {
      for (std::int64_t x = ix - 1; x <= ix + 1; ++x) {
        const std::int64_t key = packCell(x, y, z);
        const std::size_t bucket = hashCell(key) & g.mask;
        scanSlots(cache, work, i, p, r, skin, cache.cellStart[bucket], cache.cellStart[bucket + 1],
                  true, key);
      }
    }
  }
}

// Whether the neighbour list still holds every touching grid pair: built for
// this revision, and no grid particle moved more than skin / 2 since (nor
// changed its radius). A non-finite position fails too.
bool neighbourListHolds(const Model& model, const std::vector<Vec3>& position, double skin,
                        const ContactScratch& cache) {
  const NeighbourList& list = cache.neighbours;
  const std::vector<std::int32_t>& grid = cache.tables->gridParticles;
  if (list.revision != cache.revision || list.skin != skin || skin <= 0.0 ||
      list.referenceX.size() != grid.size()) {
    return false;
  }
  // (1 - 1e-9): rounding in the distances cannot let a pair through.
  const double limit = 0.25 * skin * skin * (1.0 - 1e-9);
  bool holds = true;
  const auto count = grid.size();
  for (std::size_t k = 0; k < count; ++k) {
    const std::int32_t i = grid[k];
    const double dx = position[i].x - list.referenceX[k];
    const double dy = position[i].y - list.referenceY[k];
    const double dz = position[i].z - list.referenceZ[k];
    holds &= dx * dx + dy * dy + dz * dz <= limit;
    holds &= model.radius[i] == list.referenceRadius[k];
  }
  return holds;
}

// The number of chunks of the grid particles (of detail::kParallelChunk each).
std::int64_t gridChunkCount(const ContactScratch& cache) {
  const auto count = static_cast<std::int64_t>(cache.tables->gridParticles.size());
  return (count + detail::kParallelChunk - 1) / detail::kParallelChunk;
}

// The grid particles' chunks (of detail::kParallelChunk) on up to `threads`
// threads: body(work, begin, end) for each.
template <class Body>
void forGridChunks(int threads, ContactScratch& cache, const Body& body) {
  const auto count = static_cast<std::int64_t>(cache.tables->gridParticles.size());
  const std::int64_t chunks = gridChunkCount(cache);
  if (cache.gridChunks.size() < static_cast<std::size_t>(chunks))
    cache.gridChunks.resize(static_cast<std::size_t>(chunks));
  struct Context {
    const Body* body;
    GridChunk* chunks;
    std::int64_t count;
  } context{&body, cache.gridChunks.data(), count};
  detail::runChunks(
      count >= detail::kParallelMinimum ? threads : 1, chunks,
      [](void* raw, std::int64_t c) {
        const Context& x = *static_cast<const Context*>(raw);
        GridChunk& work = x.chunks[c];
        work.pairTests = 0;
        work.environmentTests = 0;
        (*x.body)(work, c * detail::kParallelChunk,
                  std::min(x.count, (c + 1) * detail::kParallelChunk));
      },
      &context);
}

// Rebuilds the neighbour list from `grid` (cells of the largest diameter + skin).
void buildNeighbourList(const Model& model, const std::vector<Vec3>& position, const GridFrame& g,
                        double skin, int threads, ContactScratch& cache) {
  NeighbourList& list = cache.neighbours;
  const std::vector<std::int32_t>& grid = cache.tables->gridParticles;
  const auto count = grid.size();
  list.revision = cache.revision;
  list.skin = skin;
  ++list.builds;
  ++cache.stats.neighbourListBuilds;
  list.referenceX.resize(count);
  list.referenceY.resize(count);
  list.referenceZ.resize(count);
  list.referenceRadius.resize(count);
  list.start.resize(count + 1);
  forGridChunks(threads, cache, [&](GridChunk& work, std::int64_t begin, std::int64_t end) {
    work.partners.clear();
    work.rowEnds.clear();
    for (auto k = static_cast<std::size_t>(begin); k < static_cast<std::size_t>(end); ++k) {
      const std::int32_t i = grid[k];
      const Vec3& p = position[i];
      list.referenceX[k] = p.x;
      list.referenceY[k] = p.y;
      list.referenceZ[k] = p.z;
      list.referenceRadius[k] = model.radius[i];
      work.row.clear();
      gridNeighbours(model, g, cache, work, i, p, skin);
      std::sort(work.row.begin(), work.row.end());
      work.partners.insert(work.partners.end(), work.row.begin(), work.row.end());
      work.rowEnds.push_back(static_cast<std::int32_t>(work.partners.size()));
    }
  });
  list.partner.clear();
  list.start[0] = 0;
  std::size_t k = 0;
  for (std::int64_t c = 0; c < gridChunkCount(cache); ++c) {
    const GridChunk& work = cache.gridChunks[static_cast<std::size_t>(c)];
    const auto offset = static_cast<std::int32_t>(list.partner.size());
    list.partner.insert(list.partner.end(), work.partners.begin(), work.partners.end());
    for (const std::int32_t rowEnd : work.rowEnds) list.start[++k] = offset + rowEnd;
    cache.stats.pairTests += work.pairTests;
  }
}

// Room for `more` seeds after a chunk's finds (GridChunk::seeds, grown only).
inline ContactSeed* seedRoom(GridChunk& work, std::size_t more) {
  if (work.seeds.size() < work.seedCount + more) work.seeds.resize(work.seedCount + more);
  return work.seeds.data() + work.seedCount;
}

inline void addSeed(GridChunk& work, const ContactSeed& seed) {
  *seedRoom(work, 1) = seed;
  ++work.seedCount;
}

// Appends to work.seeds the touching partners of grid particle k of the
// neighbour list (ascending partner): bare pairs, built by the contact stage.
inline void listedContacts(const Model& model, const std::vector<Vec3>& position, std::int32_t k,
                           std::int32_t i, const ContactScratch& cache, GridChunk& work) {
  const NeighbourList& list = cache.neighbours;
  const Vec3 p = position[i];
  const double r = model.radius[i];
  const std::int32_t begin = list.start[k], end = list.start[k + 1];
  work.pairTests += end - begin;
  const ContactTables& tables = *cache.tables;
  if (tables.movable[i] != 0 && tables.exclusionStart[i] == tables.exclusionStart[i + 1]) {
    // The common row (i moves, no connector ties it): every partner within
    // reach touches. Each is written and kept by the test's outcome, not
    // branched on: about half the listed partners touch, a coin toss for the
    // branch predictor.
    ContactSeed* const first = seedRoom(work, static_cast<std::size_t>(end - begin));
    ContactSeed* out = first;
    for (std::int32_t s = begin; s < end; ++s) {
      const std::int32_t j = list.partner[s];
      const Vec3& q = position[j];
      const double dx = p.x - q.x, dy = p.y - q.y, dz = p.z - q.z;
      const double reach = r + model.radius[j];
      const bool touching = !(dx * dx + dy * dy + dz * dz >= reach * reach);  // (as below)
      *out = ContactSeed::pair(i, j);
      out += static_cast<std::ptrdiff_t>(touching);
    }
    work.seedCount += static_cast<std::size_t>(out - first);
    return;
  }
  for (std::int32_t s = begin; s < end; ++s) {
    const std::int32_t j = list.partner[s];
    const Vec3& q = position[j];
    const double dx = p.x - q.x, dy = p.y - q.y, dz = p.z - q.z;
    const double reach = r + model.radius[j];
    if (dx * dx + dy * dy + dz * dz >= reach * reach) continue;
    if (tables.movable[i] == 0 && tables.movable[j] == 0) continue;
    if (excluded(*cache.tables, i, j) || sameRigidBody(tables, i, j)) continue;
    addSeed(work, ContactSeed::pair(i, j));
  }
}

// Particle i against every environment item, appended to work.seeds (the
// contacts to work.found) in key order: Contact::key() puts item e at other =
// -1 - e, so the last item first. (In item order, a ball touching two items
// was out of key order: the history merge passed over the second item's record
// when the first's contact started, and its friction anchor restarted.)
inline void particleVersusEnvironment(const Model& model, const Vec3& p, std::int32_t i,
                                      const ContactScratch& cache, GridChunk& work) {
  const std::int32_t items = model.environment.itemCount();
  const double r = model.radius[i];
  for (std::int32_t e = items - 1; e >= 0; --e) {
    // Cheap cull: the particle's sphere must reach the item's bounding box.
    const Vec3& low = cache.tables->environmentLow[e];
    const Vec3& high = cache.tables->environmentHigh[e];
    // (Above a heightfield, its distance is the vertical gap times n_z: reach r · steepness.)
    if (p.x + r < low.x || p.x - r > high.x || p.y + r < low.y || p.y - r > high.y ||
        p.z + r < low.z || p.z - r * cache.tables->environmentReaches[e].steepness > high.z) {
      continue;
    }
    ++work.environmentTests;
    // (The probe is written only when it touches: nothing to clear per test.)
    if (touchesEnvironment(model.environment, i, p, r, e, work.probe)) {
      addSeed(work, ContactSeed::found(work.probe, static_cast<std::int32_t>(work.found.size())));
      work.found.push_back(work.probe);
    }
  }
}

// Tree objects against the grid particles near their root sphere.
void treesVersusGrid(const Model& model, const std::vector<Vec3>& position, const GridFrame& g,
                     ContactScratch& cache) {
  if (cache.tables->gridParticles.empty()) return;
  const double h = cache.tables->cellSize;
  for (const TreeObject& tree : cache.trees) {
    const TreeNode& root = cache.nodes[tree.rootNode];
    const double reach = outerRadius(cache, root) + 0.5 * h;
    const Vec3 lo = root.center - Vec3{reach, reach, reach};
    const Vec3 hi = root.center + Vec3{reach, reach, reach};
    const auto visit = [&](std::int32_t begin, std::int32_t end, bool checkKey, std::int64_t key) {
      for (std::int32_t s = begin; s < end; ++s) {
        if (checkKey && cache.sortedKey[s] != key) continue;
        const std::int32_t j = cache.sortedParticle[s];
        if (tree.allFixed && cache.tables->movable[j] == 0) continue;
        treeVersusParticle(model, position, cache, tree.rootNode, j);
      }
    };
    const std::int64_t x0 = cellCoordinate(lo.x, g.origin.x, g.inverseCell);
    const std::int64_t y0 = cellCoordinate(lo.y, g.origin.y, g.inverseCell);
    const std::int64_t z0 = cellCoordinate(lo.z, g.origin.z, g.inverseCell);
    const std::int64_t x1 = cellCoordinate(hi.x, g.origin.x, g.inverseCell);
    const std::int64_t y1 = cellCoordinate(hi.y, g.origin.y, g.inverseCell);
    const std::int64_t z1 = cellCoordinate(hi.z, g.origin.z, g.inverseCell);
    if (g.dense) {
      const std::int64_t xa = std::max<std::int64_t>(x0, 0), xb = std::min(x1, g.nx - 1);
      if (xa > xb) continue;
      for (std::int64_t z = std::max<std::int64_t>(z0, 0); z <= std::min(z1, g.nz - 1); ++z) {
        for (std::int64_t y = std::max<std::int64_t>(y0, 0); y <= std::min(y1, g.ny - 1); ++y) {
          const std::int64_t row = (z * g.ny + y) * g.nx;
          visit(cache.cellStart[static_cast<std::size_t>(row + xa)],
                cache.cellStart[static_cast<std::size_t>(row + xb + 1)], false, 0);
        }
      }
      continue;
    }
    const double cells = static_cast<double>(x1 - x0 + 1) * static_cast<double>(y1 - y0 + 1) *
                         static_cast<double>(z1 - z0 + 1);
    if (cells > static_cast<double>(cache.tables->gridParticles.size())) {
      visit(0, static_cast<std::int32_t>(cache.sortedParticle.size()), false, 0);
      continue;
    }
    for (std::int64_t z = z0; z <= z1; ++z) {
      for (std::int64_t y = y0; y <= y1; ++y) {
        for (std::int64_t x = x0; x <= x1; ++x) {
          const std::int64_t key = packCell(x, y, z);
          const std::size_t bucket = hashCell(key) & g.mask;
          visit(cache.cellStart[bucket], cache.cellStart[bucket + 1], true, key);
        }
      }
    }
  }
}

// Sort-and-sweep along x over the tree objects' root spheres (grown by pad / 2),
// then visit(rootA, rootB) for each pair that may touch.
template <class Visit>
void sweepTrees(ContactScratch& cache, double pad, const Visit& visit) {
  const auto count = static_cast<std::int32_t>(cache.trees.size());
  if (count < 2) return;
  auto& order = cache.sweepOrder;
  order.resize(static_cast<std::size_t>(count));
  for (std::int32_t t = 0; t < count; ++t) order[t] = t;
  const auto minX = [&](std::int32_t t) {
    const TreeNode& root = cache.nodes[cache.trees[t].rootNode];
    return root.center.x - outerRadius(cache, root) - 0.5 * pad;
  };
  std::sort(order.begin(), order.end(), [&](std::int32_t a, std::int32_t b) {
    const double xa = minX(a), xb = minX(b);
    return xa < xb || (xa == xb && a < b);
  });
  for (std::int32_t k = 0; k < count; ++k) {
    const TreeObject& a = cache.trees[order[k]];
    const TreeNode& rootA = cache.nodes[a.rootNode];
    const double maxX = rootA.center.x + outerRadius(cache, rootA) + 0.5 * pad;
    for (std::int32_t l = k + 1; l < count && minX(order[l]) <= maxX; ++l) {
      const TreeObject& b = cache.trees[order[l]];
      if (a.allFixed && b.allFixed) continue;
      if (objectsExcluded(*cache.tables, a.object, b.object)) continue;
      visit(a.rootNode, b.rootNode);
    }
  }
}

// Whether the tree objects' pair list applies and holds at `position`.
bool treePairListKept(const Model& model, const std::vector<Vec3>& position,
                      const ContactScratch& cache) {
  return treePairListApplies(model, cache) && treePairListHolds(model, position, cache);
}

// The tree objects against each other and themselves (self-collision): through
// their pair list when it applies (rebuilt unless `listKept`), else by the tree
// search at every evaluation. The same finds either way.
void treesVersusTrees(const Model& model, const std::vector<Vec3>& position, bool listKept,
                      ContactScratch& cache) {
  const auto selfSearched = [&](const TreeObject& tree) {
    return model.contact.selfCollision && !tree.allFixed && !tree.rigid;
  };
  if (!treePairListApplies(model, cache)) {
    sweepTrees(cache, 0.0, [&](std::int32_t rootA, std::int32_t rootB) {
      treeVersusTree(model, position, cache, rootA, rootB);
    });
    for (const TreeObject& tree : cache.trees)
      if (selfSearched(tree)) treeSelf(model, position, cache, tree.rootNode);
    return;
  }
  if (!listKept) {
    startTreePairList(model, position, treePairSkin(model, cache), cache);
    sweepTrees(cache, cache.treePairs.skin, [&](std::int32_t rootA, std::int32_t rootB) {
      listTreeVersusTree(model, position, cache, rootA, rootB);
    });
    for (const TreeObject& tree : cache.trees)
      if (selfSearched(tree)) listTreeSelf(model, position, cache, tree.rootNode);
  }
  testTreePairs(model, position, cache);
}

// The last evaluation's finds and counts, cleared.
void clearFinds(ContactScratch& cache) {
  cache.stats = ContactStats{};
  cache.seeds.clear();
  cache.detectedContacts.clear();
  cache.treeContacts.clear();
  cache.facetCandidates.clear();
  cache.edgeCandidates.clear();
}

}  // namespace

void detectContacts(const Model& model, const std::vector<Vec3>& position,
                    const std::vector<Vec3>& velocity, int threads,
                    const std::vector<Contact>& previous, ContactScratch& cache) {
  clearFinds(cache);
  // The trees' node spheres are refitted when a search reads them: the tree
  // search, a rebuild of the trees' pair list, or the grid cells and
  // environment items the trees search at every evaluation.
  const std::int32_t items = model.environment.itemCount();
  const bool treeListKept = treePairListKept(model, position, cache);
  if (!treeListKept || !cache.tables->gridParticles.empty() || items > 0)
    refitSphereTrees(model, position, cache);
  updateSurfacePositions(model, position, cache);  // MODEL §3.8
  if (!cache.tables->edges.empty()) updateEdgeShapes(cache);
  // Grid particles: the neighbour list (rebuilt when a particle has moved more
  // than half the skin), then each particle's touching partners in ascending
  // order, then the environment. The trees search the grid at every evaluation.
  const double skin = std::max(0.0, model.contact.neighbourSkin) * cache.tables->cellSize;
  const bool listHolds = neighbourListHolds(model, position, skin, cache);
  GridFrame grid;
  if (!listHolds || !cache.trees.empty()) {
    grid = buildGrid(model, position, cache.tables->cellSize + skin, cache);
  }
  if (!listHolds) buildNeighbourList(model, position, grid, skin, threads, cache);
  const std::vector<std::int32_t>& gridParticles = cache.tables->gridParticles;
  forGridChunks(threads, cache, [&](GridChunk& work, std::int64_t begin, std::int64_t end) {
    work.seedCount = 0;
    work.found.clear();
    for (auto k = static_cast<std::size_t>(begin); k < static_cast<std::size_t>(end); ++k) {
      const std::int32_t i = gridParticles[k];
      listedContacts(model, position, static_cast<std::int32_t>(k), i, cache, work);
      if (cache.tables->movable[i] != 0)
        particleVersusEnvironment(model, position[i], i, cache, work);
    }
  });
  for (std::int64_t c = 0; c < gridChunkCount(cache); ++c) {
    const GridChunk& work = cache.gridChunks[static_cast<std::size_t>(c)];
    const auto offset = static_cast<std::int32_t>(cache.detectedContacts.size());
    for (std::size_t s = 0; s < work.seedCount; ++s) {
      ContactSeed seed = work.seeds[s];
      if (seed.full >= 0) seed.full += offset;
      cache.seeds.push_back(seed);
    }
    cache.detectedContacts.insert(cache.detectedContacts.end(), work.found.begin(),
                                  work.found.end());
    cache.stats.pairTests += work.pairTests;
    cache.stats.environmentTests += work.environmentTests;
  }

  // Tree objects: against each other, themselves, the grid and the environment.
  treesVersusTrees(model, position, treeListKept, cache);
  treesVersusGrid(model, position, grid, cache);
  for (const TreeObject& tree : cache.trees) {
    if (tree.allFixed) continue;
    for (std::int32_t e = 0; e < items; ++e) {
      treeVersusEnvironment(model, position, cache, tree.rootNode, e);
    }
  }
  rimsVersusEnvironment(model, position, cache);
  resolveFacetCandidates(model, position, cache);  // MODEL §3.8: closest triangles
  resolveEdgeCandidates(model, velocity, previous, cache);  // MODEL §3.8: crossed edges
  if (!cache.treeContacts.empty()) {
    // Merged in (as std::merge: on equal keys the grid's first).
    const auto byKey = [](const Contact& x, const Contact& y) { return x.key() < y.key(); };
    std::sort(cache.treeContacts.begin(), cache.treeContacts.end(), byKey);
    std::vector<ContactSeed>& merged = cache.mergedSeeds;
    merged.clear();
    merged.reserve(cache.seeds.size() + cache.treeContacts.size());
    std::size_t s = 0;
    for (std::size_t t = 0; t < cache.treeContacts.size(); ++t) {
      const Contact::Key key = cache.treeContacts[t].key();
      while (s < cache.seeds.size() && !(key < cache.seeds[s].key))
        merged.push_back(cache.seeds[s++]);
      merged.push_back(
          ContactSeed::found(cache.treeContacts[t], -2 - static_cast<std::int32_t>(t)));
    }
    merged.insert(merged.end(), cache.seeds.begin() + static_cast<std::ptrdiff_t>(s),
                  cache.seeds.end());
    std::swap(cache.seeds, merged);
  }
}

}  // namespace robophi
