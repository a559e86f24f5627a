#pragma once
/// \file
/// A URDF robot as rigid bodies (docs/robots.md "Rigid bodies", docs/model.md §7):
/// every link keeps the URDF's mass, centre of mass and inertia exactly; links
/// welded by fixed joints are merged into one body (their frames kept); every
/// revolute, continuous and prismatic joint is one joint of a tree in reduced
/// coordinates. What real URDFs carry is accepted with MuJoCo's compiler's
/// switches, each adjustment listed with the link's name and line.

#include <string>
#include <vector>

#include "robophi/build/urdf_error.h"
#include "robophi/multibody.h"
#include "robophi/rotation.h"

namespace robophi::build {

/// How to read a URDF as rigid bodies.
struct UrdfMultibodySpec {
  /// The URDF file.
  std::string path;
  /// Folders searched for package:// meshes (before ROS_PACKAGE_PATH).
  std::vector<std::string> packagePaths;
  /// Prefix of body, frame and joint names; empty: the URDF's robot name.
  std::string name;
  /// The root link's frame in the world.
  Pose placement{};
  /// true: the root link is welded to the world; false: it floats (a free joint).
  bool fixedBase = true;
  /// MuJoCo's balanceinertia: an inertia whose principal moments break the
  /// triangle inequality (A + B < C) is raised to the nearest one that holds
  /// (each moment at least |the other two's difference|), with a warning. false:
  /// such a link is an error naming it.
  bool balanceInertia = true;
  /// MuJoCo's inertiafromgeom: every link's mass properties computed from its
  /// <collision> geometry at its URDF mass (uniform density).
  bool inertiaFromGeometry = false;
  /// Links whose mass properties come from their geometry (as above), by URDF link name.
  std::vector<std::string> inertiaFromGeometryLinks;
  /// The mass (kg) given to a moving link that has none (a leaf with no mass would
  /// make the mass matrix singular), with a warning; > 0.
  double minimumMass = 1e-3;
};

/// A <collision> element of a link, in the frame of the body it belongs to.
struct UrdfCollisionShape {
  enum class Kind { kBox, kCylinder, kSphere, kMesh };
  Kind kind = Kind::kBox;
  /// The body (index into Multibody::bodies) and the URDF link it came from.
  std::int32_t body = 0;
  std::string link;
  /// The shape's frame in the body's frame (box centred; cylinder along its z).
  Pose X_BS{};
  /// Box: full sides (m); cylinder: radius, radius, length; sphere: radius ×3.
  Vec3 size{};
  /// Mesh: the resolved file and its scale.
  std::string mesh;
  Vec3 scale{1, 1, 1};
  int line = 0;
};

/// A URDF joint as a model joint: where its value sits in q and v.
struct UrdfMultibodyJoint {
  std::string urdfName, name, type;
  /// The body the joint moves; its coordinate in q and rate in v.
  std::int32_t body = -1, positionIndex = -1, velocityIndex = -1;
  /// <mimic>: the joint it follows (URDF name; empty: none), q = multiplier q_j + offset.
  std::string mimicJoint;
  double multiplier = 1.0, offset = 0.0;
  int line = 0;
};

/// A URDF robot as rigid bodies.
struct UrdfMultibody {
  Multibody multibody;
  std::vector<UrdfMultibodyJoint> joints;
  std::vector<UrdfCollisionShape> collisions;
  /// Every change made to what the file says (balanced inertias, merged links,
  /// notional masses, ignored mimics...), each "link 'x' (FILE:LINE): what".
  std::vector<std::string> adjustments;
  /// Elements robophi ignores (one a kind).
  std::vector<UrdfWarning> warnings;
};

/// Reads a URDF as rigid bodies; throws UrdfError (FILE:LINE: the element and value).
UrdfMultibody makeUrdfMultibody(const UrdfMultibodySpec& spec);

}  // namespace robophi::build
