// Gravity and the per-particle linear damping (MODEL §2 lists them among the net force).
#include "core/parallel.h"
#include "forces/forces.h"

namespace robophi {

// F_i = m_i g; potential -m_i g·p_i, over the free particles (a fixed one gets neither).
ForceTally accumulateGravity(const Model& model, int threads, const std::vector<Vec3>& position,
                             std::vector<Vec3>& force) {
  const std::array<double, 1> total = detail::parallelSum<1>(
      threads, model.particleCount(), {0.0},
      [&](std::int64_t begin, std::int64_t end, std::array<double, 1>& sum) {
        double potential = sum[0];  // a local sum: the force stores cannot alias it
        for (std::int64_t k = begin; k < end; ++k) {
          const auto i = static_cast<std::size_t>(k);
          if (model.inverseMass[i] == 0.0) continue;
          force[i] += model.gravity * model.mass[i];
          potential -= model.mass[i] * dot(model.gravity, position[i]);
        }
        sum[0] = potential;
      });
  ForceTally tally;
  tally.potential = total[0];
  return tally;
}

// F_i = -c_i v_i; power -c_i |v_i|².
ForceTally accumulateLinearDamping(const Model& model, int threads,
                                   const std::vector<Vec3>& velocity, std::vector<Vec3>& force) {
  const std::array<double, 1> total =
      detail::parallelSum<1>(threads, model.particleCount(), {0.0},
                             [&](std::int64_t begin, std::int64_t end, std::array<double, 1>& sum) {
                               double power = sum[0];
                               for (std::int64_t k = begin; k < end; ++k) {
                                 const auto i = static_cast<std::size_t>(k);
                                 const double c = model.linearDamping[i];
                                 if (c == 0.0) continue;
                                 force[i] -= velocity[i] * c;
                                 power -= c * squaredNorm(velocity[i]);
                               }
                               sum[0] = power;
                             });
  ForceTally tally;
  tally.dissipativePower = total[0];
  return tally;
}

}  // namespace robophi
