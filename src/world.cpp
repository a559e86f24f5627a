// World::step: the list of stages of one step (docs/architecture.md), nothing else.
#include "robophi/world.h"

#include <cmath>

#include "collision/contact_stage.h"
#include "forces/forces.h"
#include "integrate/integrators.h"

namespace robophi {

World::World(Model model, State initial, Integrator integrator)
    : model_(std::move(model)), state_(std::move(initial)), integrator_(integrator) {
  state_.force.assign(state_.position.size(), Vec3{});
  state_.forcesValid = false;
}

void computeForces(const Model& model, State& state) {
  for (Vec3& f : state.force) f = Vec3{};
  EnergyTally& e = state.energy;
  const ForceTally gravity = accumulateGravity(model, state.position, state.force);
  const ForceTally damping = accumulateLinearDamping(model, state.velocity, state.force);
  const ForceTally linear =
      accumulateLinearSprings(model, state.position, state.velocity, state.force);
  const ForceTally torsion =
      accumulateTorsionSprings(model, state.position, state.velocity, state.force);
  const ForceTally joint =
      accumulateJointSprings(model, state.position, state.velocity, state.force);
  e.gravity = gravity.potential;
  e.linearSpring = linear.potential;
  e.torsionSpring = torsion.potential;
  e.jointSpring = joint.potential;
  state.dissipativePower = damping.dissipativePower + linear.dissipativePower +
                           torsion.dissipativePower + joint.dissipativePower;
  // MODEL §3: contacts, friction, viscosity (sets e.contact, adds to the power).
  accumulateContacts(model, state);
  state.forcesValid = true;
}

void World::refresh() {
  if (state_.forcesValid) return;
  computeForces(model_, state_);
  measureKineticAndDriving(model_, state_);
}

double World::bookExternalWork() {
  if (state_.forcesValid) return 0.0;
  const double before = state_.energy.total();
  refresh();
  const double work = state_.energy.total() - before;
  state_.energy.external += work;
  return work;
}

StepStatus World::step(double dt) {
  // 1. Forces at t (cached from the previous step when nothing changed).
  refresh();
  const double powerAtStart = state_.dissipativePower;
  const double drivingAtStart = state_.drivingPower;

  // 2. Integrate to t + δ; 3. forces and potentials at t + δ.
  switch (integrator_) {
    case Integrator::kTaylor:
      integrateTaylor(model_, dt, state_);
      computeForces(model_, state_);
      break;
    case Integrator::kSymplecticEuler:
      integrateSymplecticEuler(model_, dt, state_);
      computeForces(model_, state_);
      break;
    case Integrator::kVelocityVerlet:
      integrateVerletDrift(model_, dt, state_);
      computeForces(model_, state_);
      integrateVerletKick(model_, dt, state_);
      break;
  }

  // 4. Energy account: kinetic at t + δ; dissipated work and the work of moving
  // fixed particles by the trapezoid rule.
  measureKineticAndDriving(model_, state_);
  state_.energy.dissipated -= 0.5 * (powerAtStart + state_.dissipativePower) * dt;
  state_.energy.external += 0.5 * (drivingAtStart + state_.drivingPower) * dt;
  state_.time += dt;
  ++state_.stepCount;

  // 5. Numerical trouble shows in the energy: one check covers every particle.
  return std::isfinite(state_.energy.total()) ? StepStatus::kOk : StepStatus::kNonFinite;
}

ParticleIndex World::firstNonFiniteParticle() const {
  const auto n = model_.particleCount();
  for (ParticleIndex i = 0; i < n; ++i) {
    if (!isFinite(state_.position[i]) || !isFinite(state_.velocity[i])) return i;
  }
  return kNoParticle;
}

}  // namespace robophi
