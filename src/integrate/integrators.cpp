#include "integrate/integrators.h"

namespace robophi {

// Fixed particles (inverse mass 0) get no acceleration; they keep their
// velocity, so a fixed particle given a velocity moves kinematically.

void integrateTaylor(const Model& model, double dt, State& state) {
  const auto n = model.particleCount();
  const double halfDtSquared = 0.5 * dt * dt;
  for (ParticleIndex i = 0; i < n; ++i) {
    const Vec3 acceleration = state.force[i] * model.inverseMass[i];
    state.position[i] += state.velocity[i] * dt + acceleration * halfDtSquared;
    state.velocity[i] += acceleration * dt;
  }
}

void integrateSymplecticEuler(const Model& model, double dt, State& state) {
  const auto n = model.particleCount();
  for (ParticleIndex i = 0; i < n; ++i) {
    state.velocity[i] += state.force[i] * (model.inverseMass[i] * dt);
    state.position[i] += state.velocity[i] * dt;
  }
}

void integrateVerletDrift(const Model& model, double dt, State& state) {
  const auto n = model.particleCount();
  for (ParticleIndex i = 0; i < n; ++i) {
    state.velocity[i] += state.force[i] * (model.inverseMass[i] * 0.5 * dt);
    state.position[i] += state.velocity[i] * dt;
  }
}

void integrateVerletKick(const Model& model, double dt, State& state) {
  const auto n = model.particleCount();
  for (ParticleIndex i = 0; i < n; ++i) {
    state.velocity[i] += state.force[i] * (model.inverseMass[i] * 0.5 * dt);
  }
}

void measureKineticAndDriving(const Model& model, State& state) {
  double energy = 0.0, driving = 0.0;
  const auto n = model.particleCount();
  for (ParticleIndex i = 0; i < n; ++i) {
    if (model.inverseMass[i] == 0.0) {
      driving -= dot(state.force[i], state.velocity[i]);
    } else {
      energy += 0.5 * model.mass[i] * squaredNorm(state.velocity[i]);
    }
  }
  state.energy.kinetic = energy;
  state.drivingPower = driving;
}

}  // namespace robophi
