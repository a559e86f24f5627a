#pragma once
// The explicit integrators of MODEL §2, as stages over the particle arrays.
// Each uses `force`, evaluated at the state's positions and velocities.

#include <vector>

#include "robophi/evaluation.h"
#include "robophi/model.h"
#include "robophi/state.h"

namespace robophi {

/// Paper's scheme: p += v δ + ½ a δ², then v += a δ.
void integrateTaylor(const Model& model, double dt, const std::vector<Vec3>& force, State& state);
/// Symplectic Euler: v += a δ, then p += v δ.
void integrateSymplecticEuler(const Model& model, double dt, const std::vector<Vec3>& force,
                              State& state);
/// Velocity Verlet, first part: v += ½ a δ, then p += v δ (forces must be
/// evaluated at the new positions before the second part).
void integrateVerletDrift(const Model& model, double dt, const std::vector<Vec3>& force,
                          State& state);
/// Velocity Verlet, second part: v += ½ a(t+δ) δ.
void integrateVerletKick(const Model& model, double dt, const std::vector<Vec3>& force,
                         State& state);

/// In one pass over the particles, at `velocity` and the evaluation's forces:
/// the kinetic energy ½ Σ m_i |v_i|² of the free particles (J, into
/// evaluation.energy.kinetic) and the power -Σ F_i·v_i put in by the fixed ones
/// that move kinematically (W, into evaluation.drivingPower).
void measureKineticAndDriving(const Model& model, const std::vector<Vec3>& velocity,
                              Evaluation& evaluation);

}  // namespace robophi
