#include "robophi/model.h"

#include <fmt/format.h>

#include <cmath>

namespace robophi {

ParticleIndex Model::addParticle(double particleMass, double particleRadius, bool fixed,
                                 std::int32_t object, double damping) {
  const auto index = particleCount();
  mass.push_back(particleMass);
  inverseMass.push_back(fixed ? 0.0 : 1.0 / particleMass);
  radius.push_back(particleRadius);
  linearDamping.push_back(damping);
  objectOf.push_back(object);
  if (object >= 0 && object < static_cast<std::int32_t>(objects.size())) {
    auto& info = objects[object];
    if (info.particleCount == 0) info.firstParticle = index;
    ++info.particleCount;
  }
  return index;
}

std::int32_t Model::addObject(std::string name, std::string kind, std::int32_t material) {
  objects.push_back(ObjectInfo{std::move(name), std::move(kind), particleCount(), 0, material});
  return static_cast<std::int32_t>(objects.size()) - 1;
}

namespace {

bool inRange(ParticleIndex i, ParticleIndex n) { return i >= 0 && i < n; }

}  // namespace

std::string checkModel(const Model& model) {
  const auto n = model.particleCount();
  const auto size = static_cast<std::size_t>(n);
  if (model.inverseMass.size() != size || model.radius.size() != size ||
      model.linearDamping.size() != size || model.objectOf.size() != size) {
    return "particle arrays have different sizes";
  }
  for (ParticleIndex i = 0; i < n; ++i) {
    if (!(model.mass[i] > 0.0) || !std::isfinite(model.mass[i]))
      return fmt::format("particle {}: mass {} must be a positive number (kg)", i, model.mass[i]);
    if (!(model.radius[i] > 0.0) || !std::isfinite(model.radius[i]))
      return fmt::format("particle {}: radius {} must be a positive number (m)", i,
                         model.radius[i]);
    if (!(model.linearDamping[i] >= 0.0))
      return fmt::format("particle {}: damping {} must be >= 0 (N·s/m)", i, model.linearDamping[i]);
  }
  for (std::size_t k = 0; k < model.linearSprings.size(); ++k) {
    const auto& s = model.linearSprings[k];
    if (!inRange(s.a, n) || !inRange(s.b, n) || s.a == s.b)
      return fmt::format("LS {}: particles ({}, {}) must be two different particles of {}", k, s.a,
                         s.b, n);
    if (!(s.restLength > 0.0))
      return fmt::format("LS {}: rest length {} must be > 0", k, s.restLength);
    if (!(s.stiffness >= 0.0) || !(s.damping >= 0.0))
      return fmt::format("LS {}: stiffness {} and damping {} must be >= 0", k, s.stiffness,
                         s.damping);
  }
  for (std::size_t k = 0; k < model.torsionSprings.size(); ++k) {
    const auto& s = model.torsionSprings[k];
    if (!inRange(s.a, n) || !inRange(s.b, n) || !inRange(s.c, n) || s.a == s.c || s.b == s.c ||
        s.a == s.b)
      return fmt::format("TS {}: particles ({}, {}, {}) must be three different particles of {}", k,
                         s.a, s.c, s.b, n);
    if (!(s.restAngle >= 0.0 && s.restAngle <= M_PI))
      return fmt::format("TS {}: rest angle {} must be in [0, π]", k, s.restAngle);
    if (!(s.stiffness >= 0.0) || !(s.damping >= 0.0))
      return fmt::format("TS {}: stiffness {} and damping {} must be >= 0", k, s.stiffness,
                         s.damping);
  }
  for (std::size_t k = 0; k < model.jointSprings.size(); ++k) {
    const auto& s = model.jointSprings[k];
    if (!inRange(s.a, n) || !inRange(s.b, n) || !inRange(s.c, n) || !inRange(s.d, n) ||
        s.a == s.c || s.b == s.c || s.a == s.b || s.d == s.c)
      return fmt::format("JS {}: particles ({}, {}, {}, {}) must be different particles of {}", k,
                         s.a, s.c, s.b, s.d, n);
    if (!(s.restAngle >= 0.0 && s.restAngle < 2.0 * M_PI))
      return fmt::format("JS {}: rest angle {} must be in [0, 2π)", k, s.restAngle);
    if (!(s.stiffness >= 0.0) || !(s.damping >= 0.0))
      return fmt::format("JS {}: stiffness {} and damping {} must be >= 0", k, s.stiffness,
                         s.damping);
  }
  for (const auto& joint : model.joints) {
    const auto count = joint.kind == JointKind::kRevolute ? model.jointSprings.size()
                                                          : model.torsionSprings.size();
    if (joint.connector < 0 || static_cast<std::size_t>(joint.connector) >= count)
      return fmt::format("joint '{}': connector {} does not exist", joint.name, joint.connector);
    if (joint.driveSpring >= 0 &&
        static_cast<std::size_t>(joint.driveSpring) >= model.linearSprings.size())
      return fmt::format("joint '{}': drive spring {} does not exist", joint.name,
                         joint.driveSpring);
  }
  return {};
}

}  // namespace robophi
