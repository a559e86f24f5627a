#include "integrate/integrators.h"

#include <algorithm>

#include "core/parallel.h"
#include "forces/forces.h"

namespace robophi {

// Fixed particles (inverse mass 0) get no acceleration; they keep their
// velocity, so a fixed particle given a velocity moves kinematically. Every
// particle's update is its own: the loops run in parallel (core/parallel.h).

namespace {

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
        state.spin[i] += torque[i] * (inverseSpinInertia[i] * spinDt);
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
                    const Vec3 acceleration = force[i] * model.inverseMass[i];
                    state.position[i] += state.velocity[i] * dt + acceleration * halfDtSquared;
                    state.velocity[i] += acceleration * dt;
                  });
}

void integrateSymplecticEuler(const Model& model, const std::vector<double>& inverseSpinInertia,
                              int threads, double dt, const Evaluation& evaluation, State& state) {
  const std::vector<Vec3>& force = evaluation.force;
  forEachParticle(model, inverseSpinInertia, threads, dt, evaluation.torque, state,
                  [&](std::size_t i) {
                    state.velocity[i] += force[i] * (model.inverseMass[i] * dt);
                    state.position[i] += state.velocity[i] * dt;
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

void measureKineticAndDriving(const Model& model, const std::vector<double>& inverseSpinInertia,
                              int threads, const std::vector<RigidMotion>& bodyMotion,
                              const State& state, Evaluation& evaluation) {
  const std::vector<Vec3>& velocity = state.velocity;
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
