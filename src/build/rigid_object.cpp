// A generated object as one free rigid body (build/rigid_object.h, docs/model.md §7).
#include "robophi/build/rigid_object.h"

#include <algorithm>

#include "robophi/build/spec_error.h"
#include "robophi/model.h"
#include "robophi/multibody.h"

namespace robophi::build {

PlacedRigidObject placeRigidObject(ModelBuilder& builder, ObjectPlacement object,
                                   const Vec3& velocity, const Vec3& angularVelocity) {
  GeneratedObject& g = object.geometry;
  const std::string what = "rigid object '" + object.name + "'";
  if (g.size() == 0) throw SpecError("placeRigidObject", "geometry", what + " has no particles");
  if (!g.joints.empty())
    throw SpecError("placeRigidObject", "rigid",
                    what + " has joints: a robot is not one rigid body (import it as a rigid tree)");
  if (std::any_of(g.fixed.begin(), g.fixed.end(), [](bool f) { return f; }))
    throw SpecError("placeRigidObject", "fixed",
                    what + " has fixed particles: a rigid object moves as a whole");
  // Mass properties of the particles, each a uniform ball.
  double mass = 0.0;
  Vec3 moment{};
  for (std::size_t i = 0; i < g.size(); ++i) {
    mass += g.mass[i];
    moment += g.position[i] * g.mass[i];
  }
  const Vec3 center = moment / mass;
  Mat3 inertia = Mat3::zero();
  for (std::size_t i = 0; i < g.size(); ++i) {
    const Vec3 r = g.position[i] - center;
    const double ball = 0.4 * g.mass[i] * g.radius[i] * g.radius[i];
    const double rr = dot(r, r);
    const double rv[3] = {r.x, r.y, r.z};
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        inertia.m[a][b] += g.mass[i] * ((a == b ? rr : 0.0) - rv[a] * rv[b]) + (a == b ? ball : 0.0);
  }
  // The particles are its surface: fixed, moved by the body, no connectors between them.
  g.fixed.assign(g.size(), true);
  g.rigid = true;
  g.linearSprings.clear();
  g.torsionSprings.clear();
  g.jointSprings.clear();
  // A faceted object keeps its surface mesh: its vertices, embedded in the
  // particles, ride the body exactly (the embedding is exact for any rigid
  // motion), and the contact law sees the body's inverse mass at each
  // (ContactTables::vertexInverseMass).
  object.velocity.clear();
  const PlacedObject placed = builder.addObject(object);

  RigidTree tree;
  MultibodyBody body;
  body.name = object.name;
  body.joint = BodyJointKind::kFree;
  body.X_PJ.translation = center;
  body.mass = {mass, Vec3{}, inertia};
  tree.multibody.name = object.name;
  tree.multibody.bodies.push_back(body);
  for (std::size_t i = 0; i < g.size(); ++i)
    tree.particles.push_back({placed.firstParticle + static_cast<ParticleIndex>(i), 0, g.position[i] - center});
  std::vector<double> q{center.x, center.y, center.z, 1.0, 0.0, 0.0, 0.0};
  std::vector<double> v{angularVelocity.x, angularVelocity.y, angularVelocity.z,
                        velocity.x,        velocity.y,        velocity.z};
  const std::int32_t index = builder.addRigidTree(std::move(tree), std::move(q), std::move(v));
  return {placed, index};
}

}  // namespace robophi::build
