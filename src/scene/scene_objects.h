#pragma once
// Reading the "objects" of a scene: one entry → its builder's spec
// (robophi/build/) → a GeneratedObject plus what the entry says about its
// particles (fixed, initial velocity, linear damping).

#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "robophi/build/model_builder.h"
#include "robophi/build/urdf.h"
#include "robophi/build/urdf_multibody.h"
#include "scene/scene_fields.h"

namespace robophi::scene {

/// One scene object, read and generated (local indices), before placement:
/// what build::ModelBuilder places, and where the entry is in the file.
struct SceneObject : build::ObjectPlacement {
  /// JSON pointer of the entry, e.g. "/objects/2".
  std::string pointer;
  /// False when the entry had an error: its particles are unknown.
  bool valid = false;
  /// Index of its first particle in the model, once placed.
  ParticleIndex firstParticle = 0;
  /// A URDF robot ({"type": "urdf"}): placed by build::placeUrdfRobot, one
  /// object per link; `geometry` stays empty.
  std::shared_ptr<const build::UrdfRobot> urdf{};
  /// A URDF robot as rigid bodies ({"type": "urdf", "rigid": true}; docs/robots.md
  /// "Rigid bodies"): placed by build::placeUrdfMultibody, one object per body
  /// with <collision>, its joints the model's; `geometry` stays empty.
  struct RigidUrdf {
    build::UrdfMultibody robot;
    build::UrdfMultibodyPlacement placement;
    /// holdJoints: servos that hold the start pose, with gravity compensation.
    bool holdJoints = false;
    /// A built-in robot's jointStiffness (N·m/rad, > 0: every joint's servo holds
    /// its start coordinate) and jointDamping (N·m·s/rad; unset: 2 √(κ M_ii)).
    double servoStiffness = 0.0;
    std::optional<double> servoDamping{};
  };
  std::shared_ptr<const RigidUrdf> rigidUrdf{};
  /// "rigid": true — one free rigid body of its particles (build::placeRigidObject),
  /// starting at the entry's velocity and angularVelocity.
  bool rigid = false;
  Vec3 rigidVelocity{}, rigidSpin{};
  bool isRobot() const { return urdf != nullptr || rigidUrdf != nullptr; }
};

/// The generator names a scene may use (aliases included), for suggestions.
const std::vector<std::string>& objectTypeNames();

/// Reads the object entry at `pointer`. Errors go to `sink`; the result is
/// valid only if this entry added none. Files an entry names (a mesh) are
/// relative to `sceneDirectory`.
SceneObject readSceneObject(DiagnosticSink& sink, const nlohmann::json& entry,
                            const std::string& pointer, const std::string& sceneDirectory = "");
/// The optional "rotation" [ax, ay, az, angle] and "rpy" [roll, pitch, yaw] of
/// an entry, applied to `object` about `pivot`; false when one is bad (reported).
bool applyRotation(ObjectReader& r, build::GeneratedObject& object, const Vec3& pivot);

/// Reads the keys every generated object shares (stiffness, damping,
/// naturalFrequency and, when `bend`, bendStiffness and bendDamping; docs/scene-format.md).
build::SpringSettings readSprings(ObjectReader& r, bool bend = true);

}  // namespace robophi::scene
