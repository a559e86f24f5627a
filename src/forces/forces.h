#pragma once
// The force stages: each adds its forces to `force` and reports the potential
// energy it holds and the power of its dissipative part.

#include <array>
#include <atomic>
#include <cstdint>
#include <vector>

#include "robophi/connector_forces.h"
#include "robophi/model.h"
#include "robophi/vec3.h"

namespace robophi {

/// What a force stage reports besides its forces.
struct ForceTally {
  /// Potential energy of the stage (J).
  double potential = 0.0;
  /// Power of its dissipative forces (W, <= 0).
  double dissipativePower = 0.0;
};

// Arrays are (particleCount) long.
// `threads`: the most the stage may use; the result does not depend on it.
/// The per-particle forces in one pass, which starts the evaluation: force and
/// torque set to zero, then gravity F_i = m_i g on the free particles (potential
/// -m_i g·p_i) and the linear damping F_i = -c_i v_i (power -c_i |v_i|²).
/// Returns {gravity's potential, 0} and {0, damping's power}.
struct ParticleForceTally {
  ForceTally gravity, damping;
};
ParticleForceTally startParticleForces(const Model& model, int threads,
                                       const std::vector<Vec3>& position,
                                       const std::vector<Vec3>& velocity, std::vector<Vec3>& force,
                                       std::vector<Vec3>& torque);
/// startParticleForces for particle i: its force and torque set, gravity's
/// potential added to `potential` and damping's power to `power`.
inline void startParticleForce(const Model& model, std::size_t i, const Vec3* position,
                               const Vec3* velocity, Vec3* force, Vec3* torque, double& potential,
                               double& power) {
  Vec3 f;
  torque[i] = Vec3{};
  if (model.inverseMass[i] != 0.0) {  // a fixed particle gets no gravity
    f += model.gravity * model.mass[i];
    potential -= model.mass[i] * dot(model.gravity, position[i]);
  }
  const double c = model.linearDamping[i];
  if (c != 0.0) {
    f -= velocity[i] * c;
    power -= c * squaredNorm(velocity[i]);
  }
  force[i] = f;
}

/// The linear springs that meet at each particle, compiled once per model topology
/// (CompiledModel): particle i's entries are entry[start[i] .. start[i + 1]), each 2k
/// (spring k's end a) or 2k + 1 (its end b), in ascending k, the order in which a
/// serial scatter over the springs adds them.
/// For the parallel LS job (accumulateLinearSprings), by chunks of kParallelChunk
/// springs: dependent[k] bit 0 (bit 1) when spring k's end a (b) has a spring in an
/// earlier chunk, and waitFrom[s] the first chunk before s that shares a particle
/// with chunk s (s: none).
struct SpringIncidence {
  std::vector<std::int32_t> start;      // (particleCount + 1)
  std::vector<std::int32_t> entry;      // (2 * linearSprings)
  std::vector<std::uint8_t> dependent;  // (linearSprings)
  std::vector<std::int32_t> waitFrom;   // (spring chunks)
  /// With a ParticlePrologue: the chunks of particles each spring chunk reads
  /// ({0, -1}: none), and the job's order: spring chunk s as s, particle chunk g
  /// as -1 - g, each particle chunk soon before the first spring chunk that reads it.
  std::vector<std::array<std::int32_t, 2>> reads;  // (spring chunks)
  std::vector<std::int32_t> order;                 // (spring chunks + particle chunks)
};
SpringIncidence compileSpringIncidence(const Model& model);

/// MODEL §1.7: a set of particles' rigid motion — mass (kg), centre (m), the
/// centre's velocity (m/s), the inverse of the inertia tensor about the centre
/// (1/(kg·m²)), the angular velocity ω = I⁻¹ L (rad/s) and, for a body with a rest
/// shape, the rotation R from it that fits best (shape matching's).
struct RigidMotion {
  bool valid = false;
  double mass = 0.0;
  Vec3 center{}, velocity{}, spin{};
  std::array<std::array<double, 3>, 3> inverseInertia{};
  std::array<std::array<double, 3>, 3> rotation{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  Vec3 solve(const Vec3& torque) const;       // I⁻¹ t
  Vec3 rotate(const Vec3& restOffset) const;  // R r
  Vec3 velocityAt(const Vec3& point) const;   // v̄ + ω × (point − p̄)
};
/// The sums of the fused per-particle pass (FusedParticlePass), per chunk of
/// kParallelChunk particles: {gravity's potential, damping's power, kinetic energy,
/// the spins' kinetic energy (from chunk 1 on)}, and flags: 1 a fixed particle in
/// the chunk, 2 a spinning one.
struct ParticlePassSums {
  std::vector<std::array<double, 4>> sums;
  std::vector<std::uint8_t> flags;
};
/// A workspace's buffers for the force stages.
struct ForceScratch {
  /// The forces on ends a: one chunk's on one thread; the dependent ends' (by spring) on more.
  std::vector<Vec3> springForce;
  /// The parallel LS job's state: each spring chunk's {potential, power}, and
  /// the job's stamp in done[s] once spring chunk s is written.
  std::vector<std::array<double, 2>> springChunkSums;
  std::vector<std::atomic<std::uint32_t>> springChunkDone;
  std::vector<std::atomic<std::uint32_t>> particleChunkDone;  // the same, for a ParticlePrologue
  std::uint32_t springJob = 0;
  ParticlePassSums particlePass;
  /// (bodies): every body's rigid motion at the last evaluation's positions (and, once
  /// measureKinetic has run, at its state's velocities): measured once per evaluation.
  std::vector<RigidMotion> bodyMotion;
  /// (bodyLinks): each link's weight preload on its child at its joint point (force, N;
  /// couple, N·m) at the last evaluation, for its driving power (bodyLinkPreloadPower).
  std::vector<std::array<Vec3, 2>> linkPreload;
  /// (torsion or joint springs): each one's forces, computed on the threads
  /// before they are added in order (accumulateTorsionSprings, accumulateJointSprings).
  std::vector<AngularSpringForce> angularForce;
  /// evaluate.cpp: whether a small model's contacts are worked out beside its
  /// connector stages (on two threads) or after them (on one), chosen by timing
  /// both now and then. The results are the same either way; the time is not on
  /// a machine whose other core is taken.
  struct OverlapChoice {
    std::int64_t evaluations = 0;  // counted over the periods
    double serialSeconds = 0.0, besideSeconds = 0.0;
    bool beside = true;
  } overlap;
};

/// A per-particle pass run in the LS job (accumulateLinearSprings): run(context, g)
/// once for each chunk g of kParallelChunk particles, before the springs that
/// read or load its particles (FusedParticlePass, in one job with LS).
struct ParticlePrologue {
  void (*run)(void* context, std::int64_t chunk) = nullptr;
  void* context = nullptr;
};
/// LS in one parallel job of spring chunks (energy and power summed in fixed
/// chunks): each chunk's forces, then their scatter to the particles whose first
/// spring is in it; the other ends (incidence.dependent) wait in
/// scratch.springForce and are scattered in chunk order once every earlier chunk
/// is done. Each particle adds its springs in ascending order: the forces are
/// bit-identical to a serial scatter's, whatever the thread count. `prologue`:
/// a per-particle pass to run first, each chunk of it in the job before the
/// spring chunks that read its particles (or, off the job, as a loop of its own).
ForceTally accumulateLinearSprings(const Model& model, const SpringIncidence& incidence,
                                   int threads, const std::vector<Vec3>& position,
                                   const std::vector<Vec3>& velocity, std::vector<Vec3>& force,
                                   ForceScratch& scratch,
                                   const ParticlePrologue* prologue = nullptr);
/// TS and JS: each connector's forces computed on up to `threads` threads
/// (from kParallelMinimum connectors) into scratch.angularForce, then added to
/// the particles and summed in connector order, as the serial loop does: the
/// same bits on any count.
ForceTally accumulateTorsionSprings(const Model& model, int threads,
                                    const std::vector<Vec3>& position,
                                    const std::vector<Vec3>& velocity, std::vector<Vec3>& force,
                                    ForceScratch& scratch);
ForceTally accumulateJointSprings(const Model& model, int threads,
                                  const std::vector<Vec3>& position,
                                  const std::vector<Vec3>& velocity, std::vector<Vec3>& force,
                                  ForceScratch& scratch);

/// MODEL §1.6: the motor effort τ (N·m or N) of a drive at joint rate `rate`, after
/// its effort and velocity limits, and the losses' effort (damping and friction).
bool hasDrive(const JointDrive& drive);
double motorEffort(const JointDrive& drive, double rate);
double lossEffort(const JointDrive& drive, double rate);
/// A rigid tree joint's servo and drive effort at coordinate q and rate (docs/model.md
/// §7): −κ (q − q*) − β q̇ + motor + losses, within the joint's effort limit (the
/// gravity compensation's effort not included).
double treeJointEffort(const Model& model, const Joint& joint, double q, double rate);
/// Joint motors and losses (MODEL §1.6): adds Q ∂q/∂p_j for every joint with a
/// drive (a wrench on its bodies, and their servo, for a joint with bodies: MODEL
/// §1.7, whose servo energy is the tally's potential); `motor` and `loss` (resized to the joints)
/// get each joint's efforts. Reports the losses' power (<= 0) as dissipative; the motors' power is
/// the driving power's (jointMotorPower).
/// `motion`: every body's rigid motion at (position, velocity) (bodyMotions).
/// `dampingRate` (unless null): a bound on the largest rate (1/s) of the damping
/// that the drives acting through connector particles add, M⁻¹ Σ g Ḡ Ḡᵀ (g: rate
/// gain, damping and friction slope; Ḡ: ∂q̇/∂v), for the adaptive step.
ForceTally accumulateJointDrives(const Model& model, const std::vector<RigidMotion>& motion,
                                 const std::vector<Vec3>& position,
                                 const std::vector<Vec3>& velocity, std::vector<Vec3>& force,
                                 std::vector<double>& motor, std::vector<double>& loss,
                                 double* dampingRate = nullptr);
/// The rigid motion of `particles`; `rest` (their rest offsets, same order) or null.
RigidMotion rigidMotion(const Model& model, const std::vector<ParticleIndex>& particles,
                        const std::vector<Vec3>* rest, const std::vector<Vec3>& position,
                        const std::vector<Vec3>& velocity);
/// Every Model::bodies' rigid motion, into `out` (resized to the bodies).
void bodyMotions(const Model& model, const std::vector<Vec3>& position,
                 const std::vector<Vec3>& velocity, std::vector<RigidMotion>& out);
/// Re-measures the centre velocities and spins of `motion` (bodyMotions at the same
/// positions) at new velocities, bit-identical to a fresh bodyMotions there.
void updateBodyVelocities(const Model& model, const std::vector<Vec3>& position,
                          const std::vector<Vec3>& velocity, std::vector<RigidMotion>& motion);
/// Adds to `particles` the wrench (force f through `point`, couple t) as the rigid
/// motion it causes: f_i = m_i (a + α × (p_i − p̄)), a = f/M, α = I⁻¹ (t + (point − p̄) × f);
/// the forces sum to f, their moment about `point` is t, and their power is
/// f·v(point) + t·ω exactly.
void applyWrench(const Model& model, const std::vector<ParticleIndex>& particles,
                 const RigidMotion& motion, const std::vector<Vec3>& position, const Vec3& f,
                 const Vec3& t, const Vec3& point, std::vector<Vec3>& force);
/// A body link's joint points, axes and normals in the world, by each body.
struct BodyLinkFrame {
  Vec3 childPoint{}, parentPoint{}, childAxis{}, parentAxis{}, childNormal{}, parentNormal{};
};
BodyLinkFrame bodyLinkFrame(const BodyLink& link, const RigidMotion& child,
                            const RigidMotion& parent);
/// MODEL §1.7: shape matching of every body and the body links' wrenches; their
/// potential and the power of their dampers.
/// Also each link's weight preload (BodyLink::weightBodies) into `preload` (resized to
/// the links; zero where none).
ForceTally accumulateRigidBodies(const Model& model, const std::vector<RigidMotion>& motion,
                                 const std::vector<Vec3>& position,
                                 const std::vector<Vec3>& velocity, std::vector<Vec3>& force,
                                 std::vector<std::array<Vec3, 2>>& preload);
/// The power (W) of the body links' weight preloads `preload` at the bodies' motion:
/// Σ F·(v_child(s_c) − v_parent(s_c)) + T·(ω_child − ω_parent).
double bodyLinkPreloadPower(const Model& model, const std::vector<RigidMotion>& motion,
                            const std::vector<std::array<Vec3, 2>>& preload);

/// MODEL §1.7: the servo effort (N·m or N) of a joint that acts through its bodies
/// (−κ e − β q̇, q̇ the bodies' relative rigid rate); 0 for any other joint.
double bodyServoEffort(const Model& model, const Joint& joint, const std::vector<Vec3>& position,
                       const std::vector<Vec3>& velocity);
/// Σ τ_j q̇_j (W) of the joints' motor efforts `motor` at the given positions and velocities.
/// `motion`: every body's rigid motion at those positions and velocities.
double jointMotorPower(const Model& model, const std::vector<RigidMotion>& motion,
                       const std::vector<Vec3>& position, const std::vector<Vec3>& velocity,
                       const std::vector<double>& motor);
/// The kick power of velocity Verlet (docs/model.md §2.4): K = Σ_term F_term·δv for the
/// kick δv_i = F_i/m_i · halfStep (World::step passes 1: W/s), at fixed positions, where
/// the rates are linear in the velocities (q̇(v + δv) = q̇(v) + q̇(δv)). `driving`: the
/// motors' (gravity compensation included); `dissipative`: the losses' and the body
/// servos' dampers' (−β q̇ at `velocity`). `motion`: every body's rigid motion at
/// (position, velocity); `motor`, `loss`: accumulateJointDrives'.
struct PowerKick {
  double driving = 0.0, dissipative = 0.0;  // W
};
PowerKick verletKickPower(const Model& model, const std::vector<RigidMotion>& motion,
                          const std::vector<Vec3>& position, const std::vector<Vec3>& velocity,
                          const std::vector<Vec3>& force, double halfStep,
                          const std::vector<double>& motor, const std::vector<double>& loss,
                          const std::vector<std::array<Vec3, 2>>& preload);
/// The same for accumulateRigidBodies' dampers (shape matching, body links) and the
/// links' weight preloads: their forces at (motion, velocity) times the velocities
/// `kick` (whose bodies' rigid motion is `kickMotion`).
PowerKick rigidBodyPowerKick(const Model& model, const std::vector<RigidMotion>& motion,
                             const std::vector<RigidMotion>& kickMotion,
                             const std::vector<Vec3>& position, const std::vector<Vec3>& velocity,
                             const std::vector<Vec3>& kick,
                             const std::vector<std::array<Vec3, 2>>& preload);

}  // namespace robophi
