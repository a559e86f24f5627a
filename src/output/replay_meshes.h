#pragma once
// The mesh files of the robots' visuals, embedded once in the replay page
// (docs/viewer.md "Robots as they look", the mesh budget).

#include <cstddef>
#include <string>
#include <vector>

#include "output/mesh_decimation.h"

namespace robophi::output {

/// The most bytes of mesh files a page embeds (before base64): files past it are
/// left out (their visuals are not drawn, and the page says so).
inline constexpr std::size_t kMeshBudgetBytes = std::size_t{32} << 20;

/// `,"meshFiles":[...]` for the data object: for each of world.json's
/// robots.meshes (the JSON text `world`), {"format", "bytes", "data"} with the
/// file's bytes in base64, or "data": null and a "note" (not read by the checked
/// reader: not found, not a regular file, past a budget; or over the page's
/// budget: at most `budgetBytes` of files, and a third of `capBytes` in base64),
/// each note also a warning in `warnings` when given. A mesh of more than
/// `triangleBudget` triangles, whatever its format, goes in written back
/// (output/mesh_decimation.h pageMesh), with "triangles" and "decimatedFrom" (its
/// triangle counts). An OBJ, as it is or written back, has "mtl" (an MTL of its
/// materials' colours). Empty when the world has no meshes.
std::string meshFilesJson(const std::string& world, double capBytes,
                          std::size_t budgetBytes = kMeshBudgetBytes,
                          std::size_t triangleBudget = kMeshTriangleBudget,
                          std::vector<std::string>* warnings = nullptr);

}  // namespace robophi::output
