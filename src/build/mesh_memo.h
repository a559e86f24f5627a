#pragma once
// What is worked out from a mesh alone (its volume, its lattice at a spacing),
// kept for the next shape with the same triangles: a robot's links share mesh
// files, the rigid importer places a robot twice (the trial finds its lowest
// point), the particle importer tries up to ten spacings, and a process that
// loads many models (a sweep, the Python bindings, the fuzz targets) meets the
// same meshes again. Keyed by the mesh's exact bytes (and a spacing's bits) and
// compared in full on a hit, so a kept value is the one the work would give and
// results never depend on what was kept. Bounded in bytes, the least recently
// used mesh dropped first; a mutex makes it safe from threads.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <utility>
#include <vector>

#include "build/shape_fill.h"

namespace robophi::build::detail {

/// A 64-bit digest of a mesh's vertex and triangle bytes (a hit is then
/// confirmed by comparing the meshes).
std::uint64_t meshDigest(const TriangleMesh& mesh);

/// Do two meshes hold the same bytes?
bool sameMesh(const TriangleMesh& a, const TriangleMesh& b);

/// A mesh's lattice in its own frame (fillShape, before the shape's frame).
struct MeshLattice {
  std::vector<Vec3> local;  // shape frame (m)
  MeshReport report{};
};

class MeshWorkMemo {
 public:
  explicit MeshWorkMemo(std::size_t budgetBytes) : budgetBytes_(budgetBytes) {}

  /// The process's memo (shapeVolume, fillShape).
  static MeshWorkMemo& shared();

  std::optional<double> volume(const TriangleMesh& mesh, std::uint64_t digest);
  void keepVolume(const TriangleMesh& mesh, std::uint64_t digest, double volume);
  std::shared_ptr<const MeshLattice> lattice(const TriangleMesh& mesh, std::uint64_t digest,
                                             double spacing);
  void keepLattice(const TriangleMesh& mesh, std::uint64_t digest, double spacing,
                   std::shared_ptr<const MeshLattice> made);

 private:
  struct Entry {
    std::uint64_t digest = 0;
    std::shared_ptr<const TriangleMesh> mesh;
    std::optional<double> volume;
    // (spacing, lattice)
    std::vector<std::pair<double, std::shared_ptr<const MeshLattice>>> lattices;
    std::size_t bytes = 0;
    std::uint64_t used = 0;
  };
  Entry* findLocked(const TriangleMesh& mesh, std::uint64_t digest);
  Entry& entryLocked(const TriangleMesh& mesh, std::uint64_t digest);
  void trimLocked(const Entry* keep);

  std::size_t budgetBytes_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<Entry>> entries_;
  std::size_t bytes_ = 0;
  std::uint64_t clock_ = 0;
};

}  // namespace robophi::build::detail
