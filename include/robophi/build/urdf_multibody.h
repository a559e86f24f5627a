#pragma once
/// \file
/// A URDF robot as rigid bodies (docs/robots.md "Rigid bodies", docs/model.md §7):
/// every link keeps the URDF's mass, centre of mass and inertia exactly; links
/// welded by fixed joints are merged into one body (their frames kept); every
/// revolute, continuous and prismatic joint is one joint of a tree in reduced
/// coordinates. What real URDFs carry is accepted with MuJoCo's compiler's
/// switches, each adjustment listed with the link's name and line.

#include <limits>
#include <string>
#include <vector>

#include "robophi/build/urdf_error.h"
#include "robophi/build/urdf_visuals.h"
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
  /// The bound on |q̇| (rad/s or m/s; <limit velocity>); infinity: none (or not read).
  double velocityLimit = std::numeric_limits<double>::infinity();
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
  /// Its links' <visual> elements (display only), placed with it as Model::visuals.
  std::vector<UrdfVisual> visuals{};
};

/// Reads a URDF as rigid bodies; throws UrdfError (FILE:LINE: the element and value).
UrdfMultibody makeUrdfMultibody(const UrdfMultibodySpec& spec);

/// Its wheels: continuous joints whose body has a <collision> round about the joint's
/// line (roundAbout: a coaxial cylinder or a sphere centred on it). A robot on two or
/// more stands free on them; a continuous knee is no wheel.
int wheelCount(const UrdfMultibody& robot);

class ModelBuilder;

/// How a rigid URDF robot enters a model: the particles that carry its contact
/// surface and how it starts.
struct UrdfMultibodyPlacement {
  /// Lattice spacing of the particles that fill each body's <collision> shapes (m),
  /// > 0; 0: about particlesPerBody particles a body.
  double particleSize = 0.0;
  int particlesPerBody = 30;
  /// Coordinates (nq; empty: neutral) and rates (nv; empty: at rest) it starts at.
  std::vector<double> q{}, v{};
  /// Index into the model's materials of its surface.
  std::int32_t material = 0;
  /// false: its bodies never touch each other; true: all but a joint's two bodies do.
  bool selfCollision = false;
};

/// Where a rigid URDF robot went in the model.
struct PlacedUrdfMultibody {
  /// Index into Model::rigidTrees.
  std::int32_t tree = -1;
  /// (bodies) the object of each body's surface particles (Model::objects), -1: a
  /// body without <collision>, which touches nothing.
  std::vector<std::int32_t> objectOfBody{};
  /// The collision meshes read (each distinct file and scale once).
  int meshesRead = 0;
};

/// Places a rigid URDF robot: every body's <collision> shapes (box, cylinder,
/// sphere, mesh) filled with fixed particles that move with the body, an object
/// (kind "link", named as the body) for each body that has them, and the tree.
/// Throws UrdfError for a mesh that cannot be read, SpecError for bad settings.
PlacedUrdfMultibody placeUrdfMultibody(ModelBuilder& builder, const UrdfMultibody& robot,
                                       const UrdfMultibodyPlacement& placement);

}  // namespace robophi::build
