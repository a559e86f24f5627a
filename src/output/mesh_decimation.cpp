// Decimation of the robots' visual meshes: see output/mesh_decimation.h.
#include "output/mesh_decimation.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>
#include <cstring>
#include <map>
#include <set>

#include <fmt/format.h>

namespace robophi::output {

namespace {

using Cell = std::array<std::int64_t, 3>;
using Triangle = std::array<std::int32_t, 3>;

// The vertices clustered on a grid of side `cell` from `origin`, and the triangles
// left with three distinct clusters (a set of corners kept once, the first).
ClusteredMesh clusterOnGrid(const std::vector<Vec3>& vertices, const std::vector<Triangle>& triangles,
                            const Vec3& origin, double cell) {
  ClusteredMesh out;
  out.cell = cell;
  out.clusterOf.resize(vertices.size());
  std::map<Cell, std::int32_t> clusterOfCell;
  std::vector<Vec3> sum;
  std::vector<double> count;
  for (std::size_t v = 0; v < vertices.size(); ++v) {
    const Vec3 d = (vertices[v] - origin) / cell;
    const Cell key{static_cast<std::int64_t>(std::floor(d.x)), static_cast<std::int64_t>(std::floor(d.y)),
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
  std::set<Triangle> seen;
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

// A mesh file as read by assimp: vertices (through its nodes' transforms), their
// normals, triangles, and each triangle's material name.
struct ReadMesh {
  std::vector<Vec3> vertices, normals;
  std::vector<Triangle> triangles;
  std::vector<std::size_t> groupOf;  // (triangleCount) index into groups
  std::vector<std::string> groups;   // material names
};

bool readMesh(const std::string& path, ReadMesh& out) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(
      path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType);
  if (scene == nullptr || scene->mRootNode == nullptr) return false;
  std::vector<std::pair<const aiNode*, aiMatrix4x4>> stack{{scene->mRootNode, aiMatrix4x4{}}};
  while (!stack.empty()) {
    const auto [node, parent] = stack.back();
    stack.pop_back();
    const aiMatrix4x4 transform = parent * node->mTransformation;
    const aiMatrix3x3 turn(transform);
    for (unsigned m = 0; m < node->mNumMeshes; ++m) {
      const aiMesh& mesh = *scene->mMeshes[node->mMeshes[m]];
      const auto base = static_cast<std::int32_t>(out.vertices.size());
      for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
        const aiVector3D p = transform * mesh.mVertices[v];
        out.vertices.push_back({p.x, p.y, p.z});
        aiVector3D n = mesh.HasNormals() ? turn * mesh.mNormals[v] : aiVector3D(0, 0, 0);
        if (n.Length() > 0) n.Normalize();
        out.normals.push_back({n.x, n.y, n.z});
      }
      std::string material = "default";
      if (mesh.mMaterialIndex < scene->mNumMaterials)
        material = scene->mMaterials[mesh.mMaterialIndex]->GetName().C_Str();
      const auto group = static_cast<std::size_t>(
          std::find(out.groups.begin(), out.groups.end(), material) - out.groups.begin());
      if (group == out.groups.size()) out.groups.push_back(material);
      for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
        const aiFace& face = mesh.mFaces[f];
        if (face.mNumIndices != 3) continue;
        out.triangles.push_back({base + static_cast<std::int32_t>(face.mIndices[0]),
                                 base + static_cast<std::int32_t>(face.mIndices[1]),
                                 base + static_cast<std::int32_t>(face.mIndices[2])});
        out.groupOf.push_back(group);
      }
    }
    for (unsigned c = node->mNumChildren; c-- > 0;) stack.emplace_back(node->mChildren[c], transform);
  }
  return !out.triangles.empty();
}

// An OBJ: the clusters as `v`, the kept corners' own normals as `vn` (so that a
// sharp edge stays sharp), the triangles in their groups (`usemtl`).
std::string objText(const ReadMesh& mesh, const ClusteredMesh& clustered) {
  std::string out = fmt::format("# decimated for the replay page: {} of {} triangles (vertex clustering, cell {:.6g})\n",
                                clustered.keptTriangles.size(), mesh.triangles.size(), clustered.cell);
  for (const Vec3& p : clustered.positions) out += fmt::format("v {:.6g} {:.6g} {:.6g}\n", p.x, p.y, p.z);
  std::map<std::int32_t, std::size_t> normalOf;  // input vertex -> vn index (1-based)
  std::string faces;
  std::size_t group = mesh.groups.size();
  for (const std::size_t t : clustered.keptTriangles) {
    if (mesh.groupOf[t] != group) {
      group = mesh.groupOf[t];
      faces += "usemtl " + mesh.groups[group] + "\n";
    }
    faces += 'f';
    for (const std::int32_t v : mesh.triangles[t]) {
      const auto [at, added] = normalOf.emplace(v, normalOf.size() + 1);
      if (added) {
        const Vec3& n = mesh.normals[static_cast<std::size_t>(v)];
        out += fmt::format("vn {:.4g} {:.4g} {:.4g}\n", n.x, n.y, n.z);
      }
      faces += fmt::format(" {}//{}", clustered.clusterOf[static_cast<std::size_t>(v)] + 1, at->second);
    }
    faces += '\n';
  }
  return out + faces;
}

// A binary STL of the kept triangles (facet normals from the clustered corners).
std::string binaryStl(const ReadMesh& mesh, const ClusteredMesh& clustered) {
  std::string out(80, ' ');
  const std::string title = "robophi: decimated for the replay page";
  out.replace(0, title.size(), title);
  const auto count = static_cast<std::uint32_t>(clustered.keptTriangles.size());
  out.append(reinterpret_cast<const char*>(&count), 4);
  for (const std::size_t t : clustered.keptTriangles) {
    std::array<Vec3, 3> p{};
    for (std::size_t k = 0; k < 3; ++k)
      p[k] = clustered.positions[static_cast<std::size_t>(
          clustered.clusterOf[static_cast<std::size_t>(mesh.triangles[t][k])])];
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
                              std::size_t budget) {
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
  ClusteredMesh best = clusterOnGrid(vertices, triangles, lower, coarse);
  for (int halving = 0; halving < 24; ++halving) {
    const double cell = 0.5 * (fine + coarse);
    ClusteredMesh trial = clusterOnGrid(vertices, triangles, lower, cell);
    if (trial.keptTriangles.size() <= budget) {
      coarse = cell;
      best = std::move(trial);
    } else {
      fine = cell;
    }
  }
  return best;
}

DecimatedFile decimatedMeshFile(const std::string& path, const std::string& format, std::size_t budget) {
  DecimatedFile out;
  if (format != "obj" && format != "stl") return out;
  ReadMesh mesh;
  if (!readMesh(path, mesh)) return out;
  out.trianglesBefore = out.trianglesAfter = mesh.triangles.size();
  if (mesh.triangles.size() <= budget) return out;
  const ClusteredMesh clustered = clusterToBudget(mesh.vertices, mesh.triangles, budget);
  out.trianglesAfter = clustered.keptTriangles.size();
  out.bytes = format == "obj" ? objText(mesh, clustered) : binaryStl(mesh, clustered);
  return out;
}

}  // namespace robophi::output
