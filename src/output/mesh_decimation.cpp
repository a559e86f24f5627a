// Decimation of the robots' visual meshes: see output/mesh_decimation.h.
#include "output/mesh_decimation.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <exception>
#include <map>
#include <unordered_map>
#include <unordered_set>

#include <fmt/format.h>

#include "robophi/build/shaded_mesh.h"

namespace robophi::output {

namespace {

using Cell = std::array<std::int64_t, 4>;  // a vertex's group, then its grid cell
using Triangle = std::array<std::int32_t, 3>;

// A hash of a few integers (a group's grid cell, a triangle's sorted corners):
// lookups only; what is kept and its order follow the input's, never the table's.
struct IntsHash {
  template <typename T, std::size_t N>
  std::size_t operator()(const std::array<T, N>& a) const {
    std::uint64_t h = 0x9E3779B97F4A7C15ULL;
    for (const T value : a) {
      h ^= static_cast<std::uint64_t>(value) + 0x9E3779B97F4A7C15ULL + (h << 6) + (h >> 2);
      h *= 0xC2B2AE3D27D4EB4FULL;
    }
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};

// The vertices clustered on a grid of side `cell` from `origin`, each group's
// (`groupOf`, per vertex; empty: one group) apart, and the triangles left with
// three distinct clusters (a set of corners kept once, the first).
ClusteredMesh clusterOnGrid(const std::vector<Vec3>& vertices, const std::vector<std::uint32_t>& groupOf,
                            const std::vector<Triangle>& triangles, const Vec3& origin, double cell) {
  ClusteredMesh out;
  out.cell = cell;
  out.clusterOf.resize(vertices.size());
  std::unordered_map<Cell, std::int32_t, IntsHash> clusterOfCell;
  clusterOfCell.reserve(vertices.size());
  std::vector<Vec3> sum;
  std::vector<double> count;
  for (std::size_t v = 0; v < vertices.size(); ++v) {
    const Vec3 d = (vertices[v] - origin) / cell;
    const Cell key{groupOf.empty() ? 0 : static_cast<std::int64_t>(groupOf[v]),
                   static_cast<std::int64_t>(std::floor(d.x)), static_cast<std::int64_t>(std::floor(d.y)),
                   static_cast<std::int64_t>(std::floor(d.z))};
    const auto [at, added] = clusterOfCell.emplace(key, static_cast<std::int32_t>(sum.size()));
    if (added) {
      sum.push_back({0, 0, 0});
      count.push_back(0.0);
    }
    sum[static_cast<std::size_t>(at->second)] += vertices[v];
    count[static_cast<std::size_t>(at->second)] += 1.0;
    out.clusterOf[v] = at->second;
  }
  out.positions.resize(sum.size());
  for (std::size_t c = 0; c < sum.size(); ++c) out.positions[c] = sum[c] / count[c];
  std::unordered_set<Triangle, IntsHash> seen;
  seen.reserve(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    Triangle corners{};
    for (int k = 0; k < 3; ++k)
      corners[static_cast<std::size_t>(k)] =
          out.clusterOf[static_cast<std::size_t>(triangles[t][static_cast<std::size_t>(k)])];
    if (corners[0] == corners[1] || corners[1] == corners[2] || corners[0] == corners[2]) continue;
    Triangle sorted = corners;
    std::sort(sorted.begin(), sorted.end());
    if (seen.insert(sorted).second) out.keptTriangles.push_back(t);
  }
  return out;
}

// A material's name as an OBJ and MTL name: its index (names may repeat) and its
// own name with anything but [A-Za-z0-9_.-] as '_'.
std::string materialName(const build::ShadedMesh& mesh, std::size_t k) {
  std::string name = "m" + std::to_string(k);
  if (!mesh.materials[k].name.empty()) name += '_';
  for (const char c : mesh.materials[k].name)
    name += std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '.' || c == '-' ? c : '_';
  return name;
}

// An OBJ: the clusters as `v`, the kept corners' own normals as `vn` (so that a
// sharp edge stays sharp; those equal to two decimals once), the triangles in their materials'
// groups (`usemtl`). Without normals in the file, none: the page computes them.
std::string objText(const build::ShadedMesh& mesh, const ClusteredMesh& clustered) {
  const bool withNormals = std::none_of(mesh.normals.begin(), mesh.normals.end(),
                                        [](const Vec3& n) { return n.x == 0 && n.y == 0 && n.z == 0; });
  std::string out = fmt::format(
      "# written for the replay page: {} of {} triangles (vertex clustering, cell {:.6g})\n",
      clustered.keptTriangles.size(), mesh.mesh.triangles.size(), clustered.cell);
  for (const Vec3& p : clustered.positions) out += fmt::format("v {:.6g} {:.6g} {:.6g}\n", p.x, p.y, p.z);
  std::map<std::string, std::size_t> normalIndex;  // "x y z" -> vn index (1-based)
  std::string faces;
  std::size_t group = mesh.materials.size();
  for (const std::size_t t : clustered.keptTriangles) {
    if (mesh.materialOf[t] != group) {
      group = mesh.materialOf[t];
      faces += "usemtl " + materialName(mesh, group) + "\n";
    }
    faces += 'f';
    for (const std::int32_t v : mesh.mesh.triangles[t]) {
      const std::int32_t cluster = clustered.clusterOf[static_cast<std::size_t>(v)] + 1;
      if (!withNormals) {
        faces += fmt::format(" {}", cluster);
        continue;
      }
      const Vec3& n = mesh.normals[static_cast<std::size_t>(v)];
      // Two decimals (within 0.4 degrees): near-equal normals written once.
      std::string text = fmt::format("{:.2f} {:.2f} {:.2f}", n.x, n.y, n.z);
      for (std::size_t at = text.find("-0.00"); at != std::string::npos; at = text.find("-0.00"))
        text.erase(at, 1);
      const auto [at, added] = normalIndex.emplace(text, normalIndex.size() + 1);
      if (added) out += "vn " + text + "\n";
      faces += fmt::format(" {}//{}", cluster, at->second);
    }
    faces += '\n';
  }
  return out + faces;
}

// The MTL of the materials: each one's diffuse colour (Kd) and opacity (d), by
// objText's names, or (`ownNames`, an OBJ as it is) by the file's own (one line).
std::string mtlText(const build::ShadedMesh& mesh, bool ownNames) {
  std::string out = "# the materials of a mesh for the replay page\n";
  for (std::size_t k = 0; k < mesh.materials.size(); ++k) {
    const build::MeshMaterial& m = mesh.materials[k];
    if (ownNames && m.name.find_first_of("\r\n") != std::string::npos) continue;
    out += "newmtl " + (ownNames ? m.name : materialName(mesh, k)) + "\n";
    if (!m.hasColor) continue;
    out += fmt::format("Kd {:.4g} {:.4g} {:.4g}\n", m.rgba[0], m.rgba[1], m.rgba[2]);
    // An opacity of 0 is taken as 1: Meshlab's "Tr 1" means opaque, and assimp
    // reads it as transparent (a visual never meant to be unseen).
    if (m.rgba[3] > 0.0 && m.rgba[3] < 1.0) out += fmt::format("d {:.4g}\n", m.rgba[3]);
  }
  return out;
}

// A binary STL of the kept triangles (facet normals from the clustered corners).
std::string binaryStl(const build::ShadedMesh& mesh, const ClusteredMesh& clustered) {
  std::string out(80, ' ');
  const std::string title = "robophi: decimated for the replay page";
  out.replace(0, title.size(), title);
  const auto count = static_cast<std::uint32_t>(clustered.keptTriangles.size());
  out.append(reinterpret_cast<const char*>(&count), 4);
  for (const std::size_t t : clustered.keptTriangles) {
    std::array<Vec3, 3> p{};
    for (std::size_t k = 0; k < 3; ++k)
      p[k] = clustered.positions[static_cast<std::size_t>(
          clustered.clusterOf[static_cast<std::size_t>(mesh.mesh.triangles[t][k])])];
    Vec3 n = cross(p[1] - p[0], p[2] - p[0]);
    const double length = norm(n);
    if (length > 0) n = n / length;
    std::array<float, 12> values{};
    for (std::size_t i = 0; i < 4; ++i) {
      const Vec3& v = i == 0 ? n : p[i - 1];
      values[3 * i] = static_cast<float>(v.x);
      values[3 * i + 1] = static_cast<float>(v.y);
      values[3 * i + 2] = static_cast<float>(v.z);
    }
    out.append(reinterpret_cast<const char*>(values.data()), sizeof(values));
    out.append(2, '\0');
  }
  return out;
}

}  // namespace

ClusteredMesh clusterToBudget(const std::vector<Vec3>& vertices, const std::vector<Triangle>& triangles,
                              std::size_t budget, const std::vector<std::uint32_t>& groupOf) {
  if (vertices.empty()) return {};
  Vec3 lower = vertices[0], upper = vertices[0];
  for (const Vec3& v : vertices) {
    lower = {std::min(lower.x, v.x), std::min(lower.y, v.y), std::min(lower.z, v.z)};
    upper = {std::max(upper.x, v.x), std::max(upper.y, v.y), std::max(upper.z, v.z)};
  }
  if (triangles.size() <= budget) {
    ClusteredMesh same;
    same.positions = vertices;
    for (std::size_t v = 0; v < vertices.size(); ++v) same.clusterOf.push_back(static_cast<std::int32_t>(v));
    for (std::size_t t = 0; t < triangles.size(); ++t) same.keptTriangles.push_back(t);
    return same;
  }
  // Bisection on the cell: (fine, coarse] with coarse under the budget (the whole
  // box one cell wide: nothing left) and fine over it.
  double fine = 0.0;
  double coarse = 2.0 * norm(upper - lower) + 1e-300;
  ClusteredMesh best = clusterOnGrid(vertices, groupOf, triangles, lower, coarse);
  for (int halving = 0; halving < 24; ++halving) {
    const double cell = 0.5 * (fine + coarse);
    ClusteredMesh trial = clusterOnGrid(vertices, groupOf, triangles, lower, cell);
    if (trial.keptTriangles.size() <= budget) {
      coarse = cell;
      best = std::move(trial);
    } else {
      fine = cell;
    }
  }
  return best;
}

PageMesh pageMesh(const std::string& path, const std::string& format, std::size_t budget) {
  PageMesh out;
  out.format = format;
  build::ShadedMesh mesh;
  try {
    mesh = build::loadShadedMesh(path);
  } catch (const std::exception& e) {
    // loadShadedMesh's "mesh '<path>': <problem>", less its first word.
    out.problem = e.what();
    if (out.problem.starts_with("mesh ")) out.problem.erase(0, 5);
    return out;
  }
  out.trianglesBefore = out.trianglesAfter = mesh.mesh.triangles.size();
  const bool pageLoads = format == "stl" || format == "obj" || format == "dae";
  if (pageLoads && mesh.mesh.triangles.size() <= budget) {
    out.bytes = std::move(mesh.bytes);
    // An OBJ's colours as its .mtl gives them (assimp read it), as a decimated one's.
    if (format == "obj") out.materials = mtlText(mesh, true);
    return out;
  }
  // Each material's vertices clustered apart: a thin dark ring on a white shell
  // stays a ring (clustered together, the shell showed through it in speckles).
  std::vector<std::uint32_t> materialOfVertex(mesh.mesh.vertices.size(), 0);
  for (std::size_t t = 0; t < mesh.mesh.triangles.size(); ++t)
    for (const std::int32_t v : mesh.mesh.triangles[t])
      materialOfVertex[static_cast<std::size_t>(v)] = mesh.materialOf[t];
  const ClusteredMesh clustered =
      clusterToBudget(mesh.mesh.vertices, mesh.mesh.triangles, budget, materialOfVertex);
  out.trianglesAfter = clustered.keptTriangles.size();
  out.rewritten = true;
  if (format == "stl") {
    out.bytes = binaryStl(mesh, clustered);
  } else {
    out.format = "obj";
    out.bytes = objText(mesh, clustered);
    out.materials = mtlText(mesh, false);
  }
  return out;
}

}  // namespace robophi::output
