#pragma once
// Reading what ties particles together across a scene: particle references
// ("object:index"), explicit connectors (LS, TS, JS) and named joints
// (revolute, prismatic). Runs after every object is placed in the model.

#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "robophi/model.h"
#include "scene/scene_fields.h"
#include "scene/scene_objects.h"

namespace robophi::scene {

/// What particle references resolve against.
struct ParticleLookup {
  const std::vector<scene::SceneObject>* objects = nullptr;
  /// Object index by name (the first object of each name).
  const std::map<std::string, std::size_t>* byName = nullptr;
  /// Initial positions of every particle of the model (m).
  const std::vector<Vec3>* position = nullptr;
  /// Inside a "particles" object: plain integers are indices into it.
  const scene::SceneObject* local = nullptr;
  /// With rigid robots: resolves a point of a link, "robot.link" (no ':') or
  /// {"link", "point"}, adding the particle the link carries there
  /// (scene_robotics.h resolveLinkPoint); unset: such references are errors.
  std::function<std::optional<ParticleIndex>(DiagnosticSink&, const nlohmann::json&,
                                             const std::string&)>
      linkPoint{};
};

/// Resolves "object:index" (negative counts from the end), a plain integer
/// when `lookup.local` is set, or a link point through `lookup.linkPoint`. Reports bad references; returns nullopt for them
/// and, silently, for references into an object that failed to load.
std::optional<ParticleIndex> resolveParticle(DiagnosticSink& sink, const nlohmann::json& ref,
                                             const std::string& pointer,
                                             const ParticleLookup& lookup);

/// Reads an array of connectors at `pointer` into the model.
void readConnectors(DiagnosticSink& sink, const nlohmann::json& list, const std::string& pointer,
                    const ParticleLookup& lookup, Model& model);

/// Reads the array of named joints at `pointer` into the model (their
/// connectors and Model::joints).
void readJoints(DiagnosticSink& sink, const nlohmann::json& list, const std::string& pointer,
                const ParticleLookup& lookup, Model& model);

}  // namespace robophi::scene
