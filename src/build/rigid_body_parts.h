#pragma once
// The parts of a rigid body before it is one (build/rigid_body.h): its
// particles with their roles, and the LS that hold them.

#include <vector>

#include "robophi/build/objects.h"
#include "robophi/vec3.h"

namespace robophi::build::detail {

/// What a particle is, for the connectors it gets.
enum class Role { kLattice, kRequired, kCarrier };

struct Particle {
  Vec3 position;  // body frame (m)
  double radius;  // m
  double reach;   // LS to every lattice particle within this distance (m)
  Role role;
};

/// LS for `object` (whose particles are `particles`, in order): lattice
/// neighbours by distance (axis, face and body diagonals of their cells); every
/// particle whose neighbours do not span 3-D (required points, carriers, thin
/// sheets) tied to its nearest; separate pieces joined (4 particles × 3 LS); a
/// body of up to 250 particles checked for mechanisms and braced with longer LS
/// until rigid. Returns the LS the bracing added.
int connect(GeneratedObject& object, const std::vector<Particle>& particles);

}  // namespace robophi::build::detail
