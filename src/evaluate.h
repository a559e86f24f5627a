#pragma once
// The force evaluation's stages (MODEL §1–§3), shared by evaluate() and
// World::step, which evaluates at the intermediate states of an integrator.

#include <cstdint>
#include <vector>

#include "robophi/compiled_model.h"
#include "robophi/evaluation.h"

namespace robophi {

struct FusedParticlePass;
struct ParticlePassSums;

/// Net forces (and the spinning particles' torques) and potentials at the
/// state's positions, velocities and spins with its friction history (only
/// read) into `out`: clear → gravity → linear damping → LS → TS
/// → JS → joint drives (MODEL §1.6) → contacts (which set out.contacts, out.releasedAnchorEnergy,
/// out.contactCriticalStep, out.contactStats). Not the kinetic energy or the
/// driving power (measureKineticAndDriving), which need the final velocities.
/// The force stages, the integration and the sums use up to workspace.threadCount()
/// threads (core/parallel.h), with the same result for any count.
/// `pass`: an integration fused with the first stage (clear, gravity, damping) to
/// run in place of that stage, in the LS job (its chunks before the springs that
/// read their particles), or null.
void evaluateForces(const CompiledModel& model, const State& state, Workspace& workspace,
                    Evaluation& out, FusedParticlePass* pass = nullptr);

/// The kinetic energy and driving power at the state (measureKineticAndDriving), whose
/// positions are those of the last evaluateForces in `workspace` (its bodies' motions are
/// reused, their velocities re-measured).
/// `pass`: the kinetic sums of the FusedParticlePass that made the state, or null.
void measureKinetic(const CompiledModel& model, const State& state, Workspace& workspace,
                    Evaluation& out, const ParticlePassSums* pass = nullptr);

}  // namespace robophi
