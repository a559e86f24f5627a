#pragma once
/// \file
/// World: a model, its state, and the step that advances it (MODEL.md §2).

#include <string>

#include "robophi/model.h"
#include "robophi/state.h"

namespace robophi {

/// The explicit integrators (MODEL §2). All cost one force evaluation per step.
enum class Integrator : std::uint8_t {
  /// The paper's scheme: v += a δ, p += v(t) δ + ½ a δ².
  kTaylor,
  /// Symplectic (semi-implicit) Euler: v += a δ, p += v(t+δ) δ.
  kSymplecticEuler,
  /// Velocity Verlet (kick-drift-kick); damping forces use the half-step velocity.
  kVelocityVerlet,
};

/// Parses "taylor", "symplectic", "verlet"; returns false on an unknown name.
bool parseIntegrator(const std::string& name, Integrator& out);
const char* integratorName(Integrator integrator);

/// How a step ended.
enum class StepStatus : std::uint8_t {
  kOk,
  /// A position, velocity or energy became NaN or infinite.
  kNonFinite,
};

/// The stability estimate of a model (MODEL §2): δ must stay below 2/ω_max.
struct StabilityEstimate {
  /// Upper bound of the fastest angular frequency ω_max (rad/s), from the
  /// connectors' stiffness and the particles' masses (Gershgorin bound).
  double omegaMax = 0.0;
  /// Critical step (s) for the symplectic schemes, reduced for damping; infinite
  /// when nothing is stiff.
  double criticalStep = 0.0;
  /// The particle that sets it, or kNoParticle.
  ParticleIndex limitingParticle = kNoParticle;
};
/// From the model alone: a Gershgorin bound, conservative. Given positions, the
/// linear springs' part is found by power iteration on the stiffness linearised
/// there, which is much tighter on braced lattices.
StabilityEstimate estimateStability(const Model& model,
                                    const std::vector<Vec3>* position = nullptr);

/// The largest stable explicit step (s) of a damped oscillator of angular
/// frequency ω (rad/s) and damping rate 2ζω (1/s): 2/ω (√(1+ζ²) - ζ); 2/(2ζω)
/// without stiffness; infinite with neither.
double dampedCriticalStep(double omega, double dampingRate);

/// Evaluates the net force on every particle at the state's positions and
/// velocities and the potentials of the energy account (not `dissipated`).
void computeForces(const Model& model, State& state);

/// The simulation: owns an immutable model and its state.
class World {
 public:
  World(Model model, State initial, Integrator integrator = Integrator::kSymplecticEuler);

  /// Advances the state by one step of `dt` seconds.
  StepStatus step(double dt);

  /// Brings the cached forces and the energy account up to date with the
  /// current positions and velocities (done by step() when needed).
  void refresh();

  const Model& model() const { return model_; }
  const State& state() const { return state_; }
  /// For tools that move particles by hand (tests, robotics targets).
  /// Changing positions or velocities invalidates the cached forces.
  State& mutableState() {
    state_.forcesValid = false;
    return state_;
  }
  /// Between steps only (robotics tasks, docs/robotics.md): joint targets and
  /// stiffness, attractors, virtual obstacles. Invalidates the cached forces; a
  /// change of the model's size or topology also rebuilds the contact cache.
  Model& mutableModel() {
    state_.forcesValid = false;
    return model_;
  }
  /// After changes made between steps (mutableModel, mutableState): brings the
  /// energy account up to date and books the jump in E + dissipated as work done
  /// from outside, so that total() stays the conserved quantity. Returns the
  /// work (J); 0 when nothing was changed.
  double bookExternalWork();
  /// Puts back a state saved earlier (a snapshot copy): undoes steps exactly.
  void restore(const State& saved) { state_ = saved; }
  Integrator integrator() const { return integrator_; }
  void setIntegrator(Integrator integrator) { integrator_ = integrator; }

  /// The first particle whose state is not finite, or kNoParticle.
  ParticleIndex firstNonFiniteParticle() const;

 private:
  Model model_;
  State state_;
  Integrator integrator_;
};

}  // namespace robophi
