#pragma once
// Worlds built from scene text, as a user writes them, and the motion of their
// objects: for the contact tests.

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "robophi/scene/scene.h"
#include "robophi/world.h"

namespace robophi::test {

/// The world of a scene given as JSON text (its own integrator is ignored:
/// symplectic Euler, stepped by the test).
inline World sceneWorld(const std::string& text,
                        Integrator integrator = Integrator::kSymplecticEuler) {
  SceneLoadResult loaded = loadSceneText(text, "<test scene>");
  if (!loaded.scene) {
    for (const Diagnostic& d : loaded.errors) ADD_FAILURE() << d.format();
    throw std::runtime_error("the test scene did not load");
  }
  return World(std::move(loaded.scene->model), std::move(loaded.scene->initial), integrator);
}

/// Mass-weighted mean of `values` over the particles of object `object` (all
/// particles when object < 0).
inline Vec3 objectMean(const World& world, const std::vector<Vec3>& values, int object = -1) {
  const Model& model = world.model();
  Vec3 sum;
  double mass = 0.0;
  for (ParticleIndex i = 0; i < model.particleCount(); ++i) {
    if (object >= 0 && model.objectOf[i] != object) continue;
    sum += values[i] * model.mass[i];
    mass += model.mass[i];
  }
  return sum / mass;
}

inline Vec3 centerOfMass(const World& world, int object = -1) {
  return objectMean(world, world.state().position, object);
}
inline Vec3 comVelocity(const World& world, int object = -1) {
  return objectMean(world, world.state().velocity, object);
}

/// Steps `world` by `dt` for `seconds` (rounded to whole steps).
inline void advance(World& world, double seconds, double dt) {
  const auto steps = static_cast<long>(std::lround(seconds / dt));
  for (long k = 0; k < steps; ++k) ASSERT_EQ(world.step(dt), StepStatus::kOk);
}

}  // namespace robophi::test
