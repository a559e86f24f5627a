#pragma once
// The force stages: each adds its forces to `force` and reports the potential
// energy it holds and the power of its dissipative part.

#include <cstdint>
#include <vector>

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
ForceTally accumulateGravity(const Model& model, int threads, const std::vector<Vec3>& position,
                             std::vector<Vec3>& force);
ForceTally accumulateLinearDamping(const Model& model, int threads,
                                   const std::vector<Vec3>& velocity, std::vector<Vec3>& force);

/// The linear springs that meet at each particle, compiled once per model topology
/// (CompiledModel): particle i's entries are entry[start[i] .. start[i + 1]), each 2k
/// (spring k's end a) or 2k + 1 (its end b), in ascending k, the order in which a
/// serial scatter over the springs adds them.
struct SpringIncidence {
  std::vector<std::int32_t> start;  // (particleCount + 1)
  std::vector<std::int32_t> entry;  // (2 * linearSprings)
};
SpringIncidence compileSpringIncidence(const Model& model);

/// A workspace's buffers for the force stages.
struct ForceScratch {
  std::vector<Vec3> springForce;  // (linearSprings): the force on end a
};

/// LS in two parallel passes: each spring's force on its end a into
/// scratch.springForce (energy and power summed in fixed chunks), then each
/// particle gathers its springs in ascending order (`incidence`): the forces are
/// bit-identical to a serial scatter's, whatever the thread count.
ForceTally accumulateLinearSprings(const Model& model, const SpringIncidence& incidence,
                                   int threads, const std::vector<Vec3>& position,
                                   const std::vector<Vec3>& velocity, std::vector<Vec3>& force,
                                   ForceScratch& scratch);
ForceTally accumulateTorsionSprings(const Model& model, const std::vector<Vec3>& position,
                                    const std::vector<Vec3>& velocity, std::vector<Vec3>& force);
ForceTally accumulateJointSprings(const Model& model, const std::vector<Vec3>& position,
                                  const std::vector<Vec3>& velocity, std::vector<Vec3>& force);

/// MODEL §1.6: the motor effort τ (N·m or N) of a drive at joint rate `rate`, after
/// its effort and velocity limits, and the losses' effort (damping and friction).
bool hasDrive(const JointDrive& drive);
double motorEffort(const JointDrive& drive, double rate);
double lossEffort(const JointDrive& drive, double rate);
/// Joint motors and losses (MODEL §1.6): adds Q ∂q/∂p_j for every joint with a
/// drive; `motor` and `loss` (resized to the joints) get each joint's efforts.
/// Reports the losses' power (<= 0) as dissipative; the motors' power is the
/// driving power's (jointMotorPower).
ForceTally accumulateJointDrives(const Model& model, const std::vector<Vec3>& position,
                                 const std::vector<Vec3>& velocity, std::vector<Vec3>& force,
                                 std::vector<double>& motor, std::vector<double>& loss);
/// Σ τ_j q̇_j (W) of the joints' motor efforts `motor` at the given positions and velocities.
double jointMotorPower(const Model& model, const std::vector<Vec3>& position,
                       const std::vector<Vec3>& velocity, const std::vector<double>& motor);

}  // namespace robophi
