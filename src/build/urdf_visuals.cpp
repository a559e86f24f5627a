// The URDF's <visual> elements as display shapes (docs/viewer.md "Robots as they
// look"): see build/urdf_visuals.h.
#include "build/urdf_visuals.h"

#include <utility>

namespace robophi::build {

namespace {

VisualShape::Kind visualKindOf(urdf::Geometry::Kind kind) {
  switch (kind) {
    case urdf::Geometry::Kind::kBox:
      return VisualShape::Kind::kBox;
    case urdf::Geometry::Kind::kCylinder:
      return VisualShape::Kind::kCylinder;
    case urdf::Geometry::Kind::kSphere:
      return VisualShape::Kind::kSphere;
    case urdf::Geometry::Kind::kMesh:
      break;
  }
  return VisualShape::Kind::kMesh;
}

Pose poseOfFrame(const Frame& frame) {
  Pose X;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      const Vec3& axis = frame.axes[static_cast<std::size_t>(c)];
      X.rotation.m[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)] =
          r == 0 ? axis.x : (r == 1 ? axis.y : axis.z);
    }
  }
  X.translation = frame.origin;
  return X;
}

}  // namespace

std::vector<UrdfVisual> urdfVisuals(const urdf::Description& d, const std::string& prefix) {
  std::vector<UrdfVisual> out;
  for (std::size_t l = 0; l < d.links.size(); ++l) {
    const urdf::Link& link = d.links[l];
    for (const urdf::Visual& v : link.visuals) {
      UrdfVisual visual;
      visual.link = static_cast<int>(l);
      VisualShape& s = visual.shape;
      s.kind = visualKindOf(v.geometry.kind);
      s.robot = prefix;
      s.link = prefix + "." + link.name;
      s.size = v.geometry.size;
      s.radius = v.geometry.radius;
      s.length = v.geometry.length;
      s.mesh = v.geometry.mesh;
      s.scale = v.geometry.scale;
      s.rgba = v.rgba;
      s.hasColor = v.hasColor;
      // A colour given by name only: the robot's <material> of that name.
      if (!s.hasColor && !v.material.empty()) {
        for (const auto& [name, rgba] : d.materials) {
          if (name != v.material) continue;
          s.rgba = rgba;
          s.hasColor = true;
        }
      }
      s.X_WV = {rotationFromRollPitchYaw(v.origin.rpy), v.origin.xyz};
      s.warning = v.warning;
      out.push_back(std::move(visual));
    }
  }
  return out;
}

void placeUrdfVisuals(ModelBuilder& builder, const UrdfRobot& robot, const PlacedUrdfRobot& placed) {
  for (const UrdfVisual& visual : robot.visuals) {
    const auto l = static_cast<std::size_t>(visual.link);
    if (l >= robot.links.size()) continue;
    const UrdfLink& link = robot.links[l];
    const int carrier = link.attachedTo >= 0 ? link.attachedTo : visual.link;
    VisualShape shape = visual.shape;
    shape.body = placed.body[static_cast<std::size_t>(carrier)];
    if (shape.body < 0) continue;  // a link with nothing that moves it
    shape.X_WV = poseOfFrame(link.frame) * visual.shape.X_WV;
    builder.addVisual(std::move(shape));
  }
}

void placeUrdfMultibodyVisuals(ModelBuilder& builder, const UrdfMultibody& robot,
                               std::int32_t tree, const MultibodyKinematics& kin) {
  const Multibody& mb = robot.multibody;
  for (const UrdfVisual& visual : robot.visuals) {
    const std::int32_t f = mb.frameIndex(visual.shape.link);
    if (f < 0) continue;
    const MultibodyFrame& frame = mb.frames[static_cast<std::size_t>(f)];
    if (frame.body < 0 || static_cast<std::size_t>(frame.body) >= kin.X_WB.size()) continue;
    VisualShape shape = visual.shape;
    shape.tree = tree;
    shape.treeBody = frame.body;
    shape.X_WV = kin.X_WB[static_cast<std::size_t>(frame.body)] * frame.X_BF * visual.shape.X_WV;
    builder.addVisual(std::move(shape));
  }
}

}  // namespace robophi::build
