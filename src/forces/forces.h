#pragma once
// The force stages: each adds its forces to `force` and reports the potential
// energy it holds and the power of its dissipative part.

#include <vector>

#include "robophi/model.h"
#include "robophi/vec3.h"

namespace robophi {

/// What a force stage reports besides its forces.
struct ForceTally {
  /// Potential energy of the stage (J).
  double potential = 0.0;
  /// Power of its dissipative forces (W, <= 0).
  double dissipativePower = 0.0;
};

// Arrays are (particleCount) long.
ForceTally accumulateGravity(const Model& model, const std::vector<Vec3>& position,
                             std::vector<Vec3>& force);
ForceTally accumulateLinearDamping(const Model& model, const std::vector<Vec3>& velocity,
                                   std::vector<Vec3>& force);
ForceTally accumulateLinearSprings(const Model& model, const std::vector<Vec3>& position,
                                   const std::vector<Vec3>& velocity, std::vector<Vec3>& force);
ForceTally accumulateTorsionSprings(const Model& model, const std::vector<Vec3>& position,
                                    const std::vector<Vec3>& velocity, std::vector<Vec3>& force);
ForceTally accumulateJointSprings(const Model& model, const std::vector<Vec3>& position,
                                  const std::vector<Vec3>& velocity, std::vector<Vec3>& force);

}  // namespace robophi
