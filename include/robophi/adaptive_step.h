#pragma once
/// \file
/// The energy-based adaptive time step (ATS, MODEL §4; the rule is written
/// out in docs/adaptive-step.md). The paper's factors are lost: every factor
/// here is our own choice, set in AdaptiveStepSettings.

#include <atomic>
#include <cstdint>
#include <limits>
#include <string>

#include "robophi/world.h"

namespace robophi {

/// The controller's settings, with their defaults and units.
struct AdaptiveStepSettings {
  /// First trial step δ0 (s).
  double initialStep = 1.0e-4;
  /// Smallest step (s): below it the run stops and says where it got stuck.
  /// 0 (default): relative, 1e-8 × the first trial step (no absolute floor that
  /// a change of units crosses).
  double minStep = 0.0;
  /// Largest step (s); infinite (default): no absolute ceiling. The step is
  /// bounded by the model's own scales instead: the stability caps, and the
  /// approach bound (maxApproachFraction).
  double maxStep = std::numeric_limits<double>::infinity();
  /// Accepted energy error per step, relative to the energy scale (-): a step is
  /// rejected when (ΔE + ΔW_dissipated) / scale > tolerance (energy created).
  double energyTolerance = 1.0e-5;
  /// A step is also rejected when it loses more than this many tolerances
  /// (energy destroyed by the integration, not by dissipation). 1 makes the
  /// test symmetric, which keeps a variable-step symplectic scheme from drifting.
  double lossToleranceFactor = 1.0;
  /// Absolute floor of the energy scale (J); 0 (default): none. The scale is
  /// never below the energy gravity can release in the scene
  /// (gravityEnergyScale), nor below the round-off guard of the energy sums
  /// (MODEL §4.1), so a system at rest does not force tiny steps.
  double energyFloor = 0.0;
  /// Largest step factor after a rejection (-), < 1: a rejected step is at least
  /// halved, more when its error was far above the tolerance (down to 0.1).
  double shrinkFactor = 0.5;
  /// Largest step factor after an accepted step (-), > 1.
  double growFactor = 2.0;
  /// Safety factor of the step proposal (-), < 1 (see errorOrder).
  double safety = 0.8;
  /// Order p of the per-step energy error in δ (error ∝ δ^p): the next step is
  /// δ · safety · (tolerance / |error|)^(1/p), within [0.1, shrinkFactor] after a
  /// rejection and [1, growFactor] after an acceptance. 0: from the integrator
  /// (3 for velocity Verlet, 2 for symplectic Euler and the paper's scheme).
  double errorOrder = 0.0;
  /// Largest growth within one step of the deepest contact penetration, as a
  /// fraction of the smaller radius in the contact (-): a step that pushes in
  /// further is rejected. The depth a contact settles at is set by κ_c, not here.
  double maxPenetrationFraction = 0.1;
  /// Anti-tunnelling bound (MODEL §4.4): in one step no pair of approaching
  /// surfaces (two particles, or a particle and the environment) may close by
  /// more than this fraction of the smaller radius beyond their gap (-), > 0.
  double maxApproachFraction = 0.5;
  /// The step stays below this fraction of the connectors' stability estimate 2/ω_max (-).
  double stabilitySafety = 0.9;
  /// Rejections in a row before the run stops with a diagnosis.
  int maxRejectionsInARow = 200;
  /// Largest jump of the energy accepted (relative to the energy scale, -). A
  /// step's error that stays within 10% of the first trial's while the step is
  /// cut 16-fold is no error of the step: the potential itself jumps there (a
  /// contact's geometry that is only continuous up to its search's round-off, a
  /// terrain's kink). Up to this size the smallest trial is taken, its error
  /// counted in the energy account like any other and the step counted as set
  /// by "a jump of the energy"; beyond it the step shrinks to the floor (a stall).
  double jumpLimit = 1.0e-3;
};

/// The velocity of the scene's own frame (m/s), MODEL §4.1: the mean velocity
/// of the fixed particles when there are any; else zero when the environment
/// holds anything but planes, or the medium is viscous; else the free
/// particles' centre-of-mass velocity with its components along the planes'
/// normals removed. It moves with the observer: a Galilean boost u of the whole
/// scene (the planes only along themselves) adds u to it.
Vec3 sceneFrameVelocity(const Model& model, const State& state);

/// The energy that can turn into motion, in the scene's own frame (J):
/// Σ_free ½ m |v − V_frame|² + U_LS + U_TS + U_JS + U_contact. Independent of
/// the observer's velocity and of where z = 0 is.
double activeEnergy(const Model& model, const State& state, const EnergyTally& energy);

/// The energy gravity can release within the scene (J): Σ_free m |g| × L, L the
/// largest of the particles' bounding-box diagonal, their largest height above
/// a plane that faces against gravity and the largest free particle's
/// diameter. Independent of the datum.
double gravityEnergyScale(const Model& model, const State& state);

/// The round-off of an energy account (J): 64 ε × the sum of the magnitudes of
/// its terms. A change of E_total below it is round-off of the sums, not
/// physics; it is the only term of the energy scales that sees the datum and
/// the observer, and it matters only where the physical scale is below it.
double energyRoundoffScale(const EnergyTally& energy);

/// The energy scale of a run's account (J), for the drift E_total(t) − E_total(0)
/// and the divergence verdict: max(activeEnergy, gravityEnergyScale,
/// 1e6 × energyRoundoffScale) at the given state. Independent of the datum and
/// of the observer.
double energyAccountScale(const Model& model, const State& state, const EnergyTally& energy);

/// The anti-tunnelling bound (s), MODEL §4.4: the largest step in which no pair
/// of approaching surfaces closes by more than `fraction` × the smaller radius
/// beyond its gap, with each particle's velocity and acceleration (`force`/m,
/// `force` of particleCount entries) held over the step. Two objects are bounded
/// through the gap between the spheres around their particles and the
/// difference and spread of their velocities and accelerations (Galilean: no
/// frame enters; one object's particles are not bounded against each other;
/// above 128 objects, all together without gaps); a particle against a plane
/// through its gap and normal speed, against other environment items through
/// its speed. Infinite when nothing approaches.
double approachStepBound(const Model& model, const State& state, const std::vector<Vec3>& force,
                         double fraction);

/// A lower bound of approachStepBound (s), in one pass without a square root
/// per particle: each object's positions, velocities and accelerations boxed,
/// and the spreads and radii of approachStepBound bounded from the boxes (with a
/// margin for round-off). Where it is at least every other limit of a step, the
/// bound cannot bind and need not be worked out: the steps are the same.
double approachStepFloor(const Model& model, const State& state, const std::vector<Vec3>& force,
                         double fraction);

/// A lower bound of approachStepFloor's bound (s) from the whole scene at once: in
/// one pass, the largest velocity and acceleration component c_v, c_a of any
/// particle and the smallest radius r; every pair and environment term of
/// approachStepBound closes at most at 4√3 c_v with 4√3 c_a (the differences of
/// the objects' box centres and their spreads) over at least `fraction` × r.
/// Checked first: a pile at rest clears the other limits here without the
/// per-object pass. 0 when a number is not finite.
double approachStepQuickFloor(const Model& model, const State& state,
                              const std::vector<Vec3>& force, double fraction);

/// A constant step that does not tunnel (MODEL §4.4): advances `world` by `dt`
/// in one step, or, when approachStepBound(`fraction`) or `contactSafety` × the
/// touching contacts' stability limit (Evaluation::contactCriticalStep; 0: not
/// used) is shorter, in as many equal substeps as they require (re-bounded
/// after each); the last substep lands on t + dt exactly. Adds the number of
/// extra substeps to `*splits` when given. Stops at the first non-finite substep
/// (kNonFinite). Bounded work: returns kStopped at the end of a whole substep,
/// short of t + dt, when `maxSubsteps` (> 0) substeps are taken and more are
/// needed, or when `stop` is set and true (checked before every substep: a
/// signal's flag, InterruptGuard).
StepStatus stepWithoutTunnelling(World& world, double dt, double fraction = 0.1,
                                 double contactSafety = 0.9, std::int64_t* splits = nullptr,
                                 std::int64_t maxSubsteps = 0,
                                 const std::atomic<bool>* stop = nullptr);

/// Counters of an adaptive run.
struct AdaptiveStepStats {
  std::int64_t accepted = 0;
  std::int64_t rejected = 0;
  double smallestStep = 0.0;
  double largestStep = 0.0;
  double sumOfSteps = 0.0;
  /// Relative energy error and size (s) of the last accepted step.
  double lastEnergyError = 0.0;
  double lastStep = 0.0;
  /// What set each accepted step's size (they add up to `accepted`): the
  /// energy-error controller (its proposal, or a rejection's shrink); the
  /// connectors' stability cap; the touching contacts' stability limit; the
  /// anti-tunnelling bound; maxStep; the time left to the run's end.
  std::int64_t setByError = 0, setByConnectors = 0, setByContacts = 0, setByApproach = 0,
               setByMaxStep = 0, setByTimeLeft = 0, setByJump = 0;
  double meanStep() const {
    return accepted > 0 ? sumOfSteps / static_cast<double>(accepted) : 0.0;
  }
};

/// The causes of a step's size, in the order checkpoints keep their counts:
/// summary.json's key (`adaptive.steps_set_by`), the run line's words, and the
/// count in AdaptiveStepStats.
struct StepCause {
  const char* key;
  const char* words;
  std::int64_t AdaptiveStepStats::*count;
};
inline constexpr StepCause kStepCauses[] = {
    {"energy_error", "the energy error", &AdaptiveStepStats::setByError},
    {"connector_stability", "the connectors' stability", &AdaptiveStepStats::setByConnectors},
    {"contact_stability", "the contacts' stability", &AdaptiveStepStats::setByContacts},
    {"approach", "the approach bound", &AdaptiveStepStats::setByApproach},
    {"max_step", "maxStep", &AdaptiveStepStats::setByMaxStep},
    {"time_left", "the time left", &AdaptiveStepStats::setByTimeLeft},
    {"energy_jump", "a jump of the energy", &AdaptiveStepStats::setByJump}};

/// The outcome of one adaptive advance.
struct AdaptiveStepResult {
  bool ok = true;
  /// The step taken (s).
  double dt = 0.0;
  /// Relative energy error of the accepted step.
  double energyError = 0.0;
  /// Trials rejected before it.
  int rejections = 0;
  /// The step was taken across a jump of the energy (AdaptiveStepSettings::jumpLimit).
  bool jumped = false;
  /// When !ok: what went wrong and where (particles, connectors, contacts).
  std::string failure;
  /// When !ok: the particle the failure is blamed on (the largest acceleration
  /// in the failed trial), or kNoParticle.
  ParticleIndex particle = kNoParticle;
  /// When !ok: a stop was requested (advance's `stop`) between trials; the
  /// world is as it was before the call, and `failure` is empty.
  bool stopped = false;
};

/// Takes accepted steps of a World, rejecting and retrying the ones that create
/// energy or penetrate too deep. A rejected trial leaves no trace in the state:
/// the state is restored from a copy.
class AdaptiveStepper {
 public:
  /// Throws std::invalid_argument naming a setting out of its range.
  AdaptiveStepper(const Model& model, AdaptiveStepSettings settings);

  /// Advances `world` by one accepted step of at most `maxDt` seconds. A trial
  /// whose step the model's own limits (the touching contacts' stability, the
  /// drives' damping, the approach bound) hold below floor() fails as a stall,
  /// as does a rejection that shrinks the step below it. When `stop` is set and
  /// true before a retry, the world is restored and the result says `stopped`.
  AdaptiveStepResult advance(World& world, double maxDt,
                             const std::atomic<bool>* stop = nullptr);

  const AdaptiveStepStats& stats() const { return stats_; }
  const AdaptiveStepSettings& settings() const { return settings_; }
  /// The step the next trial will use (s).
  double nextStep() const { return step_; }
  /// The step floor in use (s): settings().minStep, or when that is 0, 1e-8 ×
  /// the first trial step (the initial step within maxStep and the stability cap).
  double floor() const { return minStep_; }

  /// The controller's state between steps, for a checkpoint: a plain value.
  struct Progress {
    double step = 0.0;
    double stabilityLimit = 0.0;
    double stabilityOmega = 0.0, stabilityDamping = 0.0;
    double errorOrder = 0.0;
    double gravityScale = -1.0;
    bool refinedLimit = false;
    AdaptiveStepStats stats;
    double jumpError = 0.0, jumpTrial = 0.0, jumpTime = 0.0;
  };
  Progress progress() const {
    return {step_,       stabilityLimit_, stabilityOmega_, stabilityDamping_, errorOrder_,
            gravityScale_, refinedLimit_, stats_,         jumpError_,        jumpTrial_,
            jumpTime_};
  }
  /// Continues from the progress() of a stepper of the same settings and model.
  void resume(const Progress& p) {
    step_ = p.step;
    stabilityLimit_ = p.stabilityLimit;
    stabilityOmega_ = p.stabilityOmega;
    stabilityDamping_ = p.stabilityDamping;
    errorOrder_ = p.errorOrder;
    gravityScale_ = p.gravityScale;
    refinedLimit_ = p.refinedLimit;
    stats_ = p.stats;
    jumpError_ = p.jumpError;
    jumpTrial_ = p.jumpTrial;
    jumpTime_ = p.jumpTime;
  }

 private:
  /// Relative energy error of a trial from the energy account `before` to
  /// `after`, whose active energies (activeEnergy) are given.
  double energyError(const EnergyTally& before, const EnergyTally& after, double activeBefore,
                     double activeAfter) const;
  /// The step factor δ_next/δ that an error calls for (unclamped).
  double proposal(double error) const;
  /// What went wrong in the last trial, in words; `blamed` (if set) gets the
  /// particle with the largest acceleration (kNoParticle when none).
  std::string diagnose(const World& world, ParticleIndex* blamed = nullptr) const;

  AdaptiveStepSettings settings_;
  double stabilityLimit_;
  /// The ω_max and damping rate (1/s) of the estimate that set stabilityLimit_,
  /// to which a joint drive's damping is added (Evaluation::driveDampingRate).
  double stabilityOmega_ = 0.0, stabilityDamping_ = 0.0;
  /// The Taylor scheme's stable step (StabilityEstimate::taylorStep, s), the
  /// larger of the model-only and the refined estimates'.
  double taylorStep_ = 0.0;
  double step_;
  /// The error order in use (set at the first step from the integrator).
  double errorOrder_ = 0.0;
  /// gravityEnergyScale (J), measured at the first step; -1 until then.
  double gravityScale_ = -1.0;
  /// The step floor in use (s): minStep, or relative to the first trial step.
  double minStep_ = 0.0;
  AdaptiveStepStats stats_;
  World::Snapshot saved_;
  /// Whether stabilityLimit_ has been refined with the first state's positions.
  bool refinedLimit_ = false;
  /// A suspected jump of the energy (AdaptiveStepSettings::jumpLimit): the error
  /// of the last rejected trial that differed from the one before (0: none) and
  /// the largest trial step (s) that has shown it since, from time jumpTime_ (s):
  /// the jump lies within that trial, and a later time clears the suspicion.
  double jumpError_ = 0.0, jumpTrial_ = 0.0, jumpTime_ = 0.0;
  /// What the last accepted step measured at the state it ended at: its active
  /// energy and deepest penetration, the next step's "before" while that world
  /// has not changed since (World::changeCount, its time and step count).
  struct Measured {
    const World* world = nullptr;
    std::uint64_t changes = 0;
    std::int64_t step = -1;
    double time = 0.0;
    double activeEnergy = 0.0;
    double penetration = 0.0;
    bool holdsFor(const World& w) const;
  } after_;
};

}  // namespace robophi
