#pragma once
/// \file
/// The stability estimate of a model (MODEL §2): an explicit step δ must stay
/// below 2/ω_max, ω_max the fastest angular frequency of the linearised system.

#include <vector>

#include "robophi/model.h"
#include "robophi/vec3.h"

namespace robophi {

/// The stability estimate of a model (MODEL §2): δ must stay below 2/ω_max.
struct StabilityEstimate {
  /// Upper bound of the fastest angular frequency ω_max (rad/s), from the
  /// connectors' stiffness and the particles' masses (Gershgorin bound).
  double omegaMax = 0.0;
  /// Upper bound of the fastest damping rate 2ζω (1/s) that goes with it (the
  /// model-only bound: the largest particle's; with positions: the whole's).
  double dampingRate = 0.0;
  /// Critical step (s) for the symplectic schemes, reduced for damping; infinite
  /// when nothing is stiff.
  double criticalStep = 0.0;
  /// The particle that sets it, or kNoParticle.
  ParticleIndex limitingParticle = kNoParticle;
  /// The largest step (s) at which the paper's Taylor scheme is stable (MODEL
  /// §2, docs/model.md "The paper's scheme"): 2 γ_min / ω_max² + 2 τ_min, γ_min
  /// the smallest damping rate c/m of a particle with stiffness, τ_min the
  /// smallest damping-to-stiffness ratio c/k of a connector. 0 when both are 0
  /// (an undamped connector on an undamped particle: no step is stable, the
  /// energy grows by 1 + (ωδ)²/2 a step); infinite when nothing is stiff.
  double taylorStep = 0.0;
};

/// The step an explicit scheme must stay below: criticalStep, and for the
/// Taylor scheme (`taylor` true) also taylorStep where it is not 0 (with no
/// damping there is no stable step: the adaptive step's energy test judges).
double criticalStepFor(const StabilityEstimate& estimate, bool taylor);

/// From the model alone: a Gershgorin bound, conservative. Given positions
/// ((particleCount) entries), the linear springs' part is found by power
/// iteration on the stiffness linearised there, which is much tighter on braced
/// lattices.
StabilityEstimate estimateStability(const Model& model,
                                    const std::vector<Vec3>* position = nullptr);

/// The largest stable explicit step (s) of a damped oscillator of angular
/// frequency ω (rad/s) and damping rate 2ζω (1/s): 2/ω (√(1+ζ²) - ζ); 2/(2ζω)
/// without stiffness; infinite with neither.
double dampedCriticalStep(double omega, double dampingRate);

}  // namespace robophi
