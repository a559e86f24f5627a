#pragma once
/// \file
/// What the replay page draws besides the particles (docs/viewer.md): the
/// environment (planes, heightfields, boxes, spheres, with the security distance
/// of the robotics obstacles), the objects (fixed or not, virtual), the goals and
/// paths of motion generation, the virtual obstacles the escape task adds during
/// the run (with the time each appears), and which linear springs are attractors
/// rather than connectors. A run writes it as world.json (kWorldViewFile); the
/// replay page embeds it as its "world" block.

#include <string>
#include <string_view>
#include <vector>

#include "robophi/contact.h"
#include "robophi/scene/scene.h"
#include "robophi/world.h"

namespace robophi::output {

/// The world description's file in a run folder.
inline constexpr std::string_view kWorldViewFile = "world.json";

/// Records a run's world for the replay: built from the scene, it notes the
/// environment items that appear during the run (observe) and writes them all.
class WorldView {
 public:
  WorldView() = default;
  explicit WorldView(const Scene& scene);

  /// Notes environment items added since the last call (World's edit API: a
  /// virtual obstacle of the escape task), with the world's time (s).
  void observe(const World& world);

  /// The world description as JSON text (docs/viewer.md "World").
  std::string json() const;

  /// Writes `dir`/world.json whole (output::writeFileAtomically); throws
  /// std::runtime_error when it cannot.
  void write(const std::string& dir) const;

 private:
  std::string sceneJson_;  // what the scene fixes: objects, goals, paths, security distances
  Environment initial_;    // the environment at the start
  Environment latest_;     // and at the last observe()
  std::vector<double> sphereAddedAt_, boxAddedAt_, planeAddedAt_;  // (s), items beyond initial_
  bool valid_ = false;
};

/// The linear springs of `model` that are attractors (MODEL §5.1, §5.3) and not
/// connectors: goal and path springs to virtual particles, finger-tip
/// attractors (rest length build::kAttractorRestLength). Their strain means
/// nothing; the replay leaves them out of the strain scale.
std::vector<int> attractorSprings(const Model& model);

}  // namespace robophi::output
