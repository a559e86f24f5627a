// Mesh files → TriangleMesh through assimp (private to the build layer).

#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <filesystem>
#include <stdexcept>
#include <system_error>

#include "build/checks.h"
#include "robophi/build/input_files.h"
#include "robophi/build/rigid_body.h"

namespace robophi::build {

namespace {

[[noreturn]] void meshError(const std::string& path, const std::string& problem) {
  throw std::runtime_error("mesh '" + path + "': " + problem);
}

// Appends the node's meshes (vertices through the node's accumulated transform)
// and recurses into its children.
void collect(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent, const Vec3& scale,
             TriangleMesh& out) {
  const aiMatrix4x4 transform = parent * node.mTransformation;
  for (unsigned m = 0; m < node.mNumMeshes; ++m) {
    const aiMesh& mesh = *scene.mMeshes[node.mMeshes[m]];
    const auto base = static_cast<std::int32_t>(out.vertices.size());
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D p = transform * mesh.mVertices[v];
      out.vertices.push_back({p.x * scale.x, p.y * scale.y, p.z * scale.z});
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines carry no volume
      out.triangles.push_back({base + static_cast<std::int32_t>(face.mIndices[0]),
                               base + static_cast<std::int32_t>(face.mIndices[1]),
                               base + static_cast<std::int32_t>(face.mIndices[2])});
    }
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c) {
    collect(scene, *node.mChildren[c], transform, scale, out);
  }
}

}  // namespace

TriangleMesh loadMesh(const std::string& path, const Vec3& scale) {
  check::finite("loadMesh", "scale", scale, "");
  InputFileLog::record(path);
  std::error_code error;
  const std::filesystem::path file(path);
  if (!std::filesystem::exists(file, error)) meshError(path, "no such file");
  if (std::filesystem::is_directory(file, error)) meshError(path, "is a folder, not a mesh file");
  Assimp::Importer importer;
  // ROS meshes are Z-up whatever a COLLADA file's <up_axis> says (as rviz reads them).
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                              aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* scene = importer.ReadFile(
      path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType);
  if (scene == nullptr) {
    const std::string reason = importer.GetErrorString();
    meshError(path,
              "cannot be read (" + (reason.empty() ? std::string("unknown format") : reason) + ")");
  }
  TriangleMesh mesh;
  if (scene->mRootNode != nullptr) collect(*scene, *scene->mRootNode, aiMatrix4x4{}, scale, mesh);
  if (mesh.triangles.empty()) meshError(path, "has no triangles");
  for (const Vec3& v : mesh.vertices) {
    if (!isFinite(v)) meshError(path, "has a vertex that is not a finite number");
  }
  // A mirroring scale (an odd number of negative factors) turns the winding inside out.
  if (scale.x * scale.y * scale.z < 0.0) {
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  }
  return mesh;
}

}  // namespace robophi::build
