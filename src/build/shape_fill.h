#pragma once
// Shapes → lattice points (build/rigid_body.h): the cell-centre lattice of one
// shape at a spacing, inside tests (primitives by formula, meshes by a voxel
// classification), and uniform-density mass properties.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "robophi/build/rigid_body.h"

namespace robophi::build::detail {

/// A mesh's cells classified on a regular grid of cell centres lo + (i + ½) cell.
struct VoxelGrid {
  Vec3 lo{}, cell{};
  std::array<int, 3> n{0, 0, 0};
  std::vector<std::uint8_t> inside;   // (cells) 1: the centre is inside the mesh
  std::vector<std::uint8_t> surface;  // (cells) 1: the surface passes through the cell
  std::vector<Vec3> surfacePoint;     // (cells) mean of the surface samples in the cell
  std::size_t index(int i, int j, int k) const {
    return static_cast<std::size_t>((i * n[1] + j) * n[2] + k);
  }
  Vec3 centre(int i, int j, int k) const {
    return {lo.x + (i + 0.5) * cell.x, lo.y + (j + 0.5) * cell.y, lo.z + (k + 0.5) * cell.z};
  }
};

/// How a mesh was classified.
struct MeshReport {
  int openEdges = 0;      // edges not shared by exactly two opposite triangles
  int enclosedCells = 0;  // cells added by the flood fill of an open mesh
  int thinParticles = 0;  // surface cells without an inside cell near them
};

/// Classifies the cells of `grid` (lo, cell, n set) for `mesh` (same frame):
/// inside by the non-zero winding rule along rays on the three axes (majority of
/// the columns whose crossings balance), surface by sampling the triangles; an
/// open mesh also gets the cells its surface encloses (flood fill from outside).
void classifyMesh(const TriangleMesh& mesh, VoxelGrid& grid, MeshReport& report);

/// Edges of `mesh` not shared by exactly two triangles of opposite winding
/// (vertices at equal positions welded): 0 for a closed, consistently wound mesh.
int openEdges(const TriangleMesh& mesh);

/// The lattice of one shape at spacing h, in the body frame: cell centres of a
/// max(2, round(extent/h)) cells per axis lattice over the shape's box, those
/// inside kept (a mesh also keeps a particle on each thin surface cell);
/// stretched along a prism's axes (see fillShape).
struct ShapeLattice {
  std::vector<Vec3> position;       // body frame (m)
  Vec3 cell{};                      // cell sides (m), shape frame
  std::array<bool, 3> stretched{};  // the axes whose cell centres are stretched
  MeshReport report{};
};
ShapeLattice fillShape(const ShapeSpec& shape, double spacing);

/// Axis-aligned box of a shape in its own frame (m).
void shapeBounds(const ShapeSpec& shape, Vec3& lo, Vec3& hi);
/// Volume of a shape (m³): exact for primitives and closed meshes, voxel count otherwise.
double shapeVolume(const ShapeSpec& shape);
/// Volume of a mesh (m³), as shapeVolume gives it (which keeps it per mesh).
double meshVolume(const TriangleMesh& mesh);
/// A first lattice spacing (m) for about `count` particles in the union:
/// the volume per particle, or the area per particle for a sheet.
double spacingFor(const std::vector<ShapeSpec>& shapes, int count);
/// Is the body-frame point inside the shape? (a mesh: by its 96-cell grid.)
class ShapeInside {
 public:
  explicit ShapeInside(const ShapeSpec& shape);
  bool operator()(const Vec3& bodyPoint) const;

 private:
  const ShapeSpec* shape_;
  Frame toShape_;
  VoxelGrid grid_;
};

}  // namespace robophi::build::detail
