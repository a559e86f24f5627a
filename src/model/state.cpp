#include "robophi/state.h"

#include <cstring>

namespace robophi {

State State::sizedFor(const Model& model) {
  State state;
  const auto n = static_cast<std::size_t>(model.particleCount());
  state.position.assign(n, Vec3{});
  state.velocity.assign(n, Vec3{});
  state.spin.assign(n, Vec3{});
  for (const RigidTree& tree : model.rigidTrees) {
    state.treePositions.push_back(neutralConfiguration(tree.multibody));
    state.treeVelocities.emplace_back(static_cast<std::size_t>(tree.multibody.velocityCount), 0.0);
  }
  return state;
}

namespace {

constexpr std::uint64_t kFnvOffset = 1469598103934665603ULL;
constexpr std::uint64_t kFnvPrime = 1099511628211ULL;

void hashBytes(std::uint64_t& h, const void* data, std::size_t size) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    h ^= bytes[i];
    h *= kFnvPrime;
  }
}

template <class T>
void hashValue(std::uint64_t& h, const T& value) {
  hashBytes(h, &value, sizeof(value));
}

}  // namespace

std::uint64_t stateHash(const State& state) {
  std::uint64_t h = kFnvOffset;
  hashValue(h, state.time);
  hashBytes(h, state.position.data(), state.position.size() * sizeof(Vec3));
  hashBytes(h, state.velocity.data(), state.velocity.size() * sizeof(Vec3));
  hashBytes(h, state.spin.data(), state.spin.size() * sizeof(Vec3));
  hashValue(h, state.stepCount);
  hashValue(h, state.dissipated);
  if (state.implicitLoss != 0.0) hashValue(h, state.implicitLoss);  // (rigid trees' contacts only)
  hashValue(h, state.external);
  // The friction history field by field (Contact has padding bytes).
  for (const Contact& c : state.frictionHistory) {
    hashValue(h, c.a);
    hashValue(h, c.other);
    hashValue(h, c.depth);
    hashValue(h, c.normalForce);
    hashValue(h, c.anchorEnergy);
    hashValue(h, c.normal);
    hashValue(h, c.slip);
    hashValue(h, c.anchor);
    hashValue(h, c.rollVelocity);
    hashValue(h, c.rim);
    hashValue(h, c.giveWay);
    hashValue(h, c.arm);
    hashValue(h, c.sliding);
    hashValue(h, c.vertex);
    hashValue(h, c.facet);
    hashValue(h, c.facetWeights);
    if (c.edgeVertex >= 0) {  // (none: hashed as before edges)
      hashValue(h, c.edgeVertex);
      hashValue(h, c.edgeWeight);
    }
    hashValue(h, c.frictionForce);  // a sliding anchor holds it (MODEL §3.3)
  }
  // Rigid trees (none: nothing hashed, so a model without them hashes as before).
  for (const auto& q : state.treePositions) hashBytes(h, q.data(), q.size() * sizeof(double));
  for (const auto& v : state.treeVelocities) hashBytes(h, v.data(), v.size() * sizeof(double));
  return h;
}

}  // namespace robophi
