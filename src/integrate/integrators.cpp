#include "integrate/integrators.h"

#include <algorithm>

#include "forces/forces.h"

namespace robophi {

// Fixed particles (inverse mass 0) get no acceleration; they keep their
// velocity, so a fixed particle given a velocity moves kinematically.

namespace {

// ω_i += J_i⁻¹ τ_i δ for the spinning particles (orientation is not tracked:
// a sphere looks the same whichever way it has turned).
void kickSpin(const std::vector<double>& inverseSpinInertia, double dt,
              const std::vector<Vec3>& torque, State& state) {
  if (torque.empty()) return;
  const std::size_t n = inverseSpinInertia.size();
  if (state.spin.size() != n) state.spin.assign(n, Vec3{});
  for (std::size_t i = 0; i < n; ++i) {
    if (inverseSpinInertia[i] != 0.0) state.spin[i] += torque[i] * (inverseSpinInertia[i] * dt);
  }
}

}  // namespace

void integrateTaylor(const Model& model, const std::vector<double>& inverseSpinInertia, double dt,
                     const Evaluation& evaluation, State& state) {
  const auto n = model.particleCount();
  const double halfDtSquared = 0.5 * dt * dt;
  const std::vector<Vec3>& force = evaluation.force;
  for (ParticleIndex i = 0; i < n; ++i) {
    const Vec3 acceleration = force[i] * model.inverseMass[i];
    state.position[i] += state.velocity[i] * dt + acceleration * halfDtSquared;
    state.velocity[i] += acceleration * dt;
  }
  kickSpin(inverseSpinInertia, dt, evaluation.torque, state);
}

void integrateSymplecticEuler(const Model& model, const std::vector<double>& inverseSpinInertia,
                              double dt, const Evaluation& evaluation, State& state) {
  const auto n = model.particleCount();
  const std::vector<Vec3>& force = evaluation.force;
  for (ParticleIndex i = 0; i < n; ++i) {
    state.velocity[i] += force[i] * (model.inverseMass[i] * dt);
    state.position[i] += state.velocity[i] * dt;
  }
  kickSpin(inverseSpinInertia, dt, evaluation.torque, state);
}

void integrateVerletDrift(const Model& model, const std::vector<double>& inverseSpinInertia,
                          double dt, const Evaluation& evaluation, State& state) {
  const auto n = model.particleCount();
  const std::vector<Vec3>& force = evaluation.force;
  for (ParticleIndex i = 0; i < n; ++i) {
    state.velocity[i] += force[i] * (model.inverseMass[i] * 0.5 * dt);
    state.position[i] += state.velocity[i] * dt;
  }
  kickSpin(inverseSpinInertia, 0.5 * dt, evaluation.torque, state);
}

void integrateVerletKick(const Model& model, const std::vector<double>& inverseSpinInertia,
                         double dt, const Evaluation& evaluation, State& state) {
  const auto n = model.particleCount();
  const std::vector<Vec3>& force = evaluation.force;
  for (ParticleIndex i = 0; i < n; ++i) {
    state.velocity[i] += force[i] * (model.inverseMass[i] * 0.5 * dt);
  }
  kickSpin(inverseSpinInertia, 0.5 * dt, evaluation.torque, state);
}

void measureKineticAndDriving(const Model& model, const std::vector<double>& inverseSpinInertia,
                              const State& state, Evaluation& evaluation) {
  double energy = 0.0, driving = 0.0;
  const auto n = model.particleCount();
  const std::vector<Vec3>& velocity = state.velocity;
  for (ParticleIndex i = 0; i < n; ++i) {
    if (model.inverseMass[i] == 0.0) {
      driving -= dot(evaluation.force[i], velocity[i]);
    } else {
      energy += 0.5 * model.mass[i] * squaredNorm(velocity[i]);
    }
  }
  {
    const std::size_t spins = std::min(state.spin.size(), inverseSpinInertia.size());
    for (std::size_t i = 0; i < spins; ++i) {
      if (inverseSpinInertia[i] != 0.0 && model.inverseMass[i] != 0.0) {
        energy += 0.5 * squaredNorm(state.spin[i]) / inverseSpinInertia[i];
      }
    }
  }
  evaluation.energy.kinetic = energy;
  // MODEL §1.6, §2.4: the motors' power τ q̇ at the state's velocities.
  const double motorPower =
      jointMotorPower(model, state.position, velocity, evaluation.jointMotorEffort);
  evaluation.drivingPower = motorPower == 0.0 ? driving : driving + motorPower;
}

}  // namespace robophi
