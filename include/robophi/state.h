#pragma once
/// \file
/// State: what a step advances (MODEL §2). A plain value: copying it is a
/// snapshot. Everything computed *from* a state (forces, potentials, the contacts
/// at its positions) is an Evaluation (evaluation.h), never part of the state.

#include <cstdint>
#include <vector>

#include "robophi/contact.h"
#include "robophi/model.h"
#include "robophi/vec3.h"

namespace robophi {

/// The energy account at a state (J). Kinetic energy and potentials are measured
/// at the state (an Evaluation); `dissipated` and `external` are accumulated by
/// the steps (State).
struct EnergyTally {
  double kinetic = 0.0;
  double linearSpring = 0.0;
  double torsionSpring = 0.0;
  double jointSpring = 0.0;
  double gravity = 0.0;
  /// Potential of contacts and of the environment, friction anchors included.
  double contact = 0.0;
  /// Work removed so far by damping, friction and viscosity (>= 0 when the
  /// account is right; it only grows).
  double dissipated = 0.0;
  /// Of `dissipated`, the rigid trees' implicit contact loads' scheme loss (J,
  /// docs/model.md §7): integration error, not the work of a dissipative force,
  /// so the adaptive step's energy test counts it as error (MODEL §4.1).
  double implicitLoss = 0.0;
  /// Work done on the system from outside (J): by fixed particles moving
  /// kinematically (a moving virtual robot), and by edits made between steps
  /// (World's edit API: joint targets, virtual obstacles, a disturbance).
  /// 0 for a closed system.
  double external = 0.0;

  double potential() const {
    return linearSpring + torsionSpring + jointSpring + gravity + contact;
  }
  /// Mechanical energy E = kinetic + potential.
  double mechanical() const { return kinetic + potential(); }
  /// E + dissipated - external work: constant for an exact integration.
  double total() const { return mechanical() + dissipated - external; }
};

/// The mutable state of a model.
struct State {
  /// Model time t (s).
  double time = 0.0;
  /// Number of steps taken.
  std::int64_t stepCount = 0;
  // Particle arrays, each of Model::particleCount() entries.
  /// p_i (m).
  std::vector<Vec3> position;
  /// v_i (m/s).
  std::vector<Vec3> velocity;
  /// Angular velocity ω_i (rad/s) of the particles that spin on their own: the
  /// particles no LS ties to another, a ball of one particle (MODEL §3.3 rolling). Zero for the
  /// particles an LS ties to others, which turn with their neighbours. Missing
  /// entries (a shorter vector) are zero; World sizes it.
  std::vector<Vec3> spin;
  /// Friction history (MODEL §3.3): the contacts, with their anchors and
  /// sliding flags, that the force evaluation at this state starts from — the
  /// contacts of the evaluation that ended the previous step, committed by the
  /// step. Sorted by Contact::key(). Empty at the start.
  std::vector<Contact> frictionHistory;
  /// (Model::rigidTrees) each tree's coordinates q and rates v (docs/model.md §7).
  std::vector<std::vector<double>> treePositions, treeVelocities;
  /// Work removed by dissipative forces since t = 0 (J), EnergyTally::dissipated.
  double dissipated = 0.0;
  /// Of it, the implicit contact loads' scheme loss (J), EnergyTally::implicitLoss.
  double implicitLoss = 0.0;
  /// Work done from outside since t = 0 (J), EnergyTally::external.
  double external = 0.0;

  /// A state at rest with every particle at the origin, sized for `model`.
  static State sizedFor(const Model& model);
};

/// A 64-bit FNV-1a hash of the bits of the whole state: time, step count,
/// positions, velocities, spins, the friction history and the energy accumulators.
/// Equal hashes mean bit-identical states.
std::uint64_t stateHash(const State& state);

}  // namespace robophi
