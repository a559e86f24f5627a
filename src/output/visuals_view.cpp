// The robots' visual shapes for the replay page: see output/visuals_view.h.
#include "output/visuals_view.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace robophi::output {

namespace {

using Json = nlohmann::ordered_json;

const char* kindName(VisualShape::Kind kind) {
  switch (kind) {
    case VisualShape::Kind::kBox:
      return "box";
    case VisualShape::Kind::kCylinder:
      return "cylinder";
    case VisualShape::Kind::kSphere:
      return "sphere";
    case VisualShape::Kind::kMesh:
      break;
  }
  return "mesh";
}

// "stl", "obj", "dae" (lower case), or the extension as it is (the page says it cannot load it).
std::string meshFormat(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// The particles that carry a visual: its body's (particle form, carriers
// included), or those its tree body moves (rigid form).
std::vector<ParticleIndex> carrierParticles(const Model& model, const VisualShape& v) {
  std::vector<ParticleIndex> out;
  if (v.body >= 0 && static_cast<std::size_t>(v.body) < model.bodies.size()) {
    out = model.bodies[static_cast<std::size_t>(v.body)].particles;
  } else if (v.tree >= 0 && static_cast<std::size_t>(v.tree) < model.rigidTrees.size()) {
    for (const BodyParticle& p : model.rigidTrees[static_cast<std::size_t>(v.tree)].particles)
      if (p.body == v.treeBody) out.push_back(p.particle);
  }
  return out;
}

}  // namespace

Json visualsJson(const Scene& scene) {
  const Model& model = scene.model;
  if (model.visuals.empty()) return nullptr;
  Json carriers = Json::array(), meshes = Json::array(), visuals = Json::array();
  std::map<std::pair<std::int64_t, std::int64_t>, std::size_t> carrierOf;  // (body, tree body)
  std::map<std::string, std::size_t> meshOf;
  for (const VisualShape& v : model.visuals) {
    const std::pair<std::int64_t, std::int64_t> key =
        v.body >= 0 ? std::pair<std::int64_t, std::int64_t>{v.body, -1}
                    : std::pair<std::int64_t, std::int64_t>{-2 - v.tree, v.treeBody};
    auto found = carrierOf.find(key);
    if (found == carrierOf.end()) {
      Json particles = Json::array(), rest = Json::array();
      for (const ParticleIndex i : carrierParticles(model, v)) {
        if (i < 0 || static_cast<std::size_t>(i) >= scene.initial.position.size()) continue;
        const Vec3& p = scene.initial.position[static_cast<std::size_t>(i)];
        particles.push_back(i);
        for (const double value : {p.x, p.y, p.z}) rest.push_back(value);
      }
      found = carrierOf.emplace(key, carriers.size()).first;
      carriers.push_back({{"particles", particles}, {"rest", rest}});
      // (A rigid tree's body: its particles are fixed ones the tree moves, which the
      // live view's drag strikes through the tree, World::applyImpulse.)
      if (v.body < 0 && v.tree >= 0) carriers.back()["rigidTree"] = true;
    }
    Json item = {{"robot", v.robot}, {"link", v.link}, {"kind", kindName(v.kind)},
                 {"carrier", found->second}};
    switch (v.kind) {
      case VisualShape::Kind::kBox:
        item["size"] = {v.size.x, v.size.y, v.size.z};
        break;
      case VisualShape::Kind::kCylinder:
        item["radius"] = v.radius;
        item["length"] = v.length;
        break;
      case VisualShape::Kind::kSphere:
        item["radius"] = v.radius;
        break;
      case VisualShape::Kind::kMesh: {
        std::int64_t mesh = -1;
        if (!v.mesh.empty()) {
          auto at = meshOf.find(v.mesh);
          if (at == meshOf.end()) {
            at = meshOf.emplace(v.mesh, meshes.size()).first;
            meshes.push_back({{"path", v.mesh}, {"format", meshFormat(v.mesh)}});
          }
          mesh = static_cast<std::int64_t>(at->second);
        }
        item["mesh"] = mesh;
        item["scale"] = {v.scale.x, v.scale.y, v.scale.z};
        break;
      }
    }
    if (v.hasColor) item["rgba"] = v.rgba;
    // X_WV as built: rotation row by row, then the translation.
    Json pose = Json::array();
    for (const auto& row : v.X_WV.rotation.m)
      for (const double value : row) pose.push_back(value);
    for (const double value : {v.X_WV.translation.x, v.X_WV.translation.y, v.X_WV.translation.z})
      pose.push_back(value);
    item["pose"] = pose;
    if (!v.warning.empty()) item["warning"] = v.warning;
    visuals.push_back(std::move(item));
  }
  return {{"carriers", carriers}, {"meshes", meshes}, {"visuals", visuals}};
}

Json shapesJson(const Model& model) {
  Json rims = Json::array();
  for (const RimRing& r : model.rims) {
    rims.push_back({{"first", r.first},
                    {"count", r.count},
                    {"hub", r.hub},
                    {"sphereRadius", r.sphereRadius},
                    {"axisParticle", r.axisParticle},
                    {"halfLength", r.halfLength},
                    {"axialOffset", r.axialOffset}});
  }
  Json particles = Json::array(), weights = Json::array(), triangles = Json::array(),
       objects = Json::array();
  for (const SurfaceVertex& v : model.surfaceVertices) {
    for (std::size_t k = 0; k < SurfaceVertex::kMaxParticles; ++k) {
      particles.push_back(v.particle[k]);
      weights.push_back(v.weight[k]);
    }
  }
  for (const SurfaceTriangle& t : model.surfaceTriangles) {
    for (const std::int32_t v : t.vertex) triangles.push_back(v);
    objects.push_back(t.object);
  }
  if (rims.empty() && triangles.empty()) return nullptr;
  return {{"rims", rims},
          {"surfaces",
           {{"slots", SurfaceVertex::kMaxParticles},
            {"particles", particles},
            {"weights", weights},
            {"triangles", triangles},
            {"objects", objects}}}};
}

}  // namespace robophi::output
