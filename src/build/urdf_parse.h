#pragma once
// The URDF reader (tinyxml2, private to src/build): the file as plain data with
// the line of every element, mesh paths resolved, and the checks that need only
// the file (kinds, axes, names, the tree). urdf.cpp builds the particles.

#include <array>
#include <string>
#include <utility>
#include <vector>

#include "robophi/build/urdf_error.h"
#include "robophi/vec3.h"

namespace robophi::build::urdf {

/// <origin xyz rpy> (m, rad).
struct Origin {
  Vec3 xyz{};
  Vec3 rpy{};
};

struct Geometry {
  enum class Kind { kBox, kCylinder, kSphere, kMesh };
  Kind kind = Kind::kBox;
  Vec3 size{};         // box: full sides (m)
  double radius = 0;   // cylinder, sphere (m)
  double length = 0;   // cylinder (m)
  std::string mesh{};  // resolved path of the mesh file
  Vec3 scale{1, 1, 1};
};

struct Collision {
  Origin origin{};
  Geometry geometry{};
  int line = 0;
};

/// A <visual> (display only): its shape, and its <material>'s name and colour.
struct Visual {
  Origin origin{};
  Geometry geometry{};
  std::string material{};
  bool hasColor = false;
  std::array<double, 4> rgba{0.7, 0.7, 0.7, 1.0};
  /// Why its geometry cannot be drawn (a mesh not found), or empty.
  std::string warning{};
  int line = 0;
};

struct Inertial {
  bool present = false;
  Origin origin{};
  double mass = 0.0;                // kg
  std::array<double, 6> inertia{};  // ixx iyy izz ixy ixz iyz (kg·m²), in the inertial frame
  int line = 0;
};

struct Link {
  std::string name{};
  int line = 0;
  Inertial inertial{};
  std::vector<Collision> collisions{};
  std::vector<Visual> visuals{};
};

struct Joint {
  enum class Type { kRevolute, kContinuous, kPrismatic, kFixed };
  std::string name{};
  Type type = Type::kFixed;
  std::string typeName{};
  int line = 0;
  Origin origin{};
  Vec3 axis{1, 0, 0};  // unit, in the joint frame
  std::string parent{}, child{};
  int parentIndex = -1, childIndex = -1;  // into Description::links
  bool hasLimit = false;
  double lower = 0, upper = 0, velocity = 0, effort = 0;
  double damping = 0, friction = 0;
  bool hasMimic = false;
  std::string mimicJoint{};
  double multiplier = 1.0, offset = 0.0;
};

struct Description {
  std::string file{};  // as given
  std::string robotName{};
  std::vector<Link> links{};
  std::vector<Joint> joints{};     // in tree order: a joint's parent link is the root or
                                   // the child of an earlier joint
  int root = 0;                    // index into links
  std::vector<int> parentJoint{};  // (links) index into joints, -1 for the root
  std::vector<UrdfWarning> warnings{};
  /// The robot's named <material> colours (RGBA), for visuals that name one.
  std::vector<std::pair<std::string, std::array<double, 4>>> materials{};
};

/// Reads and checks a URDF file; throws UrdfError (file:line and the element).
/// packagePaths are searched before ROS_PACKAGE_PATH for package:// meshes.
Description readUrdf(const std::string& path, const std::vector<std::string>& packagePaths);

}  // namespace robophi::build::urdf
