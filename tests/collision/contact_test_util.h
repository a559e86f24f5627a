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

/// A dense pile of side × side × layers balls of radius r, `spacing` apart
/// (below 2r: pressed together from the start), each its own object of
/// `material` (added: κ_c 4e4 N/m, μ_c 2 N·s/m, μ_s 0.5, μ_k 0.4) on a ground
/// plane of it, rows slightly out of line; returns the material's index and the
/// balls' mass (kg) in `mass`.
inline std::int32_t addBallPile(Model& model, State& state, int side, int layers, double radius,
                                double spacing, double& mass) {
  model.gravity = {0.0, 0.0, -9.81};
  Material grain;
  grain.name = "grain";
  grain.contactStiffness = 4.0e4;
  grain.contactDamping = 2.0;
  grain.staticFriction = 0.5;
  grain.kineticFriction = 0.4;
  model.materials.push_back(grain);
  const auto material = static_cast<std::int32_t>(model.materials.size() - 1);
  model.environment.planes.push_back(GroundPlane{{0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, material});
  mass = 1000.0 * 4.0 / 3.0 * M_PI * radius * radius * radius;
  for (int k = 0; k < layers; ++k) {
    for (int j = 0; j < side; ++j) {
      for (int i = 0; i < side; ++i) {
        addBall(model, state,
                {i * spacing + 1e-4 * std::sin(1.3 * k + j), j * spacing, radius + k * spacing},
                mass, radius, material);
      }
    }
  }
  return material;
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
