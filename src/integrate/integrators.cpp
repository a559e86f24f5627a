#include "integrate/integrators.h"

namespace robophi {

// Fixed particles (inverse mass 0) get no acceleration; they keep their
// velocity, so a fixed particle given a velocity moves kinematically.

void integrateTaylor(const Model& model, double dt, const std::vector<Vec3>& force, State& state) {
  const auto n = model.particleCount();
  const double halfDtSquared = 0.5 * dt * dt;
  for (ParticleIndex i = 0; i < n; ++i) {
    const Vec3 acceleration = force[i] * model.inverseMass[i];
    state.position[i] += state.velocity[i] * dt + acceleration * halfDtSquared;
    state.velocity[i] += acceleration * dt;
  }
}

void integrateSymplecticEuler(const Model& model, double dt, const std::vector<Vec3>& force,
                              State& state) {
  const auto n = model.particleCount();
  for (ParticleIndex i = 0; i < n; ++i) {
    state.velocity[i] += force[i] * (model.inverseMass[i] * dt);
    state.position[i] += state.velocity[i] * dt;
  }
}

void integrateVerletDrift(const Model& model, double dt, const std::vector<Vec3>& force,
                          State& state) {
  const auto n = model.particleCount();
  for (ParticleIndex i = 0; i < n; ++i) {
    state.velocity[i] += force[i] * (model.inverseMass[i] * 0.5 * dt);
    state.position[i] += state.velocity[i] * dt;
  }
}

void integrateVerletKick(const Model& model, double dt, const std::vector<Vec3>& force,
                         State& state) {
  const auto n = model.particleCount();
  for (ParticleIndex i = 0; i < n; ++i) {
    state.velocity[i] += force[i] * (model.inverseMass[i] * 0.5 * dt);
  }
}

void measureKineticAndDriving(const Model& model, const std::vector<Vec3>& velocity,
                              Evaluation& evaluation) {
  double energy = 0.0, driving = 0.0;
  const auto n = model.particleCount();
  for (ParticleIndex i = 0; i < n; ++i) {
    if (model.inverseMass[i] == 0.0) {
      driving -= dot(evaluation.force[i], velocity[i]);
    } else {
      energy += 0.5 * model.mass[i] * squaredNorm(velocity[i]);
    }
  }
  evaluation.energy.kinetic = energy;
  evaluation.drivingPower = driving;
}

}  // namespace robophi
