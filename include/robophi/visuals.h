#pragma once
/// \file
/// What a robot looks like (docs/viewer.md "Robots as they look"): the URDF's
/// <visual> elements, kept for display only. Nothing in the step reads them; the
/// replay page draws each one moved by the pose of the body that carries it.

#include <array>
#include <cstdint>
#include <string>

#include "robophi/rotation.h"
#include "robophi/vec3.h"

namespace robophi {

/// One <visual> of a URDF link: its shape, colour, and what moves it.
struct VisualShape {
  enum class Kind : std::uint8_t { kBox, kCylinder, kSphere, kMesh };
  Kind kind = Kind::kBox;
  /// The robot's name (its objects' prefix) and the link's, "<robot>.<link>".
  std::string robot{};
  std::string link{};
  /// Box: full sides (m). Cylinder: radius and length along its z (m). Sphere: radius (m).
  Vec3 size{};
  double radius = 0.0, length = 0.0;
  /// Mesh: the file (resolved path; empty when it was not found) and its scale (-).
  std::string mesh{};
  Vec3 scale{1, 1, 1};
  /// RGBA (0..1) of its <material> (by name from the robot's materials when only
  /// named); hasColor false: none given, the viewer picks one (a mesh's own
  /// materials, e.g. a DAE's or OBJ's, are used then).
  std::array<double, 4> rgba{0.7, 0.7, 0.7, 1.0};
  bool hasColor = false;
  /// What carries it: a body of particles (index into Model::bodies), or a rigid
  /// tree's body (Model::rigidTrees[tree], its multibody's bodies[treeBody]).
  std::int32_t body = -1;
  std::int32_t tree = -1, treeBody = -1;
  /// Its pose in the world as built (X_WV: the shape's frame, meshes in their file's
  /// coordinates), when the carrying body is where its particles start.
  Pose X_WV{};
  /// Why it cannot be drawn as given (a mesh file not found), or empty.
  std::string warning{};
};

}  // namespace robophi
