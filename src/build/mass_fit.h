#pragma once
// The mass fit of a rigid body (build/rigid_body.h): masses m_i >= a floor whose
// mass, centre of mass and inertia tensor are the target's (10 linear
// conditions), as near as possible to equal masses.

#include <vector>

#include "robophi/build/rigid_body.h"
#include "robophi/vec3.h"

namespace robophi::build::detail {

struct MassFit {
  std::vector<double> mass;  // (n) kg
  /// The 10 conditions hold (relative residual below 1e-10) with every mass >= the floor.
  bool feasible = false;
};

/// Minimises Σ (m_i − M/n)² subject to Σ m_i = M, Σ m_i x_i = M c, the second
/// moments Σ m_i (x_i − c)(x_i − c)ᵀ = tr(I)/2 𝟙 − I, and m_i >= floor·M/n.
/// withInertia false: the mass and centre conditions only (4). When no such
/// masses exist, `feasible` is false and `mass` is the last iterate clamped to
/// the floor and rescaled to M.
MassFit fitMasses(const std::vector<Vec3>& position, const MassProperties& target,
                  double floorFraction, bool withInertia = true);

}  // namespace robophi::build::detail
