#pragma once
/// \file
/// An MJCF model as rigid bodies (docs/robots.md "MJCF"), read by MuJoCo's own
/// compiler (Debian's libmujoco-dev, with all its defaults, classes and includes)
/// and converted from the compiled mjModel: bodies with their exact mass, centre of
/// mass and inertia; hinge, slide and free joints with axes, ranges, damping,
/// armature and friction loss; collision geoms (box, sphere, cylinder, capsule as
/// its bounding cylinder, meshes) as the URDF importer's collision shapes;
/// actuators (motor, position, velocity) and joint couplings (<equality joint>
/// as a mimic) as data. What robophi cannot represent (ball joints, tendons,
/// ellipsoids, other equalities and actuators) is refused naming the element.
/// Optional: without libmujoco at build time, makeMjcfMultibody throws a
/// UrdfError saying so.

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "robophi/build/urdf_multibody.h"
#include "robophi/rotation.h"
#include "robophi/vec3.h"

namespace robophi::build {

/// How to read an MJCF file as rigid bodies.
struct MjcfMultibodySpec {
  /// The MJCF (.xml) file.
  std::string path;
  /// Prefix of body, frame and joint names; empty: the model's name (<mujoco model=...>).
  std::string name;
  /// The world body's frame in robophi's world (every top-level body is placed by it).
  Pose placement{};
  /// The mass (kg) given to a body that has none (a base without inertial, a body of
  /// joints only), as a 1 cm sphere, with an adjustment listed; > 0.
  double minimumMass = 1e-3;
};

/// An MJCF actuator on a joint, as data (docs/robots.md "MJCF"): what it applies is
/// τ = gear · force, force = ctrl (motor), kp (ctrl − q) (position) or kv (ctrl − q̇)
/// (velocity), clamped to forceLower..forceUpper.
struct MjcfActuator {
  enum class Kind { kMotor, kPosition, kVelocity };
  std::string name;
  Kind kind = Kind::kMotor;
  /// The joint (the MJCF name) and its rate in v.
  std::string joint;
  std::int32_t velocityIndex = -1;
  /// Gear ratio (-); the servo's gain: kp (N·m/rad or N/m) or kv (N·m·s/rad or N·s/m).
  double gear = 1.0;
  double gain = 0.0;
  /// The control's range and the force's (±infinity: unlimited).
  double ctrlLower = -std::numeric_limits<double>::infinity();
  double ctrlUpper = std::numeric_limits<double>::infinity();
  double forceLower = -std::numeric_limits<double>::infinity();
  double forceUpper = std::numeric_limits<double>::infinity();
};

/// What an MJCF file carries beside its bodies.
struct MjcfExtras {
  std::vector<MjcfActuator> actuators;
  /// <option gravity> (m/s²) and <option timestep> (s).
  Vec3 gravity{0, 0, -9.81};
  double timestep = 0.002;
};

/// Whether robophi was built with libmujoco (MJCF import).
bool mjcfAvailable();

/// Reads an MJCF file as rigid bodies (joints: UrdfMultibodyJoint::urdfName holds the
/// MJCF joint's name, type "hinge", "slide" or "free"; collisions: `link` the MJCF body's
/// name). Throws UrdfError: MuJoCo's compile error, or an element robophi cannot
/// represent, named (with its line when the main file names it on one), or "MJCF
/// needs libmujoco-dev" when built without it.
UrdfMultibody makeMjcfMultibody(const MjcfMultibodySpec& spec, MjcfExtras* extras = nullptr);

/// Whether `path` names an MJCF file (".xml", ".mjcf"), for dispatch on the extension.
bool isMjcfPath(const std::string& path);

}  // namespace robophi::build
