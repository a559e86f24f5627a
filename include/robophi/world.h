#pragma once
/// \file
/// World: a compiled model, its state, the last evaluation, and the step that
/// advances them (MODEL §2). Between steps the model and the state change
/// only through the edit functions below; each invalidates what it must (the
/// evaluation always, the contact tables when contact data change) and the
/// work an edit does is booked as external work at the next evaluation, so
/// that EnergyTally::total() stays the conserved quantity.

#include <cstdint>
#include <string>

#include "robophi/compiled_model.h"
#include "robophi/evaluation.h"
#include "robophi/model.h"
#include "robophi/stability.h"
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
  /// stepWithoutTunnelling ended short of t + δ, at the end of a whole substep:
  /// its substep limit was reached or a stop was requested.
  kStopped,
};

/// The simulation: owns a compiled model, its state and its last evaluation.
class World {
 public:
  /// Compiles `model`; `initial` must be sized for it (positions and velocities
  /// of particleCount entries, finite). Throws std::invalid_argument otherwise.
  World(Model model, State initial, Integrator integrator = Integrator::kSymplecticEuler);
  World(CompiledModel model, State initial, Integrator integrator = Integrator::kSymplecticEuler);

  /// Advances the state by one step of `dt` seconds (> 0, finite).
  StepStatus step(double dt);

  /// Brings the evaluation up to date with the state (done by every accessor
  /// and by step() when needed); books the work of edits made since the last
  /// evaluation as external work.
  void refresh() const;

  const CompiledModel& compiled() const { return model_; }
  const Model& model() const { return model_.model(); }
  const State& state() const { return current_.state_; }
  /// Forces, energies and contacts at the current state.
  const Evaluation& evaluation() const {
    refresh();
    return current_.evaluation_;
  }
  /// The energy account at the current state.
  EnergyTally energy() const;
  /// The contacts at the current state (sorted by Contact::key()).
  const std::vector<Contact>& contacts() const { return evaluation().contacts; }
  /// Net force on each particle at the current state (N).
  const std::vector<Vec3>& forces() const { return evaluation().force; }

  Integrator integrator() const { return integrator_; }
  void setIntegrator(Integrator integrator) { integrator_ = integrator; }

  /// The most threads a step uses (Workspace::setThreadCount: 0 = the cores
  /// available, the default). Not part of the result: every count gives the
  /// same state, bit for bit.
  void setThreadCount(int threads) { workspace_.setThreadCount(threads); }
  int threadCount() const { return workspace_.threadCount(); }

  // ---- Edits of the state (between steps). Indices are checked
  // (std::out_of_range), values must be finite (std::invalid_argument).
  void setPosition(ParticleIndex particle, const Vec3& position);
  void setVelocity(ParticleIndex particle, const Vec3& velocity);
  /// An impulse p (N·s, in W) at a particle: a free particle's velocity changes by
  /// p/m; a particle carried by a rigid tree's body (Model::isCarried) changes the
  /// tree's rates v by M⁻¹ Jᵀ p (M the tree's mass matrix, J the Jacobian of the
  /// point where the particle sits), the tree struck there; a fixed particle that
  /// nothing carries: no change. The kinetic energy it adds is booked as external
  /// work, as for setVelocity.
  void applyImpulse(ParticleIndex particle, const Vec3& impulse);

  // ---- Edits of the model (between steps).
  /// Joint servo (MODEL §1): the target (rad, wrapped into [0, 2π), for a
  /// revolute joint; m > 0 for a prismatic one with a drive). Throws
  /// std::invalid_argument for a prismatic joint without a drive.
  void setJointTarget(std::size_t joint, double target);
  /// The servo's stiffness (N·m/rad or N/m) and damping (N·m·s/rad or N·s/m), >= 0.
  void setJointServo(std::size_t joint, double stiffness, double damping);
  /// The joint's commanded motor effort τ0 (MODEL §1.6: N·m about the axis for a
  /// revolute joint, N along the line for a prismatic one; positive increases q),
  /// finite. Its power is booked as external work.
  void setJointEffort(std::size_t joint, double effort);
  /// Gravity compensation on or off for a joint with a body link and a subtree
  /// (Joint::compensateGravity, MODEL §1.7); throws std::invalid_argument otherwise.
  void setGravityCompensation(std::size_t joint, bool on);
  /// Replaces the joint's whole drive (motor, rate drive, limits, losses; MODEL
  /// §1.6). Throws std::invalid_argument for a drive checkJointDrive refuses.
  void setJointDrive(std::size_t joint, const JointDrive& drive);
  /// Replaces a connector (its ends are checked; new ends rebuild the
  /// contact exclusion lists).
  void setLinearSpring(std::size_t index, const LinearSpring& spring);
  void setTorsionSpring(std::size_t index, const TorsionSpring& spring);
  void setJointSpring(std::size_t index, const JointSpring& spring);
  /// Replaces material `index` (contact stiffness, damping, friction).
  void setMaterial(std::int32_t index, const Material& material);
  /// Adds a material; returns its index.
  std::int32_t addMaterial(const Material& material);
  /// Gives object `object` material `material`.
  void setObjectMaterial(std::int32_t object, std::int32_t material);
  /// Sets the contact parameters of a pair of objects (objectB = -1: the
  /// environment), replacing an override of the same pair.
  void setContactPair(const ContactPairOverride& pair);
  /// Replaces the contact settings; their pair overrides are replaced too.
  void setContactSettings(const ContactSettings& settings);
  /// Fixes a particle (inverse mass 0: it keeps its velocity) or frees it.
  void setParticleFixed(ParticleIndex particle, bool fixed);
  /// Gravity g (m/s²).
  void setGravity(const Vec3& gravity);
  /// Adds a fixed sphere to the environment; returns its environment item index.
  std::int32_t addSphereObstacle(const SphereObstacle& sphere);
  /// Puts environment item `item`, a sphere (as addSphereObstacle returned it),
  /// at `center`: a virtual obstacle placed by trial (the escape, MODEL §5.2).
  /// Throws std::invalid_argument for an item that is not a sphere.
  void moveSphereObstacle(std::int32_t item, const Vec3& center);
  /// The viscosity of the medium k (N·s/m), >= 0.
  void setViscosity(double viscosity);

  /// Brings the evaluation up to date and returns the work (J) booked as
  /// external for the edits made since the last evaluation (0 when none).
  double bookExternalWork();

  /// Everything needed to undo steps exactly: the state, its evaluation and
  /// the edit bookkeeping. A plain value.
  class Snapshot {
   public:
    const State& state() const { return state_; }
    /// The evaluation at the state (valid when evaluated()).
    const Evaluation& evaluation() const { return evaluation_; }
    bool evaluated() const { return evaluated_; }
    /// The energy account of the saved state (valid when evaluated()).
    EnergyTally energy() const;

   private:
    friend class World;
    State state_;
    Evaluation evaluation_;
    bool evaluated_ = false;
    /// Edits made since the evaluation; their work is booked at the next one
    /// against `totalBeforeEdits_`.
    bool edited_ = false;
    double totalBeforeEdits_ = 0.0;
    /// The released anchor energy (J) of the evaluation that State::dissipated
    /// already holds.
    double bookedRelease_ = 0.0;
  };
  /// The state and its evaluation, brought up to date.
  const Snapshot& snapshot() const {
    refresh();
    return current_;
  }
  /// Puts back a snapshot taken earlier: undoes steps exactly.
  /// Throws std::invalid_argument for a snapshot not sized for this model.
  void restore(const Snapshot& saved);

  /// For a world built from a state that a step ended (a checkpoint, with the
  /// model edits it had): puts back `evaluation`, the evaluation the world had
  /// at that state (World::evaluation() then), which is not always a function of
  /// the state alone (velocity Verlet evaluates at the half-step velocity).
  /// Its released anchor energy is taken as already in State::dissipated. Call
  /// before any accessor or edit; then the world steps on bit-identically to the
  /// one that wrote the checkpoint. Throws std::invalid_argument for an
  /// evaluation not sized for the model.
  void resumeAfterStep(Evaluation evaluation);

  /// The first particle whose state is not finite, or kNoParticle.
  ParticleIndex firstNonFiniteParticle() const;

  /// Counts what changed the state or the model: steps, edits, restores. Two
  /// equal counts mean the same state and model (and so the same evaluation):
  /// a caller may keep what it measured at the first for the second.
  std::uint64_t changeCount() const { return changes_; }

 private:
  /// Marks the evaluation stale after an edit of the state or the model,
  /// remembering the energy total that the edit's work is booked against.
  void edited();
  /// Evaluates the current state into current_.evaluation_ (forces, contacts,
  /// kinetic energy, driving power).
  void evaluateCurrent() const;

  CompiledModel model_;
  Integrator integrator_;
  /// The state, its evaluation and the edit bookkeeping (mutable: evaluation
  /// is brought up to date lazily by const accessors).
  mutable Snapshot current_;
  mutable Workspace workspace_;
  /// The rigid trees' scratch (Model::rigidTrees, one each).
  mutable std::vector<MultibodyWorkspace> treeWorkspaces_;
  /// Work booked as external for edits since the last bookExternalWork() (J).
  mutable double unreportedWork_ = 0.0;
  std::uint64_t changes_ = 0;  // changeCount()
};

}  // namespace robophi
