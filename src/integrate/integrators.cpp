#include "integrate/integrators.h"

#include <algorithm>

#include "core/parallel.h"
#include "forces/forces.h"

namespace robophi {

// Fixed particles (inverse mass 0) get no acceleration; they keep their
// velocity, so a fixed particle given a velocity moves kinematically. Every
// particle's update is its own: the loops run in parallel (core/parallel.h).

namespace {

// One particle's update by each integrator (and by the fused pass, which must
// do the same operations).
inline void taylorUpdate(const Vec3& force, double inverseMass, double dt, double halfDtSquared,
                         Vec3& position, Vec3& velocity) {
  const Vec3 acceleration = force * inverseMass;
  position += velocity * dt + acceleration * halfDtSquared;
  velocity += acceleration * dt;
}

inline void symplecticEulerUpdate(const Vec3& force, double inverseMass, double dt, Vec3& position,
                                  Vec3& velocity) {
  velocity += force * (inverseMass * dt);
  position += velocity * dt;
}

// The spin's kick ω += J⁻¹ τ dt of a spinning particle.
inline void kickSpin(const Vec3& torque, double inverseSpinInertia, double dt, Vec3& spin) {
  spin += torque * (inverseSpinInertia * dt);
}

// body(i) for every particle, then the kick of its spin, ω_i += J_i⁻¹ τ_i spinDt,
// for the spinning particles (orientation is not tracked: a sphere looks the
// same whichever way it has turned), in one parallel pass.
template <class Body>
void forEachParticle(const Model& model, const std::vector<double>& inverseSpinInertia, int threads,
                     double spinDt, const std::vector<Vec3>& torque, State& state,
                     const Body& body) {
  const bool spins = !torque.empty() &&
                     inverseSpinInertia.size() == static_cast<std::size_t>(model.particleCount());
  if (spins && state.spin.size() != inverseSpinInertia.size())
    state.spin.assign(inverseSpinInertia.size(), Vec3{});
  detail::parallelFor(threads, model.particleCount(), [&](std::int64_t begin, std::int64_t end) {
    for (auto i = static_cast<std::size_t>(begin); i < static_cast<std::size_t>(end); ++i) {
      body(i);
      if (spins && inverseSpinInertia[i] != 0.0)
        kickSpin(torque[i], inverseSpinInertia[i], spinDt, state.spin[i]);
    }
  });
}

}  // namespace

void integrateTaylor(const Model& model, const std::vector<double>& inverseSpinInertia, int threads,
                     double dt, const Evaluation& evaluation, State& state) {
  const double halfDtSquared = 0.5 * dt * dt;
  const std::vector<Vec3>& force = evaluation.force;
  forEachParticle(model, inverseSpinInertia, threads, dt, evaluation.torque, state,
                  [&](std::size_t i) {
                    taylorUpdate(force[i], model.inverseMass[i], dt, halfDtSquared,
                                 state.position[i], state.velocity[i]);
                  });
}

void integrateSymplecticEuler(const Model& model, const std::vector<double>& inverseSpinInertia,
                              int threads, double dt, const Evaluation& evaluation, State& state) {
  const std::vector<Vec3>& force = evaluation.force;
  forEachParticle(model, inverseSpinInertia, threads, dt, evaluation.torque, state,
                  [&](std::size_t i) {
                    symplecticEulerUpdate(force[i], model.inverseMass[i], dt, state.position[i],
                                          state.velocity[i]);
                  });
}

void integrateVerletDrift(const Model& model, const std::vector<double>& inverseSpinInertia,
                          int threads, double dt, const Evaluation& evaluation, State& state) {
  const std::vector<Vec3>& force = evaluation.force;
  forEachParticle(model, inverseSpinInertia, threads, 0.5 * dt, evaluation.torque, state,
                  [&](std::size_t i) {
                    state.velocity[i] += force[i] * (model.inverseMass[i] * 0.5 * dt);
                    state.position[i] += state.velocity[i] * dt;
                  });
}

void integrateVerletKick(const Model& model, const std::vector<double>& inverseSpinInertia,
                         int threads, double dt, const Evaluation& evaluation, State& state) {
  const std::vector<Vec3>& force = evaluation.force;
  forEachParticle(
      model, inverseSpinInertia, threads, 0.5 * dt, evaluation.torque, state,
      [&](std::size_t i) { state.velocity[i] += force[i] * (model.inverseMass[i] * 0.5 * dt); });
}

bool canIntegrateAndStartForces(const Model& model, const std::vector<double>& inverseSpinInertia,
                                const Evaluation& evaluation, const State& state) {
  const auto n = static_cast<std::size_t>(model.particleCount());
  return n > 0 && state.position.size() == n && state.velocity.size() == n &&
         state.spin.size() == n && evaluation.force.size() == n && evaluation.torque.size() == n &&
         (inverseSpinInertia.empty() || inverseSpinInertia.size() == n);
}

FusedParticlePass makeFusedParticlePass(const Model& model,
                                        const std::vector<double>& inverseSpinInertia, double dt,
                                        bool taylor, Evaluation& evaluation, State& state,
                                        ParticlePassSums& sums) {
  const std::int64_t chunks =
      (model.particleCount() + detail::kParallelChunk - 1) / detail::kParallelChunk;
  sums.sums.resize(static_cast<std::size_t>(chunks));
  sums.flags.resize(static_cast<std::size_t>(chunks));
  return {&model, &inverseSpinInertia, dt, taylor, &evaluation, &state, &sums};
}

void FusedParticlePass::run(void* raw, std::int64_t chunk) {
  // forEachParticle's body and spin kick, startParticleForces' loop and
  // measureKineticAndDriving's terms, particle by particle, each sum in its own
  // chunks (core/parallel.h).
  const FusedParticlePass& x = *static_cast<const FusedParticlePass*>(raw);
  const Model& model = *x.model;
  const std::vector<double>& inverseSpinInertia = *x.inverseSpinInertia;
  const bool spins = !inverseSpinInertia.empty();
  const double dt = x.dt;
  const double halfDtSquared = 0.5 * dt * dt;
  Vec3* force = x.evaluation->force.data();
  Vec3* torque = x.evaluation->torque.data();
  Vec3* position = x.state->position.data();
  Vec3* velocity = x.state->velocity.data();
  Vec3* spin = x.state->spin.data();
  const std::int64_t begin = chunk * detail::kParallelChunk;
  const std::int64_t end =
      std::min(static_cast<std::int64_t>(model.particleCount()), begin + detail::kParallelChunk);
  double potential = 0.0, power = 0.0, kinetic = 0.0, spinning = 0.0;
  std::uint8_t flags = 0;
  const bool first = chunk == 0;
  for (auto i = static_cast<std::size_t>(begin); i < static_cast<std::size_t>(end); ++i) {
    // The integrator (integrateSymplecticEuler, integrateTaylor).
    if (x.taylor) {
      taylorUpdate(force[i], model.inverseMass[i], dt, halfDtSquared, position[i], velocity[i]);
    } else {
      symplecticEulerUpdate(force[i], model.inverseMass[i], dt, position[i], velocity[i]);
    }
    if (spins && inverseSpinInertia[i] != 0.0)
      kickSpin(torque[i], inverseSpinInertia[i], dt, spin[i]);
    startParticleForce(model, i, position, velocity, force, torque, potential, power);
    // measureKineticAndDriving's terms (the driving power's once the forces are final).
    if (model.inverseMass[i] == 0.0) {
      flags |= 1;
    } else {
      kinetic += 0.5 * model.mass[i] * squaredNorm(velocity[i]);
      if (spins && inverseSpinInertia[i] != 0.0) {
        flags |= 2;
        // Chunk 0's spin sum starts from the kinetic total: measureKineticAndDriving.
        if (!first) spinning += 0.5 * squaredNorm(spin[i]) / inverseSpinInertia[i];
      }
    }
  }
  const auto c = static_cast<std::size_t>(chunk);
  x.sums->sums[c] = {potential, power, kinetic, spinning};
  x.sums->flags[c] = flags;
}

ParticleForceTally FusedParticlePass::tally() const {
  // The chunks' sums in chunk order.
  std::array<double, 2> total = {sums->sums[0][0], sums->sums[0][1]};
  for (std::size_t c = 1; c < sums->sums.size(); ++c) {
    total[0] += sums->sums[c][0];
    total[1] += sums->sums[c][1];
  }
  ParticleForceTally result;
  result.gravity.potential = total[0];
  result.damping.dissipativePower = total[1];
  return result;
}

void measureKineticAndDriving(const Model& model, const std::vector<double>& inverseSpinInertia,
                              int threads, const std::vector<RigidMotion>& bodyMotion,
                              const State& state, Evaluation& evaluation,
                              const ParticlePassSums* pass) {
  const std::vector<Vec3>& velocity = state.velocity;
  if (pass != nullptr) {
    // The parallelSums below from the pass's chunk sums: a chunk with no fixed
    // (spinning) particle adds +0 to the driving power (the spins' energy), which
    // changes no sum that starts from +0 (none becomes -0).
    const std::int64_t n = model.particleCount();
    double kinetic = pass->sums[0][2];
    for (std::size_t c = 1; c < pass->sums.size(); ++c) kinetic += pass->sums[c][2];
    double driving = 0.0, energy = kinetic;
    for (std::size_t c = 0; c < pass->sums.size(); ++c) {
      const auto begin =
          static_cast<std::size_t>(static_cast<std::int64_t>(c) * detail::kParallelChunk);
      const auto end = static_cast<std::size_t>(
          std::min(n, static_cast<std::int64_t>(c + 1) * detail::kParallelChunk));
      if ((pass->flags[c] & 1) != 0) {
        double sum = 0.0;
        for (std::size_t i = begin; i < end; ++i) {
          if (model.inverseMass[i] == 0.0) sum -= dot(evaluation.force[i], velocity[i]);
        }
        if (c == 0)
          driving = sum;
        else
          driving += sum;
      }
      if ((pass->flags[c] & 2) != 0) {
        if (c == 0) {
          for (std::size_t i = begin; i < end; ++i) {
            if (inverseSpinInertia[i] != 0.0 && model.inverseMass[i] != 0.0)
              energy += 0.5 * squaredNorm(state.spin[i]) / inverseSpinInertia[i];
          }
        } else {
          energy += pass->sums[c][3];
        }
      }
    }
    evaluation.energy.kinetic = energy;
    const double motorPower =
        jointMotorPower(model, bodyMotion, state.position, velocity, evaluation.jointMotorEffort);
    evaluation.drivingPower = motorPower == 0.0 ? driving : driving + motorPower;
    return;
  }
  // Sums in fixed chunks (core/parallel.h): {kinetic energy, driving power}.
  const std::array<double, 2> particles = detail::parallelSum<2>(
      threads, model.particleCount(), {0.0, 0.0},
      [&](std::int64_t begin, std::int64_t end, std::array<double, 2>& sum) {
        double kinetic = sum[0], driving = sum[1];  // local sums
        for (auto i = static_cast<std::size_t>(begin); i < static_cast<std::size_t>(end); ++i) {
          if (model.inverseMass[i] == 0.0) {
            driving -= dot(evaluation.force[i], velocity[i]);
          } else {
            kinetic += 0.5 * model.mass[i] * squaredNorm(velocity[i]);
          }
        }
        sum = {kinetic, driving};
      });
  const std::size_t spins = std::min(state.spin.size(), inverseSpinInertia.size());
  const std::array<double, 1> energy = detail::parallelSum<1>(
      threads, static_cast<std::int64_t>(spins), {particles[0]},
      [&](std::int64_t begin, std::int64_t end, std::array<double, 1>& sum) {
        for (auto i = static_cast<std::size_t>(begin); i < static_cast<std::size_t>(end); ++i) {
          if (inverseSpinInertia[i] != 0.0 && model.inverseMass[i] != 0.0) {
            sum[0] += 0.5 * squaredNorm(state.spin[i]) / inverseSpinInertia[i];
          }
        }
      });
  evaluation.energy.kinetic = energy[0];
  const double driving = particles[1];
  // MODEL §1.6, §2.4: the motors' power τ q̇ at the state's velocities.
  const double motorPower =
      jointMotorPower(model, bodyMotion, state.position, velocity, evaluation.jointMotorEffort);
  evaluation.drivingPower = motorPower == 0.0 ? driving : driving + motorPower;
}

}  // namespace robophi
