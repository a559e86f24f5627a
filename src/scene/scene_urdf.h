#pragma once
// Reading a scene's URDF robots ({"type": "urdf"}, docs/robots.md "In a scene")
// into build::UrdfSpec → build::makeUrdfRobot.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "scene/scene_fields.h"
#include "scene/scene_objects.h"

namespace robophi::scene {

/// Reads the "urdf" entry at `pointer` and imports its robot into `object.urdf`
/// (the file relative to `sceneDirectory`). URDF problems are reported at the
/// entry's "file" with the URDF's file:line; the URDF's warnings as warnings.
SceneObject readUrdfObject(DiagnosticSink& sink, const nlohmann::json& entry,
                           const std::string& pointer, const std::string& sceneDirectory);

/// The servos that hold each joint of rigid tree `tree` at its coordinate in `state`
/// (ω² M_ii and 2 ω M_ii, ω = 30 rad/s, M the mass matrix there) with gravity
/// compensation on (docs/robots.md "Rigid bodies").
void holdRigidJoints(Model& model, const State& state, std::int32_t tree);

/// A built-in rigid robot's servos ("jointStiffness", "jointDamping"): each joint of
/// rigid tree `tree` held at its coordinate in `state` at `stiffness` (N·m/rad, > 0)
/// and `damping` (N·m·s/rad; unset: 2 √(κ M_ii), critical for the joint alone).
void servoRigidJoints(Model& model, const State& state, std::int32_t tree, double stiffness,
                      std::optional<double> damping);

}  // namespace robophi::scene
