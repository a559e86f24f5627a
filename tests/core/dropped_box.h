#pragma once
// A free box body on the ground for the rigid tree tests (tests/core): a rigid
// tree of one body whose contact surface is a lattice of fixed particles.

#include <utility>
#include <vector>

#include "robophi/build/model_builder.h"
#include "robophi/multibody.h"

namespace robophi::test {

// A free 0.2 × 0.1 × 0.1 m, 2 kg box body whose surface is a 5 × 3 × 3 lattice of
// fixed particles, its centre at height z.
inline build::BuiltModel droppedBox(double z, const Vec3& angularVelocity = {}) {
  build::ModelBuilder builder;
  builder.addPlane({{0, 0, 0}, {0, 0, 1}, 0});
  RigidTree tree;
  MultibodyBody body;
  body.name = "box";
  body.joint = BodyJointKind::kFree;
  const double m = 2.0, a = 0.2, b = 0.1, c = 0.1;
  body.mass = {m, {}, Mat3::diagonal(Vec3{b * b + c * c, a * a + c * c, a * a + b * b} * (m / 12.0))};
  tree.multibody.name = "box";
  tree.multibody.bodies.push_back(body);
  build::ObjectPlacement object;
  object.name = "box";
  object.kind = "link";
  object.geometry.rigid = true;
  const double r = 0.01;  // particles of radius r inside the box, their outer faces on it
  std::vector<Vec3> local;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        local.push_back({-a / 2 + r + i * (a - 2 * r) / 4, -b / 2 + r + j * (b - 2 * r) / 2,
                         -c / 2 + r + k * (c - 2 * r) / 2});
  for (const Vec3& p : local) {
    object.geometry.position.push_back(p + Vec3{0, 0, z});
    object.geometry.mass.push_back(m / static_cast<double>(local.size()));
    object.geometry.radius.push_back(r);
    object.geometry.fixed.push_back(true);
  }
  const build::PlacedObject placed = builder.addObject(object);
  for (std::size_t k = 0; k < local.size(); ++k)
    tree.particles.push_back({placed.firstParticle + static_cast<ParticleIndex>(k), 0, local[k]});
  std::vector<double> v(6, 0.0);
  v[0] = angularVelocity.x, v[1] = angularVelocity.y, v[2] = angularVelocity.z;
  builder.addRigidTree(std::move(tree), {0, 0, z, 1, 0, 0, 0}, v);
  return std::move(builder).build();
}

}  // namespace robophi::test
