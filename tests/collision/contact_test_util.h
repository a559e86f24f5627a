#pragma once
// Small builders shared by the contact tests.

#include <cmath>
#include <cstdint>

#include "robophi/compiled_model.h"
#include "robophi/evaluation.h"
#include "robophi/model.h"
#include "robophi/state.h"
#include "robophi/world.h"

namespace robophi::test {

/// Evaluates states of one model with one workspace (its sphere trees are built
/// at the first evaluation and refitted after): forces and contacts.
struct Evaluator {
  explicit Evaluator(const Model& model) : compiled(model) {}
  const Evaluation& operator()(const State& state) { return evaluate(compiled, state, workspace); }
  CompiledModel compiled;
  Workspace workspace;
};

/// Adds a single-particle object at p; returns the particle index.
inline ParticleIndex addBall(Model& model, State& state, const Vec3& p, double mass, double radius,
                             std::int32_t material = 0, bool fixed = false) {
  const std::int32_t object = model.addObject("ball", "ball", material);
  const ParticleIndex i = model.addParticle(mass, radius, fixed, object);
  state.position.push_back(p);
  state.velocity.push_back(Vec3{});
  return i;
}

/// Exact pair parameters between object `object` and the environment.
inline void overrideWithEnvironment(Model& model, std::int32_t object, double stiffness,
                                    double damping, double staticFriction, double kineticFriction) {
  model.contact.pairOverrides.push_back(
      ContactPairOverride{object, -1, stiffness, damping, staticFriction, kineticFriction});
}

/// SplitMix64 in [0, 1): a fixed sequence for the tests.
struct TestRandom {
  std::uint64_t state;
  double uniform() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    z ^= z >> 31;
    return static_cast<double>(z >> 11) * 0x1.0p-53;
  }
  double symmetric() { return 2.0 * uniform() - 1.0; }
};

}  // namespace robophi::test
