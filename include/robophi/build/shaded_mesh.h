#pragma once
/// \file
/// A mesh file read for display (the replay page's robots, docs/viewer.md "Robots
/// as they look"): the triangles with their normals and their materials' colours,
/// read by the same checked road as loadMesh (readInputFile: a regular file within
/// its byte budget, never a FIFO waited on; the face, corner and vertex budgets
/// checked before assimp triangulates).

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "robophi/build/rigid_body.h"
#include "robophi/vec3.h"

namespace robophi::build {

/// One material of a mesh file, as the file gives it.
struct MeshMaterial {
  std::string name{};  ///< the file's name for it (may be empty)
  /// Diffuse colour and opacity (0..1); hasColor false: the file gives none.
  std::array<double, 4> rgba{0.7, 0.7, 0.7, 1.0};
  bool hasColor = false;
};

/// A mesh file's triangles for display.
struct ShadedMesh {
  /// Vertices in the file's units (a COLLADA file's <unit> applied, its <up_axis>
  /// not: ROS meshes are Z-up) through its nodes' transforms, and the triangles.
  TriangleMesh mesh{};
  std::vector<Vec3> normals{};                // (vertexCount) unit; zero where the file gives none
  std::vector<std::uint32_t> materialOf{};    // (triangleCount) index into materials
  std::vector<MeshMaterial> materials{};      // the file's, in its order (at least one)
  std::string bytes{};                        // the file as read
};

/// Reads a mesh file (STL, OBJ, DAE and what else assimp reads) for display,
/// unscaled. Throws std::runtime_error as loadMesh does ("mesh '<path>': <problem>":
/// missing or not a regular file, unreadable, past a budget, no triangles).
ShadedMesh loadShadedMesh(const std::string& path);

}  // namespace robophi::build
