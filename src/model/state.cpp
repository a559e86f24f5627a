#include "robophi/state.h"

#include <cstring>

namespace robophi {

State State::sizedFor(const Model& model) {
  State state;
  const auto n = static_cast<std::size_t>(model.particleCount());
  state.position.assign(n, Vec3{});
  state.velocity.assign(n, Vec3{});
  state.force.assign(n, Vec3{});
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

}  // namespace

std::uint64_t stateHash(const State& state) {
  std::uint64_t h = kFnvOffset;
  hashBytes(h, &state.time, sizeof(state.time));
  hashBytes(h, state.position.data(), state.position.size() * sizeof(Vec3));
  hashBytes(h, state.velocity.data(), state.velocity.size() * sizeof(Vec3));
  return h;
}

}  // namespace robophi
