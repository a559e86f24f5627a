#pragma once
// The explicit integrators of MODEL §2, as stages over the particle arrays.
// Each uses the evaluation's force (and torque on the spinning particles),
// evaluated at the state's positions and velocities. `inverseSpinInertia` is
// ContactTables::inverseSpinInertia: 1/J of the particles that spin, 0 elsewhere.
// `threads`: the most a stage may use (core/parallel.h); the result does not depend on it.

#include <cstdint>
#include <vector>

#include "robophi/evaluation.h"
#include "robophi/model.h"
#include "robophi/state.h"

namespace robophi {

struct RigidMotion;
struct ParticlePassSums;
struct ParticleForceTally;

/// Paper's scheme: p += v δ + ½ a δ², then v += a δ (ω += J⁻¹τ δ).
void integrateTaylor(const Model& model, const std::vector<double>& inverseSpinInertia, int threads,
                     double dt, const Evaluation& evaluation, State& state);
/// Symplectic Euler: v += a δ, then p += v δ (ω += J⁻¹τ δ).
void integrateSymplecticEuler(const Model& model, const std::vector<double>& inverseSpinInertia,
                              int threads, double dt, const Evaluation& evaluation, State& state);
/// Velocity Verlet, first part: v += ½ a δ, then p += v δ (ω += ½ J⁻¹τ δ);
/// forces must be evaluated at the new positions before the second part.
void integrateVerletDrift(const Model& model, const std::vector<double>& inverseSpinInertia,
                          int threads, double dt, const Evaluation& evaluation, State& state);
/// Velocity Verlet, second part: v += ½ a(t+δ) δ (ω += ½ J⁻¹τ(t+δ) δ).
void integrateVerletKick(const Model& model, const std::vector<double>& inverseSpinInertia,
                         int threads, double dt, const Evaluation& evaluation, State& state);

/// In one pass over the particles, at the state's velocities and the
/// evaluation's forces: the kinetic energy ½ Σ m_i |v_i|² + ½ Σ J_i |ω_i|² of the
/// free particles (J, into evaluation.energy.kinetic) and the power -Σ F_i·v_i put
/// in by the fixed ones that move kinematically, plus the joint motors' τ q̇ (W, into
/// evaluation.drivingPower; `bodyMotion`: every body's rigid motion at the state).
/// `pass`: the kinetic sums of the FusedParticlePass that made this state, or null.
void measureKineticAndDriving(const Model& model, const std::vector<double>& inverseSpinInertia,
                              int threads, const std::vector<RigidMotion>& bodyMotion,
                              const State& state, Evaluation& evaluation,
                              const ParticlePassSums* pass = nullptr);

/// Whether a FusedParticlePass applies: a state and evaluation sized for the
/// model, spins for every particle, and a spin table for every particle or none.
bool canIntegrateAndStartForces(const Model& model, const std::vector<double>& inverseSpinInertia,
                                const Evaluation& evaluation, const State& state);
/// Symplectic Euler (Taylor's scheme if `taylor`) fused in one parallel pass with
/// the first stage of the evaluation at t + δ (startParticleForces: force and
/// torque reset, gravity, damping) and the kinetic energy's sums (into `sums`,
/// for measureKineticAndDriving once the forces are final): the same bits as the
/// three passes. run(this, g) does chunk g (kParallelChunk particles); once every
/// chunk has run, tally() is startParticleForces' result. evaluateForces runs
/// the chunks in the LS job (ParticlePrologue).
struct FusedParticlePass {
  const Model* model;
  const std::vector<double>* inverseSpinInertia;
  double dt;
  bool taylor;
  Evaluation* evaluation;
  State* state;
  ParticlePassSums* sums;  // resized to the chunks by makeFusedParticlePass
  static void run(void* pass, std::int64_t chunk);
  ParticleForceTally tally() const;
};
FusedParticlePass makeFusedParticlePass(const Model& model,
                                        const std::vector<double>& inverseSpinInertia, double dt,
                                        bool taylor, Evaluation& evaluation, State& state,
                                        ParticlePassSums& sums);

}  // namespace robophi
