#pragma once
// Decimation of the robots' visual meshes before the replay page embeds them
// (docs/viewer.md "Robots as they look", the triangle budget): vertex clustering
// on a uniform grid (Rossignac & Borrel, "Multi-resolution 3D approximations for
// rendering complex scenes", 1993), the grid's cell the finest that brings the
// mesh under the budget.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "robophi/vec3.h"

namespace robophi::output {

/// The most triangles a visual mesh file keeps in the page: a larger OBJ or STL is
/// decimated to at most this many (a DAE is embedded as it is).
inline constexpr std::size_t kMeshTriangleBudget = 10'000;

/// A mesh clustered on a grid: the clusters' positions (the mean of their
/// vertices), each input vertex's cluster, and the triangles that keep three
/// distinct clusters (one of each set of corners), as indices of the input.
struct ClusteredMesh {
  std::vector<Vec3> positions;             // (clusterCount)
  std::vector<std::int32_t> clusterOf;     // (input vertexCount)
  std::vector<std::size_t> keptTriangles;  // indices of the input's triangles
  double cell = 0.0;                       // the grid's cell (the mesh's units)
};

/// The clustering of the finest grid (cell found by bisection, 24 halvings) that
/// leaves at most `budget` triangles; the mesh as it is (cell 0) when it has no
/// more. Deterministic: clusters are numbered in the order of their first vertex.
ClusteredMesh clusterToBudget(const std::vector<Vec3>& vertices,
                              const std::vector<std::array<std::int32_t, 3>>& triangles,
                              std::size_t budget);

/// A mesh file's bytes for the page: an OBJ or STL of more than `budget` triangles
/// read (assimp) and written back decimated (an OBJ with its groups' materials by
/// name and its normals, an STL as binary STL); otherwise empty (embed the file).
/// `trianglesBefore`, `trianglesAfter` report the counts (0 when not read).
struct DecimatedFile {
  std::string bytes;
  std::size_t trianglesBefore = 0;
  std::size_t trianglesAfter = 0;
};
DecimatedFile decimatedMeshFile(const std::string& path, const std::string& format,
                                std::size_t budget = kMeshTriangleBudget);

}  // namespace robophi::output
