// Gravity and the per-particle linear damping (MODEL §2 lists them among the net force).
#include "forces/forces.h"

namespace robophi {

// F_i = m_i g; potential -m_i g·p_i, over the free particles (a fixed one gets neither).
ForceTally accumulateGravity(const Model& model, const std::vector<Vec3>& position,
                             std::vector<Vec3>& force) {
  ForceTally tally;
  const auto n = model.particleCount();
  for (ParticleIndex i = 0; i < n; ++i) {
    if (model.inverseMass[i] == 0.0) continue;
    force[i] += model.gravity * model.mass[i];
    tally.potential -= model.mass[i] * dot(model.gravity, position[i]);
  }
  return tally;
}

// F_i = -c_i v_i; power -c_i |v_i|².
ForceTally accumulateLinearDamping(const Model& model, const std::vector<Vec3>& velocity,
                                   std::vector<Vec3>& force) {
  ForceTally tally;
  const auto n = model.particleCount();
  for (ParticleIndex i = 0; i < n; ++i) {
    const double c = model.linearDamping[i];
    if (c == 0.0) continue;
    force[i] -= velocity[i] * c;
    tally.dissipativePower -= c * squaredNorm(velocity[i]);
  }
  return tally;
}

}  // namespace robophi
