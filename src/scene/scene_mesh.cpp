#include "scene/scene_mesh.h"

#include <fmt/format.h>

#include <filesystem>
#include <stdexcept>

#include "robophi/build/rigid_body.h"
#include "scene/scene_objects.h"

namespace robophi::scene {

namespace {

// "scale": a number (every axis) or [sx, sy, sz], each non-zero.
std::optional<Vec3> readScale(ObjectReader& r) {
  const nlohmann::json* value = r.member("scale");
  if (value == nullptr) return Vec3{1, 1, 1};
  std::optional<Vec3> scale;
  if (value->is_number()) {
    const double s = value->get<double>();
    scale = Vec3{s, s, s};
  } else {
    scale = r.vec3("scale", "");
    if (!scale) return std::nullopt;
  }
  if (!(scale->x != 0.0 && scale->y != 0.0 && scale->z != 0.0) || !isFinite(*scale)) {
    r.sink().error(r.memberPointer("scale"),
                   fmt::format("'scale' must be a finite non-zero number or [sx, sy, sz] of "
                               "them, got {}",
                               describeJson(*value)));
    return std::nullopt;
  }
  return scale;
}

}  // namespace

bool readMesh(ObjectReader& r, build::GeneratedObject& out, const std::string& sceneDirectory) {
  const auto file = r.string("file", true);
  const auto scale = readScale(r);
  const auto center = r.vec3("center", "m", true);
  const auto mass = r.number("mass", Bound::kPositive, "kg", true);
  const auto size = r.number("particleSize", Bound::kPositive, "m");
  const auto count = r.integer("particles", 1);
  if (size && count) {
    r.sink().error(r.memberPointer("particles"),
                   "give either 'particleSize' or 'particles', not both");
    return false;
  }
  const build::SpringSettings springs = readSprings(r, false);
  if (!file || !scale || !center || !mass) return false;

  // The mesh file, relative to the scene file's folder.
  std::filesystem::path path = *file;
  if (path.is_relative() && !sceneDirectory.empty())
    path = std::filesystem::path(sceneDirectory) / path;
  build::RigidBodySpec spec;
  try {
    build::ShapeSpec shape;
    shape.kind = build::ShapeSpec::Kind::kMesh;
    shape.mesh = build::loadMesh(path.string(), *scale);
    spec.shapes.push_back(std::move(shape));
  } catch (const std::runtime_error& e) {
    r.sink().error(r.memberPointer("file"), fmt::format("'file': {}", e.what()));
    return false;
  }
  spec.mass = *mass;
  spec.uniformDensity = true;
  spec.particleSize = size.value_or(0.0);
  spec.particleCount = count.value_or(spec.particleCount);
  spec.naturalFrequency = springs.naturalFrequency;
  build::RigidBody body = build::makeRigidBody(spec);
  // The mesh's centre of mass goes to `center`.
  const Vec3 shift = *center - body.achieved.centerOfMass;
  for (Vec3& p : body.object.position) p += shift;
  out = std::move(body.object);
  if (springs.stiffness || springs.damping) build::resolveSprings(out, springs);
  return applyRotation(r, out, *center);
}

}  // namespace robophi::scene
