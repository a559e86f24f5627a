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

/// The most triangles a visual mesh file keeps in the page: a larger one (STL, OBJ,
/// DAE alike) is decimated to at most this many.
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
/// more. With `groupOf` (a group per vertex, e.g. its material), only vertices of
/// one group share a cluster. Deterministic: clusters are numbered in the order
/// of their first vertex.
ClusteredMesh clusterToBudget(const std::vector<Vec3>& vertices,
                              const std::vector<std::array<std::int32_t, 3>>& triangles,
                              std::size_t budget, const std::vector<std::uint32_t>& groupOf = {});

/// A visual mesh file as the page embeds it.
struct PageMesh {
  std::string format{};     ///< how the page parses `bytes`: "stl", "obj" or "dae"
  std::string bytes{};      ///< the file as it is, or written back (decimated or converted)
  std::string materials{};  ///< an OBJ's MTL (its materials' colours, as assimp read them), else empty
  std::size_t trianglesBefore = 0, trianglesAfter = 0;
  bool rewritten = false;   ///< `bytes` are robophi's, not the file's
  std::string problem{};    ///< why it cannot go in ("'<path>': is a FIFO ..."), or empty
};

/// A visual mesh file (`format`: its extension, lower case) for the page, read by
/// build::loadShadedMesh, the checked reader (a regular file within the byte,
/// face, corner and vertex budgets; else `problem` says why, at once). An STL, OBJ
/// or DAE of at most `budget` triangles goes in as it is (an OBJ with an MTL of
/// its materials' colours by their names, its .mtl as assimp read it); a larger one, or another
/// format assimp reads, goes in written back through clusterToBudget: an STL as
/// binary STL, anything else as an OBJ with its normals and an MTL of its
/// materials' colours (a DAE's node transforms and <unit> in its vertices).
PageMesh pageMesh(const std::string& path, const std::string& format,
                  std::size_t budget = kMeshTriangleBudget);

}  // namespace robophi::output
