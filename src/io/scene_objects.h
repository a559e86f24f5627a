#pragma once
// Reading the "objects" of a scene: one entry → its generator's parameters →
// a GeneratedObject plus what the entry says about its particles (fixed,
// initial velocity, linear damping).

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "io/generators.h"
#include "scene/scene_fields.h"

namespace robophi::io {

/// One scene object, read and generated (local indices), before placement.
struct SceneObject {
  std::string name;
  /// The generator's canonical name (ObjectInfo::kind): rope, bar, box, plate, ball, wheel,
  /// particles.
  std::string kind;
  /// JSON pointer of the entry, e.g. "/objects/2".
  std::string pointer;
  /// False when the entry had an error: its particles are unknown.
  bool valid = false;
  GeneratedObject geometry;
  std::vector<bool> fixed;     // (n)
  std::vector<Vec3> velocity;  // (n) m/s
  /// Linear damping of each particle c (N·s/m): force -c v.
  double linearDamping = 0.0;
  /// Index of its first particle in the model, once placed.
  ParticleIndex firstParticle = 0;
};

/// The generator names a scene may use (aliases included), for suggestions.
const std::vector<std::string>& objectTypeNames();

/// Reads the object entry at `pointer`; `dt` sets default stiffnesses. Errors
/// go to `sink`; the result is valid only if this entry added none.
SceneObject readSceneObject(DiagnosticSink& sink, const nlohmann::json& entry,
                            const std::string& pointer, double dt);

}  // namespace robophi::io
