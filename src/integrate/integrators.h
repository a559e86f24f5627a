#pragma once
// The explicit integrators of MODEL §2, as stages over the particle arrays.
// Each uses state.force (valid at the state's positions and velocities).

#include "robophi/model.h"
#include "robophi/state.h"

namespace robophi {

/// Paper's scheme: p += v δ + ½ a δ², then v += a δ.
void integrateTaylor(const Model& model, double dt, State& state);
/// Symplectic Euler: v += a δ, then p += v δ.
void integrateSymplecticEuler(const Model& model, double dt, State& state);
/// Velocity Verlet, first part: v += ½ a δ, then p += v δ (forces must be
/// evaluated at the new positions before the second part).
void integrateVerletDrift(const Model& model, double dt, State& state);
/// Velocity Verlet, second part: v += ½ a(t+δ) δ.
void integrateVerletKick(const Model& model, double dt, State& state);

/// ½ Σ m_i |v_i|² over the free particles (J).
double kineticEnergy(const Model& model, const State& state);

}  // namespace robophi
