// Gravity and the per-particle linear damping (MODEL §2 lists them among the net force).
#include "core/parallel.h"
#include "forces/forces.h"

namespace robophi {

ParticleForceTally startParticleForces(const Model& model, int threads,
                                       const std::vector<Vec3>& position,
                                       const std::vector<Vec3>& velocity, std::vector<Vec3>& force,
                                       std::vector<Vec3>& torque) {
  // Sums in fixed chunks (core/parallel.h): {gravity's potential, damping's power}.
  const std::array<double, 2> total = detail::parallelSum<2>(
      threads, model.particleCount(), {0.0, 0.0},
      [&](std::int64_t begin, std::int64_t end, std::array<double, 2>& sum) {
        double potential = sum[0], power = sum[1];  // local sums: the stores cannot alias them
        for (std::int64_t k = begin; k < end; ++k) {
          startParticleForce(model, static_cast<std::size_t>(k), position.data(), velocity.data(),
                             force.data(), torque.data(), potential, power);
        }
        sum = {potential, power};
      });
  ParticleForceTally tally;
  tally.gravity.potential = total[0];
  tally.damping.dissipativePower = total[1];
  return tally;
}

}  // namespace robophi
